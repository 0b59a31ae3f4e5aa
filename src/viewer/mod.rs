//! The interactive viewer: `pointblend view [FILE]`, an eframe/egui window.
//!
//! The left panel holds the model, the mode (every entry of the mode registry,
//! [`RenderMode::ALL`](crate::frame::RenderMode::ALL), with the parameters it
//! lists), live statistics, the error measurement and the screenshot export.
//! The panels (`panels.rs`, `stats.rs`, with `widgets.rs`) edit a `UiState`
//! and return actions; the app (`app.rs`, its per-frame loop) applies them in
//! `actions.rs` (`state.rs` holds the types both sides share), loads models in
//! `loading.rs`, asks for frames in `frames.rs`, saves screenshots and
//! measures the error in `export.rs`, and `view3d.rs` draws the 3D view and
//! takes its input.
//! The 3D view shows frames from a render thread that runs the same
//! [`GpuRenderer`](crate::render::GpuRenderer) as `pointblend render`;
//! loading, grouping and the reference render run on worker threads with
//! progress and Cancel, so the window never waits on them.

mod actions;
mod annotate;
mod app;
mod camera_input;
mod colour_panel;
mod cursor_coordinates;
mod export;
mod export_points;
mod filter_panel;
mod frame_clock;
mod frames;
mod inspect;
mod inspect_panel;
mod jobs;
mod layer_list;
mod layers_panel;
mod legend;
mod lights_panel;
mod loading;
mod model;
mod panels;
mod parameter_widgets;
mod polygon_measure;
mod polygon_panel;
mod preview;
mod profile_panel;
mod profile_pick;
mod profile_view;
mod refine_steps;
mod render_thread;
mod scale_bar;
mod selection;
mod selection_clip;
mod state;
mod stats;
mod stream_layers;
mod stream_source;
mod streaming;
mod view3d;
mod view_keys;
mod widgets;

pub use app::{ViewerApp, ViewerOptions};
pub use legend::Legend;
pub use model::Model;
pub use state::{FrameKey, Inspection, ScreenshotSize};

/// Errors opening the window.
#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    #[error("no display: neither DISPLAY nor WAYLAND_DISPLAY is set")]
    NoDisplay,
    #[error("the window could not be opened: {0}")]
    Window(String),
}

/// Why no window can open here, if that is known before trying.
pub fn missing_display() -> Option<ViewerError> {
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    (!set("DISPLAY") && !set("WAYLAND_DISPLAY")).then_some(ViewerError::NoDisplay)
}

/// Opens the window and runs until it is closed.
pub fn run_window(options: ViewerOptions) -> Result<(), ViewerError> {
    if let Some(e) = missing_display() {
        return Err(e);
    }
    let title = match &options.file {
        Some(f) => format!("pointblend: {}", crate::copc::shown(&f.to_string_lossy())),
        None => "pointblend".to_string(),
    };
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(title)
            .with_inner_size([1280.0, 800.0])
            .with_min_inner_size([1.0, 1.0])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    eframe::run_native("pointblend", native, Box::new(move |cc| Ok(Box::new(ViewerApp::new(cc, options)))))
        .map_err(|e| ViewerError::Window(e.to_string()))
}
