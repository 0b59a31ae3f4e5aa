#include "tiled_common.wgsl"

// `tiled`, pass 2a, one workgroup: the prefix sum of pass 1's tile counts
// into the tiles' offsets (and zero kept entries per tile, which pass 2
// counts after them), on the GPU, so that nothing comes back to the CPU
// inside a frame. The entry buffer's room is given in `lists[ROOM]`, as
// vello gives its bump allocators theirs. A total beyond it sets
// `lists[OVERFLOW]` and leaves every list empty, so the passes after this
// one write and read nothing; the CPU reads `lists` with the frame's result
// and draws the frame again with room for `lists[TOTAL]`, which later frames
// keep. A frame whose visible splats passed the per-splat slots
// (`lists[PACKED]` beyond `tiles.room.x`) overflows too, and is drawn in
// smaller parts. It also lists the tiles whose lists are longer than SHORT
// (their count first) and writes the indirect dispatch that sorts them, one
// workgroup each (tiled_sort.wgsl, cs_sort).
//
// Each invocation sums a run of consecutive tiles; a Hillis-Steele scan of
// the 256 sums gives each run its base. At 1920x1080 a run is 127 tiles.

@group(1) @binding(0) var<uniform> tiles: Tiles;
@group(1) @binding(1) var<storage, read> counts: array<u32>;
@group(1) @binding(2) var<storage, read_write> offsets: array<u32>;
@group(1) @binding(3) var<storage, read_write> long_tiles: array<u32>;
@group(1) @binding(4) var<storage, read_write> lists: array<u32>;

var<workgroup> sums: array<u32, GROUP>;
var<workgroup> long_count: atomic<u32>;
var<workgroup> longest: atomic<u32>;
// Set when a sum passed u32: more entries than any buffer could hold.
var<workgroup> wrapped: atomic<u32>;

@compute @workgroup_size(256)
fn cs_scan(@builtin(local_invocation_index) local: u32) {
    let n = tiles.grid.x * tiles.grid.y;
    let run = (n + GROUP - 1u) / GROUP;
    let first = min(local * run, n);
    let last = min(first + run, n);
    var sum = 0u;
    var most = 0u;
    for (var t = first; t < last; t++) {
        let c = counts[t];
        if sum + c < sum {
            atomicStore(&wrapped, 1u);
        }
        sum += c;
        most = max(most, c);
        if c > SHORT {
            long_tiles[1u + atomicAdd(&long_count, 1u)] = t;
        }
    }
    atomicMax(&longest, most);
    sums[local] = sum;
    workgroupBarrier();
    for (var step = 1u; step < GROUP; step *= 2u) {
        var before = 0u;
        if local >= step {
            before = sums[local - step];
        }
        workgroupBarrier();
        if sums[local] + before < sums[local] {
            atomicStore(&wrapped, 1u);
        }
        sums[local] += before;
        workgroupBarrier();
    }
    let total = sums[GROUP - 1u];
    let too_many = atomicLoad(&wrapped) != 0u;
    // Splats packed past their slots (a part of the frame with more splats
    // than the slots hold) overflow too: the renderer draws smaller parts.
    let packed_over = tiles.room.y != 0u && lists[PACKED] > tiles.room.x;
    let overflow = too_many || total > lists[ROOM] || packed_over;
    var base = sums[local] - sum;
    for (var t = first; t < last; t++) {
        offsets[t] = select(base, 0u, overflow);
        // What the binning keeps per tile is counted after the offsets.
        offsets[n + 1u + t] = 0u;
        base += counts[t];
    }
    if local == 0u {
        offsets[n] = select(total, 0u, overflow);
        lists[TOTAL] = select(total, 0xffffffffu, too_many);
        lists[OVERFLOW] = u32(overflow);
        lists[LONGEST] = atomicLoad(&longest);
        let long = select(atomicLoad(&long_count), 0u, overflow);
        long_tiles[0] = long;
        lists[LONG_DISPATCH] = min(long, 65535u);
        lists[LONG_DISPATCH + 1u] = max(1u, (long + 65534u) / 65535u);
        lists[LONG_DISPATCH + 2u] = 1u;
    }
}
