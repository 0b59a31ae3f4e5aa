//! The font labels are drawn in: DejaVu Sans, bundled in `assets/fonts`
//! (its licence beside it), registered once with `plotters` as
//! "sans-serif", so no system font is needed. The benchmark's plots and the
//! viewer's annotated screenshots use it.

use std::sync::Once;

use plotters::style::FontStyle;

const FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// Registers the bundled font as "sans-serif" (once).
pub fn register() {
    static REGISTER: Once = Once::new();
    REGISTER.call_once(|| {
        if plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_err() {
            log::warn!("the bundled font could not be read; labels may be missing");
        }
    });
}
