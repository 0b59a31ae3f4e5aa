#include "shading.wgsl"

// The approximate last layer of Guennebaud's approximate depth peeling: every
// fragment behind the exact layers, blended in any order into one sum, and
// composited as one layer. Its colour is the weighted mean Σw·rgb/Σw and its
// normal the mean of the normals turned towards the viewer. Its opacity
// stands for l layers of mean opacity ᾱ = Σw·α/Σw: α = 1 - (1 - ᾱ)^l, with l
// the rest's weight over the weight of one surface layer, taken from the last
// exact layer at the same pixel (l = Σw_rest / Σw_last, at least 1). This is
// the slides' heuristic C = Σ w·α·c with the layer count made explicit, so
// that two half-transparent layers behind the exact ones dim by 1 - 0.25
// rather than by 1 - 0.5.

#include "peel_sums.wgsl"
// The last exact layer's colour sums, bound after the rest's own.
#ifdef LIT
@group(1) @binding(3) var last_layer_colour: texture_2d<f32>;
#else
@group(1) @binding(2) var last_layer_colour: texture_2d<f32>;
#endif

@fragment
fn fs_rest(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let rest = peeled_sums(pixel);
    if !(rest.colour.a > 1e-6) {
        return vec4<f32>(0.0);
    }
    let one_layer = colour_sums(textureLoad(last_layer_colour, pixel, 0)).a;
    let layers = select(1.0, max(rest.colour.a / one_layer, 1.0), one_layer > 1e-6);
    let alpha = 1.0 - pow(1.0 - rest.alpha, layers);
    return vec4<f32>(shade_sums(f.position.xy, rest.colour, rest.normal) * alpha, alpha);
}
