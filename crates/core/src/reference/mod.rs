//! The exact CPU reference renderer and the image error metrics.
//!
//! [`render`] is an A-buffer splat renderer: every pixel's view ray is
//! intersected with every splat disc of the scene that covers it
//! (perspective-correct, no parallel-projection approximation; parallel
//! rays in an orthographic view, [`crate::frame::eye_ray`]), the hits are
//! sorted by depth and grouped into ε-layers (split by facing when opacity is
//! read), each layer is normalised (Σw·c/Σw) and shaded, and the layers are
//! α-composited front to back with no cap on their number. It uses the camera, kernel and
//! shading of [`crate::frame`], so its images compare pixel for pixel with the
//! GPU modes. A scene's mesh triangles are intersected exactly too
//! (`triangles`): the reference draws every `mesh` and `hybrid` object as its
//! triangles, the ruler of the GPU's triangle and hybrid frames. [`metrics`] holds the ε of Zhang & Pajarola 2007 §6.3, PSNR, the
//! bad-pixel share and the difference image. [`pick`] lists the layers one
//! pixel's ray passes, for the inspection tools.

mod environment_pass;
pub mod metrics;
pub mod pick;
mod raster;
mod tiles;
mod triangles;

pub use metrics::{ImageError, LayerError, compare, difference_image, error_by_layers};
pub use raster::{ReferenceOptions, render, render_with_layers};
