#include "group_layer.wgsl"
#include "opaque_cull.wgsl"

// The geometry pass of Zhang & Pajarola's Algorithm-1 (§5.2.1): each group's
// splats back to front into its image I_k, Eq. 10 culling
// (shaders/group_layer.wgsl); fragments behind the opaque splats drawn apart
// are culled (shaders/opaque_cull.wgsl).

#ifdef OPAQUE_APART
@group(1) @binding(0) var opaque_depth: texture_2d<f32>;
#endif

@fragment
fn fs_alg1_group(v: SplatVarying) -> GroupFragment {
    let s = splat_sample(v);
    if behind_opaque(vec2<i32>(v.clip.xy), s.view_depth) {
        discard;
    }
    return group_fragment(v, s);
}
