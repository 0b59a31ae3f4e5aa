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
    return environment_level_among(d, vec2<bool>(true));
}

// environment_level over the other pixel of the quad's row (`partners.x`)
// and of its column (`partners.y`) only where they are true: the reference
// leaves out a neighbour that looks along no direction of this kind.
fn environment_level_among(d: vec3<f32>, partners: vec2<bool>) -> f32 {
    let across = select(0.0, length(dpdxFine(d)), partners.x);
    let down = select(0.0, length(dpdyFine(d)), partners.y);
    return log2(max(max(across, down) / frame.environment_up.w, 1.0));
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

// The world directions a glass pixel looks the map up along
// (crates/core/src/frame/environment.rs, glass_directions): the reflection
// of d at n, and each channel's refraction through `crossings` interfaces,
// the reflection where it is totally reflected (`refracted` 0 there).
struct GlassRays {
    reflected: vec3<f32>,
    through: array<vec3<f32>, 3>,
    refracted: vec3<f32>,
}

fn environment_glass_rays(d: vec3<f32>, n: vec3<f32>, crossings: f32) -> GlassRays {
    let red = environment_refract(d, n, environment_eta(0), crossings);
    let green = environment_refract(d, n, environment_eta(1), crossings);
    let blue = environment_refract(d, n, environment_eta(2), crossings);
    return GlassRays(
        environment_world(reflect(d, n)),
        array<vec3<f32>, 3>(environment_world(red.xyz), environment_world(green.xyz), environment_world(blue.xyz)),
        vec3<f32>(red.w, green.w, blue.w),
    );
}

// The mip levels of the rays (refracted red, green, blue, reflected), over
// the quad's neighbours in `partners` (see environment_level_among). Must
// run in uniform control flow.
fn environment_glass_levels(rays: GlassRays, partners: vec2<bool>) -> vec4<f32> {
    return vec4<f32>(
        environment_level_among(rays.through[0], partners),
        environment_level_among(rays.through[1], partners),
        environment_level_among(rays.through[2], partners),
        environment_level_among(rays.reflected, partners),
    );
}

// The colour of a pixel whose nearest layer is glass (crates/core/src/frame/
// environment.rs, glass_colour), per channel c: F·E_R + (1 - F)·(α·C_F + (1 -
// α)·(C_b + a·E_T)), with Schlick's F (1 where the channel is totally
// reflected), E_R the map along the reflection, E_T along channel c's
// refracted ray, unless `instead.a` > 0.5: then `instead.rgb` is seen beyond
// (an opaque image behind the glass). `behind` is C_b, `reaching` a.
fn environment_glass_pixel(
    d: vec3<f32>,
    n: vec3<f32>,
    rays: GlassRays,
    levels: vec4<f32>,
    alpha: f32,
    front: vec3<f32>,
    behind: vec3<f32>,
    reaching: f32,
    instead: vec4<f32>,
) -> vec3<f32> {
    let cos_i = clamp(-dot(d, n), 0.0, 1.0);
    let seen_reflected = environment_sample(rays.reflected, levels.w);
    var out = vec3<f32>(0.0);
    for (var c = 0; c < 3; c++) {
        let seen_through = environment_sample(rays.through[c], levels[c])[c];
        let beyond = select(seen_through, instead[c], instead.a > 0.5);
        let fresnel = select(1.0, environment_schlick(environment_eta(c), cos_i), rays.refracted[c] > 0.5);
        let transmitted = behind[c] + reaching * beyond;
        let surface = alpha * front[c] + (1.0 - alpha) * transmitted;
        out[c] = fresnel * seen_reflected[c] + (1.0 - fresnel) * surface;
    }
    return out;
}
