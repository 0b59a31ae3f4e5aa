//! Bad COPC hierarchies, rewritten from the shared sample
//! `1.2-with-color.copc.laz` (65 nodes on levels 0-3, one root page): two
//! entries naming one child page are read without a panic, from disk and over
//! HTTP, each page once.

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
            // Each page read once: the root page and the shared one.
            let mut s = CopcStream::open(&source, StreamOptions::default()).unwrap();
            let camera = Camera::default_for(&s.bounds_cloud(), 1.0);
            let every = SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 };
            s.select(&camera, (64, 64), every);
            assert_eq!(s.tree.pages_read, 2, "{source}");
        }
    }
}
