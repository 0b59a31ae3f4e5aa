// Per-frame constants shared by every pass (mirrors FrameUniforms in
// src/render/gpu_data.rs), and the constants of the pass being drawn
// (mirrors PassUniforms; one slot per pass, bound with a dynamic offset).
struct Frame {
    view: mat4x4<f32>,
    proj: mat4x4<f32>,
    // width, height, 1/width, 1/height
    viewport: vec4<f32>,
    // near, far, orthographic (0/1), 1/(far - near)
    depth: vec4<f32>,
    // EWA low-pass radius in pixels (0: no prefilter), Gaussian sharpness k, min |cos| of a footprint (foreshortening bound), back-face culling (0/1)
    splat: vec4<f32>,
    // direction to the light (eye space), shininess
    light: vec4<f32>,
    // ambient, diffuse, specular, unused
    material: vec4<f32>,
    background: vec4<f32>,
    // The window's half extent at view depth 1 (tan(fov_x/2), tan(fov_y/2) for a whole frame; in
    // eye units when orthographic), splat radius scale, least radius per unit of view depth
    // (--min-pixel-radius; in eye units when orthographic)
    lens: vec4<f32>,
    // Environment effects: η, dispersion δ, multi-layer (0/1), skybox (0/1)
    environment: vec4<f32>,
    // The map's up axis (world), the angle of one texel of its level 0
    environment_up: vec4<f32>,
    // The world direction of the map's centre column, unused
    environment_front: vec4<f32>,
    // Scene lights in eye space, two rows each: position (w = 1) or the
    // direction towards the light (w = 0); colour × intensity, inverse-square (0/1).
    lights: array<vec4<f32>, 16>,
    // The number of lights, unused ×3.
    light_count: vec4<u32>,
    // Clip planes in eye space (unit normal, d; n·p + d >= 0 is kept): the
    // user's, then the box's six (crates/core/src/frame/clip.rs).
    clip: array<vec4<f32>, 12>,
    // The user's planes, the box's (0 or 6), the box hides its inside (0/1), unused.
    clip_counts: vec4<u32>,
    // The centre of the frame's window at view depth 1 (eye space, in eye
    // units when orthographic; 0 for a whole frame), unused ×2 (crates/render/src/subframe.rs).
    window: vec4<f32>,
}

struct Pass {
    // The cloud's one colour (rgb) for single-channel weight targets.
    uniform_colour: vec4<f32>,
    // ε (view-depth units), low-precision depth steps n (Eq. 10/14), unused, unused
    depth: vec4<f32>,
    // this pass's layer, layer count K, Voronoi depth (0/1), unused
    layers: vec4<u32>,
    // A full-screen effect's parameters: eye-dome lighting's strength, radius
    // (pixels) and the depth buffer's push behind the front (ε or 0), unused.
    effect: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(0) @binding(1) var<uniform> this_pass: Pass;

// Linear view depth mapped to 0..1: the depth buffer holds linear f32 depth,
// so the epsilon of the visibility test is the same everywhere in the frustum.
fn depth_to_buffer(view_depth: f32) -> f32 {
    return (view_depth - frame.depth.x) * frame.depth.w;
}

// Whether the frame is orthographic: every pixel's ray runs along -z from
// the pixel's place on the eye's plane (crates/core/src/frame/projection.rs).
fn is_ortho() -> bool {
    return frame.depth.z > 0.5;
}

// The pixel's place in the window: ndc · half extent + the window's centre.
fn pixel_window(position: vec2<f32>) -> vec2<f32> {
    let ndc = vec2<f32>(position.x * frame.viewport.z * 2.0 - 1.0, 1.0 - position.y * frame.viewport.w * 2.0);
    return ndc * frame.lens.xy + frame.window.xy;
}

// The eye-space direction of the view ray through pixel `position`, scaled
// to view depth 1 (z = -1): a point at view depth t on it is origin + ray·t.
fn pixel_ray(position: vec2<f32>) -> vec3<f32> {
    return select(vec3<f32>(pixel_window(position), -1.0), vec3<f32>(0.0, 0.0, -1.0), is_ortho());
}

// Where that ray starts: the eye (the origin), or in orthographic the
// pixel's place on the eye's plane.
fn pixel_origin(position: vec2<f32>) -> vec3<f32> {
    return select(vec3<f32>(0.0), vec3<f32>(pixel_window(position), 0.0), is_ortho());
}

// From the eye towards the eye-space point `p`, not of unit length: what
// back faces and footprints are judged by (the view axis in orthographic).
fn towards(p: vec3<f32>) -> vec3<f32> {
    return select(p, vec3<f32>(0.0, 0.0, -1.0), is_ortho());
}

// Whether `normal` (eye space; a splat's, or a layer's Σw·n) points away
// from the viewer at pixel `position`: what splits ε-layers by facing.
fn faces_away(normal: vec3<f32>, position: vec2<f32>) -> bool {
    return dot(normal, pixel_ray(position)) > 0.0;
}

// Whether the point at view depth `t` along the pixel's ray (origin + ray·t,
// z = -t: where the ray meets a splat) is kept by the clip planes and box: per
// pixel, so a cut splat shows exactly its kept part. Each plane is tested
// as (n·ray)·t + (n·origin + d), so the point is never formed beside the callers'
// own (their arithmetic, and so their images, stay as they were unclipped).
// The same test as EyeClip::keeps_along on the CPU.
fn clip_keeps(origin: vec3<f32>, ray: vec3<f32>, t: f32) -> bool {
    let user = frame.clip_counts.x;
    for (var i = 0u; i < user; i++) {
        if dot(frame.clip[i].xyz, ray) * t + (dot(frame.clip[i].xyz, origin) + frame.clip[i].w) < 0.0 {
            return false;
        }
    }
    let boxed = frame.clip_counts.y;
    if boxed == 0u {
        return true;
    }
    var inside = true;
    for (var i = user; i < user + boxed; i++) {
        inside = inside && dot(frame.clip[i].xyz, ray) * t + (dot(frame.clip[i].xyz, origin) + frame.clip[i].w) >= 0.0;
    }
    return inside != (frame.clip_counts.z == 1u);
}

// A splat's drawn radius: its own times the radius scale, and at least
// --min-pixel-radius pixels at its view depth (RenderSettings::pixel_radius_floor;
// at any depth in orthographic).
fn drawn_radius(radius: f32, view_depth: f32) -> f32 {
    return max(abs(radius) * frame.lens.z, frame.lens.w * select(max(view_depth, 0.0), 1.0, is_ortho()));
}
