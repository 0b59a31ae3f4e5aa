#include "shading.wgsl"

// The compositing pass of deferred blending (Zhang & Pajarola 2007 Fig. 6):
// d = min_k depth_k over the K group images; the layers within d + ε are
// summed, normalised (Eq. 3) and shaded. No layer with weight: background.

@group(1) @binding(0) var group_color: texture_2d_array<f32>;
#ifdef LIT
@group(1) @binding(1) var group_depth: texture_2d_array<f32>;
@group(1) @binding(2) var group_normal: texture_2d_array<f32>;
#else
@group(1) @binding(1) var group_depth: texture_2d_array<f32>;
#endif

@fragment
fn fs_composite(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let layers = i32(this_pass.layers.y);
    var nearest = 3.0e38;
    for (var k = 0; k < layers; k++) {
        if colour_sums(textureLoad(group_color, pixel, k, 0)).a > 0.0 {
            nearest = min(nearest, textureLoad(group_depth, pixel, k, 0).r);
        }
    }
    var sums = vec4<f32>(0.0);
    var normal_sum = vec3<f32>(0.0);
    for (var k = 0; k < layers; k++) {
        let color = colour_sums(textureLoad(group_color, pixel, k, 0));
        if color.a > 0.0 && textureLoad(group_depth, pixel, k, 0).r <= nearest + this_pass.depth.x {
            sums += color;
#ifdef LIT
            normal_sum += textureLoad(group_normal, pixel, k, 0).xyz;
#endif
        }
    }
    if !(sums.a > 1e-6) {
        return vec4<f32>(frame.background.rgb, 1.0);
    }
    return vec4<f32>(shade_sums(f.position.xy, sums, normal_sum), 1.0);
}
