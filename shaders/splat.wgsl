// Splat geometry (Botsch & Kobbelt 2003, Sec. 3.1-3.3), shared by the splat passes.
// Each splat is an instanced screen-aligned square (a 4-vertex strip) whose
// half-size is the projected radius (Eq. 1). The fragment stage trims it to
// the projected ellipse with the depth offset of Eq. 2 and corrects the depth
// per pixel (Eq. 4, written as linear view depth).

struct SplatIn {
    @location(0) position: vec3<f32>,
    @location(1) radius: f32,
    @location(2) normal: vec3<f32>,
    @location(3) color: vec4<f32>,
}

struct SplatVarying {
    @builtin(position) clip: vec4<f32>,
    // (x, y) in [-1, 1]^2 over the square, in units of the radius.
    @location(0) corner: vec2<f32>,
    // Eye-space unit normal.
    @location(1) @interpolate(flat) normal: vec3<f32>,
    // View depth of the centre, radius in eye units.
    @location(2) @interpolate(flat) depth_radius: vec2<f32>,
    @location(3) @interpolate(flat) color: vec4<f32>,
}

const CULLED: vec4<f32> = vec4<f32>(2.0, 2.0, 2.0, 1.0);

@vertex
fn vs_splat(@builtin(vertex_index) vertex: u32, splat: SplatIn) -> SplatVarying {
    var out: SplatVarying;
    let corner = vec2<f32>(f32(vertex & 1u) * 2.0 - 1.0, f32(vertex >> 1u) * 2.0 - 1.0);
    out.corner = corner;
    out.color = splat.color;
    let centre = (frame.view * vec4<f32>(splat.position, 1.0)).xyz;
    let normal = (frame.view * vec4<f32>(splat.normal, 0.0)).xyz;
    let view_depth = -centre.z;
    // Back-face culling: the normal points away from the eye.
    let back_facing = dot(normal, centre) > 0.0 && frame.splat.w > 0.5;
    let radius = splat.radius * frame.lens.z;
    if view_depth <= frame.depth.x || view_depth >= frame.depth.y || back_facing || !(radius > 0.0) {
        out.clip = CULLED;
        return out;
    }
    // Eq. 1: size_win = r * n / z_eye * h / (t - b) = r * focal_pixels / z_eye.
    let radius_pixels = radius * frame.splat.x / view_depth;
    var clip = frame.proj * vec4<f32>(centre, 1.0);
    clip = vec4<f32>(clip.xy + corner * radius_pixels * 2.0 * frame.viewport.zw * clip.w, clip.zw);
    out.clip = clip;
    let normal_length = length(normal);
    out.normal = select(vec3<f32>(0.0, 0.0, 1.0), normal / normal_length, normal_length > 1e-20);
    out.depth_radius = vec2<f32>(view_depth, radius);
    return out;
}

struct SplatSample {
    // Squared distance from the centre in units of the radius, Eq. 2.
    rho2: f32,
    // Per-pixel corrected view depth (Eq. 4).
    view_depth: f32,
}

// Discards pixels outside the ellipse or outside the depth range.
fn splat_sample(v: SplatVarying) -> SplatSample {
    let n = v.normal;
    // Bounded foreshortening: |n_z| >= min, keeping its sign.
    let nz = select(-1.0, 1.0, n.z >= 0.0) * max(abs(n.z), frame.splat.z);
    // Eq. 2: depth offset of the splat plane at (x, y).
    let dz = -(n.x * v.corner.x + n.y * v.corner.y) / nz;
    let rho2 = dot(v.corner, v.corner) + dz * dz;
    if rho2 >= 1.0 {
        discard;
    }
    let view_depth = v.depth_radius.x - dz * v.depth_radius.y;
    if view_depth <= frame.depth.x || view_depth >= frame.depth.y {
        discard;
    }
    return SplatSample(rho2, view_depth);
}

// Set when the cloud has one colour: colour targets are single-channel and
// hold only the weight (the colour is applied when normalising).
override WEIGHT_ONLY: bool = false;

// What a splat writes to its colour target: (w·rgb, w), or w alone.
fn colour_output(rgb: vec3<f32>, w: f32) -> vec4<f32> {
    if WEIGHT_ONLY {
        return vec4<f32>(w, 0.0, 0.0, w);
    }
    return vec4<f32>(rgb * w, w);
}

// Eq. 3: Gaussian weight of the normalised distance.
fn splat_weight(rho2: f32) -> f32 {
    return exp(-rho2 * frame.splat.y);
}
