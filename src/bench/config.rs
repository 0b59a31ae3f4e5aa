//! What a benchmark run is given ([`BenchConfig`]), how it fails
//! ([`BenchError`]), and the writing of its files, which every part of the
//! run shares.

use std::path::{Path, PathBuf};

use crate::cloud::CloudError;
use crate::frame::{ModeVariant, RenderSettings};
use crate::render::GpuError;
use crate::scene::Materials;

#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error(transparent)]
    Cloud(#[from] CloudError),
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{0}")]
    Invalid(String),
}

/// What to run.
#[derive(Debug, Clone)]
pub struct BenchConfig {
    /// The mode variants, one row each per view; the reference is always
    /// rendered (it is the ruler) and gets a row when listed.
    pub variants: Vec<ModeVariant>,
    /// The settings every variant starts from (ε, kernel, shading, culling...).
    pub settings: RenderSettings,
    pub materials: Materials,
    pub width: u32,
    pub height: u32,
    pub frames: usize,
    pub warm_up: usize,
    pub views: usize,
    /// Where images, the cache and the reports go.
    pub out: PathBuf,
    pub progress: bool,
    /// Also time the back-to-front orders (`orders.json`, a table in `bench.md`).
    pub orders: bool,
    /// `--animate N`: N frames over one period of a moving scene's longest animation.
    pub animate: Option<usize>,
    /// The environment map every model is set in, if any (§5.2.3).
    pub environment: Option<std::sync::Arc<crate::scene::environment_map::EnvironmentMap>>,
    /// How streamed models (COPC files and URLs) are read, and the points they draw.
    pub stream: crate::copc::StreamOptions,
    pub stream_budget: crate::copc::StreamBudget,
    /// The camera asked for (the headless main job's `--azimuth` and the
    /// like): when it asks for anything, the first view is that camera.
    pub camera: crate::frame::CameraRequest,
    /// `--path`: the views of a camera path, measured in path order in place
    /// of the standard views, each row with what its view cost to prepare.
    pub path: Option<crate::frame::ViewPath>,
    /// The time a moving scene is measured at, in seconds (0 when `None`).
    pub time: Option<f64>,
    /// Another mode to measure every row against instead of the exact
    /// reference (`--ruler`: Zhang & Pajarola measure against 8-layer depth
    /// peeling); `None`: the reference.
    pub ruler: Option<ModeVariant>,
    /// `--no-reference`: time the GPU variants without rendering the exact
    /// reference (a scene whose CPU reference would take too long): rows
    /// have no error (ε is `null` in bench.json) and the reference no row.
    pub no_reference: bool,
}

pub(super) fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> BenchError + '_ {
    move |source| BenchError::Io { path: path.to_path_buf(), source }
}

pub(super) fn save_png(image: &image::RgbaImage, path: &Path) -> Result<(), BenchError> {
    crate::output::save_png(image, path).map_err(io_error(path))
}
