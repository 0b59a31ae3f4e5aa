//! The lidar readers (LAS, LAZ, E57): attributes, f64 coordinates, normals
//! facing up, the LAS writer's round trips, and one line per bad file.

mod common;

use std::path::Path;

use common::lidar::{self, tilted_grid};
use pointblend::cloud::{self, PointCloud, Values, attributes::names};

/// A cloud's file coordinates of splat `i`, in f64.
fn file_xyz(cloud: &PointCloud, i: usize) -> [f64; 3] {
    let p = cloud.positions[i];
    [0, 1, 2].map(|a| p[a] as f64 * cloud.unit() + cloud.origin[a])
}

fn column(cloud: &PointCloud, name: &str) -> Vec<f64> {
    let values = cloud.attributes.get(name).unwrap_or_else(|| panic!("no '{name}' attribute"));
    (0..values.len()).map(|i| values.get(i)).collect()
}

/// The splat index of each written point, found by position (loading may reorder nothing, but merging could).
fn by_position(cloud: &PointCloud, points: &[lidar::LidarPoint]) -> Vec<usize> {
    let mut index = std::collections::HashMap::new();
    for i in 0..cloud.len() {
        index.insert(file_xyz(cloud, i).map(|v| (v * 1000.0).round() as i64), i);
    }
    points.iter().map(|p| index[&p.xyz.map(|v| (v * 1000.0).round() as i64)]).collect()
}

#[test]
fn las_and_laz_keep_every_attribute_and_millimetre_coordinates_far_from_the_origin() {
    let dir = tempfile::tempdir().unwrap();
    let origin = [515_000.0, 4_900_000.0, 250.0];
    let points = tilted_grid(40, 0.37, 0.2, origin);
    for name in ["tile.las", "tile.laz"] {
        let path = lidar::write(&dir.path().join(name), &points, origin, Some("Amplitude"));
        let (cloud, report) = cloud::load(&path).unwrap();
        assert_eq!(cloud.len(), points.len(), "{name}");
        assert!(report.encoding.starts_with("LAS 1.4, point format 7"), "{name}: {}", report.encoding);
        let at = by_position(&cloud, &points);
        let (intensity, class, ret, returns, time, amplitude) = (
            column(&cloud, names::INTENSITY),
            column(&cloud, names::CLASSIFICATION),
            column(&cloud, names::RETURN_NUMBER),
            column(&cloud, names::NUMBER_OF_RETURNS),
            column(&cloud, names::GPS_TIME),
            column(&cloud, "Amplitude"),
        );
        for (k, p) in points.iter().enumerate() {
            let i = at[k];
            let got = file_xyz(&cloud, i);
            for (a, (g, w)) in got.iter().zip(p.xyz).enumerate() {
                assert!((g - w).abs() < 1e-3, "{name}: point {k} axis {a}: {g} vs {w}");
            }
            assert_eq!(intensity[i], p.intensity as f64, "{name}: intensity of {k}");
            assert_eq!(class[i], p.class as f64, "{name}: class of {k}");
            assert_eq!((ret[i], returns[i]), (p.return_number as f64, p.returns as f64), "{name}: returns of {k}");
            assert_eq!(time[i], p.gps_time, "{name}: GPS time of {k}");
            assert_eq!(amplitude[i], k as f64, "{name}: extra bytes of {k}");
            // 16-bit colour scaled to 8 bits.
            assert_eq!(cloud.colours[i], p.rgb.map(|c| (c as f64 / 65535.0 * 255.0).round() as u8), "{name}: colour");
        }
        // Narrow types: 2 + 1 + 1 + 1 + 8 + 4 bytes (intensity, class, two return counts, time, f32 extra).
        assert_eq!(
            cloud.attributes.bytes_per_point(),
            17,
            "{name}: {:?}",
            cloud.attributes.names().collect::<Vec<_>>()
        );
    }
}

#[test]
fn airborne_normals_face_up_and_match_the_plane() {
    let dir = tempfile::tempdir().unwrap();
    let slope = 0.3f64;
    let points = tilted_grid(60, 0.5, slope, [300_000.0, 5_000_000.0, 100.0]);
    let path = lidar::write(&dir.path().join("slope.laz"), &points, [300_000.0, 5_000_000.0, 0.0], None);
    let (cloud, report) = cloud::load(&path).unwrap();
    assert_eq!(report.normals, cloud::Provenance::Estimated);
    let truth = glam::DVec3::new(-slope, 0.0, 1.0).normalize().as_vec3();
    let mean_angle = cloud.normals.iter().map(|n| n.dot(truth).clamp(-1.0, 1.0).acos().to_degrees()).sum::<f32>()
        / cloud.len() as f32;
    assert!(cloud.normals.iter().all(|n| n.z > 0.0), "some normal faces down");
    assert!(mean_angle < 1.0, "mean angle to the plane's normal {mean_angle}°");
    assert!(cloud.scanner_position.is_none(), "an airborne scan has no scanner position");
}

#[test]
fn convert_round_trips_keep_every_channel() {
    let dir = tempfile::tempdir().unwrap();
    let origin = [515_000.0, 4_900_000.0, 250.0];
    let points = tilted_grid(30, 0.5, 0.1, origin);
    let source = lidar::write(&dir.path().join("source.laz"), &points, origin, Some("Amplitude"));
    let run = |from: &Path, to: &str| {
        let out = dir.path().join(to);
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
            .args(["convert"])
            .arg(from)
            .arg(&out)
            .output()
            .unwrap();
        assert!(status.status.success(), "convert {to}: {}", String::from_utf8_lossy(&status.stderr));
        out
    };
    // LAZ -> PLY -> LAZ, and PLY -> LAZ -> PLY.
    let ply = run(&source, "a.ply");
    let laz = run(&ply, "b.laz");
    let ply_again = run(&laz, "c.ply");
    let load = |p: &Path| cloud::load(p).unwrap().0;
    let (a, b, c) = (load(&ply), load(&laz), load(&ply_again));
    for (name, other) in [("LAZ", &b), ("PLY", &c)] {
        assert_eq!(other.len(), a.len(), "{name}");
        let names_a: Vec<&str> = a.attributes.names().collect();
        let names_o: Vec<&str> = other.attributes.names().collect();
        assert_eq!(names_o, names_a, "{name}: attribute names");
        for ch in &a.attributes.channels {
            let o = other.attributes.get(&ch.name).unwrap();
            for i in 0..a.len() {
                assert_eq!(o.get(i), ch.values.get(i), "{name}: {} of splat {i}", ch.name);
            }
        }
        for i in 0..a.len() {
            let (pa, po) = (file_xyz(&a, i), file_xyz(other, i));
            assert!((0..3).all(|k| (pa[k] - po[k]).abs() < 1e-4), "{name}: position {i}: {pa:?} vs {po:?}");
            assert!(a.normals[i].dot(other.normals[i]) > 0.99999, "{name}: normal {i}");
            assert!((a.radii[i] - other.radii[i]).abs() <= 1e-6 * a.radii[i].max(1.0), "{name}: radius {i}");
            assert_eq!(a.colours[i], other.colours[i], "{name}: colour {i}");
        }
    }
    assert!(matches!(a.attributes.get(names::CLASSIFICATION), Some(Values::U8(_))));
}

#[test]
fn the_shared_lidar_samples_load_with_their_attributes_and_crs() {
    let autzen = require!(common::shared_data("lidar/autzen_trim.laz"));
    let (cloud, report) = cloud::load(&autzen).unwrap();
    assert_eq!(cloud.len() + merged(&report), 110_000);
    for name in [names::INTENSITY, names::CLASSIFICATION, names::RETURN_NUMBER, names::GPS_TIME] {
        assert!(cloud.attributes.get(name).is_some(), "autzen lacks {name}");
    }
    assert!(report.crs.as_deref().is_some_and(|c| c.contains("Lambert_Conformal_Conic")), "{:?}", report.crs);
    assert_eq!(report.colours, cloud::Provenance::FromFile);

    let extra = require!(common::shared_data("lidar/extrabytes.las"));
    let (cloud, _) = cloud::load(&extra).unwrap();
    for name in ["Colors", "Intensity", "Time"] {
        assert!(cloud.attributes.get(name).is_some(), "extrabytes.las lacks its '{name}' extra bytes");
    }

    let nir = require!(common::shared_data("lidar/las_with_several_extra_byte_bloc.laz"));
    let (cloud, report) = cloud::load(&nir).unwrap();
    assert!(report.encoding.contains("point format 8"), "{}", report.encoding);
    assert!(cloud.attributes.get(names::NIR).is_some(), "format 8 keeps NIR");
    // Its two fields are described in two extra-bytes records.
    for name in ["Deviation", "confidence"] {
        assert!(cloud.attributes.get(name).is_some(), "the format-8 file lacks its '{name}' extra bytes");
    }

    let copc = require!(common::shared_data("lidar/lone-star.copc.laz"));
    let (cloud, report) = cloud::load(&copc).unwrap();
    assert_eq!(cloud.len() + merged(&report), 518_862);

    let utm = require!(common::shared_data("lidar/utm17.las"));
    let (_, report) = cloud::load(&utm).unwrap();
    assert!(report.crs.as_deref().is_some_and(|c| c.contains("32617")), "{:?}", report.crs);
}

/// How many splats loading merged into others (lidar files repeat points).
fn merged(report: &cloud::LoadReport) -> usize {
    report
        .warnings
        .iter()
        .find(|w| w.contains("were merged"))
        .and_then(|w| w.split_whitespace().next()?.parse().ok())
        .unwrap_or(0)
}

#[test]
fn e57_files_read_cartesian_integer_and_spherical_scans() {
    let float = require!(common::shared_data("e57/bunnyFloat.e57"));
    let int19 = require!(common::shared_data("e57/bunnyInt19.e57"));
    let (a, _) = cloud::load(&float).unwrap();
    let (b, _) = cloud::load(&int19).unwrap();
    assert_eq!(a.len(), 30_571);
    assert_eq!(b.len(), a.len());
    let (ba, bb) = (a.bounds().unwrap(), b.bounds().unwrap());
    assert!((ba.max - ba.min - (bb.max - bb.min)).abs().max_element() < 1e-3, "{ba:?} vs {bb:?}");
    let spherical = require!(common::shared_data("e57/tiny_spherical.e57"));
    let (s, _) = cloud::load(&spherical).unwrap();
    assert!(!s.is_empty() && s.positions.iter().all(|p| p.is_finite()));
    let rgb = require!(common::shared_data("e57/tinyCartesianFloatRgb.e57"));
    let (_, report) = cloud::load(&rgb).unwrap();
    assert_eq!(report.colours, cloud::Provenance::FromFile);
}

#[test]
fn e57_written_by_the_e57_crate_reads_back_with_intensity() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("written.e57");
    let mut writer = e57::E57Writer::from_file(&path, "guid-file").unwrap();
    let prototype = vec![
        e57::Record::CARTESIAN_X_F64,
        e57::Record::CARTESIAN_Y_F64,
        e57::Record::CARTESIAN_Z_F64,
        e57::Record {
            name: e57::RecordName::Intensity,
            data_type: e57::RecordDataType::Single { min: Some(0.0), max: Some(1000.0) },
        },
    ];
    let mut pc = writer.add_pointcloud("guid-scan", prototype).unwrap();
    for i in 0..400 {
        let (x, y) = ((i % 20) as f64 * 0.01, (i / 20) as f64 * 0.01);
        pc.add_point(vec![
            e57::RecordValue::Double(x),
            e57::RecordValue::Double(y),
            e57::RecordValue::Double(0.0),
            e57::RecordValue::Single(i as f32),
        ])
        .unwrap();
    }
    pc.finalize().unwrap();
    writer.finalize().unwrap();
    let (cloud, _) = cloud::load(&path).unwrap();
    assert_eq!(cloud.len(), 400);
    assert!(cloud.attributes.get(names::INTENSITY).is_some(), "intensity kept");
}

/// `pointblend info FILE` must fail with one line naming the file and `what`.
fn refused(path: &Path, what: &str) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend")).arg("info").arg(path).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "{what} was accepted");
    assert!(!stderr.contains("panicked"), "{what}: {stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{what}: {stderr}");
    let name = path.file_name().unwrap().to_string_lossy();
    assert!(errors[0].contains(name.as_ref()), "{what}: the line does not name the file: {}", errors[0]);
    errors[0].to_string()
}

#[test]
fn bad_lidar_files_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let points = tilted_grid(30, 0.5, 0.1, [1000.0, 2000.0, 10.0]);
    let las = std::fs::read(lidar::write(&dir.path().join("good.las"), &points, [1000.0, 2000.0, 0.0], None)).unwrap();
    let laz = std::fs::read(lidar::write(&dir.path().join("good.laz"), &points, [1000.0, 2000.0, 0.0], None)).unwrap();
    let with_extra = std::fs::read(lidar::write(&dir.path().join("x.las"), &points, [0.0; 3], Some("A"))).unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    };
    let patched = |bytes: &[u8], at: usize, with: &[u8]| {
        let mut b = bytes.to_vec();
        b[at..at + with.len()].copy_from_slice(with);
        b
    };
    // LAS 1.4 header: offset to points at 96 (u32), format at 104, legacy count at 107,
    // x scale at 131 (f64), 64-bit count at 247.
    let line = refused(&write("truncated.laz", &laz[..laz.len() * 2 / 3]), "a truncated LAZ");
    assert!(line.contains("truncated"), "{line}");
    let lying = patched(&patched(&las, 107, &10_000_000u32.to_le_bytes()), 247, &10_000_000u64.to_le_bytes());
    let line = refused(&write("count.las", &lying), "a lying count");
    assert!(line.contains("10000000"), "{line}");
    refused(&write("format.las", &patched(&las, 104, &[99])), "an unknown point format");
    let line = refused(&write("scale.las", &patched(&las, 131, &0f64.to_le_bytes())), "a scale of 0");
    assert!(line.contains("scale"), "{line}");
    refused(&write("offset.las", &patched(&las, 96, &(u32::MAX - 10).to_le_bytes())), "offsets past the end");
    // The extra-bytes descriptor's data type is the third byte of the VLR's data, 54 + 2 bytes after the
    // header (375 bytes) and the VLR header (54 bytes).
    let at = 375 + 54 + 2;
    assert_eq!(with_extra[at], 9, "the test file's layout");
    let line = refused(&write("extra.las", &patched(&with_extra, at, &[200])), "extra bytes of an undefined type");
    assert!(line.contains("data type 200"), "{line}");
    let corrupt = require!(common::shared_data("e57/corrupt_crc.e57"));
    refused(&corrupt, "an E57 with a wrong CRC");
    let empty = require!(common::shared_data("e57/empty_pc.e57"));
    refused(&empty, "an empty E57");
}
