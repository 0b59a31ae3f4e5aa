//! What a colour panel shows of a cloud's attributes: per column its range,
//! its 2nd and 98th percentiles and a histogram, and the classes present
//! with their point counts. Computed once per model, not per frame.

use super::percentile_range;
use crate::cloud::PointCloud;
use crate::cloud::attributes::names;

/// Bars of a column's histogram.
pub const BINS: usize = 48;

/// One column (an attribute, or the elevation) as a panel shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnSummary {
    pub name: String,
    pub min: f64,
    pub max: f64,
    /// The default colormap range (2nd and 98th percentiles).
    pub percentiles: (f64, f64),
    /// Counts of values in [`BINS`] equal steps from `min` to `max`.
    pub histogram: Vec<u32>,
}

/// The columns of a cloud and its classes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Summary {
    /// `elevation` first, then the attributes in the file's order.
    pub columns: Vec<ColumnSummary>,
    /// `(class, points)` when the cloud has a classification.
    pub classes: Vec<(u8, usize)>,
}

impl Summary {
    /// The column a scalar colouring of `style` reads (elevation or an
    /// attribute), if the colours show one.
    pub fn scalar_column(&self, style: &super::Style) -> Option<&ColumnSummary> {
        match style.color_by.as_ref()? {
            super::ColorBy::Elevation => self.column(super::ELEVATION),
            super::ColorBy::Attribute(name) => self.column(name),
            super::ColorBy::Rgb | super::ColorBy::Classification => None,
        }
    }

    /// The summary of `cloud` (empty when it has no attributes: nothing to colour by).
    pub fn of(cloud: &PointCloud) -> Summary {
        if cloud.attributes.is_empty() {
            return Summary::default();
        }
        let mut columns = vec![column(super::ELEVATION, &super::elevations(cloud))];
        for channel in &cloud.attributes.channels {
            let values: Vec<f64> = (0..channel.values.len()).map(|i| channel.values.get(i)).collect();
            columns.push(column(&channel.name, &values));
        }
        let classes = cloud.attributes.get(names::CLASSIFICATION).map(super::classes::counts).unwrap_or_default();
        Summary { columns, classes }
    }

    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&ColumnSummary> {
        self.columns.iter().find(|c| c.name == name)
    }
}

fn column(name: &str, values: &[f64]) -> ColumnSummary {
    let finite = values.iter().copied().filter(|v| v.is_finite());
    let (min, max) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let mut histogram = vec![0u32; BINS];
    if min.is_finite() {
        let span = (max - min).max(f64::MIN_POSITIVE);
        for v in values.iter().filter(|v| v.is_finite()) {
            histogram[(((v - min) / span * BINS as f64) as usize).min(BINS - 1)] += 1;
        }
    }
    ColumnSummary { name: name.to_string(), min, max, percentiles: percentile_range(values), histogram }
}
