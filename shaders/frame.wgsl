// Per-frame constants shared by every pass. Mirrors FrameUniforms in src/render/gpu_data.rs.
struct Frame {
    view: mat4x4<f32>,
    proj: mat4x4<f32>,
    // width, height, 1/width, 1/height
    viewport: vec4<f32>,
    // near, far, epsilon (view-depth units), 1/(far - near)
    depth: vec4<f32>,
    // focal length in pixels, Gaussian sharpness k, min |n_z|, back-face culling (0/1)
    splat: vec4<f32>,
    // direction to the light (eye space), shininess
    light: vec4<f32>,
    // ambient, diffuse, specular, lighting on (0/1)
    material: vec4<f32>,
    background: vec4<f32>,
    // tan(fov_x/2), tan(fov_y/2), splat radius scale, unused
    lens: vec4<f32>,
    // deferred: low-precision depth steps n (Eq. 10/14), Voronoi (0/1), group layers K, unused
    deferred: vec4<f32>,
    // the cloud's one colour (rgb) and 1 when colour targets hold only Σw, else 0
    scene: vec4<f32>,
}

@group(0) @binding(0) var<uniform> frame: Frame;

// Linear view depth mapped to 0..1: the depth buffer holds linear f32 depth,
// so the epsilon of the visibility test is the same everywhere in the frustum.
fn depth_to_buffer(view_depth: f32) -> f32 {
    return (view_depth - frame.depth.x) * frame.depth.w;
}
