//! The inspection tools' answers, shared by the command line and the
//! viewer: what a pick found ([`report`]: the layers of
//! [`crate::reference::pick`] with the file's attributes, as text, JSON and
//! CSV) and what a measurement of picked points gives ([`measure`]:
//! lengths, angles and heights, in f64 file coordinates), and the survey
//! tools over a file's records: [`profile`] (cross-sections) and
//! [`area_volume`] (areas and volumes inside a [`polygon`]).

pub mod area_volume;
pub mod measure;
pub mod polygon;
pub mod profile;
pub mod profile_table;
pub mod report;

pub use measure::{Measurement, Segment, measure};
pub use report::PickReport;
