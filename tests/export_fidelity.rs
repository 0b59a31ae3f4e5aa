//! Every export keeps the input's records: a LAZ of point format 8 with a
//! WKT CRS, its own scale and offset, far from the origin, and two
//! extra-bytes fields, goes through `convert --filter` and `--returns`. The
//! output (read back by the `las` crate) has the same point format,
//! version, scale, offset, CRS record and extra-bytes descriptors, and each
//! kept point has every field of its input record, bit for bit.

mod common;

use std::path::Path;

const WKT: &str = "PROJCS[\"NAD83 / Oregon GIC Lambert (ft)\",UNIT[\"foot\",0.3048]]";

/// A format 8 LAZ: 20×20 points, returns 1..3 of 3, intensity 0..399, two f64/u16 extra fields.
fn write_input(path: &Path) -> Vec<las::Point> {
    let mut builder = las::Builder::from((1, 4));
    builder.point_format = las::point::Format::new(8).unwrap();
    builder.point_format.is_compressed = true;
    builder.point_format.extra_bytes = 10;
    builder.transforms = las::Vector {
        x: las::Transform { scale: 0.0025, offset: 635_000.0 },
        y: las::Transform { scale: 0.0025, offset: 848_000.0 },
        z: las::Transform { scale: 0.001, offset: 100.0 },
    };
    builder.has_wkt_crs = true;
    let mut wkt = WKT.as_bytes().to_vec();
    wkt.push(0);
    builder.vlrs.push(las::Vlr {
        user_id: "LASF_Projection".into(),
        record_id: 2112,
        description: "wkt".into(),
        data: wkt,
    });
    let mut descriptors = Vec::new();
    for (name, kind) in [("reflectance", 10u8), ("echo_width", 3u8)] {
        let mut d = [0u8; 192];
        d[2] = kind;
        d[4..4 + name.len()].copy_from_slice(name.as_bytes());
        descriptors.extend_from_slice(&d);
    }
    builder.vlrs.push(las::Vlr {
        user_id: "LASF_Spec".into(),
        record_id: 4,
        description: "extra".into(),
        data: descriptors,
    });
    let header = builder.into_header().unwrap();
    let mut writer = las::Writer::from_path(path, header).unwrap();
    let mut points = Vec::new();
    for i in 0..400u32 {
        let (col, row) = (f64::from(i % 20), f64::from(i / 20));
        let mut extra = (f64::from(i) * 0.125 - 7.0).to_le_bytes().to_vec();
        extra.extend_from_slice(&((i * 37) as u16).to_le_bytes());
        let point = las::Point {
            x: 635_123.0 + col * 0.5,
            y: 848_456.0 + row * 0.5,
            z: 120.0 + (col * 0.3).sin(),
            intensity: i as u16,
            return_number: (i % 3 + 1) as u8,
            number_of_returns: 3,
            classification: las::point::Classification::new((2 + i % 4) as u8).unwrap(),
            scan_angle: (i % 30) as f32 - 15.0,
            user_data: (i % 7) as u8,
            point_source_id: 1000 + (i % 5) as u16,
            gps_time: Some(400_000.0 + f64::from(i) * 1e-3),
            color: Some(las::Color::new((i * 100) as u16, (i * 50) as u16, 65_535 - i as u16)),
            nir: Some((i * 150) as u16),
            is_overlap: i % 11 == 0,
            is_synthetic: i % 13 == 0,
            scanner_channel: (i % 4) as u8,
            extra_bytes: extra,
            ..Default::default()
        };
        writer.write_point(point.clone()).unwrap();
        points.push(point);
    }
    writer.close().unwrap();
    // What the file holds, as the crate reads it back.
    let mut reader = las::Reader::from_path(path).unwrap();
    reader.read_all().unwrap().points().map(Result::unwrap).collect()
}

#[test]
fn convert_with_a_filter_keeps_the_format_the_scale_the_crs_and_every_field() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.laz");
    let points = write_input(&input);
    let output = dir.path().join("out.laz");
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["convert", input.to_str().unwrap(), output.to_str().unwrap()])
        .args(["--filter", "intensity=100..299", "--returns", "first"])
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));

    let mut reader = las::Reader::from_path(&output).unwrap();
    let (header_in, header_out) = (las::Reader::from_path(&input).unwrap().header().clone(), reader.header().clone());
    assert_eq!(header_out.point_format(), header_in.point_format(), "point format");
    assert_eq!(header_out.version(), header_in.version());
    assert_eq!(header_out.transforms(), header_in.transforms(), "scale and offset");
    assert!(header_out.has_wkt_crs());
    let record = |h: &las::Header, id: u16| h.vlrs().iter().find(|v| v.record_id == id).map(|v| v.data.clone());
    assert_eq!(record(&header_out, 2112), record(&header_in, 2112), "the WKT CRS record");
    assert_eq!(record(&header_out, 4), record(&header_in, 4), "the extra-bytes descriptors");

    let expected: Vec<&las::Point> =
        points.iter().filter(|p| (100..=299).contains(&p.intensity) && p.return_number == 1).collect();
    let written: Vec<las::Point> = reader.read_all().unwrap().points().map(Result::unwrap).collect();
    assert_eq!(written.len(), expected.len(), "points written");
    assert!(written.len() > 50, "{} points", written.len());
    for (w, e) in written.iter().zip(&expected) {
        assert_eq!(w, *e, "a point's fields changed");
    }
    assert_eq!(header_out.number_of_points(), expected.len() as u64);

    // Through PLY and back is a conversion, not a copy; the direct LAS copy is exact.
    let info = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend")).arg("info").arg(&output).output().unwrap();
    let text = String::from_utf8_lossy(&info.stdout);
    assert!(text.contains("point format 8") && text.contains("international foot"), "{text}");
}
