#include "splat.wgsl"

// The splat passes of depth peeling (the baselines of Zhang & Pajarola's
// Fig. 17; Guennebaud's approximate depth peeling). Layer i keeps only the
// fragments behind layer i-1: deeper than its front + ε, which the previous
// layer's visibility pass left in its depth buffer (read here as a texture).
// Layer 0 peels nothing: its entry points (`fs_front_*`) read no texture, so
// its passes bind none.

@group(1) @binding(0) var previous_layer: texture_2d<f32>;

// Whether this fragment belongs to an earlier layer.
fn peeled(v: SplatVarying, depth01: f32) -> bool {
    return depth01 <= textureLoad(previous_layer, vec2<i32>(v.clip.xy), 0).r;
}

// The visibility pass's depth: the fragment's, pushed back by ε.
fn visible_depth(s: SplatSample) -> f32 {
    return min(depth_to_buffer(s.front_depth + this_pass.depth.x), 1.0);
}

// Visibility of layer i > 0: the nearest unpeeled fragment, pushed back by ε.
@fragment
fn fs_peel_visibility(v: SplatVarying) -> @builtin(frag_depth) f32 {
    let s = splat_sample(v);
    if peeled(v, depth_to_buffer(s.view_depth)) {
        discard;
    }
    return visible_depth(s);
}

// Visibility of layer 0: the nearest fragment, pushed back by ε.
@fragment
fn fs_front_visibility(v: SplatVarying) -> @builtin(frag_depth) f32 {
    return visible_depth(splat_sample(v));
}

struct LayerSums {
    // sum of w * rgb, sum of w (or w alone, WEIGHT_ONLY)
    @location(0) colour: vec4<f32>,
    // sum of w * opacity
    @location(1) opacity: f32,
#ifdef LIT
    // sum of w * eye-space normal, turned towards the viewer
    @location(2) normal: vec4<f32>,
#endif
    @builtin(frag_depth) depth: f32,
}

fn layer_sums(v: SplatVarying, s: SplatSample) -> LayerSums {
    let w = splat_weight(s);
    var out: LayerSums;
    out.colour = colour_output(v.colour.rgb, w);
    out.opacity = v.colour.a * w;
#ifdef LIT
    // Shaded from the side the viewer sees: a back face counts with its normal flipped.
    let n = select(v.normal, -v.normal, dot(v.normal, pixel_ray(v.clip.xy)) > 0.0);
    out.normal = vec4<f32>(n * w, 0.0);
#endif
    out.depth = depth_to_buffer(s.view_depth);
    return out;
}

// Accumulation of layer i > 0: every unpeeled fragment within ε of its front.
@fragment
fn fs_peel_accumulate(v: SplatVarying) -> LayerSums {
    let s = splat_sample(v);
    if peeled(v, depth_to_buffer(s.view_depth)) {
        discard;
    }
    return layer_sums(v, s);
}

// Accumulation of layer 0: every fragment within ε of its front.
@fragment
fn fs_front_accumulate(v: SplatVarying) -> LayerSums {
    return layer_sums(v, splat_sample(v));
}
