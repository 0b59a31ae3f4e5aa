#include "tiled_count.wgsl"

// `tiled`, pass 1 for a frame's mesh triangles (crates/core/src/hybrid), per
// drawn triangle, after the splats' projection: culled as the reference
// culls it (one-sided and facing away by its winding; wholly before the
// near or beyond the far plane), the pixel box of its three corners (the
// whole screen when one is behind the near plane) and the tiles it covers,
// counted. Its item is the splat count plus its place among the drawn
// triangles, so one list holds both and pass 3 sorts them together. The
// sort key is its nearest corner's view depth: view depth is linear over
// the triangle, so no ray meets it nearer. The raster intersects it exactly
// (tiled_raster.wgsl, `meet_triangle`).

@group(1) @binding(0) var<uniform> tiles: Tiles;
// The scene's triangle vertices (48 bytes each, TriangleVertex in gpu_data.rs), read as words.
@group(1) @binding(1) var<storage, read> triangle_vertices: array<f32>;
// The triangles drawn this frame, by index.
@group(1) @binding(2) var<storage, read> drawn_triangles: array<u32>;
// Bindings 3 and 4: the items' pixel boxes and the tiles' counts (tiled_count.wgsl).

fn corner_eye(triangle: u32, corner: u32) -> vec3<f32> {
    let b = (3u * triangle + corner) * 12u;
    let p = vec3<f32>(triangle_vertices[b], triangle_vertices[b + 1u], triangle_vertices[b + 2u]);
    return (frame.view * vec4<f32>(p, 1.0)).xyz;
}

@compute @workgroup_size(256)
fn cs_project_triangles(dispatch: Dispatch) {
    let at = invocation(dispatch);
    if at >= tiles.grid.w { return; }
    let i = tiles.grid.z + at;
    let triangle = drawn_triangles[at];
    let a = corner_eye(triangle, 0u);
    let b = corner_eye(triangle, 1u);
    let c = corner_eye(triangle, 2u);
    let face = cross(b - a, c - a);
    let one_sided = triangle_vertices[triangle * 36u + 3u] > 0.0;
    let culled = frame.splat.w > 0.5 && one_sided && dot(face, a) > 0.0;
    let near = min(min(-a.z, -b.z), -c.z);
    let far = max(max(-a.z, -b.z), -c.z);
    if culled || near >= frame.depth.y || far <= frame.depth.x || !(dot(face, face) > 0.0) {
        rects[i] = NO_TILES;
        return;
    }
    var low = vec2<f32>(0.0);
    var high = frame.viewport.xy;
    if near > frame.depth.x {
        low = vec2<f32>(3.4e38);
        high = vec2<f32>(-3.4e38);
        for (var k = 0u; k < 3u; k++) {
            let box = pixel_box_of(select(select(c, b, k == 1u), a, k == 0u), low, high);
            low = box[0];
            high = box[1];
        }
    }
    // Ordered after every splat of the scene among equal keys.
    let rect = screen_rect(low, high, depth_key(near), tiles.room.z + at);
    rects[i] = rect;
    if !covers_nothing(rect) {
        count_tiles(rect);
    }
}
