//! Loader tests: every encoding and type, the test scans, repairs and broken files.

mod common;

use common::plywriter::{Element, Encoding, ply, temp_file};
use common::tolerances::*;
use glam::{DVec3, Vec3};
use pointblend::cloud::{self, CloudError, PointCloud, Provenance};

fn absolute(cloud: &PointCloud, i: usize) -> DVec3 {
    cloud.positions[i].as_dvec3() + DVec3::from_array(cloud.origin)
}

/// A small real cloud: the first points of the bundled lion scan, with derived attributes.
fn sample_rows(count: usize) -> Vec<[f64; 3]> {
    let (lion, _) = cloud::load(&common::bundled_model()).unwrap();
    (0..count.min(lion.len())).map(|i| absolute(&lion, i).to_array()).collect()
}

#[test]
fn every_encoding_and_scalar_type_reads_the_same_values() {
    let dir = tempfile::tempdir().unwrap();
    let xyz = sample_rows(300);
    let rows: Vec<Vec<f64>> = xyz
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // x y z (double), an unknown int, colour as uchar, normal as float, confidence.
            vec![p[0], p[1], p[2], i as f64, (i % 256) as f64, 0.0, 0.0, 1.0, 0.5]
        })
        .collect();
    for enc in [Encoding::Ascii, Encoding::Little, Encoding::Big] {
        for (pos_ty, other_int) in [("double", "int"), ("float", "ushort"), ("float32", "char")] {
            for crlf in [false, true] {
                if crlf && enc != Encoding::Ascii {
                    continue;
                }
                let vertex = Element {
                    name: "vertex",
                    properties: vec![
                        (pos_ty, "x"),
                        (pos_ty, "y"),
                        (pos_ty, "z"),
                        (other_int, "unknown_index"),
                        ("uchar", "red"),
                        ("float", "nx"),
                        ("float", "ny"),
                        ("float", "nz"),
                        ("float", "confidence"),
                    ],
                    rows: rows
                        .iter()
                        .map(|r| {
                            let mut r = r.clone();
                            r[3] = r[3].min(100.0);
                            r
                        })
                        .collect(),
                };
                let extra = Element {
                    name: "range_grid",
                    properties: vec![("list uchar int", "vertex_indices")],
                    rows: vec![vec![2.0, 0.0, 1.0], vec![0.0]],
                };
                let bytes = ply(enc, &[vertex, extra], &["a comment", "another one"], crlf);
                let path = temp_file(&dir, "all.ply", &bytes);
                let (cloud, report) =
                    cloud::load(&path).unwrap_or_else(|e| panic!("{enc:?} {pos_ty} crlf={crlf}: {e}"));
                assert_eq!(cloud.len(), xyz.len());
                assert_eq!(report.comments, vec!["a comment".to_string(), "another one".to_string()]);
                assert_eq!(report.normals, Provenance::FromFile);
                for (i, p) in xyz.iter().enumerate() {
                    let got = absolute(&cloud, i);
                    let want = if pos_ty == "double" {
                        DVec3::from_array(*p)
                    } else {
                        DVec3::from_array(p.map(|c| c as f32 as f64))
                    };
                    assert!((got - want).length() < 1e-6, "{enc:?} {pos_ty}: vertex {i}: {got} != {want}");
                    assert_eq!(cloud.normals[i], Vec3::Z);
                }
            }
        }
    }
}

#[test]
fn colours_read_as_uchar_float_and_ushort() {
    let dir = tempfile::tempdir().unwrap();
    let xyz = sample_rows(64);
    for (ty, scale) in [("uchar", 1.0), ("float", 1.0 / 255.0), ("ushort", 257.0)] {
        let rows = xyz
            .iter()
            .enumerate()
            .map(|(i, p)| vec![p[0], p[1], p[2], (i * 3) as f64 * scale, 128.0 * scale, 255.0 * scale])
            .collect();
        let vertex = Element {
            name: "vertex",
            properties: vec![("float", "x"), ("float", "y"), ("float", "z"), (ty, "red"), (ty, "green"), (ty, "blue")],
            rows,
        };
        let path = temp_file(&dir, "colour.ply", &ply(Encoding::Little, &[vertex], &[], false));
        let (cloud, report) = cloud::load(&path).unwrap();
        assert_eq!(report.colours, Provenance::FromFile);
        for i in 0..xyz.len() {
            assert_eq!(cloud.colours[i], [(i * 3) as u8, 128, 255], "{ty} colour of vertex {i}");
        }
    }
}

#[test]
fn the_test_scans_load_with_every_attribute() {
    for path in common::real_scans() {
        let name = path.display();
        let (cloud, report) = cloud::load(&path).unwrap();
        assert!(cloud.is_consistent());
        assert!(!cloud.is_empty());
        assert!(cloud.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3), "{name}: unit normals");
        assert!(cloud.radii.iter().all(|r| r.is_finite() && *r > 0.0), "{name}: positive radii");
        assert!(cloud.positions.iter().all(|p| p.is_finite()));
        // Every vertex is either in the cloud or counted in a warning.
        let skipped: usize = report
            .warnings
            .iter()
            .filter(|w| w.contains("skipped"))
            .filter_map(|w| w.split_whitespace().next()?.parse::<usize>().ok())
            .sum();
        assert_eq!(cloud.len() + skipped, report.vertices_in_file, "{name}: {:?}", report.warnings);
    }
}

#[test]
fn the_ascii_mesh_loads_exactly_the_vertices_its_faces_use() {
    let path = require!(common::shared_data("bun_zipper.ply"));
    let mesh = common::read_ascii_mesh(&path);
    let (cloud, report) = cloud::load(&path).unwrap();
    assert_eq!(report.normals, Provenance::FromFaces);
    let mut used = vec![false; mesh.vertices.len()];
    for t in &mesh.triangles {
        for &i in t {
            used[i] = true;
        }
    }
    let expected: Vec<DVec3> = mesh.vertices.iter().zip(&used).filter(|(_, u)| **u).map(|(v, _)| *v).collect();
    assert_eq!(cloud.len(), expected.len());
    let size = 0.2;
    for (i, want) in expected.iter().enumerate() {
        let err = (absolute(&cloud, i) - *want).length() / size;
        assert!(err < 1e-6, "vertex {i}: relative error {err}");
    }
}

#[test]
fn estimated_normals_match_the_mesh_normals_and_face_outwards() {
    // The bunny's vertices without faces: PCA normals must agree with the face normals.
    let dir = tempfile::tempdir().unwrap();
    let path = require!(common::shared_data("bun_zipper.ply"));
    let (with_faces, _) = cloud::load(&path).unwrap();
    let rows: Vec<Vec<f64>> = (0..with_faces.len()).map(|i| absolute(&with_faces, i).to_array().to_vec()).collect();
    let vertex = Element { name: "vertex", properties: vec![("double", "x"), ("double", "y"), ("double", "z")], rows };
    let points = temp_file(&dir, "points.ply", &ply(Encoding::Little, &[vertex], &[], false));
    let (estimated, report) = cloud::load(&points).unwrap();
    assert_eq!(report.normals, Provenance::Estimated);
    assert_eq!(estimated.len(), with_faces.len());
    let n = estimated.len() as f64;
    let mean_abs_cos =
        (0..estimated.len()).map(|i| estimated.normals[i].dot(with_faces.normals[i]).abs() as f64).sum::<f64>() / n;
    let oriented =
        (0..estimated.len()).filter(|&i| estimated.normals[i].dot(with_faces.normals[i]) > 0.0).count() as f64 / n;
    println!("estimated normals: mean |cos| {mean_abs_cos:.4}, oriented share {oriented:.4}");
    assert!(mean_abs_cos >= MIN_NORMAL_MEAN_ABS_COS, "mean |cos| {mean_abs_cos}");
    assert!(oriented >= MIN_NORMAL_ORIENTED_SHARE, "consistently oriented share {oriented}");
    assert!(estimated.scanner_position.is_none(), "a closed object is not a single-view scan");
}

#[test]
fn a_single_view_scan_faces_its_scanner() {
    let (cloud, report) = cloud::load(&require!(common::shared_data("table_scene_mug_stereo_textured.ply"))).unwrap();
    assert_eq!(report.normals, Provenance::Estimated);
    let scanner = cloud.scanner_position.expect("the table scene is one stereo view from the origin");
    let facing = (0..cloud.len()).filter(|&i| cloud.normals[i].dot(scanner - cloud.positions[i]) > 0.0).count();
    println!("{facing} of {} normals face the scanner", cloud.len());
    assert!(
        facing as f64 >= MIN_SCANNER_FACING_SHARE * cloud.len() as f64,
        "{facing} of {} face the scanner",
        cloud.len()
    );
}

#[test]
fn utm_sized_coordinates_keep_their_millimetres() {
    let dir = tempfile::tempdir().unwrap();
    let base = [512_345.678_f64, 5_412_345.123, 321.5];
    let xyz = sample_rows(200);
    let extent =
        xyz.iter().map(|p| DVec3::from_array(*p) - DVec3::from_array(xyz[0])).map(|d| d.length()).fold(0.0, f64::max);
    let rows: Vec<Vec<f64>> = xyz.iter().map(|p| vec![base[0] + p[0], base[1] + p[1], base[2] + p[2]]).collect();
    let vertex = Element {
        name: "vertex",
        properties: vec![("double", "x"), ("double", "y"), ("double", "z")],
        rows: rows.clone(),
    };
    let path = temp_file(&dir, "utm.ply", &ply(Encoding::Big, &[vertex], &[], false));
    let (cloud, _) = cloud::load(&path).unwrap();
    for i in 0..rows.len() {
        for j in [0, 7, 99] {
            let got = (cloud.positions[i] - cloud.positions[j]).as_dvec3();
            let want = DVec3::from_slice(&rows[i]) - DVec3::from_slice(&rows[j]);
            assert!((got - want).length() / extent < MAX_RELATIVE_POSITION_ERROR, "pair {i},{j}: {got} vs {want}");
        }
    }
}

#[test]
fn gaussian_splat_files_take_colour_opacity_radius_and_normal_from_their_parameters() {
    let dir = tempfile::tempdir().unwrap();
    let xyz = sample_rows(50);
    let c0 = 0.282_094_791_773_878_14;
    let rows: Vec<Vec<f64>> = xyz
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let dc = (i as f64 / 50.0 - 0.5) * 2.0;
            // f_dc, opacity logit 0 (-> 0.5), scales exp(-5) x2 and exp(-9) along z, identity rotation.
            vec![p[0], p[1], p[2], dc, 0.0, -dc, 0.0, -5.0, -5.0, -9.0, 1.0, 0.0, 0.0, 0.0]
        })
        .collect();
    let names = [
        "x", "y", "z", "f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1",
        "rot_2", "rot_3",
    ];
    let vertex =
        Element { name: "vertex", properties: names.iter().map(|n| ("float", *n)).collect(), rows: rows.clone() };
    let path = temp_file(&dir, "gaussians.ply", &ply(Encoding::Little, &[vertex], &[], false));
    let (cloud, report) = cloud::load(&path).unwrap();
    assert_eq!(report.colours, Provenance::FromGaussians);
    assert_eq!(report.radii, Provenance::FromGaussians);
    for (i, row) in rows.iter().enumerate() {
        let want =
            [row[3], row[4], row[5]].map(|dc| ((0.5 + c0 * dc as f32 as f64) * 255.0).round().clamp(0.0, 255.0) as u8);
        assert_eq!(cloud.colours[i], want);
        assert!((cloud.opacity[i] - 0.5).abs() < 1e-6);
        assert!((cloud.normals[i].z.abs() - 1.0).abs() < 1e-5, "thinnest axis is z");
        assert!(cloud.radii[i] > (-5.0f32).exp() && cloud.radii[i] < 4.0 * (-5.0f32).exp());
    }
}

#[test]
fn bad_records_are_repaired_and_counted() {
    let dir = tempfile::tempdir().unwrap();
    let xyz = sample_rows(400);
    let rows: Vec<Vec<f64>> = xyz
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let mut r = vec![p[0], p[1], p[2], 0.0, 0.0, 1.0, 0.001, 0.5];
            match i % 10 {
                0 => r[0] = f64::NAN,                           // skipped
                1 => r[1] = f64::INFINITY,                      // skipped
                2 => r[3..6].copy_from_slice(&[0.0, 0.0, 0.0]), // zero normal: re-estimated
                3 => r[6] = -1.0,                               // negative radius: re-estimated
                4 => r[7] = 1.5,                                // alpha above 1: clamped
                _ => {}
            }
            r
        })
        .collect();
    let names = ["x", "y", "z", "nx", "ny", "nz", "radius", "alpha"];
    let vertex = Element { name: "vertex", properties: names.iter().map(|n| ("float", *n)).collect(), rows };
    let path = temp_file(&dir, "bad_records.ply", &ply(Encoding::Little, &[vertex], &[], false));
    let (cloud, report) = cloud::load(&path).unwrap();
    assert_eq!(cloud.len(), 320);
    let warning = |needle: &str| -> usize {
        report
            .warnings
            .iter()
            .find(|w| w.contains(needle))
            .and_then(|w| w.split_whitespace().next()?.parse().ok())
            .unwrap_or_else(|| panic!("no warning about {needle}: {:?}", report.warnings))
    };
    assert_eq!(warning("NaN or infinite"), 80);
    assert_eq!(warning("normals"), 40);
    assert_eq!(warning("radii"), 40);
    assert_eq!(warning("alpha"), 40);
    assert!(cloud.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3));
    assert!(cloud.radii.iter().all(|&r| r > 0.0));
    assert!(cloud.opacity.iter().all(|&a| (0.0..=1.0).contains(&a)));
}

#[test]
fn alpha_zero_everywhere_is_taken_as_opaque() {
    let dir = tempfile::tempdir().unwrap();
    let rows = sample_rows(100).iter().map(|p| vec![p[0], p[1], p[2], 0.0]).collect();
    let vertex = Element {
        name: "vertex",
        properties: vec![("float", "x"), ("float", "y"), ("float", "z"), ("uchar", "alpha")],
        rows,
    };
    let path = temp_file(&dir, "alpha0.ply", &ply(Encoding::Ascii, &[vertex], &[], false));
    let (cloud, report) = cloud::load(&path).unwrap();
    assert!(cloud.opacity.iter().all(|&a| a == 1.0));
    assert!(report.warnings.iter().any(|w| w.contains("alpha is 0")));
}

#[test]
fn faces_with_any_count_and_index_type_give_normals() {
    let dir = tempfile::tempdir().unwrap();
    // A unit square in z = 0 as one quad (fan-triangulated) plus a stray vertex.
    let rows =
        vec![vec![0.0, 0.0, 0.0], vec![1.0, 0.0, 0.0], vec![1.0, 1.0, 0.0], vec![0.0, 1.0, 0.0], vec![5.0, 5.0, 5.0]];
    for (list, name) in [
        ("list uchar int", "vertex_indices"),
        ("list int uint", "vertex_index"),
        ("list ushort short", "vertex_indices"),
    ] {
        for enc in [Encoding::Ascii, Encoding::Little, Encoding::Big] {
            let vertex = Element {
                name: "vertex",
                properties: vec![("float", "x"), ("float", "y"), ("float", "z")],
                rows: rows.clone(),
            };
            let face =
                Element { name: "face", properties: vec![(list, name)], rows: vec![vec![4.0, 0.0, 1.0, 2.0, 3.0]] };
            let path = temp_file(&dir, "quad.ply", &ply(enc, &[vertex, face], &[], false));
            let (cloud, report) = cloud::load(&path).unwrap_or_else(|e| panic!("{list} {enc:?}: {e}"));
            assert_eq!(report.normals, Provenance::FromFaces);
            assert_eq!(cloud.len(), 4, "the stray vertex is skipped");
            assert!(report.warnings.iter().any(|w| w.starts_with("1 vertices not used")));
            assert!(cloud.normals.iter().all(|n| (n.z - 1.0).abs() < 1e-6));
        }
    }
}

#[test]
fn a_few_bad_records_load_with_a_warning_that_counts_them() {
    let dir = tempfile::tempdir().unwrap();
    // Faces that name a vertex the file lacks are skipped; the good face still gives normals.
    let vertex = Element {
        name: "vertex",
        properties: vec![("float", "x"), ("float", "y"), ("float", "z")],
        rows: vec![vec![0.0, 0.0, 0.0], vec![1.0, 0.0, 0.0], vec![0.0, 1.0, 0.0]],
    };
    let face = Element {
        name: "face",
        properties: vec![("list uchar int", "vertex_indices")],
        rows: vec![vec![3.0, 0.0, 1.0, 7.0], vec![3.0, 0.0, 1.0, 2.0]],
    };
    let path = temp_file(&dir, "face_out_of_range.ply", &ply(Encoding::Little, &[vertex, face], &[], false));
    let (cloud, report) = cloud::load(&path).unwrap();
    assert_eq!((cloud.len(), report.normals), (3, Provenance::FromFaces));
    assert!(report.warnings.iter().any(|w| w.starts_with("1 faces that refer to vertices")), "{:?}", report.warnings);

    // ASCII: a word where a number belongs, and nan / inf tokens (organised scans write them).
    let text = b"ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n4 five 6\n1 0 nan\n0 1 0\n1 1 -inf\n1 1 1 1\n";
    let path = temp_file(&dir, "bad_ascii.ply", text);
    let (cloud, report) = cloud::load(&path).unwrap();
    assert_eq!(cloud.len(), 2);
    let warnings = report.warnings.join(" | ");
    assert!(warnings.contains("2 vertices with NaN or infinite coordinates were skipped"), "{warnings}");
    assert!(warnings.contains("2 vertex lines could not be read"), "{warnings}");
}

#[test]
fn triangle_strips_are_read_as_faces_with_restarts_and_alternating_winding() {
    let dir = tempfile::tempdir().unwrap();
    // A 3 x 3 grid in z = 0 as two strips of one row of quads each, in two records; the first
    // record ends in a 2-vertex piece after a -1 restart, which makes no triangle.
    let rows: Vec<Vec<f64>> = (0..9).map(|i| vec![(i % 3) as f64, (i / 3) as f64, 0.0]).collect();
    for enc in [Encoding::Ascii, Encoding::Little, Encoding::Big] {
        let vertex = Element {
            name: "vertex",
            properties: vec![("float", "x"), ("float", "y"), ("float", "z")],
            rows: rows.clone(),
        };
        let strips = Element {
            name: "tristrips",
            properties: vec![("list int int", "vertex_indices")],
            rows: vec![
                vec![9.0, 3.0, 0.0, 4.0, 1.0, 5.0, 2.0, -1.0, 6.0, 3.0],
                vec![6.0, 6.0, 3.0, 7.0, 4.0, 8.0, 5.0],
            ],
        };
        let path = temp_file(&dir, "strips.ply", &ply(enc, &[vertex, strips], &[], false));
        let (cloud, report) = cloud::load(&path).unwrap_or_else(|e| panic!("{enc:?}: {e}"));
        assert_eq!(report.normals, Provenance::FromFaces, "{enc:?}");
        // 4 triangles in the first strip, none in the 2-vertex piece after -1, 4 in the second record.
        assert_eq!(report.faces_in_file, 8, "{enc:?}");
        assert_eq!(cloud.len(), 9, "every vertex is used");
        // Alternating winding keeps every triangle facing the same way: all normals agree.
        let first = cloud.normals[0];
        assert!(first.z.abs() > 0.999, "{enc:?}: {first}");
        assert!(cloud.normals.iter().all(|n| n.dot(first) > 0.999), "{enc:?}: a strip triangle flipped");
    }
}

/// Loads `bytes` as `name` and returns the error, checking it names the file and is one line.
fn load_error(name: &str, bytes: &[u8]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let path = temp_file(&dir, name, bytes);
    let error: CloudError = cloud::load(&path).err().unwrap_or_else(|| panic!("{name} should not load"));
    let text = error.to_string();
    assert!(text.contains(name), "error does not name the file: {text}");
    assert!(!text.contains('\n'), "error is not one line: {text}");
    text
}

fn small_binary_cloud() -> Vec<u8> {
    let rows = sample_rows(100).iter().map(|p| p.to_vec()).collect();
    let vertex = Element { name: "vertex", properties: vec![("float", "x"), ("float", "y"), ("float", "z")], rows };
    ply(Encoding::Little, &[vertex], &[], false)
}

#[test]
fn broken_files_give_one_line_errors_naming_the_file() {
    let good = small_binary_cloud();
    let text = load_error("truncated.ply", &good[..good.len() - 7]);
    assert!(text.contains("truncated"), "{text}");

    let lying = String::from_utf8_lossy(&good).replacen("element vertex 100", "element vertex 150", 1);
    let lying_bytes: Vec<u8> = {
        let header_end = good.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        let mut b = lying.as_bytes()[..lying.find("end_header\n").unwrap() + 11].to_vec();
        b.extend_from_slice(&good[header_end..]);
        b
    };
    assert!(load_error("lying_header.ply", &lying_bytes).contains("150"));

    let absurd = b"ply\nformat binary_little_endian 1.0\nelement vertex 18446744073709551615\nproperty float x\nproperty float y\nproperty float z\nend_header\n\0\0\0\0";
    load_error("absurd_count.ply", absurd);

    assert!(load_error("not_a_ply.ply", b"solid cube\nfacet normal 0 0 1\n").contains("PLY"));
    load_error("empty.ply", b"");
    load_error(
        "no_xyz.ply",
        b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float u\nproperty float v\nend_header\n1 2\n",
    );
    load_error(
        "unknown_format.ply",
        b"ply\nformat binary_middle_endian 1.0\nelement vertex 1\nproperty float x\nend_header\n",
    );
    load_error("no_end_header.ply", b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n");

    let negative_list = {
        let vertex = Element {
            name: "vertex",
            properties: vec![("float", "x"), ("float", "y"), ("float", "z")],
            rows: vec![vec![0.0; 3]; 3],
        };
        let face =
            Element { name: "face", properties: vec![("list char int", "vertex_indices")], rows: vec![vec![-3.0]] };
        ply(Encoding::Little, &[vertex, face], &[], false)
    };
    load_error("negative_list.ply", &negative_list);

    let all_nan = {
        let vertex = Element {
            name: "vertex",
            properties: vec![("float", "x"), ("float", "y"), ("float", "z")],
            rows: vec![vec![f64::NAN; 3]; 4],
        };
        ply(Encoding::Little, &[vertex], &[], false)
    };
    load_error("all_nan.ply", &all_nan);

    let missing = std::path::Path::new("/nonexistent/cloud.ply");
    assert!(cloud::load(missing).unwrap_err().to_string().contains("cloud.ply"));
}
