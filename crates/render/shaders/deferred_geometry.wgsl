#include "splat.wgsl"

// The geometry pass of deferred blending (Zhang & Pajarola 2007 §3.2, Fig. 11):
// group S_k is drawn into layer k with its own z-test, so in each pixel the
// nearest splat of the group wins and writes its own weight (Eq. 4): w·rgb and
// w, w·n (LIT variant), and the true linear view depth for the compositing pass.
// With Voronoi rasterisation (§5.1, Eq. 14) the z-test uses
// z = floor(depth01 · n)/n + (d_i/r_i)/n: the low-precision depth separates
// surface layers, and within a layer the splat whose centre is nearest wins.

struct GroupImage {
    @location(0) colour: vec4<f32>,
#ifdef LIT
    @location(1) normal: vec4<f32>,
    @location(2) depth: f32,
#else
    @location(1) depth: f32,
#endif
    @builtin(frag_depth) z: f32,
}

// The depth of the z-test within a group: linear, or Voronoi-enhanced (Eq. 14).
// A prefiltered splat competes at its front depth (shaders/splat.wgsl), as in
// the visibility pass: the plane continued past its disc is not surface, and
// across a silhouette it would win over the splats facing the viewer.
fn group_z(s: SplatSample) -> f32 {
    let depth01 = depth_to_buffer(s.front_depth);
    let n = this_pass.depth.y;
    if this_pass.layers.z == 1u {
        return min(floor(depth01 * n) / n + sqrt(s.rho2) / n, 1.0);
    }
    return depth01;
}

@fragment
fn fs_group(v: SplatVarying) -> GroupImage {
    let s = splat_sample(v);
    let w = splat_weight(s);
    var out: GroupImage;
    out.colour = colour_output(v.colour.rgb, w);
#ifdef LIT
    out.normal = vec4<f32>(v.normal * w, v.colour.a * w);
#endif
    out.depth = s.view_depth;
    out.z = group_z(s);
    return out;
}
