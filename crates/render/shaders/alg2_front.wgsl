#include "shading.wgsl"
#include "group_images.wgsl"

// Between the two geometry passes of Algorithm-2 (§5.2.2): the nearest
// transparent layer, found once per pixel. Its view depth d = min_k depth_k
// over the groups that drew there in pass 1 (3e38 where none did), and its
// facing: whether the normal of the group image at d points away from the
// viewer. The reference splits ε-layers by facing, so the nearest layer is
// the groups within d + ε that face as it does; a layer of the other facing
// within ε (the far side of a thin shell) is one of the layers behind it.
// Pass 2 (shaders/alg2_other.wgsl) and the composite
// (shaders/alg2_composite.wgsl) read these two values instead of the K
// layers' colour, depth and normal.

@group(1) @binding(0) var nearest_colour: texture_2d_array<f32>;
@group(1) @binding(1) var nearest_depth: texture_2d_array<f32>;
@group(1) @binding(2) var nearest_normal_alpha: texture_2d_array<f32>;

@fragment
fn fs_alg2_front(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let group = nearest_group(nearest_colour, nearest_depth, pixel);
    if group < 0 {
        return vec4<f32>(3.0e38, 0.0, 0.0, 1.0);
    }
    let away = faces_away(textureLoad(nearest_normal_alpha, pixel, group, 0).xyz, f.position.xy);
    return vec4<f32>(textureLoad(nearest_depth, pixel, group, 0).r, select(0.0, 1.0, away), 0.0, 1.0);
}
