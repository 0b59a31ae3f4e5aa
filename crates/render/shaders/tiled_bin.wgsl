#include "tiled_common.wgsl"

// `tiled`, pass 2, per splat: writes one entry (sort key, splat) into each
// tile its disc may cover, at the tile's offset (the prefix sum of pass 1's
// counts, made on the CPU) plus a per-tile cursor. Every splat of a tile has
// its slot: the entry buffer is sized from the counts, so none is dropped.

@group(1) @binding(0) var<uniform> tiles: Tiles;
@group(1) @binding(1) var<storage, read> rects: array<vec4<u32>>;
@group(1) @binding(2) var<storage, read> offsets: array<u32>;
@group(1) @binding(3) var<storage, read_write> cursors: array<atomic<u32>>;
@group(1) @binding(4) var<storage, read_write> entries: array<vec2<u32>>;

@compute @workgroup_size(256)
fn cs_bin(dispatch: Dispatch) {
    let i = invocation(dispatch);
    if i >= tiles.grid.w { return; }
    let rect = rects[i];
    let first_pixel = vec2<u32>(rect.x & 0xffffu, rect.y & 0xffffu);
    let last_pixel = vec2<u32>(rect.x >> 16u, rect.y >> 16u);
    if first_pixel.x > last_pixel.x {
        return;
    }
    let t0 = first_pixel / TILE;
    let t1 = last_pixel / TILE;
    for (var ty = t0.y; ty <= t1.y; ty++) {
        for (var tx = t0.x; tx <= t1.x; tx++) {
            let tile = ty * tiles.grid.x + tx;
            let slot = offsets[tile] + atomicAdd(&cursors[tile], 1u);
            entries[slot] = vec2<u32>(rect.z, i);
        }
    }
}
