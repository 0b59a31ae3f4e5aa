#include "splat.wgsl"

// Pass 1 of the 2+1-pass pipeline: depth only, pushed back by epsilon
// (Botsch & Kobbelt 2003, Sec. 3.3), so that pass 2 blends every splat
// within epsilon of the front surface.

@fragment
fn fs_visibility(v: SplatVarying) -> @builtin(frag_depth) f32 {
    let s = splat_sample(v);
    return min(depth_to_buffer(s.front_depth + this_pass.depth.x), 1.0);
}
