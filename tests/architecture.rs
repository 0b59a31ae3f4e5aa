//! The layering the design promises. The workspace makes the compiler keep
//! the CPU core free of the GPU, the window and the UI (`pointblend-core`
//! depends on none of them, checked here on the resolved dependency tree);
//! inside the core, no module imports one above it; and only the registry
//! and the mode files name a particular render mode.

mod common;

use common::source::rust_files;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn core_src() -> PathBuf {
    root().join("crates/core/src")
}

/// Lines of code (comments cut off) of a file.
fn code_lines(file: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(file).unwrap();
    text.lines().enumerate().map(|(n, l)| (n + 1, l.split("//").next().unwrap_or("").to_string())).collect()
}

#[test]
fn the_core_crate_depends_on_no_gpu_window_or_ui_crate() {
    let tree = std::process::Command::new(env!("CARGO"))
        .args(["tree", "--offline", "-p", "pointblend-core", "--edges", "normal", "--prefix", "none"])
        .current_dir(root())
        .output()
        .expect("cargo tree runs");
    assert!(tree.status.success(), "cargo tree: {}", String::from_utf8_lossy(&tree.stderr));
    let tree = String::from_utf8_lossy(&tree.stdout);
    let crates: Vec<&str> = tree.lines().filter_map(|l| l.split_whitespace().next()).collect();
    assert!(crates.contains(&"glam") && crates.contains(&"image"), "the tree was read: {crates:?}");
    for forbidden in ["wgpu", "naga", "winit", "egui", "eframe", "egui-wgpu", "pointblend-render", "pointblend"] {
        assert!(!crates.contains(&forbidden), "pointblend-core depends on {forbidden}:\n{tree}");
    }
}

#[test]
fn no_core_module_imports_one_above_it() {
    // From the ground up; a module may use those before it in this list.
    let layers: [&[&str]; 9] = [
        &["formats", "hash", "input", "memory", "named", "output", "progress"],
        &["spatial"],
        &["cloud"],
        &["style"],
        &["grouping"],
        &["frame"],
        &["scene", "shadow", "lod", "hybrid", "copc"],
        &["reference"],
        &["inspect"],
    ];
    let mut checked = 0;
    for (level, modules) in layers.iter().enumerate() {
        let above: Vec<&str> = layers[level + 1..].iter().flat_map(|l| l.iter().copied()).collect();
        for module in *modules {
            let folder = core_src().join(module);
            let files =
                if folder.is_dir() { rust_files(&folder) } else { vec![core_src().join(format!("{module}.rs"))] };
            for file in files {
                for (n, code) in code_lines(&file) {
                    for other in &above {
                        let import = format!("crate::{other}");
                        let uses = code.match_indices(&import).any(|(at, _)| {
                            !code[at + import.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
                        });
                        assert!(!uses, "{}:{n}: {module} uses {import}, which is above it: {code}", file.display());
                    }
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 50, "{checked} files checked");
}

#[test]
fn only_the_registry_and_the_mode_files_name_a_mode() {
    let allowed = [core_src().join("frame/modes.rs"), root().join("crates/render/src/modes")];
    let mut checked = 0;
    let files = [root().join("src"), core_src(), root().join("crates/render/src")]
        .iter()
        .flat_map(|d| rust_files(d))
        .collect::<Vec<_>>();
    for file in files {
        if allowed.iter().any(|a| file.starts_with(a)) {
            continue;
        }
        for (n, line) in code_lines(&file) {
            let named = line.match_indices("RenderMode::").any(|(at, _)| {
                let rest = &line[at + "RenderMode::".len()..];
                // `RenderMode::ALL`, `::DEFAULT`, `::RULER` are the registry's own; a variant is `TwoPass`-like.
                let mut chars = rest.chars();
                chars.next().is_some_and(|c| c.is_ascii_uppercase())
                    && chars.next().is_some_and(|c| c.is_ascii_lowercase())
            });
            assert!(!named, "{}:{n}: names a mode outside the registry: {line}", file.display());
        }
        checked += 1;
    }
    assert!(checked > 100, "{checked} files checked");
}

#[test]
fn the_viewer_imports_nothing_from_the_benchmark() {
    for file in rust_files(&root().join("src/viewer")) {
        for (n, code) in code_lines(&file) {
            assert!(!code.contains("crate::bench"), "{}:{n}: the viewer uses the benchmark: {code}", file.display());
        }
    }
}

/// What a scene's frames prepared is kept in one cache with no policy
/// inside: `scene_cache.rs` reads no settings, spec or scene (it cannot
/// decide anything from them), and no type of the renderer holds a prepared
/// scene inside another (no nested cache).
#[test]
fn the_scene_cache_decides_nothing_and_no_prepared_scene_nests_another() {
    let render_src = root().join("crates/render/src");
    let cache = render_src.join("scene_cache.rs");
    let mut read = 0;
    for (n, code) in code_lines(&cache) {
        for policy in
            ["RenderSettings", "FrameSpec", "Selection", "SceneFacts", "scene::Scene", "GpuRenderer", "resolve"]
        {
            assert!(!code.contains(policy), "{}:{n}: the scene cache reads {policy}: {code}", cache.display());
        }
        read += 1;
    }
    assert!(read > 50, "{read} lines of the cache read");
    for file in rust_files(&render_src) {
        for (n, code) in code_lines(&file) {
            // A field: `[pub(…)] name: Type`, whose type holds a prepared scene, not a reference to one.
            let field = code.trim_start().split_once(':').map(|(before, ty)| (before.split_whitespace().collect(), ty));
            let nests = field.is_some_and(|(words, ty): (Vec<&str>, &str)| {
                let named = match words[..] {
                    [name] | [_, name] if words.len() == 1 || words[0].starts_with("pub") => name,
                    _ => return false,
                };
                let is_name = !named.is_empty() && named.chars().all(|c| c.is_alphanumeric() || c == '_');
                is_name && ty.contains("PreparedScene") && !ty.contains('&')
            });
            assert!(!nests, "{}:{n}: a prepared scene held inside another: {code}", file.display());
        }
    }
}

/// One styling path: a style reaches splats only through
/// `SceneObject::restyle` (which runs `Style::apply` and keeps what it
/// used, for the legend), and only the scene module calls that: every front
/// end hands its style to `Scene::apply_style` or a scene file's objects.
#[test]
fn a_style_is_applied_only_through_the_scene() {
    let scene_dir = core_src().join("scene");
    let files: Vec<PathBuf> = [root().join("src"), root().join("crates")].iter().flat_map(|d| rust_files(d)).collect();
    let mut restyles = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let code = text.split("#[cfg(test)]").next().unwrap_or_default();
        for (n, line) in code.lines().enumerate().filter(|(_, l)| !l.trim_start().starts_with("//")) {
            let place = format!("{}:{}", file.display(), n + 1);
            if line.contains(".restyle(") {
                assert!(file.starts_with(&scene_dir), "{place}: a style applied outside the scene: {line}");
                restyles += 1;
            }
            let applies = line.contains("style.apply(") || line.contains("Style::apply(");
            assert!(!applies || file.ends_with("scene/mod.rs"), "{place}: a style applied outside restyle: {line}");
        }
    }
    assert!(restyles >= 3, "{restyles} calls of restyle found");
}

/// Small files, one concept each: no source file of the project (src and
/// crates, tests excluded) is over 600 lines.
#[test]
fn no_source_file_is_over_600_lines() {
    const MOST_LINES: usize = 600;
    let files: Vec<PathBuf> = [root().join("src"), root().join("crates")].iter().flat_map(|d| rust_files(d)).collect();
    let long: Vec<String> = files
        .iter()
        .filter_map(|file| {
            let lines = std::fs::read_to_string(file).unwrap().lines().count();
            (lines > MOST_LINES).then(|| format!("{} ({lines} lines)", file.display()))
        })
        .collect();
    assert!(files.len() > 100, "{} files checked", files.len());
    assert!(long.is_empty(), "over {MOST_LINES} lines: {long:?}");
}

/// The file a module path names, from the folder of the module it is seen
/// from (`base`): `a` as `a.rs` or `a/mod.rs`, one level deeper when `a/b.rs`
/// exists.
fn module_file(base: &Path, path: &[&str]) -> Option<PathBuf> {
    let first = path.first()?;
    let (file, folder) = (base.join(format!("{first}.rs")), base.join(first));
    let found = if file.is_file() {
        file
    } else if folder.join("mod.rs").is_file() {
        folder.join("mod.rs")
    } else {
        return None;
    };
    match path.get(1) {
        Some(_) if folder.is_dir() => module_file(&folder, &path[1..]).or(Some(found)),
        _ => Some(found),
    }
}

/// The files `file` imports from (by `use` or by a path in its code), in its
/// crate rooted at `root`: `super::…` from its parent module, `crate::…`
/// from the root. A module's own `mod.rs` and its children are not edges:
/// a parent re-exporting a child, and a child using what its parent holds,
/// is how a module is split into files.
fn imports_of(file: &Path, root: &Path) -> Vec<PathBuf> {
    let folder = file.parent().unwrap();
    let is_mod = file.file_name().is_some_and(|n| n == "mod.rs" || n == "lib.rs" || n == "main.rs");
    // The folder `super` names: a file's siblings live in its folder; a mod.rs's in the folder above.
    let parent = if is_mod { folder.parent().unwrap_or(folder) } else { folder };
    let mut found = Vec::new();
    for (_, code) in code_lines(file) {
        for (prefix, base) in [("super::", parent), ("crate::", root)] {
            for (at, _) in code.match_indices(prefix) {
                let rest = &code[at + prefix.len()..];
                let path: Vec<&str> = rest
                    .split("::")
                    .map(|p| p.split(|c: char| !(c.is_alphanumeric() || c == '_')).next().unwrap_or(""))
                    .take_while(|p| p.chars().next().is_some_and(|c| c.is_ascii_lowercase()))
                    .collect();
                if let Some(target) = module_file(base, &path) {
                    let own_mod = target.parent() == Some(folder) && target.file_name().is_some_and(|n| n == "mod.rs");
                    let child = target.starts_with(folder) && is_mod;
                    if target != file && !own_mod && !child {
                        found.push(target);
                    }
                }
            }
        }
    }
    found.sort();
    found.dedup();
    found
}

/// No two modules of a crate import each other, directly or around a
/// circle: each can be read, tested and changed from the ones below it.
#[test]
fn no_module_imports_another_that_imports_it_back() {
    let mut edges = 0;
    for root in [root().join("src"), core_src(), root().join("crates/render/src")] {
        let files: Vec<PathBuf> = rust_files(&root).into_iter().filter(|f| !f.starts_with(root.join("bin"))).collect();
        let graph: std::collections::BTreeMap<PathBuf, Vec<PathBuf>> =
            files.iter().map(|f| (f.clone(), imports_of(f, &root))).collect();
        edges += graph.values().map(Vec::len).sum::<usize>();
        // Depth-first search for a back edge, reporting the circle it closes.
        fn visit(
            at: &PathBuf,
            graph: &std::collections::BTreeMap<PathBuf, Vec<PathBuf>>,
            state: &mut std::collections::BTreeMap<PathBuf, u8>,
            stack: &mut Vec<PathBuf>,
        ) -> Option<Vec<PathBuf>> {
            state.insert(at.clone(), 1);
            stack.push(at.clone());
            for next in graph.get(at).into_iter().flatten() {
                match state.get(next).copied().unwrap_or(0) {
                    1 => {
                        let from = stack.iter().position(|s| s == next).unwrap();
                        return Some(stack[from..].to_vec());
                    }
                    0 => {
                        if let Some(circle) = visit(next, graph, state, stack) {
                            return Some(circle);
                        }
                    }
                    _ => {}
                }
            }
            stack.pop();
            state.insert(at.clone(), 2);
            None
        }
        let mut state = std::collections::BTreeMap::new();
        for file in graph.keys() {
            if state.get(file).copied().unwrap_or(0) == 0 {
                let circle = visit(file, &graph, &mut state, &mut Vec::new());
                let names: Vec<String> = circle
                    .unwrap_or_default()
                    .iter()
                    .map(|f| f.strip_prefix(&root).unwrap_or(f).display().to_string())
                    .collect();
                assert!(names.is_empty(), "an import circle: {}", names.join(" -> "));
            }
        }
    }
    assert!(edges > 200, "{edges} imports found: the parser reads too little");
}
