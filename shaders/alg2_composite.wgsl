#include "shading.wgsl"
#include "opaque_under.wgsl"

// The compositing pass of Algorithm-2 (§5.2.2), the three blends in one go:
// C_F, the nearest layer: Fig. 6's ε-z compositing of the I_k (d = min_k
// depth_k, the layers within d + ε summed), normalised and shaded per pixel
// (deferred shading), with its opacity α = Σw·α / Σw; C_O, the other layers:
// the average of the O_k that cover the pixel (as in Algorithm-1), over the
// background; and the pixel I = α·C_F + (1 - α)·C_O.

@group(1) @binding(0) var nearest_color: texture_2d_array<f32>;
@group(1) @binding(1) var nearest_depth: texture_2d_array<f32>;
@group(1) @binding(2) var nearest_normal_alpha: texture_2d_array<f32>;
@group(1) @binding(3) var other_images: texture_2d_array<f32>;
#ifdef OPAQUE_APART
@group(1) @binding(4) var opaque_image: texture_2d<f32>;
#endif

@fragment
fn fs_alg2_composite(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let layers = i32(this_pass.layers.y);
    // C_O over the background.
    var others = vec4<f32>(0.0);
    var covering = 0.0;
    for (var k = 0; k < layers; k++) {
        let image = textureLoad(other_images, pixel, k, 0);
        if image.a > 0.0 {
            others += image;
            covering += 1.0;
        }
    }
    let under = beneath(pixel);
    var behind = under;
    if covering > 0.0 {
        let mean = others / covering;
        behind = mean.rgb + (1.0 - mean.a) * under;
    }
    // C_F and its opacity.
    var nearest = 3.0e38;
    for (var k = 0; k < layers; k++) {
        if textureLoad(nearest_color, pixel, k, 0).a > 0.0 {
            nearest = min(nearest, textureLoad(nearest_depth, pixel, k, 0).r);
        }
    }
    var sums = vec4<f32>(0.0);
    var normal_alpha = vec4<f32>(0.0);
    for (var k = 0; k < layers; k++) {
        let color = textureLoad(nearest_color, pixel, k, 0);
        if color.a > 0.0 && textureLoad(nearest_depth, pixel, k, 0).r <= nearest + this_pass.depth.x {
            sums += color;
            normal_alpha += textureLoad(nearest_normal_alpha, pixel, k, 0);
        }
    }
    if !(sums.a > 1e-6) {
        return vec4<f32>(behind, 1.0);
    }
    let alpha = clamp(normal_alpha.a / sums.a, 0.0, 1.0);
    let front = shade_sums(f.position.xy, sums, normal_alpha.xyz);
    return vec4<f32>(alpha * front + (1.0 - alpha) * behind, 1.0);
}
