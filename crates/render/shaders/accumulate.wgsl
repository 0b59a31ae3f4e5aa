#include "splat.wgsl"
#ifdef COVERAGE
#include "shading.wgsl"
#endif

// Pass 2 of the 2+1-pass pipeline (Botsch & Kobbelt 2003, Sec. 3.3): every
// fragment that passes the epsilon depth test adds w*colour, w and, in the LIT
// variant, w*normal. The unfiltered quality level instead keeps the nearest
// fragment (depth test and write), with weight 1.
//
// COVERAGE: the EWA prefilter's edge antialiasing (crates/core/src/frame/prefilter.rs).
// The ε test is made here, against the visibility pass's depth bound as a
// texture, so that a fragment behind the front is summed apart instead of
// lost: a partly covered front pixel shows it through. Every fragment adds
// its coverage of the pixel (`splat_coverage`), front and behind apart; one
// the filter left alone adds to a count of solid fragments instead. A
// stretched splat is below the filter's size, so what the filter averages is
// its shaded colour, as the supersampled reference averages shaded rays: in
// the LIT variant it is shaded here with its own normal and summed apart from
// the splats the normalisation shades (Botsch & Kobbelt's deferred shading,
// whose blended normals are right only for splats that cover pixels). The
// fragments behind are shaded here too.

struct Accumulated {
    // sum of w * rgb, sum of w
    @location(0) colour: vec4<f32>,
#ifdef LIT
    // sum of w * eye-space normal, sum of w * opacity
    @location(1) normal: vec4<f32>,
#endif
#ifdef COVERAGE
#ifdef LIT
    // Σw·shaded rgb, Σw of the stretched fragments within ε of the front.
    @location(2) shaded: vec4<f32>,
    // Σw·shaded rgb, Σw of the fragments behind the front + ε.
    @location(3) behind: vec4<f32>,
    // Σ coverage front (x), behind (y); solid fragments front (z), behind (w).
    @location(4) coverage: vec4<f32>,
#else
    @location(1) behind: vec4<f32>,
    @location(2) coverage: vec4<f32>,
#endif
#else
    @builtin(frag_depth) depth: f32,
#endif
}

#ifdef COVERAGE
@group(1) @binding(0) var visibility_depth: texture_2d<f32>;

// The ε test against the visibility pass (the hardware test of the plain
// variant: the fragment's buffer depth at most the front's + ε), and the
// fragment's sums where it belongs.
fn covered(v: SplatVarying, s: SplatSample, w: f32) -> Accumulated {
    var out: Accumulated;
    let stretched = s.scale < 1.0;
    let coverage = vec2<f32>(splat_coverage(s, w), select(1.0, 0.0, stretched));
#ifdef LIT
    let colour = shade(v.colour.rgb, v.normal, normalize(-pixel_ray(v.clip.xy)));
#else
    let colour = v.colour.rgb;
#endif
    if depth_to_buffer(s.view_depth) > textureLoad(visibility_depth, vec2<i32>(v.clip.xy), 0).r {
        out.behind = vec4<f32>(colour * w, w);
        out.coverage = vec4<f32>(0.0, coverage.x, 0.0, coverage.y);
        return out;
    }
    out.coverage = vec4<f32>(coverage.x, 0.0, coverage.y, 0.0);
#ifdef LIT
    if stretched {
        out.shaded = vec4<f32>(colour * w, w);
        return out;
    }
    out.normal = vec4<f32>(v.normal * w, v.colour.a * w);
#endif
    out.colour = colour_output(v.colour.rgb, w);
    return out;
}
#endif

#ifndef COVERAGE
fn accumulated(v: SplatVarying, s: SplatSample, w: f32) -> Accumulated {
    var out: Accumulated;
    out.colour = colour_output(v.colour.rgb, w);
#ifdef LIT
    out.normal = vec4<f32>(v.normal * w, v.colour.a * w);
#endif
    out.depth = depth_to_buffer(s.view_depth);
    return out;
}
#endif

@fragment
fn fs_accumulate(v: SplatVarying) -> Accumulated {
    let s = splat_sample(v);
#ifdef COVERAGE
    return covered(v, s, splat_weight(s));
#else
    return accumulated(v, s, splat_weight(s));
#endif
}

#ifndef COVERAGE
@fragment
fn fs_unfiltered(v: SplatVarying) -> Accumulated {
    let s = splat_sample(v);
    return accumulated(v, s, 1.0);
}
#endif
