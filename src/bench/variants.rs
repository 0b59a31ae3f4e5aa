//! What a plain mode name stands for in `bench --modes` (and in the
//! headless main job's table): the mode with its defaults, then the cheaper
//! settings of the parameters it reads, so that one run shows what each
//! costs and what it gives up. Bench's rule, read from the registry's
//! parameters and defaults, not a list kept beside each mode:
//! - the unfiltered quality (Botsch & Kobbelt §5's 1+1 passes), where the
//!   mode reads `quality`;
//! - fewer peeled layers, the powers of two from 2 below the mode's default
//!   k, where it reads `layers` (Guennebaud's k, and exact peeling's).

use crate::frame::{ModeVariant, Parameter, RenderMode};

/// The variants a plain `mode` stands for, as `KEY=VALUE` texts ("" for the defaults).
pub fn defaults(mode: RenderMode) -> Vec<String> {
    let mut variants = vec![String::new()];
    if mode.reads(Parameter::Quality) {
        variants.push(format!("{}=unfiltered", Parameter::Quality.key()));
    }
    if mode.reads(Parameter::PeelLayers) {
        let default = mode.info().default_peel_layers;
        let fewer = (1..).map(|p| 1u32 << p).take_while(|&k| k < default);
        let mut fewer: Vec<u32> = fewer.collect();
        fewer.reverse();
        variants.extend(fewer.into_iter().map(|k| format!("{}={k}", Parameter::PeelLayers.key())));
    }
    variants
}

/// The variants `text` stands for: itself (`MODE:KEY=VALUE...`), or for a
/// plain mode name its [`defaults`].
pub fn expand(text: &str) -> Result<Vec<ModeVariant>, String> {
    if text.contains(':') {
        return Ok(vec![text.parse()?]);
    }
    let mode: RenderMode = text.parse()?;
    defaults(mode)
        .iter()
        .map(
            |v| {
                if v.is_empty() {
                    Ok(ModeVariant { mode, overrides: Vec::new() })
                } else {
                    format!("{text}:{v}").parse()
                }
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plain_name_stands_for_its_defaults_and_its_cheaper_settings() {
        let labels = |name: &str| expand(name).unwrap().iter().map(ModeVariant::label).collect::<Vec<_>>();
        assert_eq!(labels("two-pass"), ["two-pass", "two-pass:quality=unfiltered"]);
        assert_eq!(labels("depth-peel"), ["depth-peel", "depth-peel:layers=4", "depth-peel:layers=2"]);
        assert_eq!(labels("approx-peel"), ["approx-peel", "approx-peel:layers=2"]);
        for plain in ["deferred", "alg1", "alg2", "alpha-blend", "tiled", "reference"] {
            assert_eq!(labels(plain), [plain], "{plain}");
        }
        for mode in RenderMode::ALL {
            assert!(expand(mode.name()).unwrap().iter().all(|v| v.mode == mode), "{mode}");
        }
        assert_eq!(labels("deferred:voronoi=off"), ["deferred:voronoi=off"]);
    }
}
