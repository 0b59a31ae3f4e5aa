// Pass 2 of the 2+1-pass pipeline (Botsch & Kobbelt 2003, Sec. 3.3): every
// fragment that passes the epsilon depth test adds w*colour, w and w*normal.
// The unfiltered quality level instead keeps the nearest fragment (depth test
// and write), with weight 1.

struct Accumulated {
    // sum of w * rgb, sum of w
    @location(0) color: vec4<f32>,
    // sum of w * eye-space normal, sum of w * opacity
    @location(1) normal: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_accumulate(v: SplatVarying) -> Accumulated {
    let s = splat_sample(v);
    let w = splat_weight(s.rho2);
    var out: Accumulated;
    out.color = colour_output(v.color.rgb, w);
    out.normal = vec4<f32>(v.normal * w, v.color.a * w);
    out.depth = depth_to_buffer(s.view_depth);
    return out;
}

@fragment
fn fs_unfiltered(v: SplatVarying) -> Accumulated {
    let s = splat_sample(v);
    var out: Accumulated;
    out.color = colour_output(v.color.rgb, 1.0);
    out.normal = vec4<f32>(v.normal, v.color.a);
    out.depth = depth_to_buffer(s.view_depth);
    return out;
}

// Without lighting the normal target is not allocated: colour and weight only.
struct AccumulatedUnlit {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_accumulate_unlit(v: SplatVarying) -> AccumulatedUnlit {
    let s = splat_sample(v);
    let w = splat_weight(s.rho2);
    return AccumulatedUnlit(colour_output(v.color.rgb, w), depth_to_buffer(s.view_depth));
}

@fragment
fn fs_unfiltered_unlit(v: SplatVarying) -> AccumulatedUnlit {
    let s = splat_sample(v);
    return AccumulatedUnlit(colour_output(v.color.rgb, 1.0), depth_to_buffer(s.view_depth));
}
