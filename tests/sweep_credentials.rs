//! Credentials in a URL (`http://user:password@host/...`) and the signature
//! of a signed URL's query are sent to the server but never printed: not by
//! `info` or `render`, on success or failure, in errors or in log lines; and
//! the disk cache keys on the URL without them, so two passwords for one
//! file share its chunks.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::nginx::Nginx;
use pointblend::cloud::LoadOptions;
use pointblend::copc::{CopcStream, StreamOptions};
use pointblend::frame::Camera;
use pointblend::lod::SelectOptions;

const SECRET: &str = "s3cretpw";
const SIGNATURE: &str = "f00dfacesignature";

/// A folder with the shared sample as `tile.copc.laz`.
fn served_sample() -> Option<tempfile::TempDir> {
    let sample = common::shared_data("lidar/1.2-with-color.copc.laz")?;
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(sample, dir.path().join("tile.copc.laz")).unwrap();
    Some(dir)
}

fn pointblend(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pointblend")).args(args).output().expect("pointblend runs")
}

fn render(dir: &Path, url: &str) -> Output {
    let out = dir.join("out.png").display().to_string();
    pointblend(&["render", url, "--mode", "reference", "--size", "64x64", "--out", &out])
}

#[test]
fn credentials_and_signatures_in_a_url_are_never_printed() {
    let dir = require!(served_sample());
    let server = Nginx::serve(dir.path());
    let with_password = |path: &str| format!("http://user:{SECRET}@127.0.0.1:{}/{path}", server.port);
    let closed = std::net::TcpListener::bind("127.0.0.1:0").unwrap().local_addr().unwrap().port();
    let signed = format!("{}?X-Amz-Signature={SIGNATURE}&X-Amz-Expires=60", server.url("tile.copc.laz"));
    let tile = with_password("tile.copc.laz");
    let runs = [
        ("info", pointblend(&["info", &tile]), true),
        ("render", render(dir.path(), &tile), true),
        ("render of a missing file", render(dir.path(), &with_password("missing.copc.laz")), false),
        (
            "info on a closed port",
            pointblend(&["info", &format!("http://user:{SECRET}@127.0.0.1:{closed}/tile.copc.laz")]),
            false,
        ),
        ("info of a signed URL", pointblend(&["info", &signed]), true),
        ("render of a signed URL", render(dir.path(), &signed), true),
    ];
    for (what, output, succeeds) in runs {
        let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
        assert_eq!(output.status.success(), succeeds, "{what}: {stderr}");
        for secret in [SECRET, SIGNATURE] {
            assert!(!stdout.contains(secret) && !stderr.contains(secret), "{what} shows {secret}: {stdout}{stderr}");
        }
        // The URL is still named, its credentials masked.
        let shown = if succeeds { stdout.to_string() + &stderr } else { stderr.to_string() };
        assert!(shown.contains("127.0.0.1"), "{what} does not name the server: {shown}");
        if !what.contains("signed") {
            assert!(shown.contains("***@127.0.0.1"), "{what}: {shown}");
        }
    }
}

#[test]
fn the_disk_cache_keys_on_the_url_without_its_credentials() {
    let dir = require!(served_sample());
    let server = Nginx::serve(dir.path());
    let cache = dir.path().join("chunks");
    let options = StreamOptions { cache_bytes: 1 << 30, disk_cache: Some(cache.clone()), ..Default::default() };
    let every = SelectOptions { budget: usize::MAX, radius_scale: 1.0, cull: false, finest_px: 0.0 };
    for password in ["first", "second"] {
        let url = format!("http://user:{password}@127.0.0.1:{}/tile.copc.laz", server.port);
        let mut s = CopcStream::open(&url, options.clone()).unwrap();
        let camera = Camera::default_for(&s.bounds_cloud(), 1.0);
        s.frame(&camera, (64, 64), every, &LoadOptions::default()).unwrap();
    }
    let folders = std::fs::read_dir(&cache).unwrap().count();
    assert_eq!(folders, 1, "one file under two passwords is cached in {folders} folders");
}
