#include "shading.wgsl"
#include "opaque_under.wgsl"
#include "group_images.wgsl"

// The compositing pass of Algorithm-1 (§5.2.1): the average of the K group
// images I_k, over the background. Each I_k holds premultiplied colour and
// its coverage α (0 where the group drew nothing); groups that left a pixel
// empty are left out (shaders/group_images.wgsl). So C = Σ_{α_k > 0} I_k / m
// over the m groups that cover the pixel (0 where none does), and the
// pixel is C.rgb + (1 - C.a)·B, B the background or the opaque splats drawn
// apart over it (shaders/opaque_under.wgsl).

@group(1) @binding(0) var group_images: texture_2d_array<f32>;
#ifdef OPAQUE_APART
@group(1) @binding(1) var opaque_image: texture_2d<f32>;
#endif

@fragment
fn fs_alg1_average(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let mean = mean_of_covering(group_images, pixel);
    let under = beneath(pixel);
    return vec4<f32>(mean.rgb + (1.0 - mean.a) * under, 1.0);
}
