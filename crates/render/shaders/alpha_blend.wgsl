#include "group_layer.wgsl"

// Plain α-blending of splats, the baseline Zhang & Pajarola's groups exist to
// fix (§5.2): every splat, back to front, over what is there, with no
// fragment culling. Where the discs of one surface overlap (always, for a
// closed splat surface), that surface is blended two or three times, so it
// looks more opaque and blotchy than its opacity says. The image is then put
// over the background by alg1's average with K = 1.

@fragment
fn fs_alpha_blend(v: SplatVarying) -> @location(0) vec4<f32> {
    _ = splat_sample(v); // discards outside the disc
    return premultiplied_fragment(v);
}
