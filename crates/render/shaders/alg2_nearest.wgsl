#include "deferred_geometry.wgsl"
#include "opaque_cull.wgsl"

// Pass 1 of Zhang & Pajarola's Algorithm-2 (§5.2.2): the `deferred` geometry
// pass (group k into layer k, nearest splat per group with Voronoi depth,
// Eq. 14), writing w·rgb and w, w·n and w·α (the nearest layer's opacity,
// needed lit or not), and the true view depth. Fragments behind the opaque
// splats drawn apart are culled (shaders/opaque_cull.wgsl).

#ifdef OPAQUE_APART
@group(1) @binding(0) var opaque_depth: texture_2d<f32>;
#endif

struct NearestImage {
    @location(0) colour: vec4<f32>,
    @location(1) normal_alpha: vec4<f32>,
    @location(2) depth: f32,
    @builtin(frag_depth) z: f32,
}

// The z-test value: Eq. 14's Voronoi depth with the facing split of
// Algorithm-1's layers (shaders/group_layer.wgsl): within a step, fragments
// facing the viewer come first (the first half step), those facing away
// after them, and within each half the splat whose centre is nearest wins.
// Without Voronoi, plain depth.
fn nearest_z(s: SplatSample, away: bool) -> f32 {
    if this_pass.layers.z != 1u {
        return group_z(s);
    }
    let n = this_pass.depth.y;
    let step = floor(depth_to_buffer(s.view_depth) * n) / n + select(0.0, 0.5 / n, away);
    return min(step + 0.5 * sqrt(s.rho2) / n, 1.0);
}

@fragment
fn fs_alg2_nearest(v: SplatVarying) -> NearestImage {
    let s = splat_sample(v);
    if behind_opaque(vec2<i32>(v.clip.xy), s.view_depth) {
        discard;
    }
    let w = splat_weight(s);
    // The normal as it is: its side tells the layer's facing
    // (shaders/alg2_front.wgsl); shading turns it towards the viewer.
    return NearestImage(
        vec4<f32>(v.colour.rgb * w, w),
        vec4<f32>(v.normal * w, v.colour.a * w),
        s.view_depth,
        nearest_z(s, faces_away(v.normal, v.clip.xy)),
    );
}
