//! A seeded mutation fuzz test of the PLY loader, bounded in time for CI:
//! a few thousand variants of small binary (both endians) and ASCII files,
//! made by truncation, byte flips, count lies, type swaps, huge counts and
//! line shuffles. Every variant must load or fail with an error; none may
//! panic, hang, or allocate more than [`MAX_PEAK_BYTES`] at once.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use common::plywriter::{Element, Encoding, ply};

/// Counts the bytes allocated now and the peak since the last reset.
struct CountingAllocator;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = CURRENT.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        CURRENT.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

/// Most memory one load of a file under 4 KB may hold at once. A lying count
/// that was believed would ask for gigabytes.
const MAX_PEAK_BYTES: usize = 64 << 20;

/// Longest one load may take before it counts as a hang.
const MAX_SECONDS_PER_FILE: u64 = 20;

/// Variants per seed file.
const VARIANTS: usize = 1000;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

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
    let (mut loaded, mut refused) = (0usize, 0usize);
    let mut worst_peak = 0usize;
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
            let base = CURRENT.load(Ordering::Relaxed);
            PEAK.store(base, Ordering::Relaxed);
            let t = Instant::now();
            let result = std::panic::catch_unwind(|| pointblend::cloud::load(&path));
            let elapsed = t.elapsed();
            let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
            worst_peak = worst_peak.max(peak);
            let keep = dir.path().join(format!("failing-{name}-{variant}.ply"));
            let fail = |what: String| {
                let _ = std::fs::copy(&path, &keep);
                panic!("{name} variant {variant}: {what} (kept as {})", keep.display());
            };
            match result {
                Err(_) => fail("the loader panicked".into()),
                Ok(Ok((cloud, _))) => {
                    assert!(cloud.is_consistent(), "{name} variant {variant}: inconsistent cloud");
                    assert!(cloud.positions.iter().all(|p| p.is_finite()), "{name} {variant}: non-finite position");
                    assert!(cloud.radii.iter().all(|r| r.is_finite() && *r > 0.0), "{name} {variant}: bad radius");
                    loaded += 1;
                }
                Ok(Err(e)) => {
                    let text = e.to_string();
                    assert!(!text.contains('\n') && text.contains(&format!("{name}-{variant}.ply")), "{text}");
                    refused += 1;
                }
            }
            if peak > MAX_PEAK_BYTES {
                fail(format!("a load of {} bytes allocated {peak} bytes at once", bytes.len()));
            }
            if elapsed > Duration::from_secs(MAX_SECONDS_PER_FILE) {
                fail(format!("a load took {elapsed:?}"));
            }
            let _ = std::fs::remove_file(&path);
        }
    }
    println!(
        "{} variants: {loaded} loaded, {refused} refused, largest allocation peak {:.1} MB, {:.1} s",
        loaded + refused,
        worst_peak as f64 / 1e6,
        started.elapsed().as_secs_f64()
    );
    assert!(loaded > 100 && refused > 100, "the mutations reach both outcomes: {loaded} loaded, {refused} refused");
}
