//! A style in text forms, as a screenshot's sidecar keeps it, so the image
//! can be rendered again with the same colours and opacities.

use serde::{Deserialize, Serialize};

use super::{ColorBy, Style};

/// The text form of each part of a [`Style`] (absent parts: the defaults).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct StyleRecord {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color_by: Option<String>,
    pub colormap: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<[f64; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub classes: Option<Vec<u8>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub class_opacity: Vec<(u8, f32)>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opacity_by: Option<String>,
    /// Each filter's text form, `NAME=MIN..MAX` or `NAME=V1,V2,...`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub filters: Vec<String>,
    /// `first`, `last`, `only` or a return number.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub returns: Option<String>,
    /// Selections drawn on screen, kept or hidden.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub regions: Vec<super::region::Region>,
}

impl From<&Style> for StyleRecord {
    fn from(style: &Style) -> Self {
        StyleRecord {
            color_by: style.color_by.as_ref().map(ColorBy::text),
            colormap: style.colormap.name().to_string(),
            range: style.range.map(|(lo, hi)| [lo, hi]),
            classes: style.classes.clone(),
            class_opacity: style.class_opacity.clone(),
            opacity_by: style.opacity_by.clone(),
            filters: style.filters.iter().map(super::Filter::text).collect(),
            returns: style.returns.map(super::Returns::text),
            regions: style.regions.clone(),
        }
    }
}

impl StyleRecord {
    /// The style this record describes; an error says which part is not one.
    pub fn style(&self) -> Result<Style, String> {
        let range = match self.range {
            Some([lo, hi]) => Some(super::parse::range(&format!("{lo},{hi}"))?),
            None => None,
        };
        // Through the parser every other source of a style uses: one check of each value.
        let class_opacity = match self.class_opacity.as_slice() {
            [] => Vec::new(),
            pairs => {
                let text: Vec<String> = pairs.iter().map(|(class, opacity)| format!("{class}:{opacity}")).collect();
                super::parse::class_opacity(&text.join(","))?
            }
        };
        Ok(Style {
            color_by: self.color_by.as_deref().map(str::parse).transpose()?,
            colormap: self.colormap.parse()?,
            range,
            classes: self.classes.clone(),
            class_opacity,
            opacity_by: self.opacity_by.clone(),
            filters: self.filters.iter().map(|f| f.parse()).collect::<Result<_, _>>()?,
            returns: self.returns.as_deref().map(str::parse).transpose()?,
            regions: self.regions.iter().map(|r| r.check().map(|()| r.clone())).collect::<Result<_, _>>()?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_style_reads_back_from_its_json_record() {
        let style = Style {
            color_by: Some(ColorBy::Attribute("gps_time".into())),
            colormap: super::super::Colormap::Turbo,
            range: Some((-1.5, 20.0)),
            classes: Some(vec![2, 6]),
            class_opacity: vec![(5, 0.25)],
            opacity_by: Some("intensity".into()),
            filters: vec!["gps_time=10.5..20".parse().unwrap(), "classification=2,6".parse().unwrap()],
            returns: Some(super::super::Returns::Last),
            regions: vec![super::super::region::Region {
                view_projection: glam::DMat4::IDENTITY.to_cols_array(),
                origin: [500_000.25, 4_100_000.5, 12.0],
                unit: 0.001,
                outline: vec![[-0.5, -0.5], [0.5, -0.25], [0.0, 0.75]],
                keep: false,
            }],
        };
        let json = serde_json::to_string(&StyleRecord::from(&style)).unwrap();
        let back: StyleRecord = serde_json::from_str(&json).unwrap();
        assert_eq!(back.style().unwrap(), style, "{json}");
        let bad = StyleRecord { colormap: "rainbow".into(), ..Default::default() };
        assert!(bad.style().unwrap_err().contains("rainbow"));
        // Checked by the parser every source of a style goes through, with its words.
        let bad = StyleRecord { class_opacity: vec![(5, 1.5)], ..StyleRecord::from(&style) };
        assert_eq!(bad.style().unwrap_err(), "'1.5' is not an opacity in 0..1");
        let bad = StyleRecord { filters: vec!["intensity=9..1".into()], ..StyleRecord::from(&style) };
        assert!(bad.style().unwrap_err().contains("MIN is above MAX"));
    }
}
