#include "splat.wgsl"
#include "shading.wgsl"

// One fragment of a group image of Zhang & Pajarola's Algorithm-1 (§5.2.1),
// also Algorithm-2's second pass: group S_k is drawn back to front into its
// own image I_k (layer k), α-blended over what is there (premultiplied, blend
// ONE, ONE_MINUS_SRC_ALPHA), with enlarged or duplicated splats so that the
// group covers the surface. The z-test runs on Eq. 10's low-precision depth
// floor(z·n)/n with n = (d_max - d_min)/(step·ε): a later fragment of the
// same surface layer falls in the same step and fails the strict test, so
// where a group's splats overlap the layer is blended once; a fragment of a
// nearer layer passes. Within a step, a fragment whose splat faces away from
// the viewer counts half a step farther than one facing it: the two sides of
// a thin shell closer than ε stay two layers, as the reference splits layers
// by facing. Each fragment is shaded with its splat's own normal turned to
// face the viewer (§5.2.4).

struct GroupFragment {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) z: f32,
}

// `s`: the fragment's splat sample (splat_sample, which discards outside the disc).
fn group_fragment(v: SplatVarying, s: SplatSample) -> GroupFragment {
    let n = this_pass.depth.y;
    let away = faces_away(v.normal, v.clip.xy);
    let z = floor(depth_to_buffer(s.view_depth) * n) / n + select(0.0, 0.5 / n, away);
    return GroupFragment(premultiplied_fragment(v), min(z, 1.0));
}

// A splat's fragment, shaded, premultiplied by its opacity (also plain
// α-blending's, shaders/alpha_blend.wgsl). Inside the disc only: splat_sample
// discards outside it.
fn premultiplied_fragment(v: SplatVarying) -> vec4<f32> {
    var rgb = v.colour.rgb;
#ifdef LIT
    // shade() turns the normal towards the eye.
    rgb = shade(rgb, v.normal, normalize(-pixel_ray(v.clip.xy)));
#endif
    let alpha = v.colour.a;
    return vec4<f32>(rgb * alpha, alpha);
}
