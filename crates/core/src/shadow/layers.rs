//! What one surface layer does to light: Gunjee et al. §4.1's absorbance
//! (Eq. 6, Eq. 9: A = α·l·c, transmittance 10^−A, A ≥ 2 full shadow), with
//! the two choices the paper leaves open made here, and the ε-layering that
//! keeps one surface from being counted once per overlapping splat.
//!
//! **Scale.** The paper takes l as the point's size, which makes a
//! millimetre-scale scan cast no shadow at all. Here a layer of opacity a
//! (Eq. 1's weighted mean of its splats' opacities) has concentration c = a
//! and, when translucent (α = 1), the optical length l = −log10(1 − a)/a, so
//! that A = −log10(1 − a) and the layer passes 1 − a of the light: exactly
//! the share of the background the camera sees through it. A scene looks the
//! same to the eye and to the light. An opaque layer (a = 1, α = 100) takes
//! l = 0.02, so A = 2: full shadow. A translucent layer with a ≥ 0.99 reaches
//! A ≥ 2 too and is full shadow, as the paper's threshold says.
//!
//! **Double counting.** Summing every point along a direction counts one
//! surface as many times as its splats overlap (Zhang & Pajarola's double
//! blending, seen from the light). Entries along a direction are merged into
//! ε-layers exactly as the reference merges a pixel's hits: the nearest
//! entry not yet taken opens a layer, which takes every entry within ε of it
//! that faces the same way (towards the light or away from it); each layer
//! counts once, with its Gaussian-weighted mean opacity.

/// The absorption coefficient α of translucent points (Gunjee §4.1).
pub const TRANSLUCENT_ABSORPTION: f32 = 1.0;
/// The absorption coefficient α of opaque points (Gunjee §4.1).
pub const OPAQUE_ABSORPTION: f32 = 100.0;
/// The optical length l of an opaque layer: α·l·1 = 2, full shadow.
pub const OPAQUE_LENGTH: f32 = 0.02;
/// Absorbance at and above which no light passes (Gunjee: "A > 2 is full shadow").
pub const FULL_SHADOW: f32 = 2.0;

/// The absorbance A = α·l·c of one layer of weighted mean opacity `a`.
pub fn absorbance(a: f32) -> f32 {
    if a.is_nan() || a <= 0.0 {
        return 0.0;
    }
    if a >= 1.0 {
        return OPAQUE_ABSORPTION * OPAQUE_LENGTH * 1.0;
    }
    let length = -(1.0 - a).log10() / a;
    TRANSLUCENT_ABSORPTION * length * a
}

/// The share of light that passes a total absorbance `a` (0 from [`FULL_SHADOW`] on).
pub fn transmittance(a: f32) -> f32 {
    if a >= FULL_SHADOW { 0.0 } else { 10f32.powf(-a) }
}

/// One splat met along a direction from the light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entry {
    /// Distance from the light along the direction.
    pub distance: f32,
    /// Eq. 3's Gaussian weight where the direction meets the disc (0 for a
    /// probe that only asks for its light).
    pub weight: f32,
    pub opacity: f32,
    /// Whether the splat's normal points towards the light.
    pub facing: bool,
}

/// Walks `entries`, sorted by distance from the light, layer by layer
/// (module doc), and calls `visit(index, absorbance)` for every entry with
/// the absorbance of the layers in front of its own layer. Entries of no
/// weight are probes (a splat whose light is read where its disc does not
/// reach, or a point asking for its light): they open no layer and join the
/// first layer of their facing whose ε-window holds them, else they see
/// every layer that opened in front of them.
pub fn sweep(entries: &[Entry], epsilon: f32, scratch: &mut Scratch, mut visit: impl FnMut(usize, f32)) {
    let Scratch { used, layers } = scratch;
    used.clear();
    used.resize(entries.len(), false);
    layers.clear();
    let mut total = 0.0f32;
    let mut start = 0;
    let is_probe = |e: &Entry| e.weight.is_nan() || e.weight <= 0.0;
    while start < entries.len() {
        if used[start] || is_probe(&entries[start]) {
            start += 1;
            continue;
        }
        let (front, facing) = (entries[start].distance, entries[start].facing);
        let (mut sum_w, mut sum_a) = (0.0f32, 0.0f32);
        for (k, e) in entries.iter().enumerate().skip(start).take_while(|(_, e)| e.distance <= front + epsilon) {
            if used[k] || e.facing != facing || is_probe(e) {
                continue;
            }
            used[k] = true;
            sum_w += e.weight;
            sum_a += e.weight * e.opacity;
            visit(k, total);
        }
        layers.push((front, facing, total));
        total += absorbance((sum_a / sum_w).clamp(0.0, 1.0));
        start += 1;
    }
    for (k, e) in entries.iter().enumerate().filter(|(_, e)| is_probe(e)) {
        let joined = layers
            .iter()
            .find(|(front, facing, _)| *facing == e.facing && e.distance >= *front && e.distance <= *front + epsilon);
        let before = match joined {
            Some(&(_, _, before)) => before,
            // Every layer that opened in front of it.
            None => match layers.iter().position(|(front, _, _)| *front > e.distance) {
                Some(next) => layers[next].2,
                None => total,
            },
        };
        visit(k, before);
    }
}

/// Memory [`sweep`] reuses from one direction to the next.
#[derive(Debug, Default)]
pub struct Scratch {
    used: Vec<bool>,
    /// The layers opened: (front, facing, absorbance in front of it).
    layers: Vec<(f32, bool, f32)>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_layer_passes_what_the_camera_sees_through_it() {
        for a in [0.1f32, 0.5, 0.9] {
            assert!((transmittance(absorbance(a)) - (1.0 - a)).abs() < 1e-5, "a = {a}");
        }
        assert_eq!(transmittance(absorbance(1.0)), 0.0, "opaque is full shadow");
        assert_eq!(transmittance(absorbance(0.0)), 1.0);
    }

    #[test]
    fn overlapping_splats_of_one_layer_count_once_and_facing_splits() {
        let entry = |distance, facing| Entry { distance, weight: 1.0, opacity: 0.5, facing };
        // 10 overlapping splats of one layer, then a second layer, then a probe.
        let mut entries: Vec<Entry> = (0..10).map(|i| entry(1.0 + i as f32 * 0.01, true)).collect();
        entries.push(entry(2.0, true));
        entries.push(Entry { weight: 0.0, ..entry(3.0, true) });
        let mut seen = vec![0.0; entries.len()];
        sweep(&entries, 0.2, &mut Scratch::default(), |k, a| seen[k] = a);
        assert!(seen[..10].iter().all(|&a| a == 0.0));
        assert!((transmittance(seen[11]) - 0.25).abs() < 1e-5, "{}", transmittance(seen[11]));
        // The two sides of a thin shell are two layers.
        let shell = [entry(1.0, true), entry(1.05, false), Entry { weight: 0.0, ..entry(3.0, true) }];
        let mut last = 0.0;
        sweep(&shell, 0.2, &mut Scratch::default(), |k, a| {
            if k == 2 {
                last = a
            }
        });
        assert!((transmittance(last) - 0.25).abs() < 1e-5);
    }
}
