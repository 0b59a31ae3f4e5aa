//! The units a file's CRS gives its coordinates (crates/core/src/cloud/crs_units.rs),
//! as `pick --json` and `info` report them: a file in EPSG:2994 (Oregon
//! Lambert, international feet) by its WKT, one in EPSG:2227 (California
//! zone 3, US survey feet) by a GeoTIFF code alone, one in UTM metres, and
//! one without a CRS. The files are written here by the `las` crate.

mod common;

use common::lidar::{CrsRecord, tilted_grid, write_with_crs};

const OREGON_FT: &str = r#"PROJCS["NAD83(HARN) / Oregon GIC Lambert (ft)",GEOGCS["NAD83(HARN)",DATUM["NAD83_High_Accuracy_Reference_Network",SPHEROID["GRS 1980",6378137,298.257222101,AUTHORITY["EPSG","7019"]],AUTHORITY["EPSG","6152"]],PRIMEM["Greenwich",0,AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],AUTHORITY["EPSG","4152"]],PROJECTION["Lambert_Conformal_Conic_2SP"],PARAMETER["standard_parallel_1",43],PARAMETER["standard_parallel_2",45.5],PARAMETER["latitude_of_origin",41.75],PARAMETER["central_meridian",-120.5],PARAMETER["false_easting",1312335.958],PARAMETER["false_northing",0],UNIT["foot",0.3048,AUTHORITY["EPSG","9002"]],AXIS["Easting",EAST],AXIS["Northing",NORTH],AUTHORITY["EPSG","2994"]]"#;

fn pointblend(args: &[&str]) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend")).args(args).output().expect("run");
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).unwrap()
}

/// `pick --json` at the image centre of `file`: (epsg, units, vertical units, the first layer's z).
fn picked(file: &std::path::Path) -> (serde_json::Value, String, String, f64) {
    let text = pointblend(&["pick", file.to_str().unwrap(), "--at", "64,64", "--size", "128x128", "--json"]);
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let z = json["layers"][0]["position"][2].as_f64().expect("the ray meets the ground");
    let name = |key: &str| json[key].as_str().unwrap_or_else(|| panic!("{key} in {json}")).to_string();
    (json["epsg"].clone(), name("units"), name("vertical_units"), z)
}

#[test]
fn picks_and_info_name_the_crs_units_or_say_there_are_none() {
    let dir = tempfile::tempdir().unwrap();
    let ground = tilted_grid(40, 1.0, 0.0, [1_300_000.0, 400_000.0, 150.0]);
    let offset = [1_300_000.0, 400_000.0, 0.0];
    let cases: [(&str, Option<CrsRecord>, Option<u64>, &str); 4] = [
        ("oregon.las", Some(CrsRecord::Wkt(OREGON_FT)), Some(2994), "international foot"),
        ("california.las", Some(CrsRecord::GeoTiffKeys(&[(1024, 1), (3072, 2227)])), Some(2227), "US survey foot"),
        ("utm.las", Some(CrsRecord::GeoTiffKeys(&[(1024, 1), (3072, 32610)])), Some(32610), "metre"),
        ("none.las", None, None, "units of the file"),
    ];
    for (name, crs, epsg, units) in cases {
        let path = dir.path().join(name);
        match crs {
            Some(crs) => write_with_crs(&path, &ground, offset, crs),
            None => common::lidar::write_colourless(&path, &ground, offset),
        };
        let (code, horizontal, vertical, z) = picked(&path);
        assert_eq!(code.as_u64(), epsg, "{name}: {code}");
        assert_eq!((horizontal.as_str(), vertical.as_str()), (units, units), "{name}");
        assert!((z - 150.0).abs() < 1e-3, "{name}: the pick is at the file's height, {z}");
        let info = pointblend(&["info", path.to_str().unwrap()]);
        let line = info.lines().find(|l| l.starts_with("units:")).unwrap_or_else(|| panic!("{name}: {info}"));
        assert!(line.contains(units), "{name}: {line}");
        if epsg.is_none() {
            assert!(line.contains("no CRS declared"), "{name}: {line}");
        }
    }
}
