//! Image error against a reference: ε, PSNR, bad-pixel share, ε split by the
//! reference's layer count per pixel, and a difference image.
//!
//! ε is the metric of Zhang & Pajarola 2007 §6.3: the mean over all pixels of
//! |ΔR| + |ΔG| + |ΔB| in 0..255 units (so 0..765). The bad-pixel share counts
//! pixels whose largest channel difference exceeds 8/255, which shows seams and
//! holes even when the mean is small.

use image::RgbaImage;

/// Largest channel difference (in 0..255) that does not make a pixel "bad".
pub const BAD_PIXEL_THRESHOLD: u8 = 8;

/// How far an image is from its reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageError {
    /// Mean of |ΔR|+|ΔG|+|ΔB| per pixel, 0..255 units.
    pub eps: f64,
    /// Peak signal-to-noise ratio over RGB in dB (infinite for identical images).
    pub psnr: f64,
    /// Share of pixels whose largest channel difference exceeds [`BAD_PIXEL_THRESHOLD`].
    pub bad_pixel_share: f64,
}

/// Compares `image` with `reference`; `None` if their sizes differ.
pub fn compare(image: &RgbaImage, reference: &RgbaImage) -> Option<ImageError> {
    if image.dimensions() != reference.dimensions() {
        return None;
    }
    let pixels = (image.width() as u64 * image.height() as u64).max(1) as f64;
    let (mut abs_sum, mut sq_sum, mut bad) = (0u64, 0u64, 0u64);
    for (a, b) in image.pixels().zip(reference.pixels()) {
        let mut worst = 0u8;
        for c in 0..3 {
            let d = a.0[c].abs_diff(b.0[c]);
            abs_sum += d as u64;
            sq_sum += d as u64 * d as u64;
            worst = worst.max(d);
        }
        bad += (worst > BAD_PIXEL_THRESHOLD) as u64;
    }
    let mse = sq_sum as f64 / (3.0 * pixels);
    Some(ImageError {
        eps: abs_sum as f64 / pixels,
        psnr: if mse > 0.0 { 10.0 * (255.0f64 * 255.0 / mse).log10() } else { f64::INFINITY },
        bad_pixel_share: bad as f64 / pixels,
    })
}

/// The most layers [`error_by_layers`] counts apart; rays that met more share its last bucket.
pub const MOST_LAYERS_APART: u32 = 4;

/// The part of ε carried by the pixels whose ray met `layers` ε-layers in
/// the reference (the last bucket: [`MOST_LAYERS_APART`] or more).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LayerError {
    pub layers: u32,
    /// Share of all pixels.
    pub pixel_share: f64,
    /// These pixels' part of ε: the parts of all buckets add up to ε.
    pub eps: f64,
    /// Mean |ΔR|+|ΔG|+|ΔB| over these pixels alone.
    pub mean: f64,
}

/// ε split by the number of layers each pixel's reference ray met
/// (`layers`, row-major, as [`super::render_with_layers`] gives them):
/// which pixels carry the error, the background (0), one surface, or
/// several seen through one another. `None` if the sizes differ.
pub fn error_by_layers(image: &RgbaImage, reference: &RgbaImage, layers: &[u32]) -> Option<Vec<LayerError>> {
    let pixels = image.width() as usize * image.height() as usize;
    if image.dimensions() != reference.dimensions() || layers.len() != pixels {
        return None;
    }
    let buckets = MOST_LAYERS_APART as usize + 1;
    let (mut count, mut sum) = (vec![0u64; buckets], vec![0u64; buckets]);
    for ((a, b), &l) in image.pixels().zip(reference.pixels()).zip(layers) {
        let bucket = (l as usize).min(buckets - 1);
        count[bucket] += 1;
        sum[bucket] += (0..3).map(|c| a.0[c].abs_diff(b.0[c]) as u64).sum::<u64>();
    }
    let total = pixels.max(1) as f64;
    Some(
        (0..buckets)
            .filter(|&b| count[b] > 0)
            .map(|b| LayerError {
                layers: b as u32,
                pixel_share: count[b] as f64 / total,
                eps: sum[b] as f64 / total,
                mean: sum[b] as f64 / count[b] as f64,
            })
            .collect(),
    )
}

/// A false-colour difference image: the mean channel difference, amplified
/// `gain` times, mapped black -> blue -> red -> yellow -> white.
pub fn difference_image(image: &RgbaImage, reference: &RgbaImage, gain: f32) -> Option<RgbaImage> {
    if image.dimensions() != reference.dimensions() {
        return None;
    }
    const STOPS: [[f32; 3]; 5] =
        [[0.0, 0.0, 0.0], [0.1, 0.1, 0.8], [0.85, 0.1, 0.1], [1.0, 0.85, 0.1], [1.0, 1.0, 1.0]];
    let mut out = RgbaImage::new(image.width(), image.height());
    for ((a, b), o) in image.pixels().zip(reference.pixels()).zip(out.pixels_mut()) {
        let d: f32 = (0..3).map(|c| a.0[c].abs_diff(b.0[c]) as f32).sum::<f32>() / 3.0;
        let t = (d * gain / 255.0).clamp(0.0, 1.0) * (STOPS.len() - 1) as f32;
        let i = (t.floor() as usize).min(STOPS.len() - 2);
        let f = t - i as f32;
        let rgb = [0, 1, 2].map(|c| ((STOPS[i][c] * (1.0 - f) + STOPS[i + 1][c] * f) * 255.0).round() as u8);
        *o = image::Rgba([rgb[0], rgb[1], rgb[2], 255]);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_no_error() {
        let a = RgbaImage::from_pixel(4, 3, image::Rgba([10, 20, 30, 255]));
        let e = compare(&a, &a).unwrap();
        assert_eq!(e.eps, 0.0);
        assert!(e.psnr.is_infinite());
        assert_eq!(e.bad_pixel_share, 0.0);
    }

    #[test]
    fn the_error_by_layer_count_adds_up_to_eps_and_says_where_it_is() {
        let reference = RgbaImage::from_pixel(3, 2, image::Rgba([10, 20, 30, 255]));
        let mut image = reference.clone();
        image.put_pixel(1, 0, image::Rgba([16, 20, 30, 255])); // 6, on a 2-layer pixel
        image.put_pixel(2, 1, image::Rgba([10, 20, 42, 255])); // 12, on a 7-layer pixel
        let layers = [0, 2, 1, 1, 2, 7];
        let split = error_by_layers(&image, &reference, &layers).unwrap();
        let eps = compare(&image, &reference).unwrap().eps;
        assert!((split.iter().map(|b| b.eps).sum::<f64>() - eps).abs() < 1e-12);
        assert!((split.iter().map(|b| b.pixel_share).sum::<f64>() - 1.0).abs() < 1e-12);
        let of = |l: u32| *split.iter().find(|b| b.layers == l).unwrap();
        assert_eq!(of(2).mean, 3.0, "one of its two pixels is off by 6");
        assert_eq!(of(MOST_LAYERS_APART).mean, 12.0, "7 layers count as the last bucket");
        assert_eq!(of(1).eps, 0.0);
        assert!(split.iter().all(|b| b.layers != 3), "no pixel met 3 layers");
        assert!(error_by_layers(&image, &reference, &layers[1..]).is_none(), "a count per pixel");
    }

    #[test]
    fn eps_sums_the_channels_and_averages_the_pixels() {
        let a = RgbaImage::from_pixel(2, 1, image::Rgba([10, 20, 30, 255]));
        let mut b = a.clone();
        b.put_pixel(0, 0, image::Rgba([13, 16, 30, 255])); // |3| + |4| + 0 = 7
        let e = compare(&a, &b).unwrap();
        assert_eq!(e.eps, 3.5);
        assert_eq!(e.bad_pixel_share, 0.0);
        b.put_pixel(1, 0, image::Rgba([10, 20, 39, 255])); // 9 > 8: bad
        let e = compare(&a, &b).unwrap();
        assert_eq!(e.bad_pixel_share, 0.5);
        let mse = (9.0 + 16.0 + 81.0) / 6.0;
        assert!((e.psnr - 10.0 * (255.0f64 * 255.0 / mse).log10()).abs() < 1e-9);
    }
}
