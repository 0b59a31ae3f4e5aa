#include "shading.wgsl"
#include "group_images.wgsl"

// The compositing pass of deferred blending (Zhang & Pajarola 2007 Fig. 6):
// d = min_k depth_k over the K group images; the layers within d + ε are
// summed, normalised (Eq. 3) and shaded. No layer with weight: background.

@group(1) @binding(0) var group_colour: texture_2d_array<f32>;
#ifdef LIT
@group(1) @binding(1) var group_depth: texture_2d_array<f32>;
@group(1) @binding(2) var group_normal: texture_2d_array<f32>;
#else
@group(1) @binding(1) var group_depth: texture_2d_array<f32>;
#endif

@fragment
fn fs_composite(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let group = nearest_group(group_colour, group_depth, pixel);
    if group < 0 {
        return vec4<f32>(frame.background.rgb, 1.0);
    }
    let nearest = textureLoad(group_depth, pixel, group, 0).r;
    var sums = vec4<f32>(0.0);
    var normal_sum = vec3<f32>(0.0);
    for (var k = 0; k < i32(this_pass.layers.y); k++) {
        let colour = colour_sums(textureLoad(group_colour, pixel, k, 0));
        if in_nearest_layer(colour, textureLoad(group_depth, pixel, k, 0).r, nearest) {
            sums += colour;
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
