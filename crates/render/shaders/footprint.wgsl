// The bounded-foreshortening tilt of a splat's footprint plane (Botsch &
// Kobbelt §3.2, relative to the ray to the centre), shared by the splat
// passes (splat.wgsl) and the tile pipeline's projection
// (tiled_project.wgsl); crates/core/src/frame/kernel.rs has the same on the CPU.

// The normal of the plane a disc is rasterised in: `n` tilted towards the
// view ray `v` (unit, eye to centre) until |n·v| >= min_cos, keeping its side.
fn footprint_normal(n: vec3<f32>, v: vec3<f32>, min_cos: f32) -> vec3<f32> {
    let k = dot(n, v);
    if abs(k) >= min_cos {
        return n;
    }
    let side = select(1.0, -1.0, k < 0.0);
    let across = normalize(n - k * v);
    return across * sqrt(1.0 - min_cos * min_cos) + v * (side * min_cos);
}
