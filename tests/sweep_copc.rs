//! Bad COPC hierarchies, rewritten from the shared sample
//! `1.2-with-color.copc.laz` (65 nodes on levels 0-3, one root page): two
//! entries naming one child page are read without a panic, from disk and over
//! HTTP, each page once; failures and refused entries by the thousand are a
//! few lines and a count; and a root node that lies about its points is
//! named as the reason, never "no point of the file is in view".

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::copcbytes::{Copc, Entry, page};
use common::nginx::Nginx;
use pointblend::copc::{CopcStream, StreamOptions};
use pointblend::frame::Camera;
use pointblend::lod::SelectOptions;

fn sample() -> Option<Copc> {
    let path = common::shared_data("lidar/1.2-with-color.copc.laz")?;
    Some(Copc::new(std::fs::read(path).unwrap()))
}

fn write(dir: &Path, name: &str, copc: &Copc) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, &copc.bytes).unwrap();
    path
}

fn pointblend(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pointblend")).args(args).output().expect("pointblend runs")
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// `render FILE` on the CPU at `size`, into `dir` (64x64 selects the root alone, 512x512 some 36 nodes).
fn render(dir: &Path, file: &str, size: &str) -> Output {
    let out = dir.join("out.png").display().to_string();
    pointblend(&["render", file, "--mode", "reference", "--size", size, "--out", &out])
}

/// The one error line of a refusal: a non-zero exit, no panic, at most three lines on stderr.
fn refusal(output: &Output, what: &str) -> String {
    let stderr = text(&output.stderr);
    assert!(!output.status.success(), "{what} was accepted: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(stderr.lines().count() <= 3, "{what}: {} lines on stderr: {stderr}", stderr.lines().count());
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "{what}: {stderr}");
    errors[0].to_string()
}

/// The sample with its first `how_many` level-3 entries turned into pointers at one new page that lists them all.
fn shared_page(how_many: usize) -> Option<Copc> {
    let mut copc = sample()?;
    let (at, size) = copc.root_page();
    let mut root = copc.entries(at, size);
    let chosen: Vec<usize> = (0..root.len()).filter(|&i| root[i].key[0] == 3).take(how_many).collect();
    assert_eq!(chosen.len(), how_many, "the sample's level 3");
    let listed: Vec<Entry> = chosen.iter().map(|&i| root[i]).collect();
    let bytes = page(&listed);
    let page_at = copc.append(&bytes);
    for &i in &chosen {
        root[i] = Entry { offset: page_at, byte_size: bytes.len() as i32, count: -1, ..root[i] };
    }
    copc.put_entries(at, &root);
    Some(copc)
}

#[test]
fn entries_naming_one_hierarchy_page_read_it_once_without_a_panic_from_disk_and_over_http() {
    let (two, all) = (require!(shared_page(2)), require!(shared_page(48)));
    let dir = tempfile::tempdir().unwrap();
    let files = [write(dir.path(), "shared_page.copc.laz", &two), write(dir.path(), "shared_page_48.copc.laz", &all)];
    let server = Nginx::serve(dir.path());
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy().to_string();
        for source in [file.display().to_string(), server.url(&name)] {
            let output = pointblend(&["info", &source]);
            let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
            assert!(output.status.success() && !stderr.contains("panicked"), "info {source}: {stderr}");
            // The page settles its own entry; the others it lists lie outside that entry's subtree.
            assert!(stdout.contains("refused:") && stdout.contains("outside the subtree"), "{source}: {stdout}");
            let warnings = stderr.lines().filter(|l| l.contains("skipped")).count();
            assert!(warnings <= 4, "{source}: {warnings} lines of skipped nodes: {stderr}");
            // Each page read once: the root page and the shared one.
            let mut s = CopcStream::open(&source, StreamOptions::default()).unwrap();
            let camera = Camera::default_for(&s.bounds_cloud(), 1.0);
            let every = SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 };
            s.select(&camera, (64, 64), every);
            assert_eq!(s.tree.pages_read, 2, "{source}");
        }
    }
}

#[test]
fn every_node_failing_is_a_few_lines_then_a_count_and_says_why_nothing_is_drawn() {
    let mut copc = require!(sample());
    // The octree moved by one half-size: every node's points lie outside its cube.
    let (centre, half) = copc.octree();
    copc.set_centre([centre[0] + half, centre[1], centre[2]]);
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "outside_cube.copc.laz", &copc);
    let output = render(dir.path(), &file.display().to_string(), "512x512");
    let stderr = text(&output.stderr);
    let skipped = stderr.lines().filter(|l| l.contains("skipped:")).count();
    assert!(skipped <= 3, "{skipped} lines of skipped nodes: {stderr}");
    assert_eq!(stderr.lines().filter(|l| l.contains("more nodes skipped")).count(), 1, "{stderr}");
    let line = stderr.lines().find(|l| l.starts_with("error: ")).unwrap_or_else(|| panic!("no error: {stderr}"));
    assert!(!line.contains("no point of the file is in view"), "{line}");
    assert!(line.contains("could be read") && line.contains("outside its cube"), "{line}");
}

#[test]
fn a_page_of_200000_refused_entries_shows_a_few_and_a_count() {
    let mut copc = require!(sample());
    let (at, size) = copc.root_page();
    let mut root = copc.entries(at, size);
    // Level 1 has keys 0..=1 on each axis: x = 7 is no key of the octree.
    root.extend((0..200_000).map(|i| Entry { key: [1, 7, i % 2, (i / 2) % 2], offset: 0, byte_size: 0, count: 0 }));
    let bytes = page(&root);
    let page_at = copc.append(&bytes);
    copc.set_root_page(page_at, bytes.len() as u64);
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "refused_200k.copc.laz", &copc);
    let output = pointblend(&["info", &file.display().to_string()]);
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let refused = stdout.lines().filter(|l| l.starts_with("refused:")).count();
    assert!(refused <= 6, "{refused} refused lines");
    assert!(stdout.contains("200000 in all") && stdout.contains("not a key of the octree"), "{stdout}");
}

#[test]
fn a_root_that_lies_about_its_points_is_named_as_the_reason() {
    let dir = tempfile::tempdir().unwrap();
    let lying = |name: &str, count: &dyn Fn(i32) -> i32| {
        let mut copc = sample()?;
        let (at, size) = copc.root_page();
        let mut root = copc.entries(at, size);
        let r = root.iter().position(|e| e.key == [0; 4]).expect("a root entry");
        root[r].count = count(root[r].count);
        copc.put_entries(at, &root);
        Some(write(dir.path(), name, &copc))
    };
    // A thousand times its points: more than the whole file holds, refused on open.
    let file = require!(lying("lying_root.copc.laz", &|n| n * 1000)).display().to_string();
    for output in [pointblend(&["info", &file]), render(dir.path(), &file, "64x64")] {
        let line = refusal(&output, "a root counting more points than the file");
        assert!(line.contains("root node was refused") && line.contains("more than the"), "{line}");
    }
    // One point more: its chunk ends early. `info` says so; `render` names the node.
    let file = require!(lying("lying_root_plus1.copc.laz", &|n| n + 1)).display().to_string();
    let output = pointblend(&["info", &file]);
    let stdout = text(&output.stdout);
    assert!(stdout.contains("root node:   not decoded") && stdout.contains("ends early"), "{stdout}");
    let output = render(dir.path(), &file, "64x64");
    let stderr = text(&output.stderr);
    assert!(!stderr.contains("no point of the file is in view") && !stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("node 0-0-0-0") && stderr.contains("ends early"), "{stderr}");
}
