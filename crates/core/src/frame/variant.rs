//! Mode variants: a mode with some of its settings given, written
//! `MODE[:KEY=VALUE]...`, e.g. `deferred:group=wgc-k8:voronoi=off` or
//! `two-pass:quality=unfiltered`. The keys are the parameters' own names
//! ([`Parameter::key`]), the values those of the matching command-line
//! options, and a key must be one the mode reads. What a plain mode name
//! stands for in `bench` is bench's rule (`src/bench/variants.rs`).

use super::{Parameter, RenderMode, RenderSettings};

/// A mode and the settings that differ from the run's.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeVariant {
    pub mode: RenderMode,
    pub overrides: Vec<(Parameter, String)>,
}

impl ModeVariant {
    /// `base` with this variant's mode and settings.
    pub fn apply(&self, base: &RenderSettings) -> Result<RenderSettings, String> {
        let mut settings = RenderSettings { mode: self.mode, ..*base };
        for (parameter, value) in &self.overrides {
            parameter.apply(&mut settings, value)?;
        }
        Ok(settings)
    }

    /// The name rows and images carry: the text form.
    pub fn label(&self) -> String {
        self.to_string()
    }

    /// The label made safe for file names: `:` becomes `_`, `=` becomes `-`,
    /// and anything else outside `[A-Za-z0-9.-]` becomes `_`.
    pub fn file_tag(&self) -> String {
        self.label()
            .chars()
            .map(|c| match c {
                '=' => '-',
                c if c.is_ascii_alphanumeric() || "-.".contains(c) => c,
                _ => '_',
            })
            .collect()
    }
}

impl std::fmt::Display for ModeVariant {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.mode.name())?;
        for (parameter, value) in &self.overrides {
            write!(f, ":{}={value}", parameter.key())?;
        }
        Ok(())
    }
}

impl std::str::FromStr for ModeVariant {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let mut parts = text.split(':');
        let mode: RenderMode = parts.next().unwrap_or_default().parse()?;
        let mut overrides = Vec::new();
        for part in parts {
            let (key, value) = part.split_once('=').ok_or_else(|| format!("'{part}' in '{text}' is not KEY=VALUE"))?;
            let parameter = Parameter::from_key(key).ok_or_else(|| {
                let keys: Vec<&str> = mode.parameters().iter().map(|p| p.key()).collect();
                format!("'{key}' is not a setting; {mode} reads {}", keys.join(", "))
            })?;
            if !mode.reads(parameter) {
                return Err(format!("{mode} does not read {key}"));
            }
            overrides.push((parameter, value.to_string()));
        }
        let variant = ModeVariant { mode, overrides };
        variant.apply(&RenderSettings::default())?;
        Ok(variant)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grouping::GroupingSpec;

    #[test]
    fn variants_parse_apply_and_print_back() {
        let v: ModeVariant = "deferred:group=wgc-k8:voronoi=off".parse().unwrap();
        let s = v.apply(&RenderSettings::default()).unwrap();
        assert_eq!((s.mode.name(), s.grouping, s.voronoi), ("deferred", GroupingSpec::wgc(8), false));
        assert_eq!(v.to_string(), "deferred:group=wgc-k8:voronoi=off");
        assert_eq!(v.file_tag(), "deferred_group-wgc-k8_voronoi-off");
        assert!("deferred:quality=unfiltered".parse::<ModeVariant>().unwrap_err().contains("does not read"));
        assert!("deferred:group=xyz".parse::<ModeVariant>().is_err());
        assert!("two-pass:colour=red".parse::<ModeVariant>().is_err());
        assert!("nonsense".parse::<ModeVariant>().is_err());
    }
}
