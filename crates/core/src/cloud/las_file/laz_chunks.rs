//! A whole LAZ file decoded chunk by chunk on every core, each chunk
//! straight into its rows of the columns.
//!
//! The `las` crate's reader decompresses a batch of chunks in parallel into
//! one slab of records, and the columns were then read out of the slab a
//! column at a time: fifteen passes over memory after the decoding. Here the
//! chunk table (checked by [`super::laz_check`] when the file was opened)
//! gives each chunk's first row; one task per chunk decompresses it with the
//! `laz` crate's record decompressor (as lazrs does for laspy) and writes
//! its rows of every column ([`super::column_rows`]) while its records are
//! still in that core's cache. Hand-written because neither crate decodes
//! into columns; the figures are in docs/BENCHMARKS.md.
//!
//! The columns of the whole file are allocated before decoding, so this
//! path is taken only when the chunks' counts add up to the header's and
//! the records fit in 64 times the file's size (the reader's own bound for
//! a batch). Otherwise, and when a chunk does not decode, it returns `None`
//! and the reader's batch path decodes the file and names what is wrong.

use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use laz::laszip::ChunkTable;
use laz::record::{LayeredPointRecordDecompressor, RecordDecompressor, SequentialPointRecordDecompressor};
use rayon::prelude::*;

use super::Columns;
use super::extra_bytes::Field;

/// The records of the LAZ file at `path` as columns, or `None` where the
/// reader's batch path is to decode it.
pub(super) fn decode(path: &Path, header: &las::Header, fields: &[Field]) -> Option<Columns> {
    let format = header.point_format();
    let vlr = header.laz_vlr().ok()?;
    let record_len = usize::from(format.len());
    if !format.is_compressed || vlr.items_size() as usize != record_len {
        return None;
    }
    let (file, file_len) = crate::input::open(path).ok()?;
    let mut file = BufReader::new(file);
    let start = las::raw::Header::read_from(&mut file).ok()?.offset_to_point_data as u64;
    file.seek(SeekFrom::Start(start)).ok()?;
    // Leaves the file at the first chunk.
    let table = ChunkTable::read_from(&mut file, &vlr).ok()?;
    let declared = header.number_of_points();
    let counts =
        chunk_counts(table.as_ref().iter().map(|e| e.point_count), declared, !vlr.uses_variable_size_chunks())?;
    if declared.saturating_mul(record_len as u64) > file_len.saturating_mul(64) {
        return None;
    }
    let sizes: Vec<usize> = table.as_ref().iter().map(|e| e.byte_count as usize).collect();
    let mut compressed = vec![0u8; sizes.iter().sum::<usize>()];
    file.read_exact(&mut compressed).ok()?;

    let mut columns = Columns::zeroed(declared as usize, format, fields.len());
    let mut rows = columns.rows_from(0);
    let mut chunk_bytes = compressed.as_slice();
    let mut jobs = Vec::with_capacity(counts.len());
    for (&count, &size) in counts.iter().zip(&sizes) {
        let (bytes, rest) = chunk_bytes.split_at(size);
        chunk_bytes = rest;
        jobs.push((bytes, count as usize, rows.take_head(count as usize)));
    }
    let decoded = jobs.into_par_iter().try_for_each(|(bytes, count, mut out)| {
        let mut decompressor = decompressor(bytes, format.is_extended, &vlr)?;
        let mut block = las::PointDataBuilder::new().for_header(header).build();
        let mut left = count;
        while left > 0 {
            let n = left.min(BLOCK);
            decompressor.decompress_many(block.resize_for(n)).ok()?;
            out.take_head(n).fill(&block, fields, &mut |job| job());
            left -= n;
        }
        Some(())
    });
    if decoded.is_none() {
        log::debug!("{}: a LAZ chunk did not decode alone; decoding in batches", path.display());
        return None;
    }
    Some(columns)
}

/// Each chunk's point count: the table's, the last one of fixed-size
/// chunks being what is left of `declared`; `None` unless they add up to it.
fn chunk_counts(table: impl Iterator<Item = u64>, declared: u64, fixed_size: bool) -> Option<Vec<u64>> {
    let mut counts: Vec<u64> = table.collect();
    if fixed_size {
        let before_last: u64 = counts.iter().rev().skip(1).sum();
        let last = counts.last_mut()?;
        *last = declared.checked_sub(before_last).filter(|left| (1..=*last).contains(left))?;
    }
    (counts.iter().try_fold(0u64, |sum, c| sum.checked_add(*c)) == Some(declared)).then_some(counts)
}

/// Records decoded at a time in a chunk, into one buffer per task reused
/// for the next ones: a few hundred KB a task instead of a whole chunk's
/// records (whole chunks were measured no faster).
const BLOCK: usize = 4096;

/// A decompressor of one chunk's records (point formats 6-10 are layered).
fn decompressor<'c>(
    chunk: &'c [u8],
    layered: bool,
    vlr: &laz::LazVlr,
) -> Option<Box<dyn RecordDecompressor<std::io::Cursor<&'c [u8]>> + Send + 'c>> {
    let source = std::io::Cursor::new(chunk);
    let mut decompressor: Box<dyn RecordDecompressor<_> + Send> = if layered {
        Box::new(LayeredPointRecordDecompressor::new(source))
    } else {
        Box::new(SequentialPointRecordDecompressor::new(source))
    };
    decompressor.set_fields_from(vlr.items()).ok()?;
    Some(decompressor)
}

#[cfg(test)]
mod tests {
    use super::super::{Columns, open};
    use super::{chunk_counts, decode};

    /// `n` points in LAZ of point format `format`, every field varying from point to point.
    fn write_laz(path: &std::path::Path, format: u8, n: usize) {
        let mut builder = las::Builder::from((1, 4));
        builder.point_format = las::point::Format::new(format).unwrap();
        builder.point_format.is_compressed = true;
        let mut writer = las::Writer::from_path(path, builder.into_header().unwrap()).unwrap();
        let format = *writer.header().point_format();
        for k in 0..n {
            let point = las::Point {
                x: 1000.0 + (k % 400) as f64 * 0.5,
                y: 2000.0 + (k / 400) as f64 * 0.5,
                z: 50.0 + (k % 7) as f64 * 0.25,
                intensity: (k * 37 % 4000) as u16,
                return_number: 1 + (k % 3) as u8,
                number_of_returns: 3,
                classification: las::point::Classification::new([2, 5, 6][k % 3]).unwrap(),
                is_synthetic: k % 5 == 0,
                is_withheld: k % 11 == 0,
                scan_angle: ((k % 60) as f32 - 30.0) * if format.is_extended { 0.006 } else { 1.0 },
                user_data: (k % 200) as u8,
                point_source_id: (k % 1000) as u16,
                gps_time: format.has_gps_time.then_some(1000.0 + k as f64 * 0.25),
                color: format.has_color.then(|| las::Color::new(k as u16, (k * 3) as u16, (k * 7) as u16)),
                ..Default::default()
            };
            writer.write_point(point).unwrap();
        }
        writer.close().unwrap();
    }

    #[test]
    fn chunks_decode_to_the_columns_the_readers_batches_give() {
        let dir = tempfile::tempdir().unwrap();
        // 120,000 points: chunks of 50,000, the last one partial.
        for format in [1, 3, 7] {
            let path = dir.path().join(format!("f{format}.laz"));
            write_laz(&path, format, 120_000);
            let (mut reader, _) = open(&path).unwrap();
            let header = reader.header().clone();
            let chunked = decode(&path, &header, &[]).expect("the chunk table accounts for every point");
            let mut batch = las::PointDataBuilder::new().for_header(&header).build();
            assert_eq!(reader.fill_points(200_000, &mut batch).unwrap(), 120_000);
            let mut read = Columns::default();
            read.append(&batch, &[]);
            assert!(chunked == read, "point format {format}: the columns differ");
        }
    }

    #[test]
    fn chunk_counts_add_up_to_the_header_or_are_refused() {
        let fixed = |n: usize| std::iter::repeat_n(50_000u64, n);
        assert_eq!(chunk_counts(fixed(3), 110_000, true), Some(vec![50_000, 50_000, 10_000]));
        assert_eq!(chunk_counts(fixed(3), 150_000, true), Some(vec![50_000; 3]));
        assert_eq!(chunk_counts(fixed(3), 150_001, true), None, "more than the chunks hold");
        assert_eq!(chunk_counts(fixed(3), 100_000, true), None, "an empty last chunk");
        assert_eq!(chunk_counts([5, 7].into_iter(), 12, false), Some(vec![5, 7]));
        assert_eq!(chunk_counts([5, 7].into_iter(), 13, false), None);
        assert_eq!(chunk_counts(std::iter::empty(), 0, true), None);
    }
}
