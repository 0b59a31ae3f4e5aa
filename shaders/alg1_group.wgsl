#include "splat.wgsl"
#include "shading.wgsl"

// The geometry pass of Zhang & Pajarola's Algorithm-1 (§5.2.1): group S_k is
// drawn back to front into its own image I_k (layer k), α-blended over what
// is there (premultiplied, blend ONE, ONE_MINUS_SRC_ALPHA), with enlarged or
// duplicated splats so that the group covers the surface. The z-test runs on
// Eq. 10's low-precision depth floor(z·n)/n with n = (d_max - d_min)/ε: a
// later fragment of the same surface layer falls in the same step and fails
// the strict test, so where a group's splats overlap the layer is blended
// once; a fragment of a nearer layer passes. Each fragment is shaded with its
// splat's own normal turned to face the viewer (§5.2.4).

struct GroupFragment {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) z: f32,
}

@fragment
fn fs_alg1_group(v: SplatVarying) -> GroupFragment {
    return group_fragment(v);
}

// One fragment of a group image (also Algorithm-2's second pass).
fn group_fragment(v: SplatVarying) -> GroupFragment {
    let s = splat_sample(v);
    var rgb = v.color.rgb;
#ifdef LIT
    // shade() turns the normal towards the eye.
    rgb = shade(rgb, v.normal, normalize(-pixel_ray(v.clip.xy)));
#endif
    let alpha = v.color.a;
    let n = this_pass.depth.y;
    let z = min(floor(depth_to_buffer(s.view_depth) * n) / n, 1.0);
    return GroupFragment(vec4<f32>(rgb * alpha, alpha), z);
}
