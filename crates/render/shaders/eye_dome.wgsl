#include "shading.wgsl"
#include "group_images.wgsl"

// Eye-dome lighting (Boucheny 2009, as Potree implements it): the last pass
// of an opaque frame that asks for it. It reads the shaded image and the
// nearest surface's view depth, compares log2 of that depth with 8
// neighbours on a circle of this_pass.effect.y pixels, and multiplies the
// colour by exp(-300 · strength · mean of max(0, log2 d - log2 d_n)).
// Pixels with no surface keep the background. EyeDome::shade
// (crates/core/src/frame/eye_dome.rs) is the same formula for the reference.

@group(1) @binding(0) var shaded_image: texture_2d<f32>;
#ifdef GROUP_DEPTH
// deferred: the nearest of K group images' true view depths.
@group(1) @binding(1) var group_colour: texture_2d_array<f32>;
@group(1) @binding(2) var group_depth: texture_2d_array<f32>;
#else
// two-pass: the visibility buffer (linear depth mapped to 0..1, pushed back by this_pass.effect.z).
@group(1) @binding(1) var depth_buffer: texture_2d<f32>;
#endif

const NEIGHBOURS: i32 = 8;
const RESPONSE_SCALE: f32 = 300.0;

// The view depth of the nearest surface at `pixel`, 0 where there is none
// (or the pixel is outside the image).
fn front_depth(pixel: vec2<i32>) -> f32 {
    let size = vec2<i32>(textureDimensions(shaded_image));
    if any(pixel < vec2<i32>(0)) || any(pixel >= size) {
        return 0.0;
    }
#ifdef GROUP_DEPTH
    let group = nearest_group(group_colour, group_depth, pixel);
    if group < 0 {
        return 0.0;
    }
    return textureLoad(group_depth, pixel, group, 0).r;
#else
    let buffer = textureLoad(depth_buffer, pixel, 0).r;
    if buffer >= 1.0 {
        return 0.0;
    }
    return buffer / frame.depth.w + frame.depth.x - this_pass.effect.z;
#endif
}

@fragment
fn fs_eye_dome(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let shaded = textureLoad(shaded_image, pixel, 0);
    let depth = front_depth(pixel);
    if depth <= 0.0 {
        return shaded;
    }
    let log_depth = log2(depth);
    var response = 0.0;
    for (var i = 0; i < NEIGHBOURS; i++) {
        let angle = f32(i) * 6.28318530718 / f32(NEIGHBOURS);
        // The pixel the offset lands in, from this pixel's centre.
        let at = vec2<i32>(floor(f.position.xy + vec2<f32>(cos(angle), sin(angle)) * this_pass.effect.y));
        let neighbour = front_depth(at);
        if neighbour > 0.0 {
            response += max(0.0, log_depth - log2(neighbour));
        }
    }
    response /= f32(NEIGHBOURS);
    return vec4<f32>(shaded.rgb * exp(-response * RESPONSE_SCALE * this_pass.effect.x), shaded.a);
}
