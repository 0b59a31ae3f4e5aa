//! naga validates exactly the shader modules the renderer builds: every mode
//! is rendered in every setting that picks another module (lighting,
//! quality, a cloud of one colour or of many, transparency, opaque splats
//! drawn apart, an environment map, scene lights, mesh triangles, eye-dome
//! lighting), the pipeline cache says which (root
//! file, variant) pairs it built, and each of those is composed and
//! validated. Every root file must be among them, and every WGSL file must
//! be part of one of them, so none escapes validation.

mod common;

use std::collections::BTreeSet;
use std::path::PathBuf;

use pointblend::frame::{Camera, Quality, RenderMode, RenderSettings};
use pointblend::render::GpuRenderer;
use pointblend::render::shaders::{self, Variant};
use pointblend::scene::Scene;

/// Scenes that between them reach every variant flag.
fn scenes() -> Vec<(&'static str, Scene)> {
    let assets = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets");
    let open = |name: &str| pointblend::scene::open(&assets.join(name), &Default::default()).unwrap().0;
    let lion = common::thinned_lion(4);
    let mut one_colour = lion.clone(); // one colour: weights only
    one_colour.colours.iter_mut().for_each(|c| *c = [200, 180, 150]);
    let one_colour = Scene::from(one_colour);
    let coloured = Scene::from(lion);
    let mut transparent = coloured.clone();
    transparent.set_opacity(0.5);
    vec![
        ("one colour", one_colour),
        ("colours", coloured),
        ("transparent", transparent),
        ("transparent and opaque", open("demo.toml")),
        ("environment", open("glass.toml")),
    ]
}

/// The (root, variant) pairs the renderer builds over every mode, scene and setting.
fn built_modules() -> BTreeSet<(&'static str, String)> {
    // Its own renderer, so that its cache starts empty.
    let mut renderer = GpuRenderer::new().expect("a Vulkan adapter (lavapipe)");
    for (what, scene) in scenes() {
        let flat = scene.flattened();
        let camera = Camera::default_for(&flat, 1.0);
        for mode in RenderMode::ALL.into_iter().filter(|m| m.is_gpu()) {
            let grouping_spec = RenderSettings { mode, ..Default::default() }.grouping_for_mode();
            let grouping = mode.needs_grouping().then(|| grouping_spec.compute(&flat).unwrap());
            let mut gpu = renderer.upload(&scene, grouping.as_ref());
            for lighting in [true, false] {
                for quality in [Quality::Filtered, Quality::Unfiltered] {
                    for prefilter in pointblend::frame::Prefilter::ALL {
                        let settings = RenderSettings { mode, lighting, quality, prefilter, ..Default::default() };
                        renderer
                            .render(&mut gpu, &camera, &settings, (48, 48))
                            .unwrap_or_else(|e| panic!("{mode} on {what}: {e}"));
                    }
                    // Eye-dome lighting (its pass reads a depth buffer or K group images).
                    let eye_dome = Some(Default::default());
                    let settings = RenderSettings { mode, lighting, quality, eye_dome, ..Default::default() };
                    renderer
                        .render(&mut gpu, &camera, &settings, (48, 48))
                        .unwrap_or_else(|e| panic!("{mode} with eye-dome lighting on {what}: {e}"));
                }
            }
        }
    }
    // Scene lights: splats lit once each with their shadow coefficients (LIGHTS).
    for (what, scene) in scenes().into_iter().filter(|(what, _)| *what != "one colour") {
        let light = pointblend::frame::Light::point(glam::Vec3::new(0.0, 0.5, 0.3));
        let mut frames = pointblend::render::PreparedScene::of(std::sync::Arc::new(scene));
        let camera = Camera::default_for(frames.cloud(), 1.0);
        for mode in RenderMode::ALL.into_iter().filter(|m| m.is_gpu()) {
            let lights = pointblend::frame::Lights::new(&[light]).unwrap();
            let settings = RenderSettings { mode, lights, ..Default::default() };
            frames
                .render(Some(&mut renderer), &camera, &settings, (48, 48), false)
                .unwrap_or_else(|e| panic!("{mode} lit by a scene light on {what}: {e}"));
        }
    }
    // Mesh triangles (TRIANGLES), opaque and transparent, of one colour and of many: drawn through
    // PreparedScene, which hands a frame its triangles (every leaf as triangles: hybrid-px 0).
    let assets = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets");
    let environment = pointblend::scene::open(&assets.join("glass.toml"), &Default::default()).unwrap().0.environment;
    for name in ["knot-hybrid.toml", "glass-mesh.toml", "glass-mesh.toml with an environment map"] {
        let file = name.split(' ').next().unwrap();
        let (mut scene, _) = pointblend::scene::open(&assets.join(file), &Default::default()).unwrap();
        if name.contains("environment") {
            scene.environment = environment.clone();
        }
        for coloured in [false, true] {
            if coloured {
                let mut cloud = scene.objects[0].cloud.as_ref().clone();
                cloud.colours.iter_mut().enumerate().for_each(|(i, c)| *c = [(i % 251) as u8, 120, 200]);
                scene.objects[0].cloud = std::sync::Arc::new(cloud);
            }
            let mut frames = pointblend::render::PreparedScene::of(std::sync::Arc::new(scene.clone()));
            let camera = Camera::default_for(frames.cloud(), 1.0);
            for mode in RenderMode::ALL.into_iter().filter(|m| m.is_gpu()) {
                for lighting in [true, false] {
                    for quality in [Quality::Filtered, Quality::Unfiltered] {
                        let settings =
                            RenderSettings { mode, lighting, quality, hybrid_pixels: 0.0, ..Default::default() };
                        frames
                            .render(Some(&mut renderer), &camera, &settings, (48, 48), false)
                            .unwrap_or_else(|e| panic!("{mode} on {name}: {e}"));
                    }
                }
            }
        }
    }
    renderer.renderer.modules_built().into_iter().map(|(root, variant)| (root, variant.to_string())).collect()
}

fn validate(root: &str, variant: Variant) {
    let source = shaders::compose(root, variant).unwrap_or_else(|e| panic!("{root} ({variant}): {e}"));
    let module = naga::front::wgsl::parse_str(&source)
        .unwrap_or_else(|e| panic!("{root} ({variant}): {}", e.emit_to_string(&source)));
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
        .validate(&module)
        .unwrap_or_else(|e| panic!("{root} ({variant}): {e:?}"));
}

#[test]
fn naga_validates_every_module_the_renderer_builds_and_every_shader_file_is_in_one() {
    let built = built_modules();
    let variant_named = |name: &str| Variant::all().find(|v| v.to_string() == name).unwrap();
    for (root, variant) in &built {
        validate(root, variant_named(variant));
    }
    println!("{} modules built and validated: {built:?}", built.len());
    // Every root file is built, so none is left unvalidated...
    let roots: BTreeSet<&str> = built.iter().map(|(root, _)| *root).collect();
    let declared: BTreeSet<&str> = shaders::roots().collect();
    assert_eq!(roots, declared, "the roots built and the files with a fragment entry point differ");
    // ...and every WGSL file is part of a module that is.
    let composed: Vec<String> =
        built.iter().map(|(root, variant)| shaders::compose(root, variant_named(variant)).unwrap()).collect();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("crates/render/shaders");
    let embedded: Vec<&str> = shaders::file_names().collect();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "wgsl") {
            let name = path.file_name().unwrap().to_string_lossy().to_string();
            assert!(embedded.contains(&name.as_str()), "{name} is not embedded (crates/render/build.rs)");
            let first_code_line = std::fs::read_to_string(&path)
                .unwrap()
                .lines()
                .find(|l| !l.trim().is_empty() && !l.starts_with('#') && !l.starts_with("//"))
                .unwrap_or_default()
                .to_string();
            assert!(
                composed.iter().any(|c| c.contains(&first_code_line)),
                "{name} is part of no module the renderer builds, so it is never validated"
            );
        }
    }
}
