#include "shading.wgsl"

// One layer of depth peeling: its sums normalised (Σw·rgb/Σw, opacity
// Σw·α/Σw), shaded facing the viewer, and written premultiplied, (α·c, α),
// with "under" blending into the composite, so the layers add up front to
// back: C += (1 - A)·α·c, A += (1 - A)·α.

@group(1) @binding(0) var layer_color: texture_2d<f32>;
@group(1) @binding(1) var layer_opacity: texture_2d<f32>;
#ifdef LIT
@group(1) @binding(2) var layer_normal: texture_2d<f32>;
#endif

@fragment
fn fs_layer(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let sums = colour_sums(textureLoad(layer_color, pixel, 0));
    if !(sums.a > 1e-6) {
        return vec4<f32>(0.0);
    }
    var normal_sum = vec3<f32>(0.0);
#ifdef LIT
    normal_sum = textureLoad(layer_normal, pixel, 0).xyz;
#endif
    let alpha = clamp(textureLoad(layer_opacity, pixel, 0).r / sums.a, 0.0, 1.0);
    return vec4<f32>(shade_sums(f.position.xy, sums, normal_sum) * alpha, alpha);
}
