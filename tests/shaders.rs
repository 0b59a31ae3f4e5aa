//! naga validates every WGSL file, as composed into the modules the renderer builds.

use pointblend::render::shaders;

#[test]
fn every_composed_shader_module_validates() {
    for shader in shaders::all() {
        let module = naga::front::wgsl::parse_str(&shader.source)
            .unwrap_or_else(|e| panic!("{}: {}", shader.name, e.emit_to_string(&shader.source)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {e:?}", shader.name));
    }
}

#[test]
fn every_wgsl_file_is_part_of_some_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let modules = shaders::all();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(
                modules.iter().any(|m| m.source.contains(&text)),
                "{} is not used by any shader module, so it is never validated",
                path.display()
            );
        }
    }
}
