// The sums one peeled layer left (depth peeling, Guennebaud's approximate
// peeling): Σw·rgb, Σw (or Σw alone for a scene of one colour), Σw·α, and
// Σw·n when lit, bound in that order at group 1. Needs shading.wgsl.

@group(1) @binding(0) var sums_colour: texture_2d<f32>;
@group(1) @binding(1) var sums_opacity: texture_2d<f32>;
#ifdef LIT
@group(1) @binding(2) var sums_normal: texture_2d<f32>;
#endif

struct PeeledSums {
    // (Σw·rgb, Σw).
    colour: vec4<f32>,
    // Σw·n (zero when unlit).
    normal: vec3<f32>,
    // The mean opacity Σw·α / Σw, in 0..1.
    alpha: f32,
}

fn peeled_sums(pixel: vec2<i32>) -> PeeledSums {
    var out: PeeledSums;
    out.colour = colour_sums(textureLoad(sums_colour, pixel, 0));
    out.normal = vec3<f32>(0.0);
#ifdef LIT
    out.normal = textureLoad(sums_normal, pixel, 0).xyz;
#endif
    out.alpha = clamp(textureLoad(sums_opacity, pixel, 0).r / max(out.colour.a, 1e-30), 0.0, 1.0);
    return out;
}
