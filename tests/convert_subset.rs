//! `convert IN OUT` with the subset flags (src/commands/subset_args.rs):
//! a generated tile of three classes and three returns, far from the
//! origin, converted with `--classes`, `--filter`, `--returns`, `--clip-box`
//! and `--clip-plane`. The points written, read back by the `las` crate, are
//! exactly those an independent selection of the input picks, attributes
//! included. A subset that keeps no point writes nothing and says so. A
//! COPC file served over HTTP (a real server) converts as the file does.

mod common;

use common::lidar::{LidarPoint, tilted_grid, write};
use common::nginx::Nginx;
use std::path::Path;

fn convert(input: &Path, output: &Path, flags: &[&str]) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["convert", input.to_str().unwrap(), output.to_str().unwrap()])
        .args(flags)
        .output()
        .unwrap();
    assert!(out.status.success(), "{flags:?}: {}", String::from_utf8_lossy(&out.stderr));
}

/// (x, y, z, intensity, class, return number) of every point of a LAS file, sorted.
fn points_of(path: &Path) -> Vec<(i64, i64, i64, u16, u8, u8)> {
    let data = las::Reader::from_path(path).unwrap().read_all().unwrap();
    let mut points: Vec<_> = data
        .points()
        .map(|p| {
            let p = p.unwrap();
            let mm = |v: f64| (v * 1000.0).round() as i64;
            (mm(p.x), mm(p.y), mm(p.z), p.intensity, u8::from(p.classification), p.return_number)
        })
        .collect();
    points.sort_unstable();
    points
}

/// Which input points a case keeps.
type Keep = Box<dyn Fn(&LidarPoint) -> bool>;

fn expected(points: &[LidarPoint], keep: &Keep) -> Vec<(i64, i64, i64, u16, u8, u8)> {
    let mm = |v: f64| (v * 1000.0).round() as i64;
    let mut kept: Vec<_> = points
        .iter()
        .filter(|p| keep(p))
        .map(|p| (mm(p.xyz[0]), mm(p.xyz[1]), mm(p.xyz[2]), p.intensity, p.class, p.return_number))
        .collect();
    kept.sort_unstable();
    kept
}

#[test]
fn convert_writes_exactly_the_points_each_subset_flag_keeps() {
    let dir = tempfile::tempdir().unwrap();
    let origin = [500_000.0, 4_200_000.0, 50.0];
    let points = tilted_grid(40, 0.5, 0.1, origin);
    let input = write(&dir.path().join("tile.las"), &points, [origin[0], origin[1], 0.0], None);
    // Edges between grid points (0.5 apart): which side an edge point lies on is not this test's subject.
    let (x0, y0) = (origin[0] + 5.1, origin[1] + 2.6);
    let clip_box = format!("{x0},{y0},0,{},{},1000", x0 + 7.5, y0 + 10.0);
    let plane = format!("1,0,0,{}", -(origin[0] + 12.1));
    let cases: Vec<(Vec<&str>, Keep)> = vec![
        (vec!["--classes", "2,6"], Box::new(|p| p.class == 2 || p.class == 6)),
        (vec!["--returns", "last"], Box::new(|p| p.return_number == p.returns)),
        (
            vec!["--filter", "intensity=1000..2500", "--returns", "first"],
            Box::new(|p| (1000..=2500).contains(&p.intensity) && p.return_number == 1),
        ),
        (
            vec!["--clip-box", &clip_box],
            Box::new(move |p| (x0..=x0 + 7.5).contains(&p.xyz[0]) && (y0..=y0 + 10.0).contains(&p.xyz[1])),
        ),
        (vec!["--clip-box", &clip_box, "--clip-hide", "inside", "--clip-plane", &plane], {
            let inside =
                move |p: &LidarPoint| (x0..=x0 + 7.5).contains(&p.xyz[0]) && (y0..=y0 + 10.0).contains(&p.xyz[1]);
            Box::new(move |p| !inside(p) && p.xyz[0] >= origin[0] + 12.1)
        }),
    ];
    for (k, (flags, keep)) in cases.iter().enumerate() {
        let output = dir.path().join(format!("subset-{k}.las"));
        convert(&input, &output, flags);
        let want = expected(&points, keep);
        assert!(!want.is_empty() && want.len() < points.len(), "{flags:?} selects some points: {}", want.len());
        assert_eq!(points_of(&output), want, "{flags:?}");
    }
}

#[test]
fn a_subset_that_keeps_no_point_writes_nothing_and_says_so_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let origin = [500_000.0, 4_200_000.0, 50.0];
    let points = tilted_grid(10, 0.5, 0.1, origin);
    let input = write(&dir.path().join("tile.las"), &points, [origin[0], origin[1], 0.0], None);
    // A box below the tile (its heights mistaken), and a class it lacks; to LAS, COPC and PLY.
    let below = format!("{},{},-1000,{},{},0", origin[0], origin[1], origin[0] + 10.0, origin[1] + 10.0);
    for (flags, name) in
        [(["--clip-box", below.as_str()], "a.las"), (["--classes", "9"], "b.copc.laz"), (["--classes", "9"], "c.ply")]
    {
        let output = dir.path().join(name);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
            .args(["convert", input.to_str().unwrap(), output.to_str().unwrap()])
            .args(flags)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
        assert!(!out.status.success() && errors.len() == 1, "{flags:?}: {stderr}");
        let said = format!("tile.las: the subset keeps none of its {} points", points.len());
        assert!(errors[0].contains(&said), "{}", errors[0]);
        assert!(!output.exists(), "{name} written");
    }
}

#[test]
fn a_copc_url_converts_the_points_of_the_nodes_its_box_meets() {
    let dir = tempfile::tempdir().unwrap();
    let origin = [500_000.0, 4_200_000.0, 50.0];
    let points = tilted_grid(40, 0.5, 0.1, origin);
    let las = write(&dir.path().join("tile.las"), &points, [origin[0], origin[1], 0.0], None);
    convert(&las, &dir.path().join("tile.copc.laz"), &[]);
    let server = Nginx::serve(dir.path());
    let url = std::path::PathBuf::from(format!("http://127.0.0.1:{}/tile.copc.laz", server.port));
    let (x0, y0) = (origin[0] + 5.1, origin[1] + 2.6);
    let clip_box = format!("{x0},{y0},0,{},{},1000", x0 + 7.5, y0 + 10.0);
    let in_box: Keep = Box::new(move |p| (x0..=x0 + 7.5).contains(&p.xyz[0]) && (y0..=y0 + 10.0).contains(&p.xyz[1]));
    let boxed = dir.path().join("boxed.laz");
    convert(&url, &boxed, &["--clip-box", &clip_box]);
    let want = expected(&points, &in_box);
    assert!(!want.is_empty() && want.len() < points.len());
    assert_eq!(points_of(&boxed), want);
    // To COPC, by class.
    let ground = dir.path().join("ground.copc.laz");
    convert(&url, &ground, &["--classes", "2"]);
    assert_eq!(points_of(&ground), expected(&points, &(Box::new(|p: &LidarPoint| p.class == 2) as Keep)));
}
