//! Where each scan's points lie in an E57 file, checked before the `e57`
//! crate decodes any of them (ASTM E2807: a scan's `points` is a
//! CompressedVector whose `fileOffset` names a binary section: a 32-byte
//! header giving the section's length and its first data packet, then data
//! packets, each carrying a slice of every field's byte stream).
//!
//! The crate trusts `recordCount`: it decodes packets until it has that many
//! points, reading past the section into whatever follows ("Found unknown
//! packet ID"), and it decodes a section once for each scan that names it, so
//! 20,000 scans naming one 34 KB section are 41.8M points. Here every
//! section's packets are walked (their headers only, each page's CRC
//! checked) to count the bytes each field's stream holds, and a scan is
//! refused when it shares or overlaps another's section or counts more
//! points than its streams hold, or when no field of its points takes a bit
//! in the file (the crate would make such values without end). Points are
//! then bounded by the file's bytes, and the columns can be reserved once.
//!
//! The walk, the fields' bit sizes and the CRC-32C are written out here
//! because the crate keeps its own private (its section header, packet
//! reader, `bit_size` and checksum are `pub(crate)`).

use std::collections::HashMap;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

use e57::{PointCloud, RecordDataType};

/// One scan's binary section.
struct Section {
    /// Logical bytes `start..end` (pages' CRC words left out).
    start: u64,
    end: u64,
    /// Points the section's streams hold: the fewest any field's stream holds.
    holds: u64,
}

/// Bytes of a section header, of a data packet's header and of each stream's size in it.
const SECTION_HEADER: u64 = 32;
const DATA_HEADER: u64 = 6;
const INDEX_HEADER: u64 = 16;
const IGNORED_HEADER: u64 = 4;

/// Checks every scan's section: none shared or overlapping, none counting
/// more points than it holds. Why not, as a reason for [`super::CloudError`].
pub(crate) fn check(path: &Path, page_size: u64, scans: &[PointCloud]) -> Result<(), String> {
    let mut pages = Pages::open(path, page_size)?;
    let mut found: Vec<Section> = Vec::with_capacity(scans.len());
    let mut by_offset: HashMap<u64, usize> = HashMap::with_capacity(scans.len());
    for (index, scan) in scans.iter().enumerate() {
        if let Some(other) = by_offset.insert(scan.file_offset, index) {
            return Err(format!(
                "scans {other} and {index} name one binary section (byte {}); each scan needs its own",
                scan.file_offset
            ));
        }
        let section = pages.section(scan).map_err(|e| format!("scan {index}: {e}"))?;
        if scan.records > section.holds {
            return Err(format!(
                "scan {index} counts {} points (recordCount), but its binary section holds only {}",
                scan.records, section.holds
            ));
        }
        found.push(section);
    }
    let mut order: Vec<usize> = (0..found.len()).collect();
    order.sort_unstable_by_key(|&i| found[i].start);
    for pair in order.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if found[b].start < found[a].end {
            return Err(format!("the binary sections of scans {} and {} overlap", a.min(b), a.max(b)));
        }
    }
    Ok(())
}

/// Bits one value of the field takes in its stream (the crate's `bit_size`, which is private).
fn bits(data_type: &RecordDataType) -> u64 {
    match *data_type {
        RecordDataType::Single { .. } => 32,
        RecordDataType::Double { .. } => 64,
        RecordDataType::ScaledInteger { min, max, .. } | RecordDataType::Integer { min, max } => {
            let range = i128::from(max) - i128::from(min);
            if range > 0 { u64::from(range.ilog2()) + 1 } else { 0 }
        }
    }
}

/// The file's pages read as one logical stream, each page's CRC checked on first use.
struct Pages {
    file: File,
    page_size: u64,
    pages: u64,
    current: Option<u64>,
    buffer: Vec<u8>,
}

impl Pages {
    fn open(path: &Path, page_size: u64) -> Result<Self, String> {
        let file = File::open(path).map_err(|e| e.to_string())?;
        let len = file.metadata().map_err(|e| e.to_string())?.len();
        // The crate has checked the page size (4 < size <= 1 MiB) and that the file is whole pages.
        if page_size <= 4 || page_size > 1 << 20 || len % page_size != 0 {
            return Err(format!("a page size of {page_size} bytes for a file of {len}"));
        }
        Ok(Self { file, page_size, pages: len / page_size, current: None, buffer: vec![0; page_size as usize] })
    }

    fn payload(&self) -> u64 {
        self.page_size - 4
    }

    /// Logical bytes in the file.
    fn len(&self) -> u64 {
        self.pages * self.payload()
    }

    fn logical(&self, physical: u64) -> u64 {
        physical - physical / self.page_size * 4
    }

    fn physical(&self, logical: u64) -> u64 {
        logical / self.payload() * self.page_size + logical % self.payload()
    }

    /// Logical bytes `at..at + buf.len()`.
    fn read(&mut self, mut at: u64, buf: &mut [u8]) -> Result<(), String> {
        let mut done = 0;
        while done < buf.len() {
            let page = at / self.payload();
            if page >= self.pages {
                return Err(format!("byte {} lies past the end of the file", self.physical(at)));
            }
            if self.current != Some(page) {
                self.current = None;
                self.file.seek(SeekFrom::Start(page * self.page_size)).map_err(|e| e.to_string())?;
                self.file.read_exact(&mut self.buffer).map_err(|e| e.to_string())?;
                let (data, stored) = self.buffer.split_at(self.payload() as usize);
                if crc32c(data).to_be_bytes() != stored {
                    return Err(format!("page {page} fails its checksum (a corrupt file)"));
                }
                self.current = Some(page);
            }
            let from = (at % self.payload()) as usize;
            let n = (buf.len() - done).min(self.payload() as usize - from);
            buf[done..done + n].copy_from_slice(&self.buffer[from..from + n]);
            done += n;
            at += n as u64;
        }
        Ok(())
    }

    fn u16_at(&mut self, at: u64) -> Result<u64, String> {
        let mut b = [0u8; 2];
        self.read(at, &mut b)?;
        Ok(u64::from(u16::from_le_bytes(b)))
    }

    /// The scan's section header, then its packets' headers: the points its streams hold.
    fn section(&mut self, scan: &PointCloud) -> Result<Section, String> {
        let at = scan.file_offset;
        let start = self.logical(at);
        let mut header = [0u8; SECTION_HEADER as usize];
        self.read(start, &mut header).map_err(|e| format!("its binary section (byte {at}): {e}"))?;
        let word = |i: usize| u64::from_le_bytes(header[i..i + 8].try_into().expect("eight bytes"));
        let (length, data) = (word(8), word(16));
        if header[0] != 1 {
            return Err(format!("byte {at} holds no compressed vector section"));
        }
        let end = start.checked_add(length).filter(|&end| length >= SECTION_HEADER && end <= self.len());
        let Some(end) = end.filter(|_| length % 4 == 0) else {
            return Err(format!(
                "its binary section (byte {at}) claims {length} bytes; the file holds {} from there",
                self.len().saturating_sub(start)
            ));
        };
        let streams: Vec<u64> = scan.prototype.iter().map(|r| bits(&r.data_type)).collect();
        if scan.records == 0 {
            return Ok(Section { start, end, holds: 0 });
        }
        if streams.iter().all(|&b| b == 0) {
            // The crate would make values for such fields without end.
            return Err("every field of its points is a constant (no bits in the file); refusing it".into());
        }
        let mut bytes = vec![0u64; streams.len()];
        let mut packet = self.logical(data);
        if packet < start + SECTION_HEADER || packet > end {
            return Err(format!("its first data packet (byte {data}) lies outside its section"));
        }
        while packet < end {
            let mut head = [0u8; 4];
            self.read(packet, &mut head)?;
            let length = u64::from(u16::from_le_bytes([head[2], head[3]])) + 1;
            let least = match head[0] {
                0 => INDEX_HEADER,
                1 => DATA_HEADER + 2 * streams.len() as u64,
                2 => IGNORED_HEADER,
                other => return Err(format!("a packet of type {other} at byte {} (corrupt?)", self.physical(packet))),
            };
            if length % 4 != 0 || length < least || packet + length > end {
                return Err(format!("a packet of {length} bytes at byte {} (corrupt?)", self.physical(packet)));
            }
            if head[0] == 1 {
                let count = self.u16_at(packet + 4)?;
                if count != streams.len() as u64 {
                    return Err(format!("a data packet of {count} streams for {} fields", streams.len()));
                }
                let mut used = DATA_HEADER + 2 * count;
                for (i, total) in bytes.iter_mut().enumerate() {
                    let size = self.u16_at(packet + DATA_HEADER + 2 * i as u64)?;
                    *total += size;
                    used += size;
                }
                // The crate reads a packet's streams, then the next packet at the next 4-byte boundary.
                if used.next_multiple_of(4) != length {
                    return Err(format!(
                        "a data packet of {length} bytes at byte {} whose streams fill {used}",
                        self.physical(packet)
                    ));
                }
            }
            packet += length;
        }
        let holds = streams.iter().zip(&bytes).filter(|(b, _)| **b > 0).map(|(b, n)| n * 8 / b).min().unwrap_or(0);
        Ok(Section { start, end, holds })
    }
}

/// CRC-32C (Castagnoli), as E57 pages carry it (stored big-endian).
fn crc32c(bytes: &[u8]) -> u32 {
    const TABLE: [u32; 256] = {
        let mut table = [0u32; 256];
        let mut i = 0;
        while i < 256 {
            let mut c = i as u32;
            let mut k = 0;
            while k < 8 {
                c = if c & 1 != 0 { (c >> 1) ^ 0x82F6_3B78 } else { c >> 1 };
                k += 1;
            }
            table[i] = c;
            i += 1;
        }
        table
    };
    !bytes.iter().fold(!0u32, |c, &b| TABLE[((c ^ u32::from(b)) & 0xff) as usize] ^ (c >> 8))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc32c_matches_the_standard_check_value() {
        assert_eq!(crc32c(b"123456789"), 0xE306_9283);
    }
}
