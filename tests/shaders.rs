//! naga validates every shader module the renderer can build: every root
//! WGSL file, composed in every variant.

use pointblend::render::shaders::{self, Variant};

#[test]
fn every_root_file_validates_in_every_variant() {
    let mut validated = 0;
    for root in shaders::ROOTS {
        for variant in Variant::all() {
            let source = shaders::compose(root, variant).unwrap_or_else(|e| panic!("{root} ({variant}): {e}"));
            let module = naga::front::wgsl::parse_str(&source)
                .unwrap_or_else(|e| panic!("{root} ({variant}): {}", e.emit_to_string(&source)));
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
                .validate(&module)
                .unwrap_or_else(|e| panic!("{root} ({variant}): {e:?}"));
            validated += 1;
        }
    }
    assert_eq!(validated, shaders::ROOTS.len() * Variant::all().count());
}

#[test]
fn every_wgsl_file_is_embedded_and_reached_from_some_root() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let embedded: Vec<&str> = shaders::file_names().collect();
    let composed: Vec<String> =
        shaders::ROOTS.iter().map(|r| shaders::compose(r, Variant::all().last().unwrap()).unwrap()).collect();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            assert!(embedded.contains(&name.as_str()), "{name} is not embedded in src/render/shaders.rs");
            let first_code_line = std::fs::read_to_string(&path)
                .unwrap()
                .lines()
                .find(|l| !l.trim().is_empty() && !l.starts_with('#') && !l.starts_with("//"))
                .unwrap_or_default()
                .to_string();
            assert!(
                composed.iter().any(|c| c.contains(&first_code_line)),
                "{name} is not part of any module, so it is never validated"
            );
        }
    }
}
