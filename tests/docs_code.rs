//! The code in docs/ADDING_*.md is the code that compiles: every `rust` and
//! `diff` block names its file in the heading above it, and each of its
//! lines (the added and unchanged lines of a diff; elisions such as `// ...`
//! and `...` left out, trailing comments aside) appears in that file, in the
//! same order. A snippet that drifts from the tree (a field added to a pass,
//! a row renamed, a table's length) fails here.

use std::path::Path;

/// A fenced block of a guide and the file its heading names.
struct Snippet {
    guide: &'static str,
    heading: String,
    file: String,
    lines: Vec<String>,
}

/// `line` without its trailing `// comment` and surrounding space.
fn code_of(line: &str) -> String {
    let trimmed = line.trim();
    if trimmed.starts_with("//") {
        return trimmed.to_string();
    }
    match trimmed.find(" // ") {
        Some(at) => trimmed[..at].trim_end().to_string(),
        None => trimmed.to_string(),
    }
}

/// Whether a snippet line stands for code left out.
fn is_elision(code: &str) -> bool {
    code.is_empty() || code == "..." || code == "// ..." || code.starts_with("// ...")
}

/// The last backquoted path in `heading`.
fn file_in(heading: &str) -> Option<String> {
    heading
        .split('`')
        .skip(1)
        .step_by(2)
        .filter(|s| s.contains('/') && s.rsplit('.').next().is_some_and(|e| ["rs", "wgsl", "toml"].contains(&e)))
        .last()
        .map(str::to_string)
}

fn snippets(guide: &'static str) -> Vec<Snippet> {
    let text = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(guide)).unwrap();
    let mut out = Vec::new();
    let mut heading = String::new();
    let mut block: Option<(bool, Vec<String>)> = None;
    for line in text.lines() {
        match &mut block {
            Some((diff, lines)) if line.starts_with("```") => {
                let file = file_in(&heading).unwrap_or_else(|| panic!("{guide}: `{heading}` names no file"));
                let kept = lines
                    .iter()
                    .filter(|l| !(*diff && l.starts_with('-')))
                    .map(|l| if *diff && !l.is_empty() { code_of(&l[1..]) } else { code_of(l) })
                    .filter(|c| !is_elision(c))
                    .collect();
                out.push(Snippet { guide, heading: heading.clone(), file, lines: kept });
                block = None;
            }
            Some((_, lines)) => lines.push(line.to_string()),
            None if line.starts_with("```rust") || line.starts_with("```diff") => {
                block = Some((line.starts_with("```diff"), Vec::new()));
            }
            None if line.starts_with('#') => heading = line.to_string(),
            None => {}
        }
    }
    out
}

/// The first snippet line not found, in order, among `file`'s lines.
fn first_missing(snippet: &Snippet) -> Option<String> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(&snippet.file);
    let source = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {}: {e}", snippet.guide, snippet.file));
    let mut file_lines = source.lines().map(code_of);
    snippet.lines.iter().find(|wanted| !file_lines.any(|l| &l == *wanted)).cloned()
}

#[test]
fn every_snippet_of_the_adding_guides_is_in_the_file_it_names() {
    let mut checked = 0;
    for guide in ["docs/ADDING_A_MODE.md", "docs/ADDING_A_PARAMETER.md", "docs/ADDING_A_FORMAT.md"] {
        let snippets = snippets(guide);
        assert!(!snippets.is_empty(), "{guide} shows no code");
        for snippet in &snippets {
            if let Some(line) = first_missing(snippet) {
                panic!(
                    "{} ({}): this line is not in {} (or not in this order):\n  {line}",
                    snippet.guide, snippet.heading, snippet.file
                );
            }
            checked += snippet.lines.len();
        }
    }
    println!("{checked} lines of the ADDING guides found in the tree");
}

#[test]
fn a_line_that_is_not_in_the_tree_is_found() {
    let snippet = Snippet {
        guide: "this test",
        heading: String::new(),
        file: "crates/render/src/modes/alpha_blend.rs".into(),
        lines: vec!["pub struct AlphaBlend;".into(), "splats: 0..frame.splats as u32,".into(), "triangles: 7,".into()],
    };
    assert_eq!(first_missing(&snippet).as_deref(), Some("triangles: 7,"));
    let reordered =
        Snippet { lines: vec!["splats: 0..frame.splats as u32,".into(), "pub struct AlphaBlend;".into()], ..snippet };
    assert_eq!(first_missing(&reordered).as_deref(), Some("pub struct AlphaBlend;"), "the order counts");
}
