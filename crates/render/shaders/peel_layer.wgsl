#include "shading.wgsl"

// One layer of depth peeling: its sums normalised (Σw·rgb/Σw, opacity
// Σw·α/Σw), shaded facing the viewer, and written premultiplied, (α·c, α),
// with "under" blending into the composite, so the layers add up front to
// back: C += (1 - A)·α·c, A += (1 - A)·α.

#include "peel_sums.wgsl"

@fragment
fn fs_layer(f: Fullscreen) -> @location(0) vec4<f32> {
    let layer = peeled_sums(vec2<i32>(f.position.xy));
    if !(layer.colour.a > 1e-6) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(shade_sums(f.position.xy, layer.colour, layer.normal) * layer.alpha, layer.alpha);
}
