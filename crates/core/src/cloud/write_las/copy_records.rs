//! A LAS/LAZ/COPC file's records copied as they are into a new LAS or LAZ:
//! what `convert` and `profile --points` write of a lidar input, so an
//! export keeps the point format, the scale and offset, the CRS and every
//! other record, and every standard and extra-bytes field, bit for bit.
//!
//! The header is the input's, less what described its old layout: the
//! laszip record (the writer adds its own when the output is compressed)
//! and COPC's records (the output is not clustered in COPC's octree; `convert
//! OUT.copc.laz` clusters it again). Counts and bounds are the writer's, of
//! the points written.

use std::path::Path;

use crate::cloud::CloudError;
use crate::cloud::las_file;

/// Records decoded at once.
const BATCH: u64 = 1 << 16;

/// Whether a record describes the input's layout, not its content.
fn describes_layout(vlr: &las::Vlr) -> bool {
    las::laz::is_laszip_vlr(vlr) || vlr.user_id.trim_end_matches('\0').eq_ignore_ascii_case("copc")
}

/// The header of a copy of records read under `input`'s header, written to `output`.
fn copy_header(input: &las::Header, output: &Path) -> Result<las::Header, CloudError> {
    let mut builder = las::Builder::from(input.clone());
    builder.vlrs.retain(|v| !describes_layout(v));
    builder.evlrs.retain(|v| !describes_layout(v));
    builder.point_format.is_compressed = super::is_laz(output);
    builder.generating_software = "pointblend".into();
    builder.into_header().map_err(|e| CloudError::content(output, format!("cannot write: {e}")))
}

/// Writes the records `keep` (ascending indices) of `records`, raw records
/// decoded under `header` (a streamed file's nodes), to `output`.
pub fn copy_raw_records(header: &las::Header, records: &[u8], keep: &[u32], output: &Path) -> Result<u64, CloudError> {
    let out_header = copy_header(header, output)?;
    let record_len = usize::from(header.point_format().len());
    super::write_with(output, out_header, |writer| {
        for chunk in keep.chunks(BATCH as usize) {
            let mut bytes = Vec::with_capacity(chunk.len() * record_len);
            for &k in chunk {
                let at = k as usize * record_len;
                bytes.extend_from_slice(&records[at..at + record_len]);
            }
            writer.write_points(&las::PointDataBuilder::new().for_header(header).build_from_bytes(bytes)?)?;
        }
        Ok(())
    })?;
    Ok(keep.len() as u64)
}

/// Copies the records of `input` whose indices (in file order, ascending)
/// are in `keep` into `output` (LAZ when its name ends in `.laz`); returns
/// how many it wrote.
pub fn copy_records(input: &Path, output: &Path, keep: &[u32]) -> Result<u64, CloudError> {
    debug_assert!(keep.windows(2).all(|w| w[0] < w[1]), "indices must ascend");
    let (mut reader, _) = las_file::open(input)?;
    let header = copy_header(reader.header(), output)?;
    let input_header = reader.header().clone();
    let compressed = input_header.point_format().is_compressed;
    let declared = input_header.number_of_points();
    let mut read_error = None;
    let written = super::write_with(output, header, |writer| {
        let mut batch = las::PointDataBuilder::new().for_header(&input_header).build();
        let record_len = batch.record_len();
        let (mut next, mut start) = (0usize, 0u64);
        while next < keep.len() && start < declared {
            let n = match reader.fill_points(BATCH.min(declared - start), &mut batch) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) => {
                    read_error = Some(las_file::points_error(input, e, compressed));
                    // Abandons the output: the temporary file is removed, nothing is renamed.
                    return Err(std::io::Error::other("the input stopped").into());
                }
            };
            let mut bytes = Vec::new();
            while next < keep.len() && u64::from(keep[next]) < start + n {
                let at = (u64::from(keep[next]) - start) as usize * record_len;
                bytes.extend_from_slice(&batch.raw_bytes()[at..at + record_len]);
                next += 1;
            }
            let chosen = las::PointDataBuilder::new().for_header(&input_header).build_from_bytes(bytes)?;
            writer.write_points(&chosen)?;
            start += n;
        }
        if next < keep.len() {
            read_error =
                Some(CloudError::content(input, format!("holds fewer records than the {} chosen", keep.len())));
            return Err(std::io::Error::other("the input stopped").into());
        }
        Ok(())
    });
    match (read_error, written) {
        (Some(e), _) => Err(e),
        (None, written) => written.map(|()| keep.len() as u64),
    }
}
