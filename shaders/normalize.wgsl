// Pass 3 of the 2+1-pass pipeline (Botsch & Kobbelt 2003, Sec. 3.4): one
// full-screen triangle divides the accumulated sums by the weight and shades
// the normalised normal with Phong lighting (src/view/shading.rs has the same
// formula for the CPU). Pixels with no weight show the background.

@group(1) @binding(0) var accumulated_color: texture_2d<f32>;
@group(1) @binding(1) var accumulated_normal: texture_2d<f32>;

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

@fragment
fn fs_normalize(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let sums = textureLoad(accumulated_color, pixel, 0);
    if !(sums.a > 1e-6) {
        return vec4<f32>(frame.background.rgb, 1.0);
    }
    let albedo = sums.rgb / sums.a;
    // Eye-space direction of this pixel's view ray.
    let ndc = vec2<f32>(f.position.x * frame.viewport.z * 2.0 - 1.0, 1.0 - f.position.y * frame.viewport.w * 2.0);
    let to_eye = normalize(vec3<f32>(-ndc * frame.lens.xy, 1.0));
    let normal_sum = textureLoad(accumulated_normal, pixel, 0).xyz;
    let length_sq = dot(normal_sum, normal_sum);
    let normal = select(to_eye, normal_sum * inverseSqrt(length_sq), length_sq > 1e-20);
    return vec4<f32>(shade(albedo, normal, to_eye), 1.0);
}
