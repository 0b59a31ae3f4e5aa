#include "shading.wgsl"

// Pass 3 of the 2+1-pass pipeline (Botsch & Kobbelt 2003, Sec. 3.4): one
// full-screen triangle divides the accumulated sums by the weight and shades
// the normalised normal with Phong lighting (src/view/shading.rs has the same
// formula for the CPU). Pixels with no weight show the background.

@group(1) @binding(0) var accumulated_colour: texture_2d<f32>;
#ifdef LIT
@group(1) @binding(1) var accumulated_normal: texture_2d<f32>;
#endif

#ifdef COVERAGE
// The EWA prefilter's edge antialiasing (shaders/accumulate.wgsl): the
// front's colour covers its share of the pixel, what is behind it the share
// the front leaves of its own, and the background the rest.
//
// Coverage is the sum of the stretched fragments' shares over the sum a
// covered pixel has: the splats' discs overlap, so a pixel inside the
// surface sums its overlap, not 1. That level is read from the neighbours:
// the mean over the 5×5 pixels around of the front sums at least half the
// largest of them (the covered ones). A pixel whose 3×3 neighbours are all
// covered at least half that much is inside the surface and covered whole,
// so the sums' spread inside (±10 %) does not show. A solid fragment (a
// splat the filter left alone) covers its pixel whole, as without coverage.
#ifdef LIT
@group(1) @binding(2) var shaded_colour: texture_2d<f32>;
@group(1) @binding(3) var behind_colour: texture_2d<f32>;
@group(1) @binding(4) var coverage: texture_2d<f32>;
#else
@group(1) @binding(1) var behind_colour: texture_2d<f32>;
@group(1) @binding(2) var coverage: texture_2d<f32>;
#endif

// How far around a pixel the covered level is read, in pixels.
const LEVEL_REACH: i32 = 2;
const LEVEL_SIDE: i32 = 2 * LEVEL_REACH + 1;
const AROUND: i32 = LEVEL_SIDE * LEVEL_SIDE;

// The coverage sums at `pixel`, clamped to the image.
fn coverage_at(pixel: vec2<i32>) -> vec4<f32> {
    let last = vec2<i32>(textureDimensions(coverage)) - 1;
    return textureLoad(coverage, clamp(pixel, vec2<i32>(0), last), 0);
}

// The share of `pixel` the front (x) and everything drawn (y) cover.
fn coverage_of(pixel: vec2<i32>, front: bool, behind: bool) -> vec2<f32> {
    let own = coverage_at(pixel);
    if own.z > 0.0 {
        return vec2<f32>(1.0);
    }
    // The front sums around, read once.
    var around: array<f32, AROUND>;
    var largest = 0.0;
    for (var k = 0; k < AROUND; k++) {
        let at = vec2<i32>(k % LEVEL_SIDE, k / LEVEL_SIDE) - LEVEL_REACH;
        around[k] = coverage_at(pixel + at).x;
        largest = max(largest, around[k]);
    }
    var level = 0.0;
    var covered = 0.0;
    for (var k = 0; k < AROUND; k++) {
        if around[k] >= 0.5 * largest {
            level += around[k];
            covered += 1.0;
        }
    }
    level = level / max(covered, 1.0);
    var inside = true;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let c = coverage_at(pixel + vec2<i32>(dx, dy));
            inside = inside && (c.x + c.y >= 0.5 * largest || c.z + c.w > 0.0);
        }
    }
    let share = select(vec2<f32>(0.0), own.xy / level, level > 0.0);
    var all = clamp(select(0.0, share.x, front) + select(0.0, share.y, behind), 0.0, 1.0);
    if inside || own.w > 0.0 {
        all = 1.0;
    }
    let front_share = select(all, min(clamp(share.x, 0.0, 1.0), all), behind);
    return vec2<f32>(select(0.0, front_share, front), all);
}

@fragment
fn fs_normalize(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let sums = colour_sums(textureLoad(accumulated_colour, pixel, 0));
    // The front: Σw·colour of the splats shaded here, and of those shaded per fragment.
    var front = vec4<f32>(0.0);
    if sums.a > 1e-6 {
        var normal_sum = vec3<f32>(0.0);
#ifdef LIT
        normal_sum = textureLoad(accumulated_normal, pixel, 0).xyz;
#endif
        front = vec4<f32>(shade_sums(f.position.xy, sums, normal_sum) * sums.a, sums.a);
    }
#ifdef LIT
    front += textureLoad(shaded_colour, pixel, 0);
#endif
    let behind = textureLoad(behind_colour, pixel, 0);
    let drawn = vec2<bool>(front.a > 1e-6, behind.a > 1e-6);
    if !drawn.x && !drawn.y {
        return vec4<f32>(frame.background.rgb, 1.0);
    }
    let share = coverage_of(pixel, drawn.x, drawn.y);
    var rgb = frame.background.rgb * (1.0 - share.y);
    if drawn.x {
        rgb += share.x * front.rgb / front.a;
    }
    if drawn.y {
        rgb += (share.y - share.x) * behind.rgb / behind.a;
    }
    return vec4<f32>(rgb, 1.0);
}
#else
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
#endif
