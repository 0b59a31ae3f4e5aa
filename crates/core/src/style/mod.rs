//! Colour and opacity by attribute: what a lidar user colours a scan by
//! (classification, intensity, elevation, returns, GPS time or any named
//! attribute), through a perceptual colormap over a range (by default the
//! 2nd to 98th percentile), classes shown or hidden, and opacity per class or
//! from an attribute.
//!
//! A [`Style`] rewrites a cloud's colours and opacities (and drops the
//! splats of hidden classes) before the scene is flattened, so every mode,
//! bench and the exact reference see the same splats: ε still compares like
//! with like. Opacity set here feeds the transparent modes as a file's own
//! alpha does (Zhang & Pajarola §4: each surface is blended once, whatever
//! its splats' overlap), so ground and buildings show through translucent
//! vegetation.

pub mod classes;
pub mod colormap;
pub mod filter;
pub mod parse;
pub mod record;
pub mod region;
pub mod summary;

pub use colormap::Colormap;
pub use filter::{Filter, Returns};

use crate::cloud::attributes::{Attributes, names};
use crate::cloud::{PointCloud, Values};

/// The name of the pseudo-attribute every summary lists first: each
/// point's height in the file's units (its z, as `--color-by elevation` colours it).
pub const ELEVATION: &str = "elevation";

/// Each point's height in the file's units: its z, off the cloud's origin and unit.
pub fn elevations(cloud: &PointCloud) -> Vec<f64> {
    let (z0, unit) = (cloud.origin[2], cloud.unit());
    cloud.positions.iter().map(|p| p.z as f64 * unit + z0).collect()
}

/// What the colours show.
#[derive(Debug, Clone, PartialEq)]
pub enum ColorBy {
    /// The file's own colours.
    Rgb,
    /// ASPRS class colours.
    Classification,
    /// The height (file z) through the colormap.
    Elevation,
    /// A named attribute through the colormap.
    Attribute(String),
}

/// How a cloud's splats are coloured, shown and made translucent by their attributes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Style {
    pub color_by: Option<ColorBy>,
    pub colormap: Colormap,
    /// The values mapped to the colormap's ends; `None`: the 2nd and 98th percentiles.
    pub range: Option<(f64, f64)>,
    /// Only these classes are shown; `None`: all.
    pub classes: Option<Vec<u8>>,
    /// Opacity per class (others keep theirs).
    pub class_opacity: Vec<(u8, f32)>,
    /// An attribute whose value over its 2-98 percentile range is the opacity.
    pub opacity_by: Option<String>,
    /// Only the points every filter keeps are shown ([`filter`]).
    pub filters: Vec<Filter>,
    /// Only these returns are shown.
    pub returns: Option<Returns>,
    /// Selections drawn on screen, each kept or hidden ([`region`]).
    pub regions: Vec<region::Region>,
}

/// What applying a style did, for the legend and the log.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Applied {
    /// The range the colormap spans, when a scalar is shown.
    pub range: Option<(f64, f64)>,
    /// Splats hidden with their class, or by a filter.
    pub hidden: usize,
    /// Whether some splat is now translucent.
    pub translucent: bool,
    /// Splats whose `--opacity-by` value is not a number (NaN): drawn fully transparent.
    pub opacity_unset: usize,
}

impl Style {
    /// The colours survey data without colours opens in, as QGIS opens a
    /// point cloud: RGB when the file has colours (no style), else its
    /// classes when it holds more than one, else its elevation. Other files
    /// (not z-up) keep their own or the default colour.
    pub fn default_for(cloud: &PointCloud) -> Option<Style> {
        if !(cloud.colourless && cloud.z_up) || cloud.is_empty() {
            return None;
        }
        let classes = cloud.attributes.get(names::CLASSIFICATION).map_or(0, |c| {
            let mut seen = [false; 256];
            (0..c.len()).for_each(|i| seen[c.get(i) as usize & 255] = true);
            seen.iter().filter(|s| **s).count()
        });
        let color_by = if classes > 1 { ColorBy::Classification } else { ColorBy::Elevation };
        Some(Style { color_by: Some(color_by), ..Default::default() })
    }

    /// True when the style changes nothing.
    pub fn is_plain(&self) -> bool {
        matches!(self.color_by, None | Some(ColorBy::Rgb))
            && self.classes.is_none()
            && self.class_opacity.is_empty()
            && self.opacity_by.is_none()
            && self.filters.is_empty()
            && self.returns.is_none()
            && self.regions.is_empty()
    }

    /// A text that identifies the style (for cache keys).
    pub fn key(&self) -> String {
        format!("{self:?}")
    }

    /// `cloud` as this style shows it; an error names what the cloud lacks.
    pub fn apply(&self, cloud: &PointCloud) -> Result<(PointCloud, Applied), String> {
        let mut applied = Applied::default();
        let hides = self.classes.is_some() || !self.filters.is_empty() || self.returns.is_some();
        let mut out = if hides || !self.regions.is_empty() {
            let keep = filter::kept(cloud, self.classes.as_deref(), &self.filters, self.returns)?;
            let keep = region::shown_by(&self.regions, keep, |i| cloud.file_position(i));
            applied.hidden = cloud.len() - keep.len();
            PointCloud {
                attributes: cloud.attributes.gather(&keep),
                scanner_position: cloud.scanner_position,
                ..cloud.select(&keep)
            }
        } else {
            cloud.clone()
        };
        // No colours asked for, on survey data without colours: the colours it opens in (its
        // classes or its elevation), as with no style at all, so a filter alone keeps them.
        let color_by = match &self.color_by {
            None => Style::default_for(cloud).and_then(|s| s.color_by),
            given => given.clone(),
        };
        match &color_by {
            None | Some(ColorBy::Rgb) => {}
            Some(ColorBy::Classification) => {
                let class = column(&out, names::CLASSIFICATION, "classification colours")?;
                out.colours = (0..out.len()).map(|i| classes::colour(class.get(i) as u8)).collect();
            }
            Some(by) => {
                let values: Vec<f64> = match by {
                    ColorBy::Elevation => elevations(&out),
                    ColorBy::Attribute(name) => {
                        let c = column(&out, name, "--color-by")?;
                        (0..out.len()).map(|i| c.get(i)).collect()
                    }
                    _ => unreachable!("handled above"),
                };
                let (lo, hi) = self.range.unwrap_or_else(|| percentile_range(&values));
                applied.range = Some((lo, hi));
                let span = if hi > lo { hi - lo } else { 1.0 };
                out.colours = values.iter().map(|&v| self.colormap.colour((v - lo) / span)).collect();
            }
        }
        if !self.class_opacity.is_empty() {
            let class = column(&out, names::CLASSIFICATION, "--class-opacity")?;
            let mut table = [1.0f32; 256];
            for &(c, a) in &self.class_opacity {
                table[c as usize] = a;
            }
            let factors: Vec<f32> = (0..out.len()).map(|i| table[class.get(i) as usize & 255]).collect();
            out.opacity.iter_mut().zip(factors).for_each(|(a, f)| *a *= f);
        }
        if let Some(name) = &self.opacity_by {
            let c = column(&out, name, "--opacity-by")?;
            let values: Vec<f64> = (0..out.len()).map(|i| c.get(i)).collect();
            if !values.iter().any(|v| v.is_finite()) && !values.is_empty() {
                return Err(format!(
                    "--opacity-by {name}: the attribute has no value that is a number (every one is NaN or infinite), so every splat would vanish"
                ));
            }
            let (lo, hi) = percentile_range(&values);
            let span = if hi > lo { hi - lo } else { 1.0 };
            for (a, v) in out.opacity.iter_mut().zip(&values) {
                if v.is_nan() {
                    applied.opacity_unset += 1;
                    *a = 0.0;
                } else {
                    *a *= ((v - lo) / span).clamp(0.0, 1.0) as f32;
                }
            }
        }
        applied.translucent = out.has_transparency();
        Ok((out, applied))
    }
}

/// The column `name` of `cloud`, or an error that lists the columns it has.
fn column<'a>(cloud: &'a PointCloud, name: &str, wanted_by: &str) -> Result<&'a Values, String> {
    column_of(&cloud.attributes, name, wanted_by)
}

/// [`column`] of a set of attributes.
fn column_of<'a>(attributes: &'a Attributes, name: &str, wanted_by: &str) -> Result<&'a Values, String> {
    attributes.get(name).ok_or_else(|| {
        let have: Vec<&str> = attributes.names().collect();
        let have = if have.is_empty() { "none".to_string() } else { have.join(", ") };
        format!("{wanted_by} needs the '{name}' attribute, which the file lacks (its attributes: {have})")
    })
}

/// The 2nd and 98th percentiles of the finite `values` ((0, 1) when there are none).
pub fn percentile_range(values: &[f64]) -> (f64, f64) {
    let mut finite: Vec<f64> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return (0.0, 1.0);
    }
    let at = |q: f64, v: &mut Vec<f64>| {
        let k = ((v.len() - 1) as f64 * q).round() as usize;
        *v.select_nth_unstable_by(k, f64::total_cmp).1
    };
    let lo = at(0.02, &mut finite);
    let hi = at(0.98, &mut finite);
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(n: usize) -> PointCloud {
        let mut cloud = PointCloud {
            positions: (0..n).map(|i| glam::Vec3::new(i as f32, 0.0, 0.0)).collect(),
            normals: vec![glam::Vec3::Z; n],
            radii: vec![0.5; n],
            colours: vec![[10, 20, 30]; n],
            opacity: vec![1.0; n],
            ..Default::default()
        };
        cloud.attributes.push("intensity", Values::U16((0..n as u16).collect()));
        cloud.attributes.push(names::CLASSIFICATION, Values::U8((0..n).map(|i| [2, 5][i % 2]).collect()));
        cloud
    }

    #[test]
    fn a_filter_alone_keeps_the_colours_survey_data_opens_in() {
        let survey = PointCloud { colourless: true, z_up: true, ..cloud(6) };
        let filter = Style { filters: vec!["intensity=1..4".parse().unwrap()], ..Default::default() };
        let (filtered, _) = filter.apply(&survey).unwrap();
        let want: Vec<[u8; 3]> = [5, 2, 5, 2].iter().map(|&c| classes::colour(c)).collect();
        assert_eq!(filtered.colours, want, "classes, as with no style");
        let rgb = Style { color_by: Some(ColorBy::Rgb), ..filter.clone() };
        assert_eq!(rgb.apply(&survey).unwrap().0.colours, vec![[10, 20, 30]; 4], "rgb asked for: the file's own");
        let coloured = PointCloud { colourless: false, ..survey };
        assert_eq!(filter.apply(&coloured).unwrap().0.colours, vec![[10, 20, 30]; 4], "a file with colours keeps them");
    }

    #[test]
    fn opacity_by_an_attribute_of_no_numbers_is_refused_and_a_few_nans_are_counted() {
        let mut all_nan = cloud(10);
        all_nan.attributes.push("height", Values::F32(vec![f32::NAN; 10]));
        let style = Style { opacity_by: Some("height".into()), ..Default::default() };
        let error = style.apply(&all_nan).unwrap_err();
        assert!(error.contains("--opacity-by height") && error.contains("NaN"), "{error}");
        let mut some_nan = cloud(10);
        some_nan
            .attributes
            .push("height", Values::F32((0..10).map(|i| if i < 3 { f32::NAN } else { i as f32 }).collect()));
        let (out, applied) = style.apply(&some_nan).unwrap();
        assert_eq!(applied.opacity_unset, 3);
        assert!(out.opacity.iter().all(|a| a.is_finite()), "no NaN opacity reaches the renderers");
        assert_eq!(&out.opacity[..3], &[0.0; 3]);
    }

    #[test]
    fn opacity_by_an_attribute_runs_from_0_to_1_over_its_percentiles_and_classes_multiply_it() {
        let style = Style { opacity_by: Some("intensity".into()), class_opacity: vec![(5, 0.5)], ..Default::default() };
        let (out, applied) = style.apply(&cloud(101)).unwrap();
        assert!(applied.translucent);
        assert_eq!(out.opacity[0], 0.0, "below the 2nd percentile");
        assert_eq!(out.opacity[100], 1.0, "above the 98th percentile (class 2)");
        assert!((out.opacity[50] - 0.5).abs() < 1e-6, "the median, class 2: {}", out.opacity[50]);
        // Percentiles 2 and 98: value 51 (class 5) is (51 - 2) / 96 of the way, times its class's 0.5.
        assert!((out.opacity[51] - 0.5 * 49.0 / 96.0).abs() < 1e-6, "{}", out.opacity[51]);
        assert_eq!(out.colours[0], [10, 20, 30], "opacity alone keeps the colours");
    }

    #[test]
    fn hidden_classes_take_their_attributes_with_them() {
        let style = Style { classes: Some(vec![5]), ..Default::default() };
        let (out, applied) = style.apply(&cloud(10)).unwrap();
        assert_eq!((out.len(), applied.hidden), (5, 5));
        assert!(out.is_consistent());
        assert_eq!(out.attributes.get("intensity"), Some(&Values::U16(vec![1, 3, 5, 7, 9])));
    }

    #[test]
    fn every_summary_column_is_the_scalar_column_of_colouring_by_it() {
        let mut cloud = cloud(10);
        cloud.positions.iter_mut().enumerate().for_each(|(i, p)| p.z = i as f32);
        let summary = summary::Summary::of(&cloud);
        assert_eq!(summary.columns[0].name, ELEVATION, "the height comes first");
        for column in &summary.columns {
            let style = Style { color_by: Some(ColorBy::of_column(&column.name)), ..Default::default() };
            assert_eq!(summary.scalar_column(&style).map(|c| &c.name), Some(&column.name));
            let (_, applied) = style.apply(&cloud).unwrap();
            assert_eq!(
                applied.range,
                Some(column.percentiles),
                "{}: the colours span the summary's range",
                column.name
            );
        }
    }
}
