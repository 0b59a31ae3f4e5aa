// Environment effects on the nearest transparent layer (Zhang & Pajarola
// §5.2.3-5.2.4), per pixel in the compositing pass: the equirectangular map
// at group 2 and the lookups, reflection, Eq. 16 refraction and Schlick's
// Fresnel. src/view/environment.rs has the same model for the CPU reference,
// src/reference/environment.rs the same choice of mip level.

@group(2) @binding(0) var environment_map: texture_2d<f32>;
@group(2) @binding(1) var environment_sampler: sampler;

const TAU: f32 = 6.2831853;
const PI: f32 = 3.14159265;
// Smallest index of refraction used (as MIN_ETA on the CPU).
const MIN_ETA: f32 = 0.05;

// Eye space to world: the view matrix is rigid, so its 3x3 transposed.
fn environment_world(d: vec3<f32>) -> vec3<f32> {
    let m = mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz);
    return normalize(transpose(m) * d);
}

// (u, v) on the map: u from the longitude around the map's up axis, 0.5
// along its front; v from the angle to up (0 at the top).
fn environment_uv(d: vec3<f32>) -> vec2<f32> {
    let up = frame.environment_up.xyz;
    let front = frame.environment_front.xyz;
    let right = cross(up, front);
    let u = 0.5 + atan2(dot(d, right), dot(d, front)) / TAU;
    // The angle to up as atan2 of its sine and cosine: acos is approximated
    // coarsely by some shader compilers (Mesa's to about 1e-4), which moves
    // a lookup by a fraction of a texel and shows as noise on a sharp map.
    let along = dot(d, up);
    let v = atan2(length(d - along * up), along) / PI;
    return vec2<f32>(u, v);
}

// The mip level of a lookup along world direction d: how far d turns to the
// next pixel of the 2x2 quad (fine derivatives), in texels of level 0. Must
// run in uniform control flow.
fn environment_level(d: vec3<f32>) -> f32 {
    let spread = max(length(dpdxFine(d)), length(dpdyFine(d)));
    return log2(max(spread / frame.environment_up.w, 1.0));
}

fn environment_sample(d: vec3<f32>, level: f32) -> vec3<f32> {
    return textureSampleLevel(environment_map, environment_sampler, environment_uv(d), level).rgb;
}

// η of channel c (0 red, 1 green, 2 blue): η - δ, η, η + δ.
fn environment_eta(c: i32) -> f32 {
    return max(frame.environment.x + (f32(c) - 1.0) * frame.environment.y, MIN_ETA);
}

// d refracted at normal n (facing the viewer) by Eq. 16 through `crossings`
// interfaces: sin θ_T = (1/η)^m sin θ_I. w = 1 when refracted; under total
// internal reflection, w = 0 and xyz is the reflection.
fn environment_refract(d: vec3<f32>, n: vec3<f32>, eta: f32, crossings: f32) -> vec4<f32> {
    let cos_i = clamp(-dot(d, n), 0.0, 1.0);
    let sin_i = sqrt(max(1.0 - cos_i * cos_i, 0.0));
    let ratio = exp(clamp(crossings * -log(max(eta, MIN_ETA)), -80.0, 80.0));
    let sin_t = ratio * sin_i;
    if sin_t >= 1.0 {
        return vec4<f32>(reflect(d, n), 0.0);
    }
    let cos_t = sqrt(max(1.0 - sin_t * sin_t, 0.0));
    let along = d + cos_i * n;
    let along_length = length(along);
    let tangent = select(vec3<f32>(0.0), along / along_length, along_length > 1e-20);
    let t = tangent * sin_t - n * cos_t;
    let t_length = length(t);
    return vec4<f32>(select(d, t / t_length, t_length > 1e-20), 1.0);
}

fn environment_schlick(eta: f32, cos_i: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    let f0 = r * r;
    let m = 1.0 - clamp(cos_i, 0.0, 1.0);
    return f0 + (1.0 - f0) * m * m * m * m * m;
}

// Eq. 15: the share of light through `layers` layers of opacity `alpha`
// (1 for none; 0 cleanly for an opaque layer or very many).
fn environment_absorption(alpha: f32, layers: f32) -> f32 {
    if layers <= 0.0 {
        return 1.0;
    }
    return exp2(layers * log2(max(1.0 - clamp(alpha, 0.0, 1.0), 1e-30)));
}

// The colour of a pixel whose nearest layer is glass, per channel c
// (crates/core/src/frame/environment.rs, glass_colour): F·E_R + (1 - F)·(α·C_F
// + (1 - α)·(C_b + a·E_T)), with Schlick's F (1 under total internal
// reflection, where `refracted` is 0), E_R the map along the reflection,
// E_T the map along channel c's refracted ray `through[c]` at `levels[c]`,
// unless `instead.a` > 0.5: then `instead.rgb` is seen beyond (an opaque
// image behind the glass).
fn environment_glass_pixel(
    d: vec3<f32>,
    n: vec3<f32>,
    alpha: f32,
    front: vec3<f32>,
    behind: vec3<f32>,
    reaching: f32,
    through: array<vec3<f32>, 3>,
    levels: vec3<f32>,
    refracted: vec3<f32>,
    seen_reflected: vec3<f32>,
    instead: vec4<f32>,
) -> vec3<f32> {
    let cos_i = clamp(-dot(d, n), 0.0, 1.0);
    var out = vec3<f32>(0.0);
    for (var c = 0; c < 3; c++) {
        let seen_through = environment_sample(through[c], levels[c])[c];
        let beyond = select(seen_through, instead[c], instead.a > 0.5);
        let fresnel = select(1.0, environment_schlick(environment_eta(c), cos_i), refracted[c] > 0.5);
        let transmitted = behind[c] + reaching * beyond;
        let surface = alpha * front[c] + (1.0 - alpha) * transmitted;
        out[c] = fresnel * seen_reflected[c] + (1.0 - fresnel) * surface;
    }
    return out;
}
