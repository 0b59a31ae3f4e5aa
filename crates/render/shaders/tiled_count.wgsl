#include "tiled_common.wgsl"

// What both projections of `tiled` (splats, tiled_project.wgsl; mesh
// triangles, tiled_triangles.wgsl) write per item: its pixel box and sort
// key, and one more in the count of every tile the box touches.

// Per item: pixel columns x0 | x1 << 16, pixel rows y0 | y1 << 16, sort key; x0 > x1 when none.
@group(1) @binding(3) var<storage, read_write> rects: array<vec4<u32>>;
@group(1) @binding(4) var<storage, read_write> counts: array<atomic<u32>>;

const NO_TILES: vec4<u32> = vec4<u32>(1u, 0u, 0u, 0u);

// The box (low, high) grown by the pixel of eye-space point `p`, in front of the near plane.
fn pixel_box_of(p: vec3<f32>, low: vec2<f32>, high: vec2<f32>) -> array<vec2<f32>, 2> {
    let size = frame.viewport.xy;
    let clip = frame.proj * vec4<f32>(p, 1.0);
    let ndc = clip.xy / clip.w;
    let px = vec2<f32>((ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y);
    return array<vec2<f32>, 2>(min(low, px), max(high, px));
}

// The pixels from `low` to `high` clamped to the screen (NO_TILES when the
// box is off screen), with the nearest view depth key `key` and the item's
// order among equal keys, `order` (its place in the scene: the sort's tie-break).
fn screen_rect(low: vec2<f32>, high: vec2<f32>, key: u32, order: u32) -> vec4<u32> {
    let size = frame.viewport.xy;
    if high.x < 0.0 || high.y < 0.0 || low.x > size.x || low.y > size.y {
        return NO_TILES;
    }
    let last = vec2<u32>(size) - vec2<u32>(1u);
    let first_pixel = min(vec2<u32>(max(floor(low), vec2<f32>(0.0))), last);
    let last_pixel = min(vec2<u32>(max(floor(high), vec2<f32>(0.0))), last);
    return vec4<u32>(first_pixel.x | (last_pixel.x << 16u), first_pixel.y | (last_pixel.y << 16u), key, order);
}

fn covers_nothing(rect: vec4<u32>) -> bool {
    return (rect.x & 0xffffu) > (rect.x >> 16u);
}

// One more in the count of every tile `rect` (not NO_TILES) touches.
fn count_tiles(rect: vec4<u32>) {
    let t0 = vec2<u32>(rect.x & 0xffffu, rect.y & 0xffffu) / TILE;
    let t1 = vec2<u32>(rect.x >> 16u, rect.y >> 16u) / TILE;
    for (var ty = t0.y; ty <= t1.y; ty++) {
        for (var tx = t0.x; tx <= t1.x; tx++) {
            atomicAdd(&counts[ty * tiles.grid.x + tx], 1u);
        }
    }
}
