//! One node's LAZ chunk to columns: the chunk is a standalone layered LAZ
//! chunk (point formats 6-8, COPC 1.0 section 6), decompressed with the
//! `laz` crate's record decompressor straight from the bytes read, then
//! split into the same columns a whole LAS/LAZ file fills
//! ([`crate::cloud::las_file`]). The chunk's layer sizes and code starts
//! are checked first ([`laz_check::check_chunk`]), as in a whole file.

use glam::DVec3;
use laz::record::{LayeredPointRecordDecompressor, RecordDecompressor};

use super::header::CopcHeader;
use crate::cloud::las_file::{Columns, laz_check};

/// The node's points, or why its chunk does not decode. `cube` (minimum
/// corner and side, file coordinates) is where they must lie: a corrupt
/// chunk often decodes without an error, to points elsewhere.
pub fn decode(header: &CopcHeader, chunk: &[u8], points: u32, cube: (DVec3, f64)) -> Result<Columns, String> {
    let record_len = usize::from(header.las.point_format().len());
    // A chunk decodes to at most ~64 times its size, so a lying count cannot ask for more.
    let bytes = points as usize * record_len;
    if bytes > chunk.len().saturating_mul(64).max(1 << 16) {
        return Err(format!("{points} points of {record_len} bytes cannot come from a chunk of {} bytes", chunk.len()));
    }
    // Before the crate zero-fills a buffer of each layer's stated size (4 GB for a flipped u32).
    laz_check::check_chunk(&mut std::io::Cursor::new(chunk), 0, chunk.len() as u64, header.laz.items())
        .map_err(|reason| format!("its LAZ chunk: {reason}"))?;
    let mut raw = vec![0u8; bytes];
    let mut decompressor = LayeredPointRecordDecompressor::new(std::io::Cursor::new(chunk));
    decompressor.set_fields_from(header.laz.items()).map_err(|e| format!("its LAZ items: {e}"))?;
    decompressor.decompress_many(&mut raw).map_err(|e| match e.kind() {
        std::io::ErrorKind::UnexpectedEof => "its LAZ chunk ends early (corrupt?)".to_string(),
        _ => format!("its LAZ chunk does not decode: {e}"),
    })?;
    let data = las::PointDataBuilder::new()
        .for_header(&header.las)
        .build_from_bytes(raw)
        .map_err(|e| format!("its records: {e}"))?;
    let mut columns = Columns::default();
    columns.append(&data, &header.fields);
    let t = header.las.transforms();
    let slack = cube.1 * 1e-3 + t.x.scale.abs().max(t.y.scale.abs()).max(t.z.scale.abs());
    let (lo, hi) = (cube.0 - DVec3::splat(slack), cube.0 + DVec3::splat(cube.1 + slack));
    let outside = (0..columns.len())
        .filter(|&i| {
            let p = DVec3::new(columns.x[i], columns.y[i], columns.z[i]);
            !(p.cmpge(lo).all() && p.cmple(hi).all())
        })
        .count();
    if outside > 0 {
        return Err(format!("{outside} of its {points} points lie outside its cube (a corrupt chunk?)"));
    }
    Ok(columns)
}
