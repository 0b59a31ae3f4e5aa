#include "shading.wgsl"

// Pass 3 of the 2+1-pass pipeline (Botsch & Kobbelt 2003, Sec. 3.4): one
// full-screen triangle divides the accumulated sums by the weight and shades
// the normalised normal with Phong lighting (src/view/shading.rs has the same
// formula for the CPU). Pixels with no weight show the background.

@group(1) @binding(0) var accumulated_colour: texture_2d<f32>;
#ifdef LIT
@group(1) @binding(1) var accumulated_normal: texture_2d<f32>;
#endif

@fragment
fn fs_normalize(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let sums = colour_sums(textureLoad(accumulated_colour, pixel, 0));
    if !(sums.a > 1e-6) {
#ifdef OPAQUE_APART
        // The opaque image of a transparent scene: α = 0 where nothing opaque is.
        return vec4<f32>(frame.background.rgb, 0.0);
#else
        return vec4<f32>(frame.background.rgb, 1.0);
#endif
    }
    var normal_sum = vec3<f32>(0.0);
#ifdef LIT
    normal_sum = textureLoad(accumulated_normal, pixel, 0).xyz;
#endif
    return vec4<f32>(shade_sums(f.position.xy, sums, normal_sum), 1.0);
}
