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
    // Eye-space centre of the disc.
    @location(0) @interpolate(flat) centre: vec3<f32>,
    // Eye-space unit normal (for shading).
    @location(1) @interpolate(flat) normal: vec3<f32>,
    // Unit normal of the plane the footprint is cast on (tilted if grazing), and 1/r².
    @location(2) @interpolate(flat) plane: vec4<f32>,
    @location(3) @interpolate(flat) colour: vec4<f32>,
}

const CULLED: vec4<f32> = vec4<f32>(2.0, 2.0, 2.0, 1.0);

@vertex
fn vs_splat(@builtin(vertex_index) vertex: u32, splat: SplatIn) -> SplatVarying {
    var out: SplatVarying;
    let corner = vec2<f32>(f32(vertex & 1u) * 2.0 - 1.0, f32(vertex >> 1u) * 2.0 - 1.0);
    out.colour = vec4<f32>(splat.colour.rgb, splat.opacity);
    let centre = (frame.view * vec4<f32>(splat.position, 1.0)).xyz;
    let normal_eye = (frame.view * vec4<f32>(splat.normal, 0.0)).xyz;
    let normal_length = length(normal_eye);
    let normal = select(vec3<f32>(0.0, 0.0, 1.0), normal_eye / normal_length, normal_length > 1e-20);
#ifdef LIGHTS
    // Lit once per splat: what the passes blend is the lit colour.
    out.colour = vec4<f32>(light_splat(splat.colour.rgb, normal, centre, splat.shadow_a, splat.shadow_b), splat.opacity);
#endif
    let distance = length(centre);
    // Back-face culling: the normal points away from the eye (two-sided splats are kept).
    let back_facing = dot(normal, centre) > 0.0 && frame.splat.w > 0.5 && splat.radius > 0.0;
    let radius = abs(splat.radius) * frame.lens.z;
    if back_facing || !(radius > 0.0) || !(distance > 0.0) || -centre.z - radius >= frame.depth.y {
        out.clip = CULLED;
        return out;
    }
    let plane = footprint_normal(normal, centre / distance, frame.splat.z);
    // Two unit tangents of the footprint plane.
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(plane.x) > 0.9);
    let s = normalize(cross(plane, helper));
    let t = cross(plane, s);
    let corner_eye = centre + (s * corner.x + t * corner.y) * radius;
    out.clip = frame.proj * vec4<f32>(corner_eye, 1.0);
    out.centre = centre;
    out.normal = normal;
    out.plane = vec4<f32>(plane, 1.0 / (radius * radius));
    return out;
}

struct SplatSample {
    // Squared distance from the centre in units of the radius.
    rho2: f32,
    // Exact view depth of the ray-plane intersection (Eq. 4).
    view_depth: f32,
}

// Casts the pixel's ray on the splat; discards pixels outside the disc or the depth range.
fn splat_sample(v: SplatVarying) -> SplatSample {
    let ray = pixel_ray(v.clip.xy);
    let n = v.plane.xyz;
    let facing = dot(ray, n);
    let t = dot(v.centre, n) / facing;
    let offset = ray * t - v.centre;
    let rho2 = dot(offset, offset) * v.plane.w;
    if !(rho2 < 1.0) || !(t > frame.depth.x && t < frame.depth.y) {
        discard;
    }
    return SplatSample(rho2, t);
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

// Eq. 3: Gaussian weight of the normalised distance.
fn splat_weight(rho2: f32) -> f32 {
    return exp(-rho2 * frame.splat.y);
}
