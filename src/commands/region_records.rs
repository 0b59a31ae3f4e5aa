//! What `profile` and `measure --polygon` read: the records a horizontal
//! box may hold, at full resolution. A streamed file (COPC, or an http(s)
//! URL) gives the points of the nodes meeting the box
//! ([`pointblend::copc::CopcStream::region_records`]); any other file is
//! read whole.

use std::path::Path;

use anyhow::Result;
use glam::DVec2;
use pointblend::cloud::LoadOptions;
use pointblend::cloud::records::Records;
use pointblend::copc::CopcStream;

use super::stream_args::StreamArgs;

/// The records of `file` the box `lo..hi` (x and y, file coordinates) may hold.
pub fn records_in(file: &Path, stream: &StreamArgs, (lo, hi): (DVec2, DVec2)) -> Result<Records> {
    let name = file.to_string_lossy();
    if pointblend::copc::is_streamed(file) || pointblend::copc::is_url(&name) {
        let mut copc = CopcStream::open(&name, stream.options(true))?;
        let records = copc.region_records((lo, hi))?;
        log::info!(
            "{}: {} of its {} points read, from the nodes that meet the region",
            pointblend::copc::shown(&name),
            records.len(),
            copc.points()
        );
        return Ok(records);
    }
    Ok(Records::read(file, &LoadOptions { progress: true, ..Default::default() })?)
}
