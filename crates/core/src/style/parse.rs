//! The text forms of a style's parts, as the command line and scene files
//! write them: `--color-by`, `--range MIN,MAX`, `--classes 2,6` and
//! `--class-opacity 5:0.3,6:1`.

use super::ColorBy;
use crate::cloud::attributes::names;

impl std::str::FromStr for ColorBy {
    type Err = String;

    /// `rgb`, `classification`, `elevation`, `intensity`, `return`, `gps-time`, or an attribute's name.
    fn from_str(text: &str) -> Result<Self, String> {
        let text = text.trim();
        Ok(match text.to_ascii_lowercase().as_str() {
            "" => return Err("the attribute to colour by is empty".into()),
            "rgb" | "colour" | "color" => ColorBy::Rgb,
            "classification" | "class" => ColorBy::Classification,
            "elevation" | "height" | "z" => ColorBy::Elevation,
            "intensity" => ColorBy::Attribute(names::INTENSITY.into()),
            "return" | "return-number" | "return_number" => ColorBy::Attribute(names::RETURN_NUMBER.into()),
            "gps-time" | "gps_time" | "time" => ColorBy::Attribute(names::GPS_TIME.into()),
            _ => ColorBy::Attribute(text.to_string()),
        })
    }
}

impl ColorBy {
    /// What colouring by the summary's column `name` is: the height for
    /// [`super::ELEVATION`], else that attribute.
    pub fn of_column(name: &str) -> ColorBy {
        if name == super::ELEVATION { ColorBy::Elevation } else { ColorBy::Attribute(name.to_string()) }
    }

    /// The text form (what [`str::parse`] reads back).
    pub fn text(&self) -> String {
        match self {
            ColorBy::Rgb => "rgb".into(),
            ColorBy::Classification => "classification".into(),
            ColorBy::Elevation => super::ELEVATION.into(),
            ColorBy::Attribute(name) if name == names::RETURN_NUMBER => "return".into(),
            ColorBy::Attribute(name) if name == names::GPS_TIME => "gps-time".into(),
            ColorBy::Attribute(name) => name.clone(),
        }
    }
}

/// `MIN,MAX` with MIN < MAX.
pub fn range(text: &str) -> Result<(f64, f64), String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let number =
        |v: &str| v.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| format!("'{v}' is not a number"));
    match parts[..] {
        [lo, hi] => {
            let (lo, hi) = (number(lo)?, number(hi)?);
            if lo < hi { Ok((lo, hi)) } else { Err(format!("'{text}': MIN must be below MAX")) }
        }
        _ => Err(format!("'{text}' is not MIN,MAX")),
    }
}

/// `2,6`: class numbers 0..255.
pub fn classes(text: &str) -> Result<Vec<u8>, String> {
    text.split(',')
        .map(str::trim)
        .map(|c| c.parse::<u8>().map_err(|_| format!("'{c}' is not a class number in 0..255")))
        .collect()
}

/// `5:0.3,6:1`: class:opacity pairs, opacity in 0..1.
pub fn class_opacity(text: &str) -> Result<Vec<(u8, f32)>, String> {
    text.split(',')
        .map(str::trim)
        .map(|pair| {
            let (class, opacity) =
                pair.split_once(':').ok_or_else(|| format!("'{pair}' is not CLASS:OPACITY, e.g. 5:0.3"))?;
            let class = class.trim().parse::<u8>().map_err(|_| format!("'{class}' is not a class number in 0..255"))?;
            let opacity = opacity
                .trim()
                .parse::<f32>()
                .ok()
                .filter(|a| (0.0..=1.0).contains(a))
                .ok_or_else(|| format!("'{opacity}' is not an opacity in 0..1"))?;
            Ok((class, opacity))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_text_forms_read_back_and_bad_ones_say_why() {
        for text in ["rgb", "classification", "elevation", "intensity", "return", "gps-time", "Amplitude"] {
            assert_eq!(text.parse::<ColorBy>().unwrap().text(), text);
        }
        assert_eq!(range("-2.5, 10").unwrap(), (-2.5, 10.0));
        assert!(range("3,1").unwrap_err().contains("below"));
        assert_eq!(classes("2,6").unwrap(), vec![2, 6]);
        assert!(classes("2,300").unwrap_err().contains("300"));
        assert_eq!(class_opacity("5:0.3,6:1").unwrap(), vec![(5, 0.3), (6, 1.0)]);
        assert!(class_opacity("5=0.3").unwrap_err().contains("CLASS:OPACITY"));
        assert!(class_opacity("5:2").unwrap_err().contains("0..1"));
    }
}
