#include "frame.wgsl"

// Full-screen triangle and deferred Phong shading, shared by the passes that
// normalise accumulated sums (normalize.wgsl, deferred_composite.wgsl).
// src/view/shading.rs has the same formula for the CPU reference.

struct Fullscreen {
    @builtin(position) position: vec4<f32>,
}

@vertex
fn vs_fullscreen(@builtin(vertex_index) vertex: u32) -> Fullscreen {
    let uv = vec2<f32>(f32((vertex << 1u) & 2u), f32(vertex & 2u));
    return Fullscreen(vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0));
}

fn shade(albedo: vec3<f32>, normal_in: vec3<f32>, to_eye: vec3<f32>) -> vec3<f32> {
    let n = select(normal_in, -normal_in, dot(normal_in, to_eye) < 0.0);
    let l = frame.light.xyz;
    let diffuse = max(dot(n, l), 0.0);
    let reflected = 2.0 * dot(n, l) * n - l;
    var specular = 0.0;
    if diffuse > 0.0 {
        specular = pow(max(dot(reflected, to_eye), 0.0), frame.light.w);
    }
    let lit = albedo * (frame.material.x + frame.material.y * diffuse) + vec3<f32>(frame.material.z * specular);
    return clamp(lit, vec3<f32>(0.0), vec3<f32>(1.0));
}

// (Σw·rgb, Σw) from a colour target's texel: in the WEIGHT_ONLY variant the
// single-channel targets hold Σw alone, and the cloud's one colour is applied here.
fn colour_sums(texel: vec4<f32>) -> vec4<f32> {
#ifdef WEIGHT_ONLY
    return vec4<f32>(this_pass.uniform_colour.rgb * texel.r, texel.r);
#else
    return texel;
#endif
}

// Normalises (Σw·rgb, Σw) and Σw·n at pixel `position` and shades the result
// (or returns the normalised colour when lighting is off).
fn shade_sums(position: vec2<f32>, sums: vec4<f32>, normal_sum: vec3<f32>) -> vec3<f32> {
    let albedo = sums.rgb / sums.a;
#ifdef LIT
    // Eye-space direction of this pixel's view ray.
    let to_eye = normalize(-pixel_ray(position));
    let length_sq = dot(normal_sum, normal_sum);
    let normal = select(to_eye, normal_sum * inverseSqrt(length_sq), length_sq > 1e-20);
    return shade(albedo, normal, to_eye);
#else
    return clamp(albedo, vec3<f32>(0.0), vec3<f32>(1.0));
#endif
}
