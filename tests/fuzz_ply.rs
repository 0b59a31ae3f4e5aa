//! A seeded mutation fuzz test of the PLY loader, bounded in time for CI:
//! a few thousand variants of small binary (both endians) and ASCII files,
//! made by truncation, byte flips, count lies, type swaps, huge counts and
//! line shuffles. Every variant must load or fail with an error; none may
//! panic, hang, or allocate more than `common::fuzz::MAX_PEAK_BYTES` at once.

mod common;

use std::time::Instant;

use common::fuzz::Rng;
use common::plywriter::{Element, Encoding, ply};

counting_allocator!();

/// Variants per seed file.
const VARIANTS: usize = 1000;

/// Small, valid seed files: a coloured, oriented cloud with faces, in each encoding.
fn seeds() -> Vec<(String, Vec<u8>)> {
    let rows: Vec<Vec<f64>> = (0..24)
        .map(|i| {
            let (x, y) = ((i % 6) as f64 * 0.1, (i / 6) as f64 * 0.1);
            vec![x, y, 0.01 * (i as f64).sin(), 0.0, 0.0, 1.0, 0.08, (i * 10) as f64, 120.0, 200.0]
        })
        .collect();
    let names = ["x", "y", "z", "nx", "ny", "nz", "radius", "red", "green", "blue"];
    let types = ["float", "float", "float", "float", "float", "float", "float", "uchar", "uchar", "uchar"];
    let vertex = || Element { name: "vertex", properties: types.into_iter().zip(names).collect(), rows: rows.clone() };
    let faces = || Element {
        name: "face",
        properties: vec![("list uchar int", "vertex_indices")],
        rows: (0..15).map(|i| vec![3.0, i as f64, i as f64 + 1.0, i as f64 + 6.0]).collect(),
    };
    let strips = || Element {
        name: "tristrips",
        properties: vec![("list int int", "vertex_indices")],
        rows: vec![vec![7.0, 0.0, 6.0, 1.0, 7.0, -1.0, 2.0, 8.0]],
    };
    [Encoding::Ascii, Encoding::Little, Encoding::Big]
        .into_iter()
        .flat_map(|enc| {
            [
                (format!("{enc:?}-faces"), ply(enc, &[vertex(), faces()], &["seed"], false)),
                (format!("{enc:?}-strips"), ply(enc, &[vertex(), strips()], &[], true)),
            ]
        })
        .collect()
}

/// One mutation of `file`.
fn mutate(file: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut out = file.to_vec();
    let header_end = file.windows(10).position(|w| w == b"end_header").unwrap_or(file.len());
    match rng.below(7) {
        // Truncation anywhere.
        0 => out.truncate(rng.below(file.len())),
        // Byte flips, anywhere or in the body.
        1 | 2 => {
            for _ in 0..1 + rng.below(8) {
                let at = rng.below(out.len());
                out[at] ^= 1 << rng.below(8);
            }
        }
        // Count lies: a different, possibly huge, element count.
        3 => {
            let counts = ["0", "1", "23", "25", "4294967295", "4294967296", "18446744073709551615", "99999999999"];
            let text = String::from_utf8_lossy(&file[..header_end]).to_string();
            let element = if rng.below(2) == 0 { "vertex" } else { "face" };
            let lie = counts[rng.below(counts.len())];
            let replaced: Vec<String> = text
                .lines()
                .map(|l| {
                    if l.starts_with(&format!("element {element} ")) {
                        format!("element {element} {lie}")
                    } else {
                        l.into()
                    }
                })
                .collect();
            out = [replaced.join("\n").as_bytes(), &file[header_end..]].concat();
        }
        // Type swaps in the header.
        4 => {
            let text = String::from_utf8_lossy(&file[..header_end]).to_string();
            let types =
                ["char", "uchar", "short", "int", "uint", "float", "double", "list uchar float", "list int int"];
            let mut lines: Vec<String> = text.lines().map(String::from).collect();
            let properties: Vec<usize> = (0..lines.len()).filter(|&i| lines[i].starts_with("property")).collect();
            let line = properties[rng.below(properties.len())];
            let name = lines[line].rsplit(' ').next().unwrap_or("x").to_string();
            lines[line] = format!("property {} {name}", types[rng.below(types.len())]);
            out = [lines.join("\n").as_bytes(), &file[header_end..]].concat();
        }
        // A run of bytes copied over another place (shuffled records, duplicated lines).
        5 => {
            let (from, to, len) = (rng.below(out.len()), rng.below(out.len()), 1 + rng.below(40));
            let chunk: Vec<u8> = out[from..(from + len).min(out.len())].to_vec();
            for (k, b) in chunk.into_iter().enumerate() {
                if let Some(slot) = out.get_mut(to + k) {
                    *slot = b;
                }
            }
        }
        // Garbage appended or inserted.
        _ => {
            let at = rng.below(out.len());
            let junk: Vec<u8> = (0..1 + rng.below(64)).map(|_| rng.next() as u8).collect();
            out.splice(at..at, junk);
        }
    }
    out
}

#[test]
fn thousands_of_mutated_ply_files_load_or_fail_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    let mut tally = common::fuzz::Tally::default();
    let started = Instant::now();
    for (s, (name, seed)) in seeds().into_iter().enumerate() {
        // Each seed file loads as it is.
        let path = dir.path().join(format!("{name}.ply"));
        std::fs::write(&path, &seed).unwrap();
        pointblend::cloud::load(&path).unwrap_or_else(|e| panic!("seed {name}: {e}"));
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15 ^ (s as u64 + 1));
        for variant in 0..VARIANTS {
            let bytes = mutate(&seed, &mut rng);
            let path = dir.path().join(format!("{name}-{variant}.ply"));
            std::fs::write(&path, &bytes).unwrap();
            checked_load(&path, &mut tally);
            let _ = std::fs::remove_file(&path);
        }
    }
    tally.finish(started);
}
