// What the transparent layers are composited over: the background, or, when
// the scene's opaque splats were drawn apart (OPAQUE_APART variant), their
// shaded image over the background, which the root shader binds as
// `opaque_image` (Zhang & Pajarola Fig. 18/19).

fn beneath(pixel: vec2<i32>) -> vec3<f32> {
#ifdef OPAQUE_APART
    return textureLoad(opaque_image, pixel, 0).rgb;
#else
    return frame.background.rgb;
#endif
}
