#include "shading.wgsl"
#ifdef ENVIRONMENT
#include "environment.wgsl"
#endif

// `tiled`, pass 5: the frame from the raster's image. With an environment
// map (ENVIRONMENT, Zhang & Pajarola §5.2.3-5.2.4) a pixel whose nearest
// layer is transparent is recomposed as the reference recomposes it
// (crates/core/src/reference/environment.rs, the formulas of
// crates/core/src/frame/environment.rs): I = F·E_R + (1 - F)·(α·C_F + (1 -
// α)·(C_b + a·E_T)), with the exact layer count behind the glass from the
// raster; a pixel where nothing is drawn shows the map (a skybox). The mip
// level of each lookup comes from how fast its direction turns across the
// 2x2 pixel quad (fine derivatives), as the reference takes it.

@group(1) @binding(0) var tiled_colour: texture_2d<f32>;
#ifdef ENVIRONMENT
@group(1) @binding(1) var glass_front: texture_2d<f32>;
@group(1) @binding(2) var glass_normal: texture_2d<f32>;
@group(1) @binding(3) var glass_behind: texture_2d<f32>;
#endif

@fragment
fn fs_tiled_present(f: Fullscreen) -> @location(0) vec4<f32> {
    let pixel = vec2<i32>(f.position.xy);
    let image = textureLoad(tiled_colour, pixel, 0);
#ifdef ENVIRONMENT
    return glass(f.position.xy, pixel, image);
#else
    return vec4<f32>(image.rgb, 1.0);
#endif
}

#ifdef ENVIRONMENT
// Every lookup direction and its level is found before any branch:
// derivatives need uniform control flow.
fn glass(position: vec2<f32>, pixel: vec2<i32>, image: vec4<f32>) -> vec4<f32> {
    let front = textureLoad(glass_front, pixel, 0);
    let normal_behind = textureLoad(glass_normal, pixel, 0);
    let behind = textureLoad(glass_behind, pixel, 0);
    let d = normalize(pixel_ray(position));
    let has_glass = dot(normal_behind.xyz, normal_behind.xyz) > 0.5;
    let n = select(-d, normal_behind.xyz, has_glass);
    let multi = frame.environment.z > 0.5;
    let crossings = select(1.0, 1.0 + normal_behind.w, multi);
    let rays = environment_glass_rays(d, n, crossings);
    let sky = environment_world(d);
    // As the reference: a neighbour of the quad counts only when it looks
    // along the same kind of direction (glass next to glass).
    let glass_flag = select(0.0, 1.0, has_glass);
    let levels = environment_glass_levels(rays, vec2<bool>(dpdxFine(glass_flag) == 0.0, dpdyFine(glass_flag) == 0.0));
    let sky_level = environment_level(sky);
    if !has_glass {
        let skybox = image.a < 0.5 && frame.environment.w > 0.5;
        return vec4<f32>(select(image.rgb, environment_sample(sky, sky_level), skybox), 1.0);
    }
    let alpha = clamp(front.a, 0.0, 1.0);
    let closed = behind.w < 0.0;
    let reaching = select(select(behind.w, environment_absorption(alpha, normal_behind.w), multi), 0.0, closed);
    let out = environment_glass_pixel(d, n, rays, levels, alpha, front.rgb, behind.rgb, reaching, vec4<f32>(0.0));
    return vec4<f32>(out, 1.0);
}
#endif
