//! Eye-dome lighting (Boucheny 2009, "Interactive scientific visualization
//! of large datasets", ch. 5), as Potree and CloudCompare implement it: a
//! screen-space shading of the nearest surface's depth alone, for clouds
//! without normals or with noisy ones.
//!
//! At each pixel with a surface, the log2 of its view depth is compared with
//! that of 8 neighbours on a circle of `radius_px` pixels (read at the pixel
//! the offset lands in): the response is the mean of max(0, log2 d − log2 dₙ)
//! over the neighbours that show a surface, and the colour is multiplied by
//! exp(−300 · strength · response). A pixel whose neighbours are nearer (the
//! lower side of a step, a crease) darkens; a flat plane facing the viewer,
//! or a pixel nearer than all around it, keeps its colour. Pixels with no
//! surface keep the background: Potree's black outline around the model is
//! not drawn (it reads as a halo over a coloured background).
//!
//! The GPU pass (shaders/eye_dome.wgsl) and the exact reference
//! (`crate::reference`) both shade with [`EyeDome::shade`]'s formula.

use glam::Vec2;

/// The neighbours each pixel is compared with.
pub const NEIGHBOURS: usize = 8;

/// The scale of the response in the exponent: Potree's 300.
pub const RESPONSE_SCALE: f32 = 300.0;

/// The largest strength and radius taken (`--edl`).
pub const MAX_STRENGTH: f32 = 100.0;
pub const MAX_RADIUS_PX: f32 = 16.0;

/// Eye-dome lighting's two parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeDome {
    /// The factor on the response in the exponent (Potree's "EDL strength").
    pub strength: f32,
    /// How far the neighbours are, in pixels (Potree's "EDL radius").
    pub radius_px: f32,
}

impl Default for EyeDome {
    /// Potree's defaults: strength 1.0, radius 1.4 px.
    fn default() -> Self {
        EyeDome { strength: 1.0, radius_px: 1.4 }
    }
}

impl EyeDome {
    /// Parses `off`, `on` (the defaults), `STRENGTH` or `STRENGTH,RADIUS`.
    pub fn parse(text: &str) -> Result<Option<EyeDome>, String> {
        match text.trim() {
            "off" => return Ok(None),
            "on" => return Ok(Some(EyeDome::default())),
            _ => {}
        }
        let mut parts = text.split(',').map(|p| p.trim().parse::<f32>().ok());
        let strength = parts.next().flatten().filter(|s| s.is_finite() && *s > 0.0 && *s <= MAX_STRENGTH);
        let strength = strength.ok_or_else(|| format!("the strength must be in (0, {MAX_STRENGTH}]"))?;
        let radius_px = match parts.next() {
            None => EyeDome::default().radius_px,
            Some(r) => r
                .filter(|r| r.is_finite() && *r >= 1.0 && *r <= MAX_RADIUS_PX)
                .ok_or_else(|| format!("the radius must be 1 to {MAX_RADIUS_PX} pixels"))?,
        };
        if parts.next().is_some() {
            return Err("at most two numbers".to_string());
        }
        Ok(Some(EyeDome { strength, radius_px }))
    }

    /// The text [`Self::parse`] reads back: `STRENGTH,RADIUS`.
    pub fn text(self) -> String {
        format!("{},{}", self.strength, self.radius_px)
    }

    /// The neighbours' offsets in pixels: 8 directions, 45° apart, from +x.
    pub fn offsets(self) -> [Vec2; NEIGHBOURS] {
        std::array::from_fn(|i| {
            let angle = i as f32 * std::f32::consts::TAU / NEIGHBOURS as f32;
            Vec2::new(angle.cos(), angle.sin()) * self.radius_px
        })
    }

    /// The factor on the colour of a pixel at view depth `depth` whose
    /// neighbours are at `neighbours` (`None`: no surface there).
    pub fn shade(self, depth: f32, neighbours: impl IntoIterator<Item = Option<f32>>) -> f32 {
        let log_depth = depth.log2();
        let response: f32 =
            neighbours.into_iter().flatten().map(|n| (log_depth - n.log2()).max(0.0)).sum::<f32>() / NEIGHBOURS as f32;
        (-response * RESPONSE_SCALE * self.strength).exp()
    }

    /// The factor of every pixel of a `width`×`height` image whose nearest
    /// surface is at view depth `front[y·width + x]` (infinite: none), row
    /// major; 1 where there is no surface.
    pub fn factors(self, front: &[f32], (width, height): (u32, u32)) -> Vec<f32> {
        let offsets = self.offsets();
        let at = |x: i64, y: i64| -> Option<f32> {
            let inside = (0..width as i64).contains(&x) && (0..height as i64).contains(&y);
            inside.then(|| front[y as usize * width as usize + x as usize]).filter(|d| d.is_finite())
        };
        (0..width as i64 * height as i64)
            .map(|i| {
                let (x, y) = (i % width as i64, i / width as i64);
                let Some(depth) = at(x, y) else { return 1.0 };
                // The pixel an offset lands in, from the pixel's centre.
                let neighbour = |o: Vec2| {
                    let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + o;
                    at(p.x.floor() as i64, p.y.floor() as i64)
                };
                self.shade(depth, offsets.iter().map(|&o| neighbour(o)))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_its_forms_and_refuses_the_rest() {
        assert_eq!(EyeDome::parse("off"), Ok(None));
        assert_eq!(EyeDome::parse("on"), Ok(Some(EyeDome::default())));
        assert_eq!(EyeDome::parse("2"), Ok(Some(EyeDome { strength: 2.0, radius_px: 1.4 })));
        let both = EyeDome::parse("0.5,3").unwrap().unwrap();
        assert_eq!(both, EyeDome { strength: 0.5, radius_px: 3.0 });
        assert_eq!(EyeDome::parse(&both.text()), Ok(Some(both)));
        for bad in ["", "0", "-1", "NaN", "x", "1,0.5", "1,2,3", "1,x", "1000"] {
            assert!(EyeDome::parse(bad).is_err(), "{bad:?}");
        }
    }

    /// A step: the left half at view depth `near`, the right half at `far`.
    fn step(near: f32, far: f32, width: u32, height: u32) -> Vec<f32> {
        (0..width * height).map(|i| if i % width < width / 2 { near } else { far }).collect()
    }

    #[test]
    fn a_step_darkens_its_lower_side_by_the_formula_and_leaves_the_rest() {
        let (width, height) = (16, 8);
        let (near, far) = (4.0f32, 4.1f32);
        for edl in [EyeDome::default(), EyeDome { strength: 0.3, radius_px: 1.4 }] {
            let factors = edl.factors(&step(near, far, width, height), (width, height));
            // At radius 1.4 the 8 neighbours are the 3×3 ring: the far pixel
            // next to the edge has 3 nearer ones, each log2(far/near) nearer
            // (2 in the first and last rows, whose third is outside the image).
            let want = |nearer: f32| (-(nearer * (far / near).log2() / 8.0) * RESPONSE_SCALE * edl.strength).exp();
            for y in 0..height {
                let row = &factors[(y * width) as usize..((y + 1) * width) as usize];
                let want = want(if y == 0 || y == height - 1 { 2.0 } else { 3.0 });
                let edge = row[width as usize / 2];
                assert!((edge - want).abs() < 1e-5, "row {y}: {edge} ≠ {want}");
                for (x, f) in row.iter().enumerate().filter(|(x, _)| *x != width as usize / 2) {
                    assert_eq!(*f, 1.0, "pixel ({x}, {y}) changed");
                }
            }
        }
    }

    #[test]
    fn a_flat_plane_and_the_background_are_unchanged() {
        let plane = vec![5.0; 64];
        assert!(EyeDome::default().factors(&plane, (8, 8)).iter().all(|f| *f == 1.0));
        let mut island = vec![f32::INFINITY; 64];
        island[27] = 5.0;
        assert!(EyeDome::default().factors(&island, (8, 8)).iter().all(|f| *f == 1.0));
    }

    #[test]
    fn a_larger_radius_reaches_further_from_the_edge() {
        let (width, height) = (16, 8);
        let wide = EyeDome { radius_px: 3.0, ..Default::default() };
        let factors = wide.factors(&step(4.0, 4.1, width, height), (width, height));
        let row = &factors[(4 * width) as usize..(5 * width) as usize];
        assert!(row[10] < 1.0 && row[11] == 1.0, "{row:?}");
    }
}
