#include "tiled_common.wgsl"

// `tiled`, pass 3, per tile: sorts the tile's entries by key (the nearest
// depth on each disc), then the item's place in the scene. A list of up to
// SHORT entries (all of them but in extreme scenes) is sorted by one invocation, by a
// bottom-up merge sort through `scratch`, with no barrier (cs_sort_short).
// A longer one, which the scan lists (tiled_scan.wgsl), is sorted
// in place by a workgroup (cs_sort) with a bitonic network in the form
// whose every comparator puts the smaller entry first (each merge starts by
// comparing i with its mirror i ^ (k - 1)). Slots past the list's end count
// as +∞, so a comparator that reaches past it does nothing and a list of
// any length sorts without padding; storage barriers separate the steps,
// so no list is too long.

@group(1) @binding(0) var<uniform> tiles: Tiles;
@group(1) @binding(1) var<storage, read> offsets: array<u32>;
@group(1) @binding(2) var<storage, read_write> entries: array<vec2<u32>>;
// Room for a copy of every list (cs_sort_short).
@group(1) @binding(3) var<storage, read_write> scratch: array<vec2<u32>>;
// The items' pixel boxes: `w` orders equal keys (tiled_count.wgsl).
@group(1) @binding(4) var<storage, read> rects: array<vec4<u32>>;
// How many tiles have lists longer than SHORT, then those tiles (cs_sort).
@group(1) @binding(5) var<storage, read> long_tiles: array<u32>;

// The entries the binning kept in tile `tile`'s list, which begins at `start`.
fn list_length(tile: u32, start: u32) -> u32 {
    let tile_count = tiles.grid.x * tiles.grid.y;
    return min(offsets[tile_count + 1u + tile], offsets[tile + 1u] - start);
}

// Key order; equal keys in the order of the items' places in the scene:
// their slots, or when the splats were packed into slots (PACKED,
// tiled_project.wgsl) the places their pixel boxes keep (tiled_count.wgsl),
// so that a packed frame sorts as a whole one does. The boxes are read only
// then, in a module of its own: a read in the comparison, even behind a
// uniform branch, made the sort of the merged scans 1.5x slower on lavapipe.
fn before(a: vec2<u32>, b: vec2<u32>) -> bool {
#ifdef PACKED
    return a.x < b.x || (a.x == b.x && rects[a.y].w < rects[b.y].w);
#else
    return a.x < b.x || (a.x == b.x && a.y < b.y);
#endif
}

// The partner of slot i in step (k, j) of the network.
fn partner(i: u32, k: u32, j: u32) -> u32 {
    return select(i ^ j, i ^ (k - 1u), j == k / 2u);
}

@compute @workgroup_size(256)
fn cs_sort_short(dispatch: Dispatch) {
    let tile = invocation(dispatch);
    if tile >= tiles.grid.x * tiles.grid.y { return; }
    let start = offsets[tile];
    // The scan chose the long lists by the room counted for them.
    if offsets[tile + 1u] - start > SHORT {
        return;
    }
    let count = list_length(tile, start);
    // Bottom-up merge sort, between the list and its slots in `scratch`.
    var in_scratch = false;
    for (var width = 1u; width < count; width *= 2u) {
        for (var low = 0u; low < count; low += 2u * width) {
            let middle = min(low + width, count);
            let high = min(low + 2u * width, count);
            var i = low;
            var j = middle;
            for (var k = low; k < high; k++) {
                let left = read_run(start + min(i, count - 1u), in_scratch);
                let right = read_run(start + min(j, count - 1u), in_scratch);
                // Ties go to the left run, so equal keys keep their order.
                let take_left = j >= high || (i < middle && !before(right, left));
                let chosen = select(right, left, take_left);
                if in_scratch {
                    entries[start + k] = chosen;
                } else {
                    scratch[start + k] = chosen;
                }
                i += select(0u, 1u, take_left);
                j += select(1u, 0u, take_left);
            }
        }
        in_scratch = !in_scratch;
    }
    if in_scratch {
        for (var k = 0u; k < count; k++) {
            entries[start + k] = scratch[start + k];
        }
    }
}

fn read_run(at: u32, in_scratch: bool) -> vec2<u32> {
    if in_scratch {
        return scratch[at];
    }
    return entries[at];
}

@compute @workgroup_size(256)
fn cs_sort(dispatch: Dispatch) {
    let index = workgroup_index(dispatch);
    if index >= long_tiles[0] {
        return;
    }
    let tile = long_tiles[1u + index];
    let start = offsets[tile];
    let count = list_length(tile, start);
    var size = 2u;
    while size < count {
        size *= 2u;
    }
    for (var k = 2u; k <= size; k *= 2u) {
        for (var j = k / 2u; j > 0u; j /= 2u) {
            for (var i = dispatch.local; i < size; i += GROUP) {
                let l = partner(i, k, j);
                if l > i && l < count && before(entries[start + l], entries[start + i]) {
                    let kept = entries[start + i];
                    entries[start + i] = entries[start + l];
                    entries[start + l] = kept;
                }
            }
            storageBarrier();
            workgroupBarrier();
        }
    }
}
