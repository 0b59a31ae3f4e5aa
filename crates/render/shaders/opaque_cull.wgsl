// The opaque splats of a transparent scene are drawn apart, in high quality
// (two-pass), before the transparent layers (Zhang & Pajarola Fig. 18/19).
// Their visibility pass left front + ε in `opaque_depth`, which the root
// shader binds (OPAQUE_APART variant): a transparent fragment behind that
// front is hidden by the opaque surface and culled. Same mapping and clamp as
// the visibility pass (shaders/visibility.wgsl), so "behind" means a view
// depth beyond the opaque front, and where nothing opaque was drawn (the far
// plane) nothing is culled.

#ifdef OPAQUE_APART
fn behind_opaque(pixel: vec2<i32>, view_depth: f32) -> bool {
    return min(depth_to_buffer(view_depth + this_pass.depth.x), 1.0) > textureLoad(opaque_depth, pixel, 0).r;
}
#else
fn behind_opaque(pixel: vec2<i32>, view_depth: f32) -> bool {
    return false;
}
#endif
