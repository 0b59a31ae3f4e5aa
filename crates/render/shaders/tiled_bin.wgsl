#include "tiled_common.wgsl"

// `tiled`, pass 2, per splat: writes one entry (sort key, splat) into each
// tile its disc meets, at the tile's offset (the prefix sum of pass 1's
// counts, tiled_scan.wgsl) plus the entries it has so far. Pass 1 counted every
// tile of the disc's pixel box; here a disc whose box spans several tiles
// of more than 2x2 tiles is tested against each of them (`disc_meets_tile`),
// so a list holds the discs a ray through its tile can hit and not the
// corners of their boxes.
// The count of entries kept per tile follows the offsets (`offsets[tiles +
// 1 + t]`, zeroed by the scan); the passes after this one read a list's
// length from it. Every disc a tile needs has its slot when the entries fit
// their buffer; when they do not, the scan left every list empty, nothing
// is written, and the frame is drawn again with room for them all, so none
// is ever dropped from a frame that is kept. Mesh triangles (items from
// tiles.grid.z on) keep their box.

@group(1) @binding(0) var<uniform> tiles: Tiles;
@group(1) @binding(1) var<storage, read> rects: array<vec4<u32>>;
// Per tile its first entry (tiles + 1 words, the last the total), then per
// tile the entries kept, counted here.
@group(1) @binding(2) var<storage, read_write> offsets: array<atomic<u32>>;
@group(1) @binding(3) var<storage, read_write> entries: array<vec2<u32>>;
@group(1) @binding(4) var<storage, read> eye: array<EyeSplat>;
// The lists' state (tiled_common.wgsl): how many splats were packed into
// the slots this frame, when they were (the slots past them hold old boxes).
@group(1) @binding(5) var<storage, read> lists: array<u32>;

// Whether a ray through tile `tile` (the pixel square from tile * TILE, a
// half pixel beyond every pixel centre it holds) may hit the disc with
// eye-space centre `centre`, unit footprint plane `plane` and squared
// radius `r2`. The rays through the tile's four corners meet the disc's
// plane at a convex quadrilateral that holds every hit point of the tile's
// rays on that plane; the disc meets it when its centre lies inside or an
// edge passes within the radius. A corner ray that misses the plane
// (parallel, or meeting it behind the eye) keeps the tile, as does an edge
// within 1.001 times the squared radius: the test may keep a tile no ray
// of which hits the disc, never drop one that has a hit.
fn disc_meets_tile(centre: vec3<f32>, plane: vec3<f32>, r2: f32, tile: vec2<u32>) -> bool {
    let low = vec2<f32>(tile * TILE);
    let high = low + vec2<f32>(f32(TILE));
    let reach = dot(plane, centre);
    // Written out corner by corner: a local array indexed in a loop was
    // kept in memory by lavapipe, and cost more than the lists it shortened.
    let a = corner_offset(low, centre, plane, reach);
    let b = corner_offset(vec2<f32>(high.x, low.y), centre, plane, reach);
    let c = corner_offset(high, centre, plane, reach);
    let d = corner_offset(vec2<f32>(low.x, high.y), centre, plane, reach);
    if a.w == 0.0 || b.w == 0.0 || c.w == 0.0 || d.w == 0.0 {
        return true;
    }
    let sides = vec4<f32>(
        edge_side(a.xyz, b.xyz, plane),
        edge_side(b.xyz, c.xyz, plane),
        edge_side(c.xyz, d.xyz, plane),
        edge_side(d.xyz, a.xyz, plane),
    );
    if all(sides >= vec4<f32>(0.0)) || all(sides <= vec4<f32>(0.0)) {
        return true;
    }
    let nearest = min(
        min(edge_distance2(a.xyz, b.xyz), edge_distance2(b.xyz, c.xyz)),
        min(edge_distance2(c.xyz, d.xyz), edge_distance2(d.xyz, a.xyz)),
    );
    return nearest <= r2 * 1.001;
}

// Where the ray through `pixel` meets the plane (unit normal `plane`,
// `reach` = plane · centre), relative to `centre`; w = 0 when it does not
// meet it in front of the eye (of the eye's plane, in orthographic).
fn corner_offset(pixel: vec2<f32>, centre: vec3<f32>, plane: vec3<f32>, reach: f32) -> vec4<f32> {
    let ray = pixel_ray(pixel);
    let origin = pixel_origin(pixel);
    let denom = dot(plane, ray);
    let t = (reach - dot(plane, origin)) / denom;
    let meets = abs(denom) >= 1e-12 && t > 0.0 && t < 3.0e38;
    return select(vec4<f32>(0.0), vec4<f32>(origin + ray * t - centre, 1.0), meets);
}

// Which side of the edge from `a` to `b` the centre (the origin) lies on, about `plane`.
fn edge_side(a: vec3<f32>, b: vec3<f32>, plane: vec3<f32>) -> f32 {
    return dot(cross(a, b - a), plane);
}

// The squared distance from the centre (the origin) to the segment from `a` to `b`.
fn edge_distance2(a: vec3<f32>, b: vec3<f32>) -> f32 {
    let edge = b - a;
    let along = clamp(-dot(a, edge) / max(dot(edge, edge), 1e-30), 0.0, 1.0);
    let closest = a + edge * along;
    return dot(closest, closest);
}

@compute @workgroup_size(256)
fn cs_bin(dispatch: Dispatch) {
    let i = invocation(dispatch);
    if i >= tiles.grid.w { return; }
    if tiles.room.y != 0u && i < tiles.grid.z && i >= lists[PACKED] { return; }
    let rect = rects[i];
    let first_pixel = vec2<u32>(rect.x & 0xffffu, rect.y & 0xffffu);
    let last_pixel = vec2<u32>(rect.x >> 16u, rect.y >> 16u);
    if first_pixel.x > last_pixel.x {
        return;
    }
    let t0 = first_pixel / TILE;
    let t1 = last_pixel / TILE;
    // A disc meets every tile of a box of up to 2x2 tiles but in rare
    // cases, so only larger boxes are tested (the test cost more than it
    // saved on the bundled lion when every box of two tiles was tested);
    // triangles keep their box.
    let box_tiles = (t1.x - t0.x + 1u) * (t1.y - t0.y + 1u);
    let test = i < tiles.grid.z && box_tiles > 4u;
    var centre = vec3<f32>(0.0);
    var plane = vec3<f32>(0.0, 0.0, 1.0);
    var r2 = 0.0;
    if test {
        let s = eye[i];
        centre = s.centre;
        plane = s.plane;
        r2 = 1.0 / s.inv_r2;
    }
    let count = tiles.grid.x * tiles.grid.y;
    for (var ty = t0.y; ty <= t1.y; ty++) {
        for (var tx = t0.x; tx <= t1.x; tx++) {
            if test && !disc_meets_tile(centre, plane, r2, vec2<u32>(tx, ty)) {
                continue;
            }
            let tile = ty * tiles.grid.x + tx;
            let slot = atomicLoad(&offsets[tile]) + atomicAdd(&offsets[count + 1u + tile], 1u);
            if slot < atomicLoad(&offsets[tile + 1u]) {
                entries[slot] = vec2<u32>(rect.z, i);
            }
        }
    }
}
