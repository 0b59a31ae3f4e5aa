//! One node's LAZ chunk to columns: the chunk is a standalone layered LAZ
//! chunk (point formats 6-8, COPC 1.0 section 6), decompressed with the
//! `laz` crate's record decompressor straight from the bytes read, then
//! split into the same columns a whole LAS/LAZ file fills
//! ([`crate::cloud::las_file`]). The chunk's layer sizes and code starts
//! are checked first ([`laz_check::check_chunk`]), as in a whole file.
//!
//! Records are decoded [`BATCH_POINTS`] at a time and checked against the
//! node's cube batch by batch, so memory grows with the points the chunk
//! really holds, not with the count its hierarchy entry claims: a lying
//! count ends at the chunk's end ("ends early") or at points outside the
//! cube. A count beyond [`MOST_RATIO`] times the chunk's bytes is refused
//! before decoding: a perfect grid of one colour, the most regular data
//! there is, compressed up to 232 times in `tests/copc.rs`.

use glam::DVec3;
use laz::record::{LayeredPointRecordDecompressor, RecordDecompressor};

use super::header::CopcHeader;
use crate::cloud::las_file::{Columns, laz_check};

/// The node's points, or why its chunk does not decode. `cube` (minimum
/// corner and side, file coordinates) is where they must lie: a corrupt
/// chunk often decodes without an error, to points elsewhere.
pub fn decode(header: &CopcHeader, chunk: &[u8], points: u32, cube: (DVec3, f64)) -> Result<Columns, String> {
    let mut columns = Columns::default();
    decode_each(header, chunk, points, cube, &mut |_, batch| columns.extend(&batch))?;
    Ok(columns)
}

/// [`decode`], and the node's records as they are in the file (decompressed),
/// for an export that copies them.
pub fn decode_with_records(
    header: &CopcHeader,
    chunk: &[u8],
    points: u32,
    cube: (DVec3, f64),
) -> Result<(Columns, Vec<u8>), String> {
    let (mut columns, mut records) = (Columns::default(), Vec::new());
    decode_each(header, chunk, points, cube, &mut |data, batch| {
        columns.extend(&batch);
        records.extend_from_slice(data.raw_bytes());
    })?;
    Ok((columns, records))
}

/// Decodes the chunk batch by batch, each batch checked against the cube
/// and handed to `take` as records and as columns.
fn decode_each(
    header: &CopcHeader,
    chunk: &[u8],
    points: u32,
    cube: (DVec3, f64),
    take: &mut dyn FnMut(&las::PointData, Columns),
) -> Result<(), String> {
    let record_len = usize::from(header.las.point_format().len());
    let bytes = points as usize * record_len;
    if bytes > chunk.len().saturating_mul(MOST_RATIO).max(1 << 16) {
        return Err(format!(
            "{points} points of {record_len} bytes cannot come from a chunk of {} bytes (at most {MOST_RATIO} times its size)",
            chunk.len()
        ));
    }
    let Some(laz) = header.laz.as_ref() else { return Err("the file has no LAZ chunks".into()) };
    // Before the crate zero-fills a buffer of each layer's stated size (4 GB for a flipped u32).
    laz_check::check_chunk(&mut std::io::Cursor::new(chunk), 0, chunk.len() as u64, laz.items())
        .map_err(|reason| format!("its LAZ chunk: {reason}"))?;
    let mut decompressor = LayeredPointRecordDecompressor::new(std::io::Cursor::new(chunk));
    decompressor.set_fields_from(laz.items()).map_err(|e| format!("its LAZ items: {e}"))?;
    let inside = Inside::of(header, cube);
    let mut left = points as usize;
    while left > 0 {
        let batch = left.min(BATCH_POINTS);
        let mut raw = vec![0u8; batch * record_len];
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
        let outside = (0..columns.len()).filter(|&i| !inside.holds(&columns, i)).count();
        if outside > 0 {
            return Err(format!("{outside} of its {points} points lie outside its cube (a corrupt chunk?)"));
        }
        take(&data, columns);
        left -= batch;
    }
    Ok(())
}

/// Records decoded at a time.
const BATCH_POINTS: usize = 65_536;

/// Most bytes of records a chunk may claim, as a multiple of its own size:
/// far above the 232 times of the most regular data tested, since memory
/// grows only with the points really decoded.
const MOST_RATIO: usize = 4096;

/// A node's cube with a slack for rounding: where its points must lie.
struct Inside {
    lo: DVec3,
    hi: DVec3,
}

impl Inside {
    fn of(header: &CopcHeader, (corner, side): (DVec3, f64)) -> Self {
        let t = header.las.transforms();
        let slack = side * 1e-3 + t.x.scale.abs().max(t.y.scale.abs()).max(t.z.scale.abs());
        Self { lo: corner - DVec3::splat(slack), hi: corner + DVec3::splat(side + slack) }
    }

    fn holds(&self, columns: &Columns, i: usize) -> bool {
        let p = DVec3::new(columns.x[i], columns.y[i], columns.z[i]);
        p.cmpge(self.lo).all() && p.cmple(self.hi).all()
    }
}
