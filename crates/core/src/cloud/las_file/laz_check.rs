//! Checks of a LAZ file's chunk table and chunks, made before the `laz`
//! crate (0.13) reads them.
//!
//! Hand-written because the crate trusts every size it reads and acts on it
//! before anything checks it: it reserves 16 bytes for each chunk the
//! table's header counts (`ChunkTable::read`; a flipped count asked for
//! 64 GB, an abort), seeks to the table's offset (2^60 gave "Invalid
//! argument"), reads as many bytes as the entries add up to
//! (`ParLasZipDecompressor::decompress_many`; a sign-extended -2^31 is a
//! capacity-overflow panic), and in a layered chunk (point formats 6-10,
//! COPC) zero-fills a buffer of each layer's stated size before it reads
//! the layer (`copy_bytes_into_decoder`): one flipped u32 costs 4 GB, times
//! the chunks decoded at once. Its arithmetic decoder, started on four ff
//! bytes, also indexes past its tables and panics.
//!
//! Nothing in a chunk can be larger than the chunk, and nothing in the
//! points can lie past the chunk table, so each size is checked against the
//! bytes that hold it: a file costs one small read per chunk (its layer
//! sizes) and one 4-byte read per code start. The layout followed is the
//! crate's reader's (and LASzip's): the i64 offset of the table at the start
//! of the points (or, where a writer could not go back to set it, in the
//! file's last 8 bytes), the chunks back to back from there, then the table:
//! u32 version, u32 count, one arithmetic code of (point count if variable,
//! byte count) per chunk.

use std::io::{BufReader, Read, Seek, SeekFrom};

use laz::laszip::ChunkTable;
use laz::{LazItem, LazItemType, LazVlr};

/// Largest LAZ chunk, in decoded bytes, that a file may ask for: the `laz`
/// crate allocates a whole chunk before it decodes one (default chunks of
/// 50,000 points take a few MB).
pub(crate) const MAX_CHUNK_BYTES: u64 = 256 << 20;

/// The four bytes no arithmetic code starts with: the encoder's first
/// interval is [0, 2^32 - 1), and the crate's decoder, started there, reads
/// past its tables (decoders.rs:171) and panics, in release builds too.
const BAD_CODE_START: [u8; 4] = [0xff; 4];

/// What the chunk table holds, checked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct ChunkSummary {
    pub(crate) chunks: u64,
    /// Most points the chunks hold (fixed-size chunks: the last may hold fewer).
    pub(crate) points: u64,
}

fn read_at<R: Read + Seek>(src: &mut R, at: u64, buf: &mut [u8]) -> std::io::Result<()> {
    src.seek(SeekFrom::Start(at))?;
    src.read_exact(buf)
}

/// A size the crate decoded from an i32 and stored `as u64` (which
/// sign-extends a negative one), as the file meant it.
fn shown(v: u64) -> String {
    if v > i64::MAX as u64 { (v as i64).to_string() } else { v.to_string() }
}

/// Checks the chunk table and every chunk of the LAZ points that start at
/// `data_start` (the header's offset to the point data) in a source of
/// `file_len` bytes, as the `laz` crate will read them with `vlr`. Errors
/// are reasons, without the file's name.
pub(crate) fn check_chunks<R: Read + Seek>(
    src: &mut R,
    file_len: u64,
    data_start: u64,
    vlr: &LazVlr,
) -> Result<ChunkSummary, String> {
    let record_len: u64 = vlr.items().iter().map(|i| u64::from(i.size())).sum();
    let table_at = table_offset(src, file_len, data_start)?;
    let chunks_start = data_start + 8;
    // Its header: a version and the number of chunks (u32 each). Every chunk
    // holds at least its first point raw (and a layered one its layer sizes):
    // the count is checked before the crate reserves 16 bytes for each.
    let mut word = [0u8; 8];
    read_at(src, table_at, &mut word).map_err(|e| format!("the LAZ chunk table cannot be read: {e}"))?;
    let count = u64::from(u32::from_le_bytes([word[4], word[5], word[6], word[7]]));
    let data_bytes = table_at - chunks_start;
    let smallest = record_len + layer_count(vlr.items()).map_or(0, |layers| 4 + 4 * layers);
    let most = data_bytes / smallest.max(1) + 1;
    if count > most {
        return Err(format!(
            "the LAZ chunk table (at byte {table_at}) lists {count} chunks, but the {data_bytes} bytes of points \
             before it hold at most {most} (a corrupt chunk table or offset?)"
        ));
    }
    if count == 0 {
        return Ok(ChunkSummary { chunks: 0, points: 0 });
    }
    let mut init = [0u8; 4];
    if read_at(src, table_at + 8, &mut init).is_err() {
        return Err(format!("the LAZ chunk table (at byte {table_at}) is cut short (truncated?)"));
    }
    if init == BAD_CODE_START {
        return Err(format!("the LAZ chunk table (at byte {table_at}) is corrupt: its entries do not decode"));
    }
    src.seek(SeekFrom::Start(table_at)).map_err(|e| format!("the LAZ chunk table cannot be read: {e}"))?;
    let table = ChunkTable::read(&mut BufReader::new(&mut *src), vlr.uses_variable_size_chunks()).map_err(|e| {
        if e.kind() == std::io::ErrorKind::UnexpectedEof {
            format!("the LAZ chunk table (at byte {table_at}) is cut short (truncated?)")
        } else {
            format!("the LAZ chunk table (at byte {table_at}) does not decode: {e}")
        }
    })?;
    // Each entry: its bytes before the table, its points within what a chunk
    // may decode to, and its contents ([`check_chunk`]).
    let fixed = (!vlr.uses_variable_size_chunks()).then(|| u64::from(vlr.chunk_size()));
    let mut at = chunks_start;
    let mut points = 0u64;
    for (i, entry) in table.as_ref().iter().enumerate() {
        let n = fixed.unwrap_or(entry.point_count);
        let Some(end) = at.checked_add(entry.byte_count).filter(|&end| end <= table_at) else {
            return Err(format!(
                "LAZ chunk {i} of {count} (at byte {at}) says it holds {} bytes, past the chunk table at byte {table_at}",
                shown(entry.byte_count)
            ));
        };
        if n.saturating_mul(record_len) > MAX_CHUNK_BYTES {
            return Err(format!(
                "LAZ chunk {i} of {count} counts {} points of {record_len} bytes, more than a chunk may hold",
                shown(n)
            ));
        }
        if entry.byte_count > 0 {
            check_chunk(src, at, entry.byte_count, vlr.items())
                .map_err(|reason| format!("LAZ chunk {i} of {count} (at byte {at}): {reason}"))?;
        }
        points = points.saturating_add(n);
        at = end;
    }
    Ok(ChunkSummary { chunks: count, points })
}

/// Where the chunk table starts, read as the crate reads it
/// (`ChunkTable::read_offset`), checked to lie after the offset itself and
/// to leave room for the table's 8-byte header before the file's end.
fn table_offset<R: Read + Seek>(src: &mut R, file_len: u64, data_start: u64) -> Result<u64, String> {
    let mut word = [0u8; 8];
    let chunks_start = data_start + 8;
    if chunks_start > file_len || read_at(src, data_start, &mut word).is_err() {
        return Err(format!(
            "the LAZ points at byte {data_start} end before their chunk-table offset ({file_len} bytes; truncated?)"
        ));
    }
    let mut table_at = i64::from_le_bytes(word);
    if table_at <= data_start as i64 {
        if read_at(src, file_len - 8, &mut word).is_ok() {
            table_at = i64::from_le_bytes(word);
        }
        if table_at <= data_start as i64 {
            return Err("the LAZ points have no chunk table (its offset was never written)".into());
        }
    }
    let table_at = table_at as u64;
    if table_at.checked_add(8).is_none_or(|end| end > file_len) {
        return Err(format!(
            "the LAZ chunk table is said to start at byte {table_at}, past the file's end \
             ({file_len} bytes; truncated, or a corrupt offset?)"
        ));
    }
    if table_at < chunks_start {
        return Err(format!("the LAZ chunk table is said to start at byte {table_at}, inside its own offset"));
    }
    Ok(table_at)
}

/// The layers of a layered chunk (items of version 3 or 4), or None for
/// point-wise items: 9 for the point, 1 for RGB and for the wave packet, 2
/// for RGB and NIR, 1 per extra byte, as the crate's field decompressors
/// read them (`read_layers_sizes`).
fn layer_count(items: &[LazItem]) -> Option<u64> {
    if !items.first().is_some_and(|i| matches!(i.version(), 3 | 4)) {
        return None;
    }
    Some(
        items
            .iter()
            .map(|i| match i.item_type() {
                LazItemType::Point14 => 9,
                LazItemType::RGB14 | LazItemType::WavePacket14 => 1,
                LazItemType::RGBNIR14 => 2,
                LazItemType::Byte14(n) => u64::from(n),
                // The crate refuses any other item in a layered chunk before it reads one.
                _ => 0,
            })
            .sum(),
    )
}

/// Checks one chunk, `len` bytes at `start` in `src`, before the crate
/// decodes it. A layered chunk (items of version 3 or 4) holds its first
/// point raw (the items' sizes), its point count (u32, which the crate
/// ignores) and one u32 size per layer, then the layers, which must fit in
/// what is left: the crate zero-fills each layer's stated size before it
/// reads it. A point-wise chunk holds its first point raw, then one
/// arithmetic code. No code may start with [`BAD_CODE_START`].
pub(crate) fn check_chunk<R: Read + Seek>(src: &mut R, start: u64, len: u64, items: &[LazItem]) -> Result<(), String> {
    let first = items.iter().map(|i| u64::from(i.size())).sum::<u64>();
    let io = |e: std::io::Error| format!("it cannot be read: {e}");
    let mut codes = Vec::new();
    match layer_count(items) {
        None => codes.push(first),
        Some(layers) => {
            let layers_at = first + 4 + 4 * layers;
            if len < layers_at {
                return Err(format!(
                    "it holds {len} bytes, fewer than its first point and {layers} layer sizes take ({layers_at})"
                ));
            }
            let mut sizes = vec![0u8; 4 * layers as usize];
            read_at(src, start + first + 4, &mut sizes).map_err(io)?;
            let sizes: Vec<u64> =
                sizes.chunks_exact(4).map(|b| u64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))).collect();
            let total: u64 = sizes.iter().sum();
            let room = len - layers_at;
            if total > room {
                return Err(format!(
                    "its layers add up to {total} bytes, but it holds only {room} after its first point \
                     (a corrupt layer size?)"
                ));
            }
            let mut at = layers_at;
            for size in sizes {
                if size > 0 {
                    codes.push(at);
                }
                at += size;
            }
        }
    }
    for at in codes {
        let mut word = [0u8; 4];
        // A code shorter than 4 bytes fails to decode, as it should.
        if at + 4 <= len && read_at(src, start + at, &mut word).is_ok() && word == BAD_CODE_START {
            return Err(format!("its code at byte {at} of the chunk starts with ff ff ff ff (corrupt data)"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    /// A LAZ record for point format 6 with variable-size chunks (COPC's): one Point14 item, 30 bytes.
    fn layered_vlr() -> LazVlr {
        laz::LazVlrBuilder::default().with_point_format(6, 0).unwrap().with_variable_chunk_size().build()
    }

    /// One layered chunk of `points` points, compressed by the crate.
    fn chunk(vlr: &LazVlr, points: usize) -> Vec<u8> {
        use laz::record::{LayeredPointRecordCompressor, RecordCompressor};
        let mut compressor = LayeredPointRecordCompressor::new(Cursor::new(Vec::new()));
        compressor.set_fields_from(vlr.items()).unwrap();
        for k in 0..points {
            let mut record = [0u8; 30];
            record[..4].copy_from_slice(&(k as i32 * 7).to_le_bytes());
            record[4..8].copy_from_slice(&(k as i32 * 3).to_le_bytes());
            record[14] = 0x11;
            compressor.compress_next(&record).unwrap();
        }
        compressor.done().unwrap();
        compressor.get_mut().get_ref().clone()
    }

    #[test]
    fn a_sound_chunk_passes_and_a_layer_larger_than_its_chunk_is_refused() {
        let vlr = layered_vlr();
        let bytes = chunk(&vlr, 500);
        let len = bytes.len() as u64;
        assert_eq!(check_chunk(&mut Cursor::new(&bytes), 0, len, vlr.items()), Ok(()));
        // The first layer size follows the 30-byte first point and the u32 count.
        let mut flipped = bytes.clone();
        flipped[34..38].copy_from_slice(&[0xff; 4]);
        let error = check_chunk(&mut Cursor::new(&flipped), 0, len, vlr.items()).unwrap_err();
        assert!(error.contains("layers add up to"), "{error}");
        // A chunk too short for its layer sizes.
        let error = check_chunk(&mut Cursor::new(&bytes[..40]), 0, 40, vlr.items()).unwrap_err();
        assert!(error.contains("fewer than its first point"), "{error}");
    }

    #[test]
    fn a_code_starting_with_four_ff_bytes_is_refused() {
        let vlr = layered_vlr();
        let mut bytes = chunk(&vlr, 500);
        let len = bytes.len() as u64;
        // The layers start after the first point, the count and 9 layer sizes.
        let layers_at = 30 + 4 + 36;
        bytes[layers_at..layers_at + 4].copy_from_slice(&[0xff; 4]);
        let error = check_chunk(&mut Cursor::new(&bytes), 0, len, vlr.items()).unwrap_err();
        assert!(error.contains("ff ff ff ff"), "{error}");
    }

    #[test]
    fn shown_sizes_are_the_files_signed_ones() {
        assert_eq!(shown(0xFFFF_FFFF_8000_0000), "-2147483648");
        assert_eq!(shown(42), "42");
    }
}
