// What the compositing passes read from K group images (2D array textures,
// layer k = group k), shared by deferred blending, Algorithm-1 and
// Algorithm-2 (Zhang & Pajarola 2007 §3, §5.2.1-5.2.2). Needs shading.wgsl
// (colour_sums) and frame.wgsl (this_pass).

// Fig. 6's ε-z test, first half: the group layer k that holds the nearest
// splat at `pixel`, d = min_k depth_k over the layers that hold one (-1
// where none does).
fn nearest_group(colour: texture_2d_array<f32>, depth: texture_2d_array<f32>, pixel: vec2<i32>) -> i32 {
    var nearest = 3.0e38;
    var group = -1;
    for (var k = 0; k < i32(this_pass.layers.y); k++) {
        if colour_sums(textureLoad(colour, pixel, k, 0)).a > 0.0 {
            let d = textureLoad(depth, pixel, k, 0).r;
            if d < nearest {
                nearest = d;
                group = k;
            }
        }
    }
    return group;
}

// Fig. 6's ε-z test, second half: whether a layer with colour sums `sums` at
// view depth `depth` belongs to the nearest surface layer, within d + ε.
fn in_nearest_layer(sums: vec4<f32>, depth: f32, nearest: f32) -> bool {
    return sums.a > 0.0 && depth <= nearest + this_pass.depth.x;
}

// The mean of the group images that cover `pixel` (premultiplied colour and
// coverage α > 0): a group that left the pixel empty is left out of the mean
// rather than counted as transparent black, which would darken the colour
// and thin the opacity by 1/K. Zero where no group covers the pixel.
//
// The opacity is a trimmed mean: with three or more covering groups, the
// most and the least opaque are left out. A group that blended one layer
// twice (its fragments straddled an Eq. 10 step) is the most opaque, one
// with a hole in a layer the least; the others agree. The colour is the
// α-weighted mean over every covering group (Σ rgb·α / Σ α), so the shading
// of all K groups' splats still averages.
fn mean_of_covering(images: texture_2d_array<f32>, pixel: vec2<i32>) -> vec4<f32> {
    var sum = vec4<f32>(0.0);
    var covering = 0.0;
    var least = 3.0e38;
    var most = -1.0;
    for (var k = 0; k < i32(this_pass.layers.y); k++) {
        let image = textureLoad(images, pixel, k, 0);
        if image.a > 0.0 {
            sum += image;
            covering += 1.0;
            least = min(least, image.a);
            most = max(most, image.a);
        }
    }
    if covering < 3.0 {
        return sum / max(covering, 1.0);
    }
    let alpha = (sum.a - least - most) / (covering - 2.0);
    return vec4<f32>(sum.rgb / sum.a * alpha, alpha);
}
