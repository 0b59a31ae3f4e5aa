#include "frame.wgsl"

// What the passes of the tile pipeline share (`tiled`: the exact reference's
// algorithm as GPU compute; crates/render/src/tile_engine.rs records them):
// the tile size, the splat record the projection writes for the per-pixel
// pass, the grid constants, and the sort key.

// Side of a square screen tile in pixels; one workgroup of TILE² invocations
// (one per pixel) rasterises a tile. Mirrors TILE in tile_engine.rs, where
// the choice is measured.
const TILE: u32 = 8u;
// Invocations of the per-splat and per-tile passes.
const GROUP: u32 = 256u;
// Lists up to this long are sorted by one invocation, longer ones by a
// workgroup (tiled_sort.wgsl). Mirrors SHORT_LIST in tile_engine.rs.
const SHORT: u32 = 4096u;

// A splat in eye space, as the per-pixel pass intersects it (48 bytes).
struct EyeSplat {
    centre: vec3<f32>,
    // 1/r² of the (scaled) radius.
    inv_r2: f32,
    // Unit normal of the plane the footprint is cast on (tilted when grazing).
    plane: vec3<f32>,
    opacity: f32,
    // Unit shading normal.
    normal: vec3<f32>,
    // rgb8 in the low three bytes.
    colour: u32,
}

struct Tiles {
    // tile columns, tile rows, the first splat this dispatch handles, how many
    grid: vec4<u32>,
    // The slots of the per-splat buffers (eye splats, pixel boxes), whether
    // the splats that reach the screen are packed into them (1, when the
    // scene has more splats than slots: a frame drawn in parts), the scene's
    // splat count (triangles are ordered after it), unused.
    room: vec4<u32>,
}

// Where things sit in the lists' state (`lists`, written by tiled_scan.wgsl;
// mirrors tile_engine.rs): the entries' room, their total, the overflow
// flag, the longest list, cs_sort's indirect dispatch, and the splats
// packed into the per-splat slots this frame.
const ROOM: u32 = 0u;
const TOTAL: u32 = 1u;
const OVERFLOW: u32 = 2u;
const LONGEST: u32 = 3u;
// x, y, z workgroups of cs_sort: bytes 16..28, an indirect dispatch.
const LONG_DISPATCH: u32 = 4u;
const PACKED: u32 = 7u;

// Where a compute invocation stands in a dispatch of workgroups laid out in
// two dimensions (a dimension holds at most 65535 workgroups): the input of
// the tile pipeline's entry points.
struct Dispatch {
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
}

// The index of this invocation among a dispatch of GROUP-wide workgroups.
fn invocation(dispatch: Dispatch) -> u32 {
    return workgroup_index(dispatch) * GROUP + dispatch.local;
}

// The workgroup's index in the dispatch.
fn workgroup_index(dispatch: Dispatch) -> u32 {
    return dispatch.workgroup.y * dispatch.workgroups.x + dispatch.workgroup.x;
}

// A view depth as a u32 whose unsigned order is the float's order.
fn depth_key(depth: f32) -> u32 {
    let bits = bitcast<u32>(depth);
    return select(bits | 0x80000000u, ~bits, (bits & 0x80000000u) != 0u);
}

fn key_depth(key: u32) -> f32 {
    return bitcast<f32>(select(~key, key & 0x7fffffffu, (key & 0x80000000u) != 0u));
}
