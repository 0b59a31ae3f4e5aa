//! Opening a LAS or LAZ file for the `las` crate, after checking what the
//! crate would act on unchecked: every reader of these files (a whole-file
//! read, `convert` to COPC) opens them through [`open`].
//!
//! The crate allocates each VLR's and EVLR's stated length before reading
//! it, seeks past the points the header counts (a count of 2^40 made that
//! seek fail with "Invalid argument"), and hands LAZ points to the `laz`
//! crate, which trusts its chunk table and chunks
//! ([`super::laz_check`]). So the raw header is read first and each of
//! those is checked against the file's length: the header's own size, the
//! records' offsets and lengths, the LAZ record, the point count against
//! the bytes (LAS) or the chunk table (LAZ).
//!
//! The crate also raises a file's version when its contents need a later
//! one, and logs that without the file's name; its line is silenced by the
//! command line and [`open`] logs one naming the file.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use super::laz_check::{self, MAX_CHUNK_BYTES};
use super::{crate_error, las_error};
use crate::cloud::CloudError;

/// Opens the LAS/LAZ file at `path` (a regular file) for reading, once its
/// header, records and LAZ chunks pass the checks of this module. Returns
/// the reader and the file's length.
pub(crate) fn open(path: &Path) -> Result<(las::Reader, u64), CloudError> {
    let (mut file, file_len) = crate::input::open(path).map_err(|e| CloudError::io(path, e))?;
    let version = check_offsets(path, &mut file, file_len)?;
    let reader = las::Reader::new(BufReader::new(file)).map_err(|e| crate_error(path, e))?;
    let read_as = reader.header().version();
    if read_as != version {
        log::warn!(
            "{}: its header says LAS {version}, but its point format or records need LAS {read_as}; read as LAS {read_as}",
            path.display()
        );
    }
    Ok((reader, file_len))
}

/// Refuses a header whose size is too small for its version, whose point
/// data, VLRs or EVLRs would lie past the file's end, whose point count
/// the file cannot hold, or whose LAZ chunks would not decode safely,
/// before the `las` crate reads them. Returns the version the header says.
fn check_offsets(path: &Path, file: &mut File, file_len: u64) -> Result<las::Version, CloudError> {
    let raw = las::raw::Header::read_from(&mut *file).map_err(|e| crate_error(path, e))?;
    let least = raw.version.header_size();
    if raw.header_size < least {
        return Err(las_error(
            path,
            format!(
                "its header says it is {} bytes long, but a LAS {} header takes {least}",
                raw.header_size, raw.version
            ),
        ));
    }
    let start = raw.offset_to_point_data as u64;
    if start > file_len {
        return Err(las_error(
            path,
            format!("the point data starts at byte {start}, past the file's end ({file_len} bytes)"),
        ));
    }
    // The first LAZ record, as the crate takes it; None where it is not chunked.
    let mut laz_vlr: Option<laz::LazVlr> = None;
    let mut laz_seen = false;
    // Each record's header holds its length at byte 20: u16 for VLRs (54-byte headers), u64 for EVLRs (60).
    let mut walk = |first: u64, count: u64, header: u64, what: &str| -> Result<(), CloudError> {
        let mut at = first;
        for i in 0..count {
            let mut bytes = [0u8; 60];
            let fits = at.checked_add(header).is_some_and(|end| end <= file_len);
            if !fits
                || file.seek(SeekFrom::Start(at)).and_then(|_| file.read_exact(&mut bytes[..header as usize])).is_err()
            {
                return Err(las_error(
                    path,
                    format!("{what} {i} of {count} starts past the file's end ({file_len} bytes)"),
                ));
            }
            let len = if header == 54 {
                u16::from_le_bytes([bytes[20], bytes[21]]) as u64
            } else {
                u64::from_le_bytes(bytes[20..28].try_into().unwrap_or([0xff; 8]))
            };
            if header == 54 && &bytes[2..16] == b"laszip encoded" && u16::from_le_bytes([bytes[18], bytes[19]]) == 22204
            {
                let vlr = check_laz_record(path, file, at + header, len, raw.point_data_record_length)?;
                if !laz_seen {
                    (laz_seen, laz_vlr) = (true, vlr);
                }
            }
            at = match at.checked_add(header + len) {
                Some(end) if end <= file_len => end,
                _ => return Err(las_error(path, format!("{what} {i} says it holds {len} bytes, past the file's end"))),
            };
        }
        Ok(())
    };
    walk(raw.header_size as u64, raw.number_of_variable_length_records as u64, 54, "VLR")?;
    if let Some(evlr) = raw.evlr.filter(|e| e.number_of_evlrs > 0) {
        walk(evlr.start_of_first_evlr, evlr.number_of_evlrs as u64, 60, "EVLR")?;
    }
    check_count(path, file, file_len, &raw, laz_vlr.as_ref())?;
    file.rewind().map_err(|e| CloudError::io(path, e))?;
    Ok(raw.version)
}

/// Refuses a point count the file cannot hold, before the crate seeks past
/// the points it counts. The count is the crate's (its private
/// `raw::Header::number_of_point_records`): the legacy u32 unless it is 0,
/// then LAS 1.4's u64. Uncompressed, the records must fit in the file;
/// compressed, the chunk table must list as many ([`laz_check::check_chunks`]).
fn check_count(
    path: &Path,
    file: &mut File,
    file_len: u64,
    raw: &las::raw::Header,
    laz_vlr: Option<&laz::LazVlr>,
) -> Result<(), CloudError> {
    let declared = match (raw.number_of_point_records, raw.large_file) {
        (0, Some(large)) => large.number_of_point_records,
        (n, _) => u64::from(n),
    };
    let start = u64::from(raw.offset_to_point_data);
    let record_len = u64::from(raw.point_data_record_length);
    if raw.point_data_record_format & 0x80 == 0 {
        let end = declared.checked_mul(record_len).and_then(|bytes| bytes.checked_add(start));
        if end.is_none_or(|end| end > file_len) {
            return Err(las_error(
                path,
                format!(
                    "the header counts {declared} points of {record_len} bytes, more than the file's {file_len} bytes hold"
                ),
            ));
        }
    } else if let Some(vlr) = laz_vlr {
        let chunks = laz_check::check_chunks(file, file_len, start, vlr).map_err(|reason| las_error(path, reason))?;
        if declared > chunks.points {
            return Err(las_error(
                path,
                format!(
                    "the header counts {declared} points, more than the LAZ chunk table lists ({} in {} chunks)",
                    chunks.points, chunks.chunks
                ),
            ));
        }
    }
    Ok(())
}

/// Refuses a LAZ record (the `laszip encoded` VLR) that the `laz` crate
/// would act on unchecked: a chunk size (u32 at byte 12; u32::MAX: chunks of
/// any size) that makes it allocate more than [`MAX_CHUNK_BYTES`] at once, or
/// items (6 bytes each from byte 34, their size at +2) whose sizes do not add
/// up to the header's record length (the crate asserts they do). Returns
/// the record when its compressor is a chunked one (2: point-wise, 3:
/// layered), whose chunks [`laz_check`] checks; the crate refuses the others.
fn check_laz_record(
    path: &Path,
    file: &mut File,
    data: u64,
    len: u64,
    record_len: u16,
) -> Result<Option<laz::LazVlr>, CloudError> {
    let mut bytes = vec![0u8; len as usize];
    if len < 34 || file.seek(SeekFrom::Start(data)).and_then(|_| file.read_exact(&mut bytes)).is_err() {
        return Err(las_error(path, "the LAZ record is too short"));
    }
    let chunk = u32::from_le_bytes(bytes[12..16].try_into().unwrap_or([0; 4]));
    if chunk != u32::MAX && chunk as u64 * record_len as u64 > MAX_CHUNK_BYTES {
        return Err(las_error(
            path,
            format!("the LAZ chunk size of {chunk} points is implausible ({record_len}-byte records)"),
        ));
    }
    let items = u16::from_le_bytes([bytes[32], bytes[33]]) as usize;
    let sizes: Option<u64> = (0..items)
        .map(|i| bytes.get(34 + 6 * i + 2..34 + 6 * i + 4).map(|b| u16::from_le_bytes([b[0], b[1]]) as u64))
        .sum();
    match sizes {
        Some(total) if total == record_len as u64 => {
            if !matches!(u16::from_le_bytes([bytes[0], bytes[1]]), 2 | 3) {
                return Ok(None);
            }
            laz::LazVlr::read_from(&bytes[..]).map(Some).map_err(|e| las_error(path, format!("its LAZ record: {e}")))
        }
        Some(total) => Err(las_error(
            path,
            format!("the LAZ items take {total} bytes per point, but the header's records are {record_len} bytes"),
        )),
        None => Err(las_error(path, format!("the LAZ record lists {items} items but holds fewer"))),
    }
}
