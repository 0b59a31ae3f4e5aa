#include "tiled_count.wgsl"
#include "footprint.wgsl"
#ifdef LIGHTS
#include "lights.wgsl"
#endif

// `tiled`, pass 1, per splat: into eye space (culled as the reference culls:
// back faces when asked, discs wholly outside the near and far planes), the
// footprint plane with bounded foreshortening, and the tiles its disc may
// cover: the exact eye-space box of the disc (c ± r·sqrt(1 - n_i²) per axis)
// projected at its 8 corners, or the whole screen when the box reaches the
// near plane (crates/core/src/reference/tiles.rs bins the same box). Each
// covered tile's count goes up by one; the scan turns the counts into
// offsets (tiled_scan.wgsl) before pass 2 writes the entries. The sort key
// is the smallest view depth on the disc, -(c.z + half.z): no ray meets the
// disc nearer than it, which the per-pixel pass relies on.
//
// A splat's eye record and pixel box go to its own slot when the scene has
// a slot for every splat. When it has more splats than slots (a frame whose
// per-splat buffers would pass one storage binding or the memory given to
// the frame, drawn in parts of the screen), the splats whose box reaches
// this part are packed into the slots in arrival order (`lists[PACKED]`
// counts them, past the slots too), and the box keeps the splat's place in
// the scene, which the sort orders equal keys by, so a packed frame sorts as
// a whole one does. More splats than slots overflow (tiled_scan.wgsl).

@group(1) @binding(0) var<uniform> tiles: Tiles;
// The scene's splat instances (36 bytes each, see gpu_data.rs), read as words.
@group(1) @binding(1) var<storage, read> splats: array<f32>;
@group(1) @binding(2) var<storage, read_write> eye: array<EyeSplat>;
// Bindings 3 and 4: the splats' pixel boxes and the tiles' counts (tiled_count.wgsl).
// A bit per slot of the scene, set where the slot holds a splat drawn: a
// node pool keeps the records of nodes no longer drawn (node_pool.rs).
@group(1) @binding(5) var<storage, read> live: array<u32>;
// The lists' state (tiled_common.wgsl): PACKED counts the packed splats.
@group(1) @binding(6) var<storage, read_write> lists: array<atomic<u32>>;
#ifdef LIGHTS
// Per splat of the chunk: its shadow coefficients, lights 0-3 and 4-7 as unorm8.
@group(1) @binding(7) var<storage, read> splat_lights: array<u32>;
#endif

@compute @workgroup_size(256)
fn cs_project(dispatch: Dispatch) {
    let at = invocation(dispatch);
    if at >= tiles.grid.w { return; }
    let i = tiles.grid.z + at;
    let b = at * 9u;
    let position = vec3<f32>(splats[b], splats[b + 1u], splats[b + 2u]);
    let signed_radius = splats[b + 3u];
    let normal_in = vec3<f32>(splats[b + 4u], splats[b + 5u], splats[b + 6u]);
    let centre = (frame.view * vec4<f32>(position, 1.0)).xyz;
    let normal_eye = (frame.view * vec4<f32>(normal_in, 0.0)).xyz;
    let normal_length = length(normal_eye);
    let normal = select(vec3<f32>(0.0, 0.0, 1.0), normal_eye / normal_length, normal_length > 1e-20);
    let depth = -centre.z;
    let radius = drawn_radius(signed_radius, depth);
    let sight = towards(centre);
    let distance = length(sight);
    let plane = footprint_normal(normal, select(vec3<f32>(0.0), sight / distance, distance > 0.0), frame.splat.z);
    var colour = bitcast<u32>(splats[b + 7u]);
#ifdef LIGHTS
    // Scene lights: the splat is lit once, here, and the raster blends the lit colour.
    let albedo = unpack4x8unorm(colour).rgb;
    let shadow_a = unpack4x8unorm(splat_lights[2u * at]);
    let shadow_b = unpack4x8unorm(splat_lights[2u * at + 1u]);
    colour = pack4x8unorm(vec4<f32>(light_splat(albedo, normal, centre, shadow_a, shadow_b), 1.0));
#endif
    // Back faces of one-sided splats (a two-sided one has a negative radius).
    let culled = frame.splat.w > 0.5 && signed_radius > 0.0 && dot(normal, sight) > 0.0;
    // A node pool's vacant and resident slots are not live (node_pool.rs).
    let live_slot = ((live[i >> 5u] >> (i & 31u)) & 1u) == 1u;
    let usable = depth - radius < frame.depth.y && depth + radius > frame.depth.x && radius > 0.0 && live_slot;
    let packing = tiles.room.y != 0u;
    var rect = NO_TILES;
    if !culled && usable {
        let half = sqrt(max(vec3<f32>(1.0) - plane * plane, vec3<f32>(0.0))) * radius;
        let lo = centre - half;
        let hi = centre + half;
        var low = vec2<f32>(0.0);
        var high = frame.viewport.xy;
        if hi.z < -frame.depth.x {
            low = vec2<f32>(3.4e38);
            high = vec2<f32>(-3.4e38);
            for (var corner = 0u; corner < 8u; corner++) {
                let p = select(lo, hi, vec3<bool>((corner & 1u) != 0u, (corner & 2u) != 0u, (corner & 4u) != 0u));
                let box = pixel_box_of(p, low, high);
                low = box[0];
                high = box[1];
            }
        }
        rect = screen_rect(low, high, depth_key(-hi.z), i);
    }
    if covers_nothing(rect) {
        if !packing {
            rects[i] = NO_TILES;
        }
        return;
    }
    var slot = i;
    if packing {
        slot = atomicAdd(&lists[PACKED], 1u);
        if slot >= tiles.room.x {
            return;
        }
    }
    eye[slot] = EyeSplat(
        centre,
        1.0 / max(radius * radius, 1e-30),
        plane,
        clamp(splats[b + 8u], 0.0, 1.0),
        normal,
        colour,
    );
    rects[slot] = rect;
    count_tiles(rect);
}
