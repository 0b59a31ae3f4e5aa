#include "group_layer.wgsl"
#include "opaque_cull.wgsl"

// Pass 2 of Algorithm-2 (§5.2.2): the Algorithm-1 geometry pass into O_k,
// culling every fragment of the nearest layer found by pass 1 (within ε of
// d = min_k depth_k and of its facing, one texel found once per pixel by
// shaders/alg2_front.wgsl), so that the nearest layer, drawn in high
// quality by pass 1, is not counted twice; and, as pass 1 does,
// every fragment behind the opaque splats drawn apart.

@group(1) @binding(0) var front_depth: texture_2d<f32>;
#ifdef OPAQUE_APART
@group(1) @binding(1) var opaque_depth: texture_2d<f32>;
#endif

@fragment
fn fs_alg2_other(v: SplatVarying) -> GroupFragment {
    let pixel = vec2<i32>(v.clip.xy);
    let nearest = textureLoad(front_depth, pixel, 0);
    let s = splat_sample(v);
    let away = faces_away(v.normal, v.clip.xy);
    let in_nearest = s.view_depth <= nearest.r + this_pass.depth.x && away == (nearest.g > 0.5);
    if in_nearest || behind_opaque(pixel, s.view_depth) {
        discard;
    }
    return group_fragment(v, s);
}
