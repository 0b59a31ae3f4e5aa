#include "splat.wgsl"

// Pass 2 of the 2+1-pass pipeline (Botsch & Kobbelt 2003, Sec. 3.3): every
// fragment that passes the epsilon depth test adds w*colour, w and, in the LIT
// variant, w*normal. The unfiltered quality level instead keeps the nearest
// fragment (depth test and write), with weight 1.

struct Accumulated {
    // sum of w * rgb, sum of w
    @location(0) colour: vec4<f32>,
#ifdef LIT
    // sum of w * eye-space normal, sum of w * opacity
    @location(1) normal: vec4<f32>,
#endif
    @builtin(frag_depth) depth: f32,
}

fn accumulated(v: SplatVarying, s: SplatSample, w: f32) -> Accumulated {
    var out: Accumulated;
    out.colour = colour_output(v.colour.rgb, w);
#ifdef LIT
    out.normal = vec4<f32>(v.normal * w, v.colour.a * w);
#endif
    out.depth = depth_to_buffer(s.view_depth);
    return out;
}

@fragment
fn fs_accumulate(v: SplatVarying) -> Accumulated {
    let s = splat_sample(v);
    return accumulated(v, s, splat_weight(s));
}

@fragment
fn fs_unfiltered(v: SplatVarying) -> Accumulated {
    let s = splat_sample(v);
    return accumulated(v, s, 1.0);
}
