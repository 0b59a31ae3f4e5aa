#include "tiled_common.wgsl"
#include "shading.wgsl"

// `tiled`, pass 4, one workgroup per tile and one invocation per pixel: the
// exact reference (crates/core/src/reference/raster.rs) on the GPU. Each
// invocation walks its tile's list on its own, with no barrier: staging the
// list in workgroup memory behind barriers measured slower on lavapipe,
// whose barriers spill every invocation's state.
//
// The tile's entries arrive sorted by the nearest depth on each disc (pass
// 3). Each pixel casts its ray on every disc in that order (Eq. 3 weight,
// Eq. 4 depth). A hit waits in a small sorted window until the next disc's
// key is beyond it: no later disc can be hit nearer than its key, so hits
// leave the window in exact depth order. Hits are ordered by (depth, entry),
// so equal depths have one order too.
//
// Should more than WINDOW hits wait at once with none yet ready, the pixel
// starts again a layer at a time (`exact_pass`): the next hit in order
// (found by reading the list up to a key beyond the nearest hit found) opens
// or joins a layer, then one read of the list adds every hit within the
// open layer's reach to it and finds the next hit beyond. Such pixels cost
// a read of the list per layer, and stay exact; `stats` counts them.
//
// Ordered hits are grouped into ε-layers as the reference groups them: a
// layer is the hits of one facing within ε of its first hit (facing is not
// split in an opaque scene), so at most two layers are open at once, one
// per facing; a hit beyond a layer's reach closes it, older layers first.
// A closed layer is normalised (Eq. 1: weighted colour, normal, opacity),
// shaded facing the viewer and composited front to back; the pixel stops
// at an opaque layer or when less than 1/1024 of the light gets through
// (EVERY_LAYER, for tests only, composites every layer instead).
// There is no cap on the number of layers. With an environment map
// (ENVIRONMENT) the pixel also keeps its nearest transparent layer and what
// lies behind it, counting layers to the end when the multi-layer effects
// need the exact count; tiled_present.wgsl looks the map up.

@group(1) @binding(0) var<uniform> tiles: Tiles;
@group(1) @binding(1) var<storage, read> offsets: array<u32>;
@group(1) @binding(2) var<storage, read> entries: array<vec2<u32>>;
@group(1) @binding(3) var<storage, read> eye: array<EyeSplat>;
// Per splat: the pixels its disc may cover (x0 | x1 << 16, y0 | y1 << 16, key).
@group(1) @binding(6) var<storage, read> rects: array<vec4<u32>>;
// rgb composited over the background, layers met
@group(1) @binding(4) var colour_out: texture_storage_2d<rgba32float, write>;
// [0]: pixels whose window overflowed, finished a layer at a time (see
// above); [1]: the entries the tiles' lists kept, over every tile.
@group(1) @binding(5) var<storage, read_write> stats: array<atomic<u32>>;
#ifdef ENVIRONMENT
// The nearest transparent layer: shaded colour and opacity; unit normal (zero: none) and layers behind;
// the layers behind composited and their transmittance (-1 when an opaque layer ends the ray).
@group(1) @binding(7) var glass_front_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(8) var glass_normal_out: texture_storage_2d<rgba32float, write>;
@group(1) @binding(9) var glass_behind_out: texture_storage_2d<rgba32float, write>;
#endif
#ifdef TRIANGLES
// The frame's mesh triangles (tiled_triangles.wgsl): items from tiles.grid.z
// on are triangles, the (item - grid.z)-th drawn one.
#ifdef ENVIRONMENT
@group(1) @binding(10) var<storage, read> triangle_vertices: array<f32>;
@group(1) @binding(11) var<storage, read> drawn_triangles: array<u32>;
#else
@group(1) @binding(7) var<storage, read> triangle_vertices: array<f32>;
@group(1) @binding(8) var<storage, read> drawn_triangles: array<u32>;
#endif
#endif

const WINDOW: u32 = 8u;
// Below this transmittance the layers behind cannot change an 8-bit colour.
const LAST_LIGHT: f32 = 0.0009765625;


struct Layer {
    front: f32,
    facing: bool,
    w: f32,
    colour: vec3<f32>,
    normal: vec3<f32>,
    alpha: f32,
}

// The pixel's state. Every array is indexed by constants only (its loops
// unroll), so the shader compiler keeps it in registers: a window indexed by
// a per-pixel count was twice as slow on lavapipe.
var<private> ray: vec3<f32>;
// Where the ray starts: the eye, or the pixel's place on its plane (orthographic).
var<private> ray_origin: vec3<f32>;
// Unit, from the surface to the eye: what layers are shaded facing.
var<private> to_eye: vec3<f32>;
var<private> split_facing: bool;
// Hits waiting, nearest first; empty slots hold NO_HIT.
var<private> window_depth: array<f32, WINDOW>;
var<private> window_weight: array<f32, WINDOW>;
// The tile-list entry of each hit (its item is entries[e].y).
var<private> window_entry: array<u32, WINDOW>;
// The open layers, the older first (at most one per facing).
var<private> older: Layer;
var<private> newer: Layer;
var<private> open_count: u32;
var<private> colour: vec3<f32>;
var<private> through: f32;
var<private> layers: u32;
var<private> done: bool;
#ifdef ENVIRONMENT
var<private> glass: bool;
var<private> glass_front: vec4<f32>;
var<private> glass_normal: vec3<f32>;
var<private> glass_behind: vec3<f32>;
var<private> glass_through: f32;
var<private> glass_layers_behind: f32;
var<private> glass_closed: bool;
#endif

const NO_HIT: f32 = 3.4e38;
const NO_ENTRY: u32 = 0xffffffffu;

fn unpack_colour(c: u32) -> vec3<f32> {
    return vec3<f32>(f32(c & 0xffu), f32((c >> 8u) & 0xffu), f32((c >> 16u) & 0xffu)) / 255.0;
}

fn close_layer(layer: Layer) {
    if !(layer.w > 0.0) {
        return;
    }
    layers += 1u;
    let alpha = clamp(layer.alpha / layer.w, 0.0, 1.0);
#ifdef ENVIRONMENT
    if glass && !glass_closed {
        if alpha < 1.0 {
            glass_layers_behind += 1.0;
        } else {
            glass_closed = true;
        }
    }
#endif
    if through <= 1e-6 {
        return; // only counted
    }
    let normal_length = length(layer.normal);
    let normal = select(to_eye, layer.normal / normal_length, normal_length > 1e-20);
    let albedo = layer.colour / layer.w;
#ifdef LIT
    let shaded = shade(albedo, normal, to_eye);
#else
    let shaded = clamp(albedo, vec3<f32>(0.0), vec3<f32>(1.0));
#endif
#ifdef ENVIRONMENT
    if glass {
        glass_behind += glass_through * alpha * shaded;
        glass_through *= 1.0 - alpha;
    } else if layers == 1u && alpha < 1.0 {
        glass = true;
        glass_front = vec4<f32>(shaded, alpha);
        glass_normal = select(normal, -normal, dot(normal, to_eye) < 0.0);
        glass_behind = vec3<f32>(0.0);
        glass_through = 1.0;
        glass_layers_behind = 0.0;
        glass_closed = false;
    }
#endif
    colour += through * alpha * shaded;
    through *= 1.0 - alpha;
    if through <= 0.0 {
#ifdef ENVIRONMENT
        if glass {
            glass_closed = true;
        }
#endif
#ifndef EVERY_LAYER
        done = true;
#endif
        return;
    }
    var counting = false;
#ifdef ENVIRONMENT
    // The multi-layer effects need every layer behind the glass counted.
    counting = glass && frame.environment.z > 0.5;
#endif
#ifndef EVERY_LAYER
    if through < LAST_LIGHT && !counting {
        done = true;
    }
#endif
}

// Closes the oldest open layer.
fn close_oldest() {
    let oldest = older;
    older = newer;
    open_count -= 1u;
    close_layer(oldest);
}

// What a hit adds to its layer, and the normal that says which way it faces.
struct Surface {
    colour: vec3<f32>,
    normal: vec3<f32>,
    opacity: f32,
    facing: vec3<f32>,
}

fn add_to(layer: ptr<private, Layer>, weight: f32, s: Surface) {
    (*layer).w += weight;
    (*layer).colour += s.colour * weight;
    (*layer).normal += s.normal * weight;
    (*layer).alpha += s.opacity * weight;
}

#ifdef TRIANGLES
struct TriangleHit {
    // View depth (the ray's parameter) and barycentric weights of corners 1
    // and 2; depth 0 when the ray misses.
    depth: f32,
    uv: vec2<f32>,
}

fn triangle_corner(triangle: u32, corner: u32, word: u32) -> vec3<f32> {
    let b = (3u * triangle + corner) * 12u + word;
    return vec3<f32>(triangle_vertices[b], triangle_vertices[b + 1u], triangle_vertices[b + 2u]);
}

fn triangle_eye(triangle: u32, corner: u32) -> vec3<f32> {
    return (frame.view * vec4<f32>(triangle_corner(triangle, corner, 0u), 1.0)).xyz;
}

// Möller & Trumbore, as crates/core/src/reference/triangles.rs intersects.
fn intersect_triangle(triangle: u32) -> TriangleHit {
    let a = triangle_eye(triangle, 0u);
    let e1 = triangle_eye(triangle, 1u) - a;
    let e2 = triangle_eye(triangle, 2u) - a;
    let p = cross(ray, e2);
    let det = dot(e1, p);
    var miss = TriangleHit(0.0, vec2<f32>(0.0));
    if abs(det) < 1e-20 {
        return miss;
    }
    let inv = 1.0 / det;
    let s = ray_origin - a;
    let u = dot(s, p) * inv;
    let q = cross(s, e1);
    let v = dot(ray, q) * inv;
    let depth = dot(e2, q) * inv;
    if u < 0.0 || u > 1.0 || v < 0.0 || u + v > 1.0 || !(depth > frame.depth.x && depth < frame.depth.y) {
        return miss;
    }
    return TriangleHit(depth, vec2<f32>(u, v));
}

// The interpolated colour, normal and opacity where the ray meets `triangle`.
fn triangle_surface(triangle: u32) -> Surface {
    let hit = intersect_triangle(triangle);
    let w = vec3<f32>(1.0 - hit.uv.x - hit.uv.y, hit.uv.x, hit.uv.y);
    var colour = vec3<f32>(0.0);
    var normal = vec3<f32>(0.0);
    var opacity = 0.0;
    for (var k = 0u; k < 3u; k++) {
        let b = (3u * triangle + k) * 12u;
        colour += unpack4x8unorm(bitcast<u32>(triangle_vertices[b + 7u])).rgb * w[k];
        normal += triangle_corner(triangle, k, 4u) * w[k];
        opacity += triangle_vertices[b + 8u] * w[k];
    }
    let eye_normal = (frame.view * vec4<f32>(normal, 0.0)).xyz;
    let face = (frame.view * vec4<f32>(triangle_corner(triangle, 0u, 9u), 0.0)).xyz;
    let unit = select(face, normalize(eye_normal), length(eye_normal) > 1e-20);
    return Surface(colour, unit, clamp(opacity, 0.0, 1.0), face);
}

#endif

// The surface of item `item` (a splat, or with TRIANGLES a triangle) where the ray met it.
fn surface_of(item: u32) -> Surface {
#ifdef TRIANGLES
    if item >= tiles.grid.z {
        return triangle_surface(drawn_triangles[item - tiles.grid.z]);
    }
#endif
    let s = eye[item];
    return Surface(unpack_colour(s.colour), s.normal, s.opacity, s.normal);
}

// Which way a hit faces: towards the viewer (true) or away, what splits
// the ε-layers of a transparent scene.
fn faces_viewer(s: Surface) -> bool {
    return dot(s.facing, ray) < 0.0;
}

// Adds a hit to the open layer of its facing; false when none is open.
fn join_open(weight: f32, s: Surface) -> bool {
    let facing = faces_viewer(s);
    if open_count > 0u && (!split_facing || older.facing == facing) {
        add_to(&older, weight, s);
        return true;
    }
    if open_count > 1u && newer.facing == facing {
        add_to(&newer, weight, s);
        return true;
    }
    return false;
}

// One hit, in depth order, into its ε-layer.
fn add_hit(depth: f32, weight: f32, splat: u32) {
    let epsilon = this_pass.depth.x;
    while open_count > 0u && depth > older.front + epsilon && !done {
        close_oldest();
    }
    if done {
        return;
    }
    let s = surface_of(splat);
    if join_open(weight, s) {
        return;
    }
    let facing = faces_viewer(s);
    if open_count == 0u {
        older = Layer(depth, facing, 0.0, vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
        add_to(&older, weight, s);
        open_count = 1u;
    } else {
        newer = Layer(depth, facing, 0.0, vec3<f32>(0.0), vec3<f32>(0.0), 0.0);
        add_to(&newer, weight, s);
        open_count = 2u;
    }
}

// The nearest waiting hit leaves the window.
fn release() {
    let depth = window_depth[0];
    let weight = window_weight[0];
    let entry = window_entry[0];
    for (var i = 0u; i < WINDOW - 1u; i++) {
        window_depth[i] = window_depth[i + 1u];
        window_weight[i] = window_weight[i + 1u];
        window_entry[i] = window_entry[i + 1u];
    }
    window_depth[WINDOW - 1u] = NO_HIT;
    add_hit(depth, weight, entries[entry].y);
}

// A hit waits for its turn, in order of depth (the window has room). Hits
// arrive in the order of their entries, so equal depths keep that order:
// the window is ordered by (depth, entry).
fn wait(depth: f32, weight: f32, entry: u32) {
    var d = depth;
    var w = weight;
    var e = entry;
    for (var i = 0u; i < WINDOW; i++) {
        let here = window_depth[i];
        let ahead = d < here;
        let kept_w = window_weight[i];
        let kept_e = window_entry[i];
        window_depth[i] = select(here, d, ahead);
        window_weight[i] = select(kept_w, w, ahead);
        window_entry[i] = select(kept_e, e, ahead);
        d = select(d, here, ahead);
        w = select(w, kept_w, ahead);
        e = select(e, kept_e, ahead);
    }
}

// Where the pixel's ray meets item `item` (a disc, or with TRIANGLES a
// triangle): (depth, weight), the depth NO_HIT on a miss.
fn hit_on(item: u32) -> vec2<f32> {
    let miss = vec2<f32>(NO_HIT, 0.0);
#ifdef TRIANGLES
    if item >= tiles.grid.z {
        let hit = intersect_triangle(drawn_triangles[item - tiles.grid.z]);
#ifdef CLIP
        if !clip_keeps(ray_origin, ray, hit.depth) {
            return miss;
        }
#endif
        return select(miss, vec2<f32>(hit.depth, 1.0), hit.depth > 0.0);
    }
#endif
    let s = eye[item];
    return disc_hit(vec4<f32>(s.centre, s.inv_r2), s.plane);
}

// Where the pixel's ray meets a disc (centre and 1/r², footprint plane):
// (depth, Eq. 3 weight), the depth NO_HIT on a miss.
fn disc_hit(disc: vec4<f32>, plane: vec3<f32>) -> vec2<f32> {
    let miss = vec2<f32>(NO_HIT, 0.0);
    let denom = dot(plane, ray);
    if abs(denom) < 1e-12 {
        return miss;
    }
    // The centre seen from the ray's origin (the centre itself in perspective).
    let centre = disc.xyz - ray_origin;
    let t = dot(plane, centre) / denom;
    if !(t > frame.depth.x && t < frame.depth.y) {
        return miss;
    }
    let offset = ray * t - centre;
    let rho2 = dot(offset, offset) * disc.w;
#ifdef CLIP
    if !clip_keeps(ray_origin, ray, t) {
        return miss;
    }
#endif
    return select(miss, vec2<f32>(t, exp(-rho2 * frame.splat.y)), rho2 < 1.0);
}

// Whether `pixel` lies in pixel bounds (x0 | x1 << 16, y0 | y1 << 16).
fn within(pixel: vec2<u32>, bounds: vec2<u32>) -> bool {
    let inside_x = pixel.x >= (bounds.x & 0xffffu) && pixel.x <= (bounds.x >> 16u);
    let inside_y = pixel.y >= (bounds.y & 0xffffu) && pixel.y <= (bounds.y >> 16u);
    return inside_x && inside_y;
}

// Whether item `item`'s pixel bounds may cover this pixel.
fn covers(pixel: vec2<u32>, item: u32) -> bool {
    return within(pixel, rects[item].xy);
}

fn finish() {
    while open_count > 0u && !done {
        close_oldest();
    }
}

// The pixel's state before its first hit.
fn start_pixel(inside: bool) {
    for (var i = 0u; i < WINDOW; i++) {
        window_depth[i] = NO_HIT;
        window_entry[i] = NO_ENTRY;
    }
    open_count = 0u;
    colour = vec3<f32>(0.0);
    through = 1.0;
    layers = 0u;
    done = !inside;
#ifdef ENVIRONMENT
    glass = false;
    glass_front = vec4<f32>(0.0);
    glass_normal = vec3<f32>(0.0);
    glass_behind = vec3<f32>(0.0);
    glass_through = 1.0;
    glass_layers_behind = 0.0;
    glass_closed = false;
#endif
}

// A hit of the exact pass: depth, weight and tile-list entry (NO_ENTRY: none).
struct Hit {
    depth: f32,
    weight: f32,
    entry: u32,
}

// Whether (depth, entry) comes after `h` in the order hits are released.
fn after(depth: f32, entry: u32, h: Hit) -> bool {
    return depth > h.depth || (depth == h.depth && entry > h.entry);
}

// The pixel's first hit: the nearest, then by entry.
fn first_hit(pixel: vec2<u32>, start: u32, end: u32) -> Hit {
    var best = Hit(NO_HIT, 0.0, NO_ENTRY);
    for (var at = start; at < end; at++) {
        let entry = entries[at];
        if key_depth(entry.x) > best.depth {
            break; // no later disc is hit nearer than its key
        }
        if covers(pixel, entry.y) {
            let h = hit_on(entry.y);
            if h.x < NO_HIT && !after(h.x, at, best) {
                best = Hit(h.x, h.y, at);
            }
        }
    }
    return best;
}

// The whole pixel again, a layer at a time (see the top): for a pixel whose
// window overflowed. The next hit in order opens or joins a layer as in
// `add_hit`; then one read of the list adds every later hit within the
// oldest open layer's reach (older.front + ε) to the open layer of its
// facing (no layer closes inside the reach, and a layer's sums do not
// depend on their order), and finds the first hit beyond it, the next in
// order. A hit in the reach whose facing has no open layer opens one: the
// nearest such, then the hits of its facing after it, in a second read.
fn exact_pass(pixel: vec2<u32>, start: u32, end: u32) {
    start_pixel(true);
    let epsilon = this_pass.depth.x;
    var next = first_hit(pixel, start, end);
    loop {
        if next.entry == NO_ENTRY || done {
            break;
        }
        add_hit(next.depth, next.weight, entries[next.entry].y);
        if done || open_count == 0u {
            break;
        }
        let reach = older.front + epsilon;
        var beyond = Hit(NO_HIT, 0.0, NO_ENTRY);
        var opener = Hit(NO_HIT, 0.0, NO_ENTRY);
        for (var at = start; at < end; at++) {
            let entry = entries[at];
            let key = key_depth(entry.x);
            if key > reach && key > beyond.depth {
                break;
            }
            if !covers(pixel, entry.y) {
                continue;
            }
            let h = hit_on(entry.y);
            if !(h.x < NO_HIT) || !after(h.x, at, next) {
                continue;
            }
            if h.x <= reach {
                if !join_open(h.y, surface_of(entry.y)) && !after(h.x, at, opener) {
                    opener = Hit(h.x, h.y, at);
                }
            } else if !after(h.x, at, beyond) {
                beyond = Hit(h.x, h.y, at);
            }
        }
        if opener.entry != NO_ENTRY {
            // Within the reach, so it closes nothing: it opens the newer layer.
            add_hit(opener.depth, opener.weight, entries[opener.entry].y);
            for (var at = start; at < end; at++) {
                let entry = entries[at];
                if key_depth(entry.x) > reach {
                    break;
                }
                if !covers(pixel, entry.y) {
                    continue;
                }
                let h = hit_on(entry.y);
                if h.x < NO_HIT && h.x <= reach && after(h.x, at, opener) {
                    let s = surface_of(entry.y);
                    let facing = faces_viewer(s);
                    if open_count > 1u && facing == newer.facing && facing != older.facing {
                        add_to(&newer, h.y, s);
                    }
                }
            }
        }
        next = beyond;
    }
}

#ifndef SUBGROUPS
// Reads the tile's list once, releasing hits in exact order; returns
// whether the window overflowed (the pixel is then finished a layer at a time).
// Hits are released lazily: a pixel reads its list until its window is
// full (or the list ends), then releases every hit no later disc can
// precede. The pixel's heavy work (layers, shading) then runs once per
// burst of hits rather than once per disc: on a SIMD device that runs
// both sides of a branch (lavapipe), code in the per-disc loop costs
// every lane every disc.
fn stream(pixel: vec2<u32>, start: u32, end: u32) -> bool {
    var at = start;
    var overflowed = false;
    loop {
        loop {
            if at >= end || done || window_depth[WINDOW - 1u] < NO_HIT {
                break;
            }
            let entry = entries[at];
            // A disc whose pixel bounds miss this pixel gives no hit.
            if covers(pixel, entry.y) {
                let hit = hit_on(entry.y);
                if hit.x < NO_HIT {
                    wait(hit.x, hit.y, at);
                }
            }
            at += 1u;
        }
        var key = NO_HIT;
        if at < end {
            key = key_depth(entries[at].x);
        }
        // A full window with nothing ready: a later disc may still be hit
        // nearer than every waiting hit.
        if window_depth[WINDOW - 1u] < NO_HIT && window_depth[0] > key && !done {
            overflowed = true;
            break;
        }
        loop {
            if done || !(window_depth[0] < NO_HIT && window_depth[0] <= key) {
                break;
            }
            release();
        }
        if done || (at >= end && window_depth[0] == NO_HIT) {
            break;
        }
    }
    return overflowed;
}
#else
// This invocation's lane in its subgroup, and the entries a subgroup reads
// at once (at most 32: one bit each in a mask).
var<private> lane: u32;
var<private> lanes: u32;
// The rectangle of the subgroup's pixels inside the image.
var<private> group_low: vec2<u32>;
var<private> group_high: vec2<u32>;

// `stream` with the subgroup reading the list together: each lane loads one
// entry (its pixel bounds, disc centre, 1/r² and plane) and tests its bounds
// against the rectangle of the subgroup's pixels, one ballot marks the
// entries that meet it, and only those are shuffled to every lane and
// tested against each lane's pixel (one ballot instead of a shuffle and a
// vote per entry: 3.5-4.5 % of the lion's frame at 512²). On lavapipe, which runs a branch for every lane
// whether taken or not, a loop over the marked entries is what skips the
// others: the tile's lists are read once per subgroup instead of once per
// pixel, and the hit test runs for a fraction of the entries (a frame of
// the lion at 256²: 150 ms of raster without subgroups, 75 ms with). A
// hardware GPU, whose caches serve a tile's pixels one load and whose
// branches skip idle lanes, reads by pixel: 5-10 % faster on an H200.
fn stream(pixel: vec2<u32>, start: u32, end: u32) -> bool {
    var overflowed = false;
    var base = start;
    loop {
        if base >= end || subgroupAll(done) {
            break;
        }
        var my_entry = vec2<u32>(0u, 0u);
        var my_bounds = vec2<u32>(0xffffu, 0u); // an empty rectangle
        var my_disc = vec4<f32>(0.0);
        var my_plane = vec3<f32>(0.0);
        if base + lane < end && lane < lanes {
            my_entry = entries[base + lane];
            my_bounds = rects[my_entry.y].xy;
#ifdef TRIANGLES
            if my_entry.y < tiles.grid.z {
#endif
            let s = eye[my_entry.y];
            my_disc = vec4<f32>(s.centre, s.inv_r2);
            my_plane = s.plane;
#ifdef TRIANGLES
            }
#endif
        }
        let count = min(lanes, end - base);
        // The entries whose pixel bounds meet the subgroup's pixels: each
        // lane tests its own entry against the subgroup's rectangle, and one
        // ballot gathers the votes.
        let meets = (my_bounds.x & 0xffffu) <= group_high.x && (my_bounds.x >> 16u) >= group_low.x
            && (my_bounds.y & 0xffffu) <= group_high.y && (my_bounds.y >> 16u) >= group_low.y;
        var marked = subgroupBallot(meets && lane < count).x;
        loop {
            if marked == 0u {
                break;
            }
            let k = firstTrailingBit(marked);
            marked &= marked - 1u;
            let inside = within(pixel, subgroupShuffle(my_bounds, k));
            let entry = subgroupShuffle(my_entry, k);
            let disc = subgroupShuffle(my_disc, k);
            let plane = subgroupShuffle(my_plane, k);
            if inside && !done {
                if window_depth[WINDOW - 1u] < NO_HIT {
                    // Full: every hit up to this entry's key is ready.
                    let key = key_depth(entry.x);
                    loop {
                        if done || !(window_depth[0] <= key) {
                            break;
                        }
                        release();
                    }
                    // Still full: a later disc may be hit nearer than every waiting hit.
                    if window_depth[WINDOW - 1u] < NO_HIT && !done {
                        overflowed = true;
                        done = true;
                    }
                }
                if !done {
#ifdef TRIANGLES
                    var hit = vec2<f32>(NO_HIT, 0.0);
                    if entry.y >= tiles.grid.z {
                        hit = hit_on(entry.y);
                    } else {
                        hit = disc_hit(disc, plane);
                    }
#else
                    let hit = disc_hit(disc, plane);
#endif
                    if hit.x < NO_HIT {
                        wait(hit.x, hit.y, base + k);
                    }
                }
            }
        }
        base += count;
    }
    // The list has ended: every waiting hit is ready.
    loop {
        if done || window_depth[0] == NO_HIT {
            break;
        }
        release();
    }
    return overflowed;
}
#endif

@compute @workgroup_size(TILE * TILE)
fn cs_raster(
#ifdef SUBGROUPS
    @builtin(subgroup_invocation_id) subgroup_lane: u32,
    @builtin(subgroup_size) subgroup_lanes: u32,
#endif
    dispatch: Dispatch,
) {
    let tile = workgroup_index(dispatch);
    let local = dispatch.local;
    let columns = tiles.grid.x;
    let inside_grid = tile < columns * tiles.grid.y;
    let pixel = vec2<u32>(tile % columns, tile / columns) * TILE + vec2<u32>(local % TILE, local / TILE);
    let size = vec2<u32>(frame.viewport.xy);
    let inside = inside_grid && pixel.x < size.x && pixel.y < size.y;
    ray = pixel_ray(vec2<f32>(pixel) + vec2<f32>(0.5));
    ray_origin = pixel_origin(vec2<f32>(pixel) + vec2<f32>(0.5));
    to_eye = -normalize(ray);
    split_facing = this_pass.layers.z != 0u;
    start_pixel(inside);
    // The tile's list (every pixel of a tile reads the same one).
    var start = 0u;
    var end = 0u;
    if inside_grid {
        start = offsets[tile];
        // The entries the binning kept, within the room counted for them.
        end = start + min(offsets[columns * tiles.grid.y + 1u + tile], offsets[tile + 1u] - start);
    }
#ifdef SUBGROUPS
    lane = subgroup_lane;
    lanes = min(subgroup_lanes, 32u);
    group_low = subgroupMin(select(vec2<u32>(0xffffu), pixel, !done));
    group_high = subgroupMax(select(vec2<u32>(0u), pixel, !done));
#endif
    if local == 0u {
        atomicAdd(&stats[1], end - start);
    }
    let overflowed = stream(pixel, start, end);
    if !inside {
        return;
    }
    if overflowed {
        exact_pass(pixel, start, end);
        atomicAdd(&stats[0], 1u);
    }
    finish();
    textureStore(colour_out, pixel, vec4<f32>(colour + through * frame.background.rgb, f32(layers)));
#ifdef ENVIRONMENT
    var behind_through = select(glass_through, -1.0, glass_closed);
    textureStore(glass_front_out, pixel, glass_front);
    textureStore(glass_normal_out, pixel, vec4<f32>(glass_normal, glass_layers_behind));
    textureStore(glass_behind_out, pixel, vec4<f32>(glass_behind, behind_through));
#endif
}
