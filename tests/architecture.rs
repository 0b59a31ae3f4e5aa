//! The layering the design promises: the CPU modules never touch the GPU or
//! the window toolkit, and only the registry and the mode files name a
//! particular render mode.

use std::path::{Path, PathBuf};

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(rust_files(&path));
        } else if path.extension().is_some_and(|e| e == "rs") {
            files.push(path);
        }
    }
    files
}

fn src() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src")
}

#[test]
fn the_cpu_modules_import_no_gpu_window_or_ui_crate() {
    let cpu = ["cloud", "scene", "spatial", "grouping", "reference", "view"];
    let cpu_files = ["progress.rs", "output.rs", "memory.rs"];
    let mut files: Vec<PathBuf> = cpu.iter().flat_map(|m| rust_files(&src().join(m))).collect();
    files.extend(cpu_files.iter().map(|f| src().join(f)));
    assert!(files.len() > 30, "the CPU modules were found: {}", files.len());
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            for gpu in ["wgpu::", "winit::", "egui::", "eframe::", "egui_wgpu::", "crate::render", "crate::viewer"] {
                assert!(!code.contains(gpu), "{}:{}: a CPU module uses {gpu}: {line}", file.display(), n + 1);
            }
        }
    }
}

#[test]
fn only_the_registry_and_the_mode_files_name_a_mode() {
    let allowed = [src().join("view/modes.rs"), src().join("render/modes")];
    let mut checked = 0;
    for file in rust_files(&src()) {
        if allowed.iter().any(|a| file.starts_with(a)) {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let named = line.match_indices("RenderMode::").any(|(at, _)| {
                let rest = &line[at + "RenderMode::".len()..];
                // `RenderMode::ALL`, `::DEFAULT`, `::RULER` are the registry's own; a variant is `TwoPass`-like.
                let mut chars = rest.chars();
                chars.next().is_some_and(|c| c.is_ascii_uppercase())
                    && chars.next().is_some_and(|c| c.is_ascii_lowercase())
            });
            assert!(!named, "{}:{}: names a mode outside the registry: {line}", file.display(), n + 1);
        }
        checked += 1;
    }
    assert!(checked > 50);
}

#[test]
fn the_lower_modules_import_nothing_from_those_above_them() {
    // (folder, the modules it must not use): the core below stays free of cycles.
    let rules: [(&str, &[&str]); 4] = [
        ("spatial", &["crate::cloud", "crate::grouping", "crate::scene"]),
        ("cloud", &["crate::grouping", "crate::scene"]),
        ("scene", &["crate::grouping", "crate::bench"]),
        ("viewer", &["crate::bench"]),
    ];
    for (folder, forbidden) in rules {
        for file in rust_files(&src().join(folder)) {
            let text = std::fs::read_to_string(&file).unwrap();
            for (n, line) in text.lines().enumerate() {
                let code = line.split("//").next().unwrap_or("");
                for module in forbidden {
                    assert!(!code.contains(module), "{}:{}: {folder} uses {module}: {line}", file.display(), n + 1);
                }
            }
        }
    }
}
