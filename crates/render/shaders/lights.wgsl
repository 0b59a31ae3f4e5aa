#include "frame.wgsl"

// Lighting by scene lights, once per splat at its centre (Gunjee et al.
// §4.1: each point is shaded with its shadow coefficient, the share of each
// light that reaches it through the translucent layers in front of it,
// crates/core/src/shadow). Mirrors Shading::shade_lit in
// crates/core/src/frame/shading.rs: Phong summed over the lights, two-sided
// (the normal turned towards the eye), ambient kept. Splat passes write the
// lit colour where they would write the albedo, so every mode's blending
// and normalising stays as it is and only the light changes.

// `albedo` at eye-space `centre` with unit eye-space `normal_in`, lit by the
// frame's lights, light k scaled by its shadow coefficient (shadow_a for
// lights 0-3, shadow_b for 4-7).
fn light_splat(albedo: vec3<f32>, normal_in: vec3<f32>, centre: vec3<f32>, shadow_a: vec4<f32>, shadow_b: vec4<f32>) -> vec3<f32> {
    let sight = towards(centre);
    let distance = length(sight);
    let to_eye = select(vec3<f32>(0.0, 0.0, 1.0), -sight / distance, distance > 0.0);
    let n = select(normal_in, -normal_in, dot(normal_in, to_eye) < 0.0);
    var diffuse = vec3<f32>(0.0);
    var specular = vec3<f32>(0.0);
    for (var k = 0u; k < frame.light_count.x; k++) {
        let place = frame.lights[2u * k];
        let colour = frame.lights[2u * k + 1u];
        var l = place.xyz;
        var radiance = colour.rgb;
        if place.w > 0.5 {
            let d = place.xyz - centre;
            let d2 = dot(d, d);
            l = select(vec3<f32>(0.0), d * inverseSqrt(d2), d2 > 0.0);
            if colour.w > 0.5 {
                radiance /= max(d2, 1e-12);
            }
        }
        radiance *= select(shadow_b[k & 3u], shadow_a[k & 3u], k < 4u);
        let cos = dot(n, l);
        if cos > 0.0 {
            diffuse += radiance * cos;
            let reflected = 2.0 * cos * n - l;
            specular += radiance * pow(max(dot(reflected, to_eye), 0.0), frame.light.w);
        }
    }
    let lit = albedo * (frame.material.x + frame.material.y * diffuse) + frame.material.z * specular;
    return clamp(lit, vec3<f32>(0.0), vec3<f32>(1.0));
}
