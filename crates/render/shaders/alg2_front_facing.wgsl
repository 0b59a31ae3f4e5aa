#include "shading.wgsl"

// The facing of a group image's nearest layer in Algorithm-2 (§5.2.2):
// whether its Σw·n at pixel `position` points away from the viewer (pass 1
// stores the splats' normals unturned). Shared by the pass that finds the
// nearest layer (shaders/alg2_front.wgsl) and the composite.
fn faces_away(position: vec2<f32>, normal_sum: vec3<f32>) -> bool {
    let ndc = vec2<f32>(position.x * frame.viewport.z * 2.0 - 1.0, 1.0 - position.y * frame.viewport.w * 2.0);
    return dot(normal_sum, vec3<f32>(ndc * frame.lens.xy, -1.0)) > 0.0;
}
