#include "shading.wgsl"
#include "opaque_under.wgsl"

// The compositing pass of Algorithm-1 (§5.2.1): the average of the K group
// images I_k, over the background. Each I_k holds premultiplied colour and
// its coverage α (0 where the group drew nothing). A group that left a pixel
// empty is left out of the average, not counted as transparent black: it
// would otherwise darken the colour and thin the opacity by 1/K there. So
// C = Σ_{α_k > 0} I_k / m over the m groups that cover the pixel, and the
// pixel is C.rgb + (1 - C.a)·B, B the background or the opaque splats drawn
// apart over it (shaders/opaque_under.wgsl).

@group(1) @binding(0) var group_images: texture_2d_array<f32>;
#ifdef OPAQUE_APART
@group(1) @binding(1) var opaque_image: texture_2d<f32>;
#endif

@fragment
fn fs_alg1_average(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    var sum = vec4<f32>(0.0);
    var covering = 0.0;
    for (var k = 0u; k < this_pass.layers.y; k++) {
        let image = textureLoad(group_images, pixel, i32(k), 0);
        if image.a > 0.0 {
            sum += image;
            covering += 1.0;
        }
    }
    let under = beneath(pixel);
    if covering == 0.0 {
        return vec4<f32>(under, 1.0);
    }
    let mean = sum / covering;
    return vec4<f32>(mean.rgb + (1.0 - mean.a) * under, 1.0);
}
