//! The README is the first thing a user reads: its quick start must hold
//! exactly the two commands that really set up, run and test pointblend, and
//! every picture it shows must exist. This keeps it from silently going empty
//! or out of date.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &str) -> String {
    std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// The command lines (comments and blank lines dropped) of the first code
/// block after the `## Quick start` heading.
fn quick_start_commands(readme: &str) -> Vec<String> {
    let section = readme.split("\n## Quick start").nth(1).expect("README has a '## Quick start' section");
    let block = section.split("```").nth(1).expect("the quick start has a code block");
    block
        .lines()
        .skip(1) // the language tag
        .map(|l| l.split('#').next().unwrap_or("").trim().to_string())
        .filter(|l| !l.is_empty())
        .collect()
}

/// Every `![alt](path)` image target of a Markdown text.
fn image_links(markdown: &str) -> Vec<String> {
    markdown.split("![").skip(1).filter_map(|s| Some(s.split_once("](")?.1.split(')').next()?.to_string())).collect()
}

#[cfg(unix)]
fn is_executable(path: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(path).is_ok_and(|m| m.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(path: &Path) -> bool {
    path.exists()
}

#[test]
fn the_quick_start_is_the_two_commands_that_ci_and_users_run() {
    let readme = read("README.md");
    let commands = quick_start_commands(&readme);
    assert_eq!(commands, ["scripts/run", "scripts/test"], "the quick start must hold exactly these two commands");
    for script in &commands {
        assert!(is_executable(&root().join(script)), "{script} is missing or not executable");
    }
    let ci = read(".ci/run");
    assert!(
        ci.lines().any(|l| l.trim() == "scripts/test"),
        ".ci/run must run the README's test command, scripts/test:\n{ci}"
    );
    let test_script = read("scripts/test");
    assert!(test_script.contains("cargo test"), "scripts/test runs the test suite");
    let run_script = read("scripts/run");
    assert!(run_script.contains("cargo build --release"), "scripts/run builds pointblend, showing cargo's progress");
    assert!(run_script.contains("exec \"$binary\" \"$@\""), "scripts/run runs the binary it built");
}

/// `scripts/setup` with `cargo` as given by `fake_cargo` (a script body, or
/// none): its exit status, its stderr, and whether it called apt-get.
fn setup_with(fake_cargo: Option<&str>) -> (std::process::ExitStatus, String, bool) {
    use std::os::unix::fs::PermissionsExt;
    let bin = tempfile::tempdir().unwrap();
    let called = bin.path().join("apt-get-called");
    let script = |name: &str, body: String| {
        let path = bin.path().join(name);
        std::fs::write(&path, format!("#!/bin/sh\n{body}\n")).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    };
    for name in ["apt-get", "sudo"] {
        script(name, format!("touch {}", called.display()));
    }
    if let Some(body) = fake_cargo {
        script("cargo", body.to_string());
    }
    let output = std::process::Command::new(root().join("scripts/setup"))
        .env("PATH", format!("{}:/usr/bin:/bin", bin.path().display()))
        .output()
        .unwrap();
    (output.status, String::from_utf8_lossy(&output.stderr).into_owned(), called.exists())
}

#[cfg(unix)]
#[test]
fn setup_checks_for_rust_1_85_before_it_installs_anything() {
    for (cargo, what) in [(Some("echo 'cargo 1.63.0'"), "Debian 12's cargo"), (None, "no cargo")] {
        let (status, stderr, installed) = setup_with(cargo);
        assert!(!status.success(), "{what}: setup must fail: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{what}: one line: {stderr}");
        assert!(stderr.contains("1.85") && stderr.contains("rustup"), "{what}: names 1.85 and rustup: {stderr}");
        assert!(!installed, "{what}: nothing is installed before Rust is there");
    }
    let (status, stderr, _) = setup_with(Some("echo 'cargo 1.95.0 (f2d3ce0bd 2026-03-21)'"));
    assert!(!stderr.contains("1.85"), "a recent cargo passes the check: {stderr} ({status})");
}

#[test]
fn every_picture_the_docs_show_exists_and_every_picture_is_shown() {
    let docs = ["README.md", "docs/USER_GUIDE.md", "docs/ALGORITHMS.md", "docs/BENCHMARKS.md"];
    let mut shown = Vec::new();
    for doc in docs {
        let text = read(doc);
        let base = root().join(doc).parent().unwrap().to_path_buf();
        for link in image_links(&text) {
            let path = base.join(&link);
            assert!(path.is_file(), "{doc} shows {link}, which does not exist");
            shown.push(path.canonicalize().unwrap());
        }
    }
    for entry in std::fs::read_dir(root().join("docs/images")).unwrap() {
        let path = entry.unwrap().path().canonicalize().unwrap();
        assert!(shown.contains(&path), "{} is shown by no document", path.display());
    }
    let readme = read("README.md");
    assert!(image_links(&readme).len() >= 4, "the README shows renders and the viewer");
    assert!(readme.lines().count() > 60, "the README has been cut short");
}

#[test]
fn the_readme_names_every_mode_and_subcommand() {
    let readme = read("README.md");
    for mode in pointblend::frame::RenderMode::ALL {
        assert!(readme.contains(&format!("`{}`", mode.name())), "the README does not describe mode {mode}");
    }
    // Every subcommand the program lists in its help.
    let help = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend")).arg("--help").output().unwrap();
    let help = String::from_utf8_lossy(&help.stdout).into_owned();
    let listed = help.split("Commands:").nth(1).expect("the help lists the subcommands");
    let commands: Vec<&str> = listed
        .lines()
        .skip_while(|l| l.trim().is_empty())
        .take_while(|l| !l.trim().is_empty())
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .collect();
    assert!(commands.len() >= 8, "{commands:?}");
    for command in commands {
        assert!(readme.contains(&format!("pointblend {command}")), "the README has no example of {command}");
    }
}

/// Every relative `[text](target)` link of a Markdown text, without its anchor.
fn relative_links(markdown: &str) -> Vec<String> {
    markdown
        .split("](")
        .skip(1)
        .filter_map(|s| s.split(')').next())
        .map(|t| t.split('#').next().unwrap_or("").trim().to_string())
        .filter(|t| !t.is_empty() && !t.contains("://") && !t.starts_with("mailto:"))
        .collect()
}

#[test]
fn every_link_of_the_readme_and_docs_resolves() {
    let mut docs = vec![root().join("README.md")];
    docs.extend(
        std::fs::read_dir(root().join("docs"))
            .unwrap()
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.extension().is_some_and(|e| e == "md")),
    );
    assert!(docs.len() >= 4, "the README, the user guide, the algorithms and the benchmarks: {docs:?}");
    for doc in docs {
        let text = std::fs::read_to_string(&doc).unwrap();
        let base = doc.parent().unwrap();
        for link in relative_links(&text) {
            assert!(base.join(&link).exists(), "{} links to {link}, which does not exist", doc.display());
        }
    }
}

#[test]
fn the_readme_is_a_front_door() {
    let readme = read("README.md");
    let lines = readme.lines().count();
    assert!(lines <= 300, "the README has {lines} lines; the rest belongs in docs/");
    for doc in ["docs/USER_GUIDE.md", "docs/ALGORITHMS.md", "docs/BENCHMARKS.md"] {
        assert!(readme.contains(doc.trim_start_matches("docs/")), "the README links to {doc}");
    }
    assert!(readme.contains("](docs/images/modes.png)"), "the README shows the contact sheet");
}
