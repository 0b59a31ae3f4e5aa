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

@fragment
fn fs_alg2_nearest(v: SplatVarying) -> NearestImage {
    let s = splat_sample(v);
    if behind_opaque(vec2<i32>(v.clip.xy), s.view_depth) {
        discard;
    }
    let w = splat_weight(s.rho2);
    // Shaded from the side the viewer sees.
    let n = select(v.normal, -v.normal, dot(v.normal, pixel_ray(v.clip.xy)) > 0.0);
    return NearestImage(vec4<f32>(v.colour.rgb * w, w), vec4<f32>(n * w, v.colour.a * w), s.view_depth, group_z(s));
}
