//! A seeded mutation fuzz test of the LAS and LAZ reader, bounded in time for
//! CI: variants of small LAS 1.4 and LAZ files (written by the `las` crate,
//! one with an extra-bytes record), made by byte flips in the header and the
//! VLRs, count and offset lies, and truncation. Every variant must load or
//! fail with one line naming the file; none may panic, hang, or allocate more
//! than `common::fuzz::MAX_PEAK_BYTES` at once.

mod common;

use std::time::Instant;

use common::fuzz::Rng;
use common::lidar::{self, tilted_grid};

counting_allocator!();

/// Variants per seed file.
const VARIANTS: usize = 600;

/// Small, valid seed files: LAS and LAZ, with and without extra bytes.
fn seeds(dir: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let points = tilted_grid(20, 0.5, 0.2, [1000.0, 2000.0, 10.0]);
    [("plain.las", None), ("extra.las", Some("Amplitude")), ("plain.laz", None), ("extra.laz", Some("Amplitude"))]
        .into_iter()
        .map(|(name, extra)| {
            let path = lidar::write(&dir.join(name), &points, [1000.0, 2000.0, 0.0], extra);
            (name.to_string(), std::fs::read(path).unwrap())
        })
        .collect()
}

/// The LAS 1.4 header's counts and offsets: (byte offset, width).
const FIELDS: [(usize, usize); 7] = [(94, 2), (96, 4), (100, 4), (105, 2), (107, 4), (235, 8), (247, 8)];

/// One mutation of `file`'s header and VLRs (what comes before the point
/// data). Flips inside LAZ chunks are not made: the `laz` crate trusts a
/// chunk's layer sizes and allocates them before it reads (up to 4 GB for a
/// flipped size), which no check before decoding can see.
fn mutate(file: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut out = file.to_vec();
    let front = u32::from_le_bytes(file[96..100].try_into().unwrap()) as usize;
    match rng.below(5) {
        0 => out.truncate(rng.below(file.len())),
        1 | 2 => {
            for _ in 0..1 + rng.below(6) {
                let at = rng.below(front);
                out[at] ^= 1 << rng.below(8);
            }
        }
        // A count, offset or size replaced by an extreme value.
        3 => {
            let (at, width) = FIELDS[rng.below(FIELDS.len())];
            let values: [u64; 6] = [0, 1, 399, 401, u32::MAX as u64, u64::MAX];
            let v = values[rng.below(values.len())].to_le_bytes();
            out[at..at + width].copy_from_slice(&v[..width]);
        }
        // The point format, the extra-bytes type or a scale replaced.
        _ => {
            let at = [104, 131, 139, 147, 375 + 54 + 2][rng.below(5)].min(front - 1);
            out[at] = rng.next() as u8;
        }
    }
    out
}

#[test]
fn hundreds_of_mutated_las_files_load_or_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let mut tally = common::fuzz::Tally::default();
    let started = Instant::now();
    for (s, (name, seed)) in seeds(dir.path()).into_iter().enumerate() {
        let (stem, ext) = name.split_once('.').unwrap();
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ (s as u64 + 1));
        for variant in 0..VARIANTS {
            let bytes = mutate(&seed, &mut rng);
            let file_name = format!("{stem}-{variant}.{ext}");
            let path = dir.path().join(&file_name);
            std::fs::write(&path, &bytes).unwrap();
            checked_load(&path, &mut tally);
            let _ = std::fs::remove_file(&path);
        }
    }
    tally.finish(started);
}
