//! The inspection tools' answers, shared by the command line and the
//! viewer: what a pick found ([`report`]: the layers of
//! [`crate::reference::pick`] with the file's attributes, as text, JSON and
//! CSV) and what a measurement of picked points gives ([`measure`]:
//! lengths, angles and heights, in f64 file coordinates).

pub mod measure;
pub mod report;

pub use measure::{Measurement, Segment, measure};
pub use report::PickReport;
