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

@group(1) @binding(0) var rest_color: texture_2d<f32>;
@group(1) @binding(1) var rest_opacity: texture_2d<f32>;
@group(1) @binding(2) var last_layer_color: texture_2d<f32>;
#ifdef LIT
@group(1) @binding(3) var rest_normal: texture_2d<f32>;
#endif

@fragment
fn fs_rest(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let sums = colour_sums(textureLoad(rest_color, pixel, 0));
    if !(sums.a > 1e-6) {
        return vec4<f32>(0.0);
    }
    var normal_sum = vec3<f32>(0.0);
#ifdef LIT
    normal_sum = textureLoad(rest_normal, pixel, 0).xyz;
#endif
    let mean_alpha = clamp(textureLoad(rest_opacity, pixel, 0).r / sums.a, 0.0, 1.0);
    let one_layer = colour_sums(textureLoad(last_layer_color, pixel, 0)).a;
    let layers = select(1.0, max(sums.a / one_layer, 1.0), one_layer > 1e-6);
    let alpha = 1.0 - pow(1.0 - mean_alpha, layers);
    return vec4<f32>(shade_sums(f.position.xy, sums, normal_sum) * alpha, alpha);
}
