//! Many splats at one spot, through the command line as a user would render
//! them: 100,000 coincident copies, and 20,000 within 1e-4 of one another.
//! Sums of that many fragments must neither stop adding (half floats stop
//! adding 1 at 2048) nor overflow, and grouping must not hold the n² pairs of
//! a complete overlap graph. Each render must peak under 8 GiB of resident
//! memory (read from /proc while it runs; a 48 GiB address-space limit keeps
//! a runaway from taking the machine down) and end within 10 minutes.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use common::plywriter::{Element, Encoding, ply};
use pointblend::frame::RenderMode;

const SIZE: u32 = 96;
const MEMORY_LIMIT_KIB: u64 = 8 << 20;
/// The address-space limit the renders run under: far above the memory limit,
/// since GPU drivers reserve large address ranges they never touch.
const ADDRESS_SPACE_KIB: u64 = 48 << 20;
const TIME_LIMIT: Duration = Duration::from_secs(600);
const RED: [f64; 3] = [200.0, 100.0, 100.0];
const BLUE: [f64; 3] = [100.0, 100.0, 200.0];

/// `count` splats of radius 1 facing +z at the origin (each moved by up to
/// `jitter` along every axis), opacity 0.5, half red and half blue; and four
/// tiny splats at (±3, ±3, 0) that set the bounds, so that the default camera
/// shows the disc about 30 px across at 96².
fn crowd(dir: &Path, name: &str, count: usize, jitter: f64) -> PathBuf {
    let mut rows = Vec::with_capacity(count + 4);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut random = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for i in 0..count {
        // The first half red, the rest blue: a mode that keeps one copy per
        // group and pixel shows mostly red unless the copies are merged.
        let c = if i < count / 2 { RED } else { BLUE };
        let p = [random() * jitter, random() * jitter, random() * jitter];
        rows.push(vec![p[0], p[1], p[2], 0.0, 0.0, 1.0, 1.0, c[0], c[1], c[2], 0.5]);
    }
    for (x, y) in [(-3.0, -3.0), (3.0, -3.0), (-3.0, 3.0), (3.0, 3.0)] {
        rows.push(vec![x, y, 0.0, 0.0, 0.0, 1.0, 0.001, 255.0, 255.0, 255.0, 0.5]);
    }
    let properties = ["x", "y", "z", "nx", "ny", "nz", "radius"].map(|p| ("float", p)).into_iter();
    let properties = properties.chain(["red", "green", "blue"].map(|p| ("uchar", p))).chain([("float", "alpha")]);
    let vertex = Element { name: "vertex", properties: properties.collect(), rows };
    let path = dir.join(name);
    std::fs::write(&path, ply(Encoding::Little, &[vertex], &[], false)).unwrap();
    path
}

/// Renders `file` in `mode`, unlit on black at 96², under the memory and time
/// limits; returns the image and what the command printed.
fn render(file: &Path, mode: RenderMode, dir: &Path) -> (image::RgbImage, String) {
    let out = dir.join(format!("{mode}.png"));
    let mut child = Command::new("sh")
        .env("POINTBLEND_CACHE", dir.join(format!("cache-{mode}"))) // each grouping computed, none read back
        .arg("-c")
        .arg(format!("ulimit -v {ADDRESS_SPACE_KIB} && exec \"$0\" \"$@\""))
        .arg(env!("CARGO_BIN_EXE_pointblend"))
        .args(["render", "--mode", mode.name(), "--unlit", "--background", "0,0,0", "--size", "96x96"])
        .arg(file)
        .arg("--out")
        .arg(&out)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    let status = format!("/proc/{}/status", child.id());
    let mut peak_kib = 0u64;
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > TIME_LIMIT {
            child.kill().unwrap();
            panic!("{mode}: still rendering after {TIME_LIMIT:?}");
        }
        // VmHWM: the process's peak resident memory so far.
        if let Some(kib) = std::fs::read_to_string(&status)
            .ok()
            .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM:"))?.split_whitespace().nth(1)?.parse::<u64>().ok())
        {
            peak_kib = peak_kib.max(kib);
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let output = child.wait_with_output().unwrap();
    let said = format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "{mode} failed:\n{said}");
    println!("{mode}: {:.1} s, peak {} MiB", started.elapsed().as_secs_f64(), peak_kib >> 10);
    assert!(peak_kib < MEMORY_LIMIT_KIB, "{mode}: {peak_kib} KiB resident at its peak");
    (image::open(&out).unwrap().to_rgb8(), said)
}

/// The closed form at the disc's centre, unlit on black: the mean colour,
/// times the opacity in the modes (and the reference) that read it.
fn closed_form(mode: RenderMode) -> [f32; 3] {
    let opacity = if mode.info().transparent || mode == RenderMode::Reference { 0.5 } else { 1.0 };
    [0, 1, 2].map(|k| (0.5 * (RED[k] + BLUE[k]) * opacity) as f32)
}

/// The worst channel error over the central 16x16 pixels, and whether the
/// frame has a black (NaN) pixel inside the disc.
fn centre_error(image: &image::RgbImage, want: [f32; 3]) -> (f32, bool) {
    let (lo, hi) = (SIZE / 2 - 8, SIZE / 2 + 8);
    let mut worst = 0.0f32;
    let mut black = false;
    for y in lo..hi {
        for x in lo..hi {
            let p = image.get_pixel(x, y).0;
            black |= p == [0, 0, 0];
            for k in 0..3 {
                worst = worst.max((p[k] as f32 - want[k]).abs());
            }
        }
    }
    (worst, black)
}

/// Derivation of the 3/255 bound: the colours are exact, the weights of
/// coincident discs equal, so the normalised sums are the mean colour up to
/// f32 rounding of 1e5 additions (relative 1e5·6e-8 = 6e-3 at worst, 0.9 of
/// 150; in practice far less), plus the final 8-bit rounding (0.5).
const MAX_CROWD_CHANNEL_ERROR: f32 = 3.0;

#[test]
fn a_hundred_thousand_coincident_splats_give_the_closed_form_in_every_mode() {
    let dir = tempfile::tempdir().unwrap();
    let file = crowd(dir.path(), "coincident.ply", 100_000, 0.0);
    for mode in RenderMode::ALL {
        let (image, said) = render(&file, mode, dir.path());
        assert!(
            said.contains("99999 splats that repeat another's"),
            "{mode}: the copies are merged, and it says so:\n{said}"
        );
        // Merged into one splat, the copies are blended once even by plain α-blending.
        let want = closed_form(mode);
        let (worst, black) = centre_error(&image, want);
        println!("{mode}: worst channel error {worst} from {want:?}");
        assert!(!black, "{mode}: a black (NaN) pixel in the disc");
        assert!(worst <= MAX_CROWD_CHANNEL_ERROR, "{mode}: off by {worst} from {want:?}");
    }
}

#[test]
fn twenty_thousand_nearly_coincident_splats_sum_without_saturating_and_group_in_bounded_memory() {
    // Within 1e-4 of one another: distinct splats, so nothing is merged,
    // and every fragment reaches the sums (f16 would stop adding at 2048).
    let dir = tempfile::tempdir().unwrap();
    let file = crowd(dir.path(), "crowd.ply", 20_000, 1e-4);
    for mode in RenderMode::ALL {
        let (image, said) = render(&file, mode, dir.path());
        assert!(!said.contains("repeat another's"), "{mode}: nothing to merge:\n{said}");
        let want = closed_form(mode);
        let (worst, black) = centre_error(&image, want);
        println!("{mode}: worst channel error {worst} from {want:?}");
        assert!(!black, "{mode}: a black (NaN) pixel in the disc");
        if mode.needs_grouping() {
            // Groups keep each pixel's nearest splat: 20,000 crowded splats
            // in K groups average K winners, not 20,000 (what deferred
            // blending approximates), and the grouping says it saw a crowd.
            assert!(said.contains("overlap too many others to list"), "{mode}: the crowd is reported:\n{said}");
        } else if mode != RenderMode::AlphaBlend {
            assert!(worst <= MAX_CROWD_CHANNEL_ERROR, "{mode}: off by {worst} from {want:?}");
        }
    }
}
