#include "shading.wgsl"
#include "opaque_under.wgsl"
#include "group_images.wgsl"
#ifdef ENVIRONMENT
#include "environment.wgsl"
#endif

// The compositing pass of Algorithm-2 (§5.2.2), the three blends in one go:
// C_F, the nearest layer: Fig. 6's ε-z compositing of the I_k (d = min_k
// depth_k and its facing, found by shaders/alg2_front.wgsl; the layers
// within d + ε that face as it does summed), normalised and shaded per pixel
// (deferred shading), with its opacity α = Σw·α / Σw; C_O, the other layers:
// the average of the O_k that cover the pixel (as in Algorithm-1), over the
// background or the opaque splats drawn apart (shaders/opaque_under.wgsl);
// and the pixel I = α·C_F + (1 - α)·C_O.
//
// With an environment map (ENVIRONMENT, §5.2.3-5.2.4) the nearest layer's
// composited normal reflects and refracts it (shaders/environment.wgsl) and
// the pixel follows crates/core/src/frame/environment.rs: I = F·E_R + (1 - F)·(α·C_F +
// (1 - α)·B), B = C_b + a·E_T, with C_b the mean of the O_k (premultiplied),
// a = 1 - C_b's coverage (single-layer) or (1 - α)^l (multi-layer, Eq. 15,
// l = Σα/α from the O_k's summed opacities), and the opaque image in place
// of E_T where an opaque splat lies behind. Where nothing is drawn, the map
// itself shows (a skybox) unless the flat background is asked for.

@group(1) @binding(0) var nearest_colour: texture_2d_array<f32>;
@group(1) @binding(1) var nearest_depth: texture_2d_array<f32>;
@group(1) @binding(2) var nearest_normal_alpha: texture_2d_array<f32>;
@group(1) @binding(3) var other_images: texture_2d_array<f32>;
// d of the nearest layer and its facing (shaders/alg2_front.wgsl).
@group(1) @binding(4) var front_depth: texture_2d<f32>;
#ifdef OPAQUE_APART
@group(1) @binding(5) var opaque_image: texture_2d<f32>;
#endif

@fragment
fn fs_alg2_composite(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    // The other layers: the mean of the O_k that cover the pixel.
    let mean = mean_of_covering(other_images, pixel);
    // C_F and its opacity.
    let nearest_layer = textureLoad(front_depth, pixel, 0);
    var sums = vec4<f32>(0.0);
    var normal_alpha = vec4<f32>(0.0);
    for (var k = 0; k < i32(this_pass.layers.y); k++) {
        let colour = colour_sums(textureLoad(nearest_colour, pixel, k, 0));
        let group_normal_alpha = textureLoad(nearest_normal_alpha, pixel, k, 0);
        let same_facing = faces_away(group_normal_alpha.xyz, f.position.xy) == (nearest_layer.g > 0.5);
        if same_facing && in_nearest_layer(colour, textureLoad(nearest_depth, pixel, k, 0).r, nearest_layer.r) {
            sums += colour;
            normal_alpha += group_normal_alpha;
        }
    }
    let has_front = sums.a > 1e-6;
    let alpha = select(0.0, clamp(normal_alpha.a / max(sums.a, 1e-30), 0.0, 1.0), has_front);
#ifdef ENVIRONMENT
    return glass(f.position.xy, pixel, has_front, alpha, sums, normal_alpha.xyz, mean);
#else
    let under = beneath(pixel);
    let behind = mean.rgb + (1.0 - mean.a) * under;
    if !has_front {
        return vec4<f32>(behind, 1.0);
    }
    let front = shade_sums(f.position.xy, sums, normal_alpha.xyz);
    return vec4<f32>(alpha * front + (1.0 - alpha) * behind, 1.0);
#endif
}

#ifdef ENVIRONMENT
// The pixel with the environment effects. Every lookup direction and its
// mip level is found before any branch: derivatives need uniform control flow.
fn glass(
    position: vec2<f32>,
    pixel: vec2<i32>,
    has_front: bool,
    alpha: f32,
    sums: vec4<f32>,
    normal_sum: vec3<f32>,
    mean: vec4<f32>,
) -> vec4<f32> {
    let d = normalize(pixel_ray(position));
    let normal_length = length(normal_sum);
    var n = select(-d, normal_sum / normal_length, normal_length > 1e-20);
    n = select(n, -n, dot(n, d) > 0.0);
    let multi = frame.environment.z > 0.5;
    let layers_behind = select(0.0, mean.a / max(alpha, 1e-6), multi && alpha > 0.0);
    let crossings = select(1.0, 1.0 + layers_behind, multi);
    let rays = environment_glass_rays(d, n, crossings);
    let levels = environment_glass_levels(rays, vec2<bool>(true));
    let sky = environment_world(d);
    let sky_level = environment_level(sky);
    // Beneath everything: the opaque splats drawn apart, else the map or the background.
    var under = select(frame.background.rgb, environment_sample(sky, sky_level), frame.environment.w > 0.5);
    var closed = false;
#ifdef OPAQUE_APART
    let opaque = textureLoad(opaque_image, pixel, 0);
    closed = opaque.a > 0.5;
    under = select(under, opaque.rgb, closed);
#endif
    if !has_front {
        return vec4<f32>(under, 1.0);
    }
    let front = shade_sums(position, sums, normal_sum);
    if alpha >= 1.0 {
        return vec4<f32>(front, 1.0);
    }
    let reaching = select(1.0 - mean.a, environment_absorption(alpha, layers_behind), multi);
    // Behind an opaque splat, `under` (the opaque image) is seen instead of the map.
    let instead = vec4<f32>(under, select(0.0, 1.0, closed));
    let out = environment_glass_pixel(d, n, rays, levels, alpha, front, mean.rgb, reaching, instead);
    return vec4<f32>(out, 1.0);
}
#endif
