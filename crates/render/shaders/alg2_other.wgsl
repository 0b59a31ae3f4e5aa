#include "group_layer.wgsl"
#include "opaque_cull.wgsl"

// Pass 2 of Algorithm-2 (§5.2.2): the Algorithm-1 geometry pass into O_k,
// culling every fragment within ε of the nearest layer found by pass 1
// (d = min_k depth_k over the groups that drew there), so that the nearest
// layer, drawn in high quality by pass 1, is not counted twice; and, as
// pass 1 does, every fragment behind the opaque splats drawn apart.

@group(1) @binding(0) var nearest_colour: texture_2d_array<f32>;
@group(1) @binding(1) var nearest_depth: texture_2d_array<f32>;
#ifdef OPAQUE_APART
@group(1) @binding(2) var opaque_depth: texture_2d<f32>;
#endif

@fragment
fn fs_alg2_other(v: SplatVarying) -> GroupFragment {
    let pixel = vec2<i32>(v.clip.xy);
    var nearest = 3.0e38;
    for (var k = 0; k < i32(this_pass.layers.y); k++) {
        if textureLoad(nearest_colour, pixel, k, 0).a > 0.0 {
            nearest = min(nearest, textureLoad(nearest_depth, pixel, k, 0).r);
        }
    }
    let s = splat_sample(v);
    if s.view_depth <= nearest + this_pass.depth.x || behind_opaque(pixel, s.view_depth) {
        discard;
    }
    return group_fragment(v, s);
}
