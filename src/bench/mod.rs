//! Error against run time: every mode from several views, timed and compared
//! with the exact reference.
//!
//! For each model and view, each GPU mode variant renders warm-up frames and then
//! timed frames (wall time to `poll(wait)`, plus per-pass GPU timestamps when
//! the adapter has them); its last image is compared with the `reference`
//! image of the same view (ε of Zhang & Pajarola 2007 §6.3, PSNR, bad-pixel
//! share). Reference images are cached in the output folder, keyed by file,
//! view, size and parameters. [`report`] writes `bench.json` and `bench.md`,
//! [`plot`] the error-against-time plot, [`sheet`] the main job's contact sheet. With `--orders`, [`orders`] times
//! the back-to-front orders on the same views. A streamed file (COPC) is
//! measured view by view on the nodes each view selects ([`streamed`]), and a
//! `.vpc` of them under one budget ([`streamed_layers`]).

pub mod cache;
pub mod config;
pub mod measure;
pub mod orders;
pub mod plot;
pub mod report;
pub mod ruler;
pub mod run;
pub mod sheet;
pub mod streamed;
pub mod streamed_layers;
pub mod timing;
pub mod variants;
pub mod views;

pub use report::{BenchRow, PassTime};
pub use run::{BenchConfig, BenchError, BenchOutcome, run};
