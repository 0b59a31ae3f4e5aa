#include "shading.wgsl"

// The end of depth peeling: the composited layers over the background,
// C + (1 - A)·background.

@group(1) @binding(0) var composite: texture_2d<f32>;

@fragment
fn fs_final(f: Fullscreen) -> @location(0) vec4<f32> {
    let layers = textureLoad(composite, vec2<i32>(f.position.xy), 0);
    return vec4<f32>(layers.rgb + (1.0 - layers.a) * frame.background.rgb, 1.0);
}
