#include "frame.wgsl"
#include "footprint.wgsl"
#ifdef LIGHTS
#include "lights.wgsl"
#endif

// Splat geometry, shared by the splat passes: perspective-correct splat
// rasterisation by ray casting (Guennebaud, "Approximate depth peeling",
// SPBG'06 slides: "perspectively correct splat rasterization", the ray-casting
// class of [Botsch et al.]), with Botsch & Kobbelt 2003's Gaussian weight
// (Eq. 3), per-pixel depth (Eq. 4) and bounded foreshortening.
//
// Splat setup (vertex stage): each splat is an instanced 4-vertex strip, the
// square that circumscribes its disc in the disc's own plane. Its corners are
// projected like any geometry, so the square is exact under perspective and
// the hardware clips it at the near plane: a splat crossing the near plane
// keeps the part in front of it, and none is dropped whole. Rasterisation
// (fragment stage): the pixel's view ray meets the splat plane at view depth
// t = (c·n)/(q·n); ρ² = |t·q - c|²/r² decides coverage (ρ² < 1) and the
// weight, and t is the fragment's exact depth. The CPU reference intersects
// the same rays with the same discs (src/reference/raster.rs).
//
// Bounded foreshortening: a disc seen at a grazing angle is drawn in a plane
// tilted towards the viewer until |n·v| >= min (the B&K bound on |n_z|, here
// relative to the ray to the centre), so edge-on splats stay slivers instead
// of vanishing; src/view/kernel.rs applies the same tilt for the reference.
//
// Prefilter (frame.splat.x > 0): Guennebaud's EWA filtering approximation
// (crates/core/src/frame/prefilter.rs). The footprint's tangents are the
// slides' s = p × n and t = n × s, and each is stretched until its
// screen-space length at the centre is at least the low-pass radius h, so a
// splat smaller than a pixel covers the pixels around it. The stretched
// footprint is the ellipse ρ² = (o·S)² + (o·T)² (S = s/(r·a_s), T = t/(r·a_t)),
// and its Gaussian's peak is divided by a_s·a_t. The stretched disc stays in
// its plane, so every fragment's depth is the exact depth of the plane on its
// ray, as for an unstretched splat: coplanar neighbours stay within ε of one
// another and blend (a depth clamped to the original disc would set rows of
// a grazing plane apart by more than ε, and the filter would not filter).
// Only the visibility pass, which sets the front surface, keeps the depth of
// the disc's rim along the fragment's offset where that is farther
// (`front_depth`): across a silhouette the plane continued past the disc
// stands in front of the surface, and as the front it culled the splats
// facing the viewer and left the outline to edge-on normals, a dark rim.
// Only splats smaller than h along s (the screen-parallel tangent, which
// foreshortening does not shorten) are filtered, in both directions: a
// larger splat seen at a grazing angle, thin along t, is drawn exactly as
// without the filter. Stretching those too widened every silhouette of the
// bench views (ε against the one-ray reference 0.06-1.19, docs/BENCHMARKS.md).

struct SplatIn {
    @location(0) position: vec3<f32>,
    // Negative for a splat of a two-sided object (never back-face culled).
    @location(1) radius: f32,
    @location(2) normal: vec3<f32>,
    // rgb; the fourth byte is unused.
    @location(3) colour: vec4<f32>,
    // Opacity in f32 (the reference's precision).
    @location(4) opacity: f32,
#ifdef LIGHTS
    // Shadow coefficients of lights 0-3 and 4-7 (a second instance buffer).
    @location(5) shadow_a: vec4<f32>,
    @location(6) shadow_b: vec4<f32>,
#endif
}

struct SplatVarying {
    @builtin(position) clip: vec4<f32>,
#ifdef TRIANGLES
    // A triangle's eye-space point, normal and colour, interpolated across it.
    @location(0) centre: vec3<f32>,
    @location(1) normal: vec3<f32>,
#else
    // Eye-space centre of the disc.
    @location(0) @interpolate(flat) centre: vec3<f32>,
    // Eye-space unit normal (for shading).
    @location(1) @interpolate(flat) normal: vec3<f32>,
#endif
    // Unit normal of the plane the footprint is cast on (tilted if grazing), and 1/r².
    @location(2) @interpolate(flat) plane: vec4<f32>,
#ifdef TRIANGLES
    @location(3) colour: vec4<f32>,
#else
    @location(3) @interpolate(flat) colour: vec4<f32>,
#endif
    // A prefiltered splat's stretched axes S (xyz) and the weight's scale
    // 1/(a_s·a_t) (w); w = 0 when the splat is not stretched.
    @location(4) @interpolate(flat) axis_s: vec4<f32>,
    // T (xyz); w: 1 for a one-sided triangle that is back-face culled per fragment.
    @location(5) @interpolate(flat) axis_t: vec4<f32>,
}

// The length in pixels of the eye-space vector `d` at the point `c` (z < 0)
// on screen, to first order (the perspective projection's Jacobian at c;
// in orthographic, d's part across the view axis).
fn screen_length(c: vec3<f32>, d: vec3<f32>) -> f32 {
    let z = -c.z;
    let along = select(d.xy / z + c.xy * (d.z / (z * z)), d.xy, is_ortho());
    let pixels_per_unit = frame.viewport.xy / (2.0 * frame.lens.xy);
    return length(along * pixels_per_unit);
}

const CULLED: vec4<f32> = vec4<f32>(2.0, 2.0, 2.0, 1.0);

// The world direction `d` in eye space, of unit length (`fallback` when it has none).
fn eye_direction(d: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let eye = (frame.view * vec4<f32>(d, 0.0)).xyz;
    let length_eye = length(eye);
    return select(fallback, eye / length_eye, length_eye > 1e-20);
}

@vertex
fn vs_splat(@builtin(vertex_index) vertex: u32, splat: SplatIn) -> SplatVarying {
    var out: SplatVarying;
    let corner = vec2<f32>(f32(vertex & 1u) * 2.0 - 1.0, f32(vertex >> 1u) * 2.0 - 1.0);
    out.colour = vec4<f32>(splat.colour.rgb, splat.opacity);
    let centre = (frame.view * vec4<f32>(splat.position, 1.0)).xyz;
    let normal = eye_direction(splat.normal, vec3<f32>(0.0, 0.0, 1.0));
#ifdef LIGHTS
    // Lit once per splat: what the passes blend is the lit colour.
    out.colour = vec4<f32>(light_splat(splat.colour.rgb, normal, centre, splat.shadow_a, splat.shadow_b), splat.opacity);
#endif
    // From the eye to the centre (along the view axis in orthographic).
    let sight = towards(centre);
    let distance = length(sight);
    // Back-face culling: the normal points away from the eye (two-sided splats are kept).
    let back_facing = dot(normal, sight) > 0.0 && frame.splat.w > 0.5 && splat.radius > 0.0;
    let radius = drawn_radius(splat.radius, -centre.z);
    // A vacant slot of a node pool holds a negative opacity (node_pool.rs).
    let vacant = splat.opacity < 0.0;
    if vacant || back_facing || !(radius > 0.0) || !(distance > 0.0) || -centre.z - radius >= frame.depth.y {
        out.clip = CULLED;
        return out;
    }
    let plane = footprint_normal(normal, sight / distance, frame.splat.z);
    // Two unit tangents of the footprint plane.
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(plane.x) > 0.9);
    var s = normalize(cross(plane, helper));
    var t = cross(plane, s);
    var stretch = vec2<f32>(1.0);
    let low_pass = frame.splat.x;
    if low_pass > 0.0 && -centre.z > frame.depth.x {
        // The slides' heuristic for discs: s = p × n is parallel to the
        // screen, t = n × s the most foreshortened direction.
        let across = cross(sight, plane);
        let across_length = length(across);
        if across_length > 1e-6 * distance {
            s = across / across_length;
            t = cross(plane, s);
        }
        let lengths = vec2<f32>(screen_length(centre, s * radius), screen_length(centre, t * radius));
        // Minification only: a splat at least h wide along s is left as it is.
        let stretched = max(vec2<f32>(1.0), low_pass / max(lengths, vec2<f32>(1e-6)));
        stretch = select(vec2<f32>(1.0), stretched, lengths.x < low_pass);
    }
    let corner_eye = centre + (s * (stretch.x * corner.x) + t * (stretch.y * corner.y)) * radius;
    out.clip = frame.proj * vec4<f32>(corner_eye, 1.0);
    out.centre = centre;
    out.normal = normal;
    out.plane = vec4<f32>(plane, 1.0 / (radius * radius));
    let stretched = stretch.x > 1.0 || stretch.y > 1.0;
    out.axis_s = vec4<f32>(s / (radius * stretch.x), select(0.0, 1.0 / (stretch.x * stretch.y), stretched));
    out.axis_t = vec4<f32>(t / (radius * stretch.y), 0.0);
    return out;
}

#ifdef TRIANGLES
// Mesh triangles (crates/core/src/hybrid), drawn by the same fragment
// entries as splats: each vertex carries its triangle's plane normal (the
// winding's), so the fragment stage's ray-plane depth is the triangle's
// exact depth; the plane's 1/r² is 0, so every fragment has ρ² = 0 and the
// weight of a splat's centre, and blends with any splat within ε of it
// (Guennebaud's hybrid transition). Normal and colour are interpolated, as
// the reference does by barycentric coordinates (src/reference/triangles.rs).
// A one-sided triangle facing away is discarded per fragment: the sign of
// n·p is the same over a plane, so the test is exact without the triangle's
// other vertices.
struct TriangleIn {
    @location(0) position: vec3<f32>,
    // Negative for a vertex of a two-sided object (never back-face culled).
    @location(1) sided: f32,
    @location(2) normal: vec3<f32>,
    @location(3) colour: vec4<f32>,
    @location(4) opacity: f32,
    @location(5) face: vec3<f32>,
}

@vertex
fn vs_triangle(vertex: TriangleIn) -> SplatVarying {
    var out: SplatVarying;
    let centre = (frame.view * vec4<f32>(vertex.position, 1.0)).xyz;
    let normal = eye_direction(vertex.normal, vec3<f32>(0.0, 0.0, 1.0));
    let face = eye_direction(vertex.face, normal);
    out.colour = vec4<f32>(vertex.colour.rgb, vertex.opacity);
#ifdef LIGHTS
    // Lit per vertex, unshadowed: shadow coefficients are per splat.
    out.colour = vec4<f32>(light_splat(vertex.colour.rgb, normal, centre, vec4<f32>(1.0), vec4<f32>(1.0)), vertex.opacity);
#endif
    out.clip = frame.proj * vec4<f32>(centre, 1.0);
    out.centre = centre;
    out.normal = normal;
    out.plane = vec4<f32>(face, 0.0);
    out.axis_s = vec4<f32>(0.0);
    out.axis_t = vec4<f32>(0.0, 0.0, 0.0, select(0.0, 1.0, frame.splat.w > 0.5 && vertex.sided > 0.0));
    return out;
}
#endif

struct SplatSample {
    // Squared distance from the centre in units of the radius (of the
    // stretched footprint when prefiltered).
    rho2: f32,
    // Exact view depth of the ray-plane intersection (Eq. 4).
    view_depth: f32,
    // The factor on the Gaussian weight: 1, or 1/(a_s·a_t) when prefiltered.
    scale: f32,
    // The depth the visibility pass keeps: the view depth, except that the
    // part of a prefiltered footprint beyond its original disc is never
    // nearer than the disc's rim along the same offset. The plane continued
    // past a disc is not surface: on a silhouette, where the footprint is
    // stretched across the outline, it stands in front of the surface and
    // would hide the splats that face the viewer.
    front_depth: f32,
}

// Casts the pixel's ray on the splat; discards pixels outside the disc or the depth range.
fn splat_sample(v: SplatVarying) -> SplatSample {
    let ray = pixel_ray(v.clip.xy);
    let origin = pixel_origin(v.clip.xy);
    let n = v.plane.xyz;
#ifdef TRIANGLES
    if v.axis_t.w > 0.5 && dot(n, towards(v.centre)) > 0.0 {
        discard;
    }
#endif
    // The centre seen from the ray's origin (the centre itself in perspective).
    let centre = v.centre - origin;
    let facing = dot(ray, n);
    let t = dot(centre, n) / facing;
    let offset = ray * t - centre;
    var rho2 = dot(offset, offset) * v.plane.w;
    var scale = 1.0;
    var front = t;
    if v.axis_s.w > 0.0 {
        let rim = v.centre + offset / max(sqrt(rho2), 1.0);
        front = max(t, -rim.z);
        let along = vec2<f32>(dot(offset, v.axis_s.xyz), dot(offset, v.axis_t.xyz));
        rho2 = dot(along, along);
        scale = v.axis_s.w;
    }
    if !(rho2 < 1.0) || !(t > frame.depth.x && t < frame.depth.y) {
        discard;
    }
#ifdef CLIP
    if !clip_keeps(origin, ray, t) {
        discard;
    }
#endif
    return SplatSample(rho2, t, scale, front);
}

// What a splat writes to its colour target: (w·rgb, w), or, in the
// WEIGHT_ONLY variant (a cloud of one colour, single-channel targets), w alone;
// the colour is applied when normalising.
fn colour_output(rgb: vec3<f32>, w: f32) -> vec4<f32> {
#ifdef WEIGHT_ONLY
    return vec4<f32>(w, 0.0, 0.0, w);
#else
    return vec4<f32>(rgb * w, w);
#endif
}

// The share of the pixel a stretched splat's fragment of weight w covers
// (the prefilter's edge antialiasing, shaders/accumulate.wgsl's COVERAGE).
// Its weight integrates over the screen to 2σ²·A, A the splat's own
// projected area and σ the kernel's deviation in radii: the stretch divides
// the peak by what it widens, and the Gaussian's deviation is σ of each
// stretched axis. So k·w = w/(2σ²) is A spread over the low-pass filter's
// Gaussian: the splat's box coverage of the pixel, to the filter's
// approximation (σ·h = 0.32 px against the box's 0.29).
fn splat_coverage(s: SplatSample, w: f32) -> f32 {
    return select(0.0, w * frame.splat.y, s.scale < 1.0);
}

// Eq. 3: Gaussian weight of the normalised distance (its peak lowered by a prefilter's stretch).
fn splat_weight(s: SplatSample) -> f32 {
    return exp(-s.rho2 * frame.splat.y) * s.scale;
}
