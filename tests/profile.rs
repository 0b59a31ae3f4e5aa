//! `pointblend profile` on a generated tile far from the origin (UTM): a
//! gently sloping ground grid and a column of points near the line's
//! start. The CSV holds exactly the points an independent selection in
//! this test picks (by rotating the tile onto the line, not by the
//! program's projection), with their distances, offsets and attributes;
//! the LAZ of `--points` holds the same records; and the side view shows
//! the column in its left third (the start on the left).

mod common;

use std::path::Path;

use common::lidar::{LidarPoint, tilted_grid, write};

const ORIGIN: [f64; 3] = [500_000.0, 4_100_000.0, 100.0];

fn tile() -> Vec<LidarPoint> {
    let mut points = tilted_grid(60, 0.5, 0.05, ORIGIN);
    let (start, end) = line();
    let len = ((end.0 - start.0).powi(2) + (end.1 - start.1).powi(2)).sqrt();
    let along = ((end.0 - start.0) / len, (end.1 - start.1) / len);
    for k in 0..40 {
        let mut p = points[k];
        p.xyz = [start.0 + along.0 * 3.0, start.1 + along.1 * 3.0, ORIGIN[2] + 0.25 * k as f64];
        p.intensity = 4000 + k as u16;
        points.push(p);
    }
    points
}

/// The line's ends, in file coordinates.
fn line() -> ((f64, f64), (f64, f64)) {
    ((ORIGIN[0] + 2.1, ORIGIN[1] + 7.3), (ORIGIN[0] + 27.7, ORIGIN[1] + 19.9))
}

const WIDTH: f64 = 3.0;

/// The test's own selection, over the file's points as the `las` crate
/// reads them (at the file's 1 mm scale): each point rotated about the
/// start by minus the line's angle; (u, v) = (along, to the left).
fn expected(points: &[las::Point]) -> Vec<(usize, f64, f64)> {
    let ((x1, y1), (x2, y2)) = line();
    let angle = (y2 - y1).atan2(x2 - x1);
    let length = (x2 - x1).hypot(y2 - y1);
    let mut kept = Vec::new();
    for (i, p) in points.iter().enumerate() {
        let (dx, dy) = (p.x - x1, p.y - y1);
        let u = dx * angle.cos() + dy * angle.sin();
        let v = -dx * angle.sin() + dy * angle.cos();
        // No point sits on an edge, so the two computations cannot disagree by rounding.
        let margin = (v.abs() - WIDTH / 2.0).abs().min(u.abs()).min((u - length).abs());
        assert!(margin > 1e-6, "point {i} lies on the slab's edge");
        if v.abs() <= WIDTH / 2.0 && (0.0..=length).contains(&u) {
            kept.push((i, u, v));
        }
    }
    kept
}

#[test]
fn a_profile_holds_exactly_the_slab_and_draws_it_from_the_side() {
    let dir = tempfile::tempdir().unwrap();
    let points = tile();
    let file = write(&dir.path().join("tile.laz"), &points, [ORIGIN[0], ORIGIN[1], 0.0], None);
    let ((x1, y1), (x2, y2)) = line();
    let (csv, laz, png) = (dir.path().join("p.csv"), dir.path().join("p.laz"), dir.path().join("p.png"));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("profile")
        .arg(&file)
        .args(["--line", &format!("{x1},{y1},{x2},{y2}"), "--width", &WIDTH.to_string()])
        .arg("--csv")
        .arg(&csv)
        .arg("--points")
        .arg(&laz)
        .arg("--out")
        .arg(&png)
        .args(["--size", "192x96"])
        .env("WGPU_BACKEND", "vulkan")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));

    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(&header[..5], &["distance", "offset", "x", "y", "z"]);
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no {name}: {header:?}"));
    let (intensity, gps) = (column("intensity"), column("gps_time"));
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    let in_file: Vec<las::Point> =
        las::Reader::from_path(&file).unwrap().read_all().unwrap().points().map(Result::unwrap).collect();
    assert_eq!(in_file.len(), points.len());
    let wanted = expected(&in_file);
    assert!(wanted.len() > 300, "{} points in the slab", wanted.len());
    assert_eq!(rows.len(), wanted.len(), "rows");
    let mut got: Vec<&Vec<f64>> = rows.iter().collect();
    got.sort_by(|a, b| a[column("gps_time")].total_cmp(&b[column("gps_time")]).then(a[4].total_cmp(&b[4])));
    let mut wanted_sorted = wanted.clone();
    wanted_sorted.sort_by(|a, b| {
        let (p, q) = (&in_file[a.0], &in_file[b.0]);
        p.gps_time.unwrap().total_cmp(&q.gps_time.unwrap()).then(p.z.total_cmp(&q.z))
    });
    for (row, &(i, u, v)) in got.iter().zip(&wanted_sorted) {
        let p = &in_file[i];
        assert_eq!([row[2], row[3], row[4]], [p.x, p.y, p.z], "point {i}");
        assert!(
            (row[0] - u).abs() < 1e-6 && (row[1] - v).abs() < 1e-6,
            "point {i}: distance/offset {row:?} vs {u} {v}"
        );
        assert_eq!(row[intensity], f64::from(p.intensity), "point {i}");
        assert_eq!(Some(row[gps]), p.gps_time, "point {i}");
    }

    // The LAZ holds the same records, in the same (file) order as the CSV.
    let written: Vec<las::Point> =
        las::Reader::from_path(&laz).unwrap().read_all().unwrap().points().map(Result::unwrap).collect();
    assert_eq!(written.len(), rows.len());
    for (p, row) in written.iter().zip(&rows) {
        assert_eq!(f64::from(p.intensity), row[intensity]);
        assert_eq!(p.gps_time, Some(row[gps]));
        assert!((p.x - row[2]).abs() < 1e-9 && (p.z - row[4]).abs() < 1e-9);
    }

    // The side view: the column (near the start) is the highest thing drawn, in the left third.
    let image = image::open(&png).unwrap().to_rgba8();
    if let Ok(keep) = std::env::var("POINTBLEND_KEEP_IMAGES") {
        std::fs::copy(&png, std::path::Path::new(&keep).join("profile-side.png")).unwrap();
    }
    let background = *image.get_pixel(0, 0);
    let top = (0..image.height())
        .find_map(|y| (0..image.width()).find(|&x| *image.get_pixel(x, y) != background).map(|x| (x, y)))
        .expect("the side view is empty");
    assert!(top.0 < image.width() / 3, "the highest drawn pixel is at {top:?}, not near the start on the left");
    let drawn = image.pixels().filter(|p| **p != background).count();
    assert!(drawn > 200, "{drawn} pixels drawn");
}

/// The profile's CSV of `file`, its rows sorted, and the log.
fn csv_of(file: &Path, dir: &Path, line: &str) -> (Vec<String>, String) {
    let csv = dir.join(format!("{}.csv", file.file_name().unwrap().to_string_lossy()));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("profile")
        .arg(file)
        .args(["--line", line, "--width", "1", "--csv"])
        .arg(&csv)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut rows: Vec<String> = text.lines().skip(1).map(str::to_string).collect();
    rows.sort();
    (rows, String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn a_streamed_profile_reads_only_the_nodes_the_slab_meets_and_finds_what_the_whole_file_holds() {
    let copc = require!(common::shared_data("lidar/lone-star.copc.laz"));
    let dir = tempfile::tempdir().unwrap();
    // The same file as plain LAZ, which is read whole.
    let whole = dir.path().join("lone-star.laz");
    std::fs::copy(&copc, &whole).unwrap();
    // Through the middle, where the deepest nodes are; and in a corner, which few nodes meet.
    let mut points_read = Vec::new();
    for line in ["515378,4918355,515392,4918366", "515369,4918343,515384,4918352"] {
        let (streamed, log) = csv_of(&copc, dir.path(), line);
        let (read_whole, _) = csv_of(&whole, dir.path(), line);
        assert!(streamed.len() > 100, "{line}: {} rows", streamed.len());
        assert_eq!(streamed, read_whole, "{line}: the streamed slab differs from the whole file's");
        let read: u64 = log
            .lines()
            .find_map(|l| {
                l.split("lone-star.copc.laz: ").nth(1)?.split(" of its 518862 points read").next()?.parse().ok()
            })
            .unwrap_or_else(|| panic!("no line of the points read: {log}"));
        points_read.push(read);
    }
    let read = points_read[1];
    assert!(read < 518_862 / 2, "{read} points read for a slab in one corner");
}
