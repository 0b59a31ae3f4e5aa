//! E57 scans bounded by their binary sections: files rewritten from the
//! shared sample `tinyCartesianFloatRgb.e57` (one scan of 2,090 points) so
//! that scans share a section, borrow another's packets, count more points
//! than their section holds or store no bit of any field are refused in one
//! line, under a 1 GB address-space limit (reading them as the `e57` crate
//! does would take gigabytes or never end), and two scans with sections of
//! their own still read.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::e57bytes::{E57, content_of, element, splice};

fn sample() -> Option<E57> {
    let path = common::shared_data("e57/tinyCartesianFloatRgb.e57")?;
    let raw = std::fs::read(path).unwrap();
    let e57 = E57::parse(&raw);
    // The rewriting is exact: the same XML gives the same bytes, every page's CRC included.
    assert!(e57.rebuilt(&e57.xml) == raw, "the E57 rewrite does not reproduce the sample");
    Some(e57)
}

/// `pointblend info FILE` under a 1 GB address-space limit.
fn info_limited(path: &Path) -> Output {
    Command::new("sh")
        .arg("-c")
        .arg(r#"ulimit -v 1048576; exec "$0" "$@""#)
        .arg(env!("CARGO_BIN_EXE_pointblend"))
        .arg("info")
        .arg(path)
        .output()
        .expect("sh runs")
}

/// The one error line of a refusal: a non-zero exit, no panic, at most three lines on stderr.
fn refusal(path: &Path, what: &str) -> String {
    let output = info_limited(path);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success(), "{what} was accepted: {stderr}");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    assert!(stderr.lines().count() <= 3, "{what}: {} lines on stderr: {stderr}", stderr.lines().count());
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "{what} (exit {:?}): {stderr}", output.status.code());
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(errors[0].contains(name.as_ref()), "{what}: the line does not name the file: {}", errors[0]);
    errors[0].to_string()
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// The XML with the content of `<data3D>` replaced by `children`.
fn with_scans(e57: &E57, children: &str) -> String {
    let (from, to) = content_of(&e57.xml, "data3D");
    splice(&e57.xml, from, to, children)
}

/// The sample's one scan, as the text of its `<vectorChild>`.
fn the_scan(e57: &E57) -> String {
    let (from, to) = content_of(&e57.xml, "data3D");
    e57.xml[from..to].trim().to_string()
}

/// The smallest scan the crate accepts: the `<points>` element alone, without whitespace between tags.
fn small_scan(e57: &E57) -> String {
    let (from, to) = element(&e57.xml, "points");
    let mut points = String::new();
    let mut pending = String::new();
    for c in e57.xml[from..to].chars() {
        if c.is_whitespace() && points.ends_with('>') {
            pending.push(c);
            continue;
        }
        if c != '<' {
            points.push_str(&pending);
        }
        pending.clear();
        points.push(c);
    }
    format!(r#"<vectorChild type="Structure">{points}</vectorChild>"#)
}

#[test]
fn scans_that_share_a_binary_section_are_refused_before_any_point_is_read() {
    let e57 = require!(sample());
    let dir = tempfile::tempdir().unwrap();
    let scan = the_scan(&e57);
    let two = write(dir.path(), "aliased_2.e57", &e57.rebuilt(&with_scans(&e57, &scan.repeat(2))));
    let line = refusal(&two, "two scans naming one section");
    assert!(line.contains("one binary section"), "{line}");
    // 20,000 scans of 2,090 points each in 14 MB: 41.8M points read naively, gigabytes of columns.
    let many = e57.rebuilt(&with_scans(&e57, &small_scan(&e57).repeat(20_000)));
    let many = write(dir.path(), "aliased_20000.e57", &many);
    let line = refusal(&many, "20,000 scans naming one section");
    assert!(line.contains("scans 0 and 1 name one binary section"), "{line}");
    // A second scan with a section header of its own whose first data packet is the first scan's.
    let (_, first_packet) = e57.section_header(48);
    let at = e57.extra_at();
    let second = scan.replace(r#"fileOffset="48""#, &format!(r#"fileOffset="{at}""#));
    let borrowed = e57.section_moved(48, at, Some(first_packet));
    let borrowed = e57.with_extra(&borrowed, |_| with_scans(&e57, &format!("{scan}{second}")));
    let line = refusal(&write(dir.path(), "borrowed_packets.e57", &borrowed), "a section borrowing packets");
    assert!(line.contains("scan 1") && line.contains("outside its section"), "{line}");
}

#[test]
fn a_record_count_larger_than_its_section_holds_is_refused_with_both_counts() {
    let e57 = require!(sample());
    let dir = tempfile::tempdir().unwrap();
    for (name, count) in [("count_plus_one.e57", 2091), ("count_x1000.e57", 2_090_000)] {
        let xml = e57.xml.replace(r#"recordCount="2090""#, &format!(r#"recordCount="{count}""#));
        let line = refusal(&write(dir.path(), name, &e57.rebuilt(&xml)), name);
        assert!(line.contains(&format!("counts {count} points")) && line.contains("holds only 2090"), "{line}");
        assert!(!line.contains("unknown packet"), "{line}");
    }
}

#[test]
fn a_scan_whose_fields_are_all_constants_is_refused_without_running_out_of_memory() {
    let e57 = require!(sample());
    let dir = tempfile::tempdir().unwrap();
    // Every field a constant (minimum = maximum): no bit of any point is stored.
    let mut xml = e57.xml.clone();
    for axis in ["cartesianX", "cartesianY", "cartesianZ"] {
        let (from, to) = element(&xml, axis);
        xml = splice(&xml, from, to, &format!(r#"<{axis} type="ScaledInteger" minimum="0" maximum="0" scale="1"/>"#));
    }
    for colour in ["colorRed", "colorGreen", "colorBlue"] {
        let (from, to) = element(&xml, colour);
        xml = splice(&xml, from, to, &format!(r#"<{colour} type="Integer" minimum="7" maximum="7"/>"#));
    }
    let line = refusal(&write(dir.path(), "constant_fields.e57", &e57.rebuilt(&xml)), "constant fields");
    assert!(line.contains("constant"), "{line}");
}

#[test]
fn two_scans_with_sections_of_their_own_still_read() {
    let e57 = require!(sample());
    let dir = tempfile::tempdir().unwrap();
    let scan = the_scan(&e57);
    let at = e57.extra_at();
    let second = scan.replace(r#"fileOffset="48""#, &format!(r#"fileOffset="{at}""#));
    let copy = e57.section_moved(48, at, None);
    let bytes = e57.with_extra(&copy, |_| with_scans(&e57, &format!("{scan}{second}")));
    let output = info_limited(&write(dir.path(), "two_scans.e57", &bytes));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(stdout.contains("2 scan(s), 4180 points"), "{stdout}");
}
