//! Small functions: no function of the project's source (src and crates,
//! test modules and tests/ excluded) is over 120 lines, from its `fn` line
//! to its closing brace. A rule no test holds comes undone, so this one
//! reads every source file: code is scanned with strings, characters and
//! comments blanked out, and each `fn` with a body is measured by its braces.

mod common;

use common::source::rust_files;
use std::path::PathBuf;

const MOST_LINES: usize = 120;

/// `text` with every string, character literal and comment replaced by
/// spaces (line breaks kept), so that only code's braces remain.
fn blank_literals(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                out.push(' ');
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0;
            loop {
                if i + 1 < chars.len() && chars[i] == '/' && chars[i + 1] == '*' {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if i + 1 < chars.len() && chars[i] == '*' && chars[i + 1] == '/' {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else if i < chars.len() {
                    out.push(blank(chars[i]));
                    i += 1;
                } else {
                    break;
                }
            }
        } else if c == 'r' && (next == Some('"') || next == Some('#')) && !prev_is_ident(&chars, i) {
            // A raw string: r"..." or r#"..."#.
            let mut hashes = 0;
            let mut j = i + 1;
            while chars.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if chars.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            let closing: String = std::iter::once('"').chain(std::iter::repeat_n('#', hashes)).collect();
            let rest: String = chars[j + 1..].iter().collect();
            let end = rest.find(&closing).map_or(chars.len(), |k| j + 1 + rest[..k].chars().count() + closing.len());
            out.extend(chars[i..end].iter().map(|&c| blank(c)));
            i = end;
        } else if c == '"' {
            out.push(' ');
            i += 1;
            while i < chars.len() && chars[i] != '"' {
                let skip = if chars[i] == '\\' { 2 } else { 1 };
                for k in 0..skip {
                    if let Some(&c) = chars.get(i + k) {
                        out.push(blank(c));
                    }
                }
                i += skip;
            }
            out.push(' ');
            i += 1;
        } else if c == '\'' && char_literal_len(&chars, i).is_some() {
            let len = char_literal_len(&chars, i).expect("checked");
            out.extend(std::iter::repeat_n(' ', len));
            i += len;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn prev_is_ident(chars: &[char], i: usize) -> bool {
    i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_')
}

/// The length of a character literal at `i` (`'x'`, `'\n'`, `'\u{1F}'`), or
/// `None` for a lifetime (`'a`).
fn char_literal_len(chars: &[char], i: usize) -> Option<usize> {
    match chars.get(i + 1)? {
        '\\' => (i + 2..chars.len().min(i + 12)).find(|&k| chars[k] == '\'').map(|k| k - i + 1),
        _ => (chars.get(i + 2) == Some(&'\'')).then_some(3),
    }
}

/// The functions of `code` (literals blanked) longer than `most` lines:
/// (name, first line, lines). An inline test module (`#[cfg(test)]` then
/// `mod … {`) and all after it are left out.
fn long_functions(code: &str, most: usize) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = code.lines().collect();
    let test_module = |k: usize| {
        lines[k].trim().starts_with("#[cfg(")
            && lines[k].contains("test")
            && lines.get(k + 1).is_some_and(|l| l.trim_start().starts_with("mod ") && l.contains('{'))
    };
    let end = (0..lines.len()).find(|&k| test_module(k)).unwrap_or(lines.len());
    let mut long = Vec::new();
    for (n, line) in lines[..end].iter().enumerate() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some(at) = words.iter().position(|w| *w == "fn") else { continue };
        let Some(name) = words.get(at + 1).map(|w| w.split(['(', '<']).next().unwrap_or(w).to_string()) else {
            continue;
        };
        // The body opens at the first `{` after the signature, unless a `;` comes first.
        let mut depth = 0i32;
        let mut opened = false;
        let mut last = None;
        'scan: for (k, l) in lines[n..end].iter().enumerate() {
            for c in l.chars() {
                match c {
                    ';' if !opened => break 'scan,
                    '{' => {
                        opened = true;
                        depth += 1;
                    }
                    '}' if opened => {
                        depth -= 1;
                        if depth == 0 {
                            last = Some(n + k);
                            break 'scan;
                        }
                    }
                    _ => {}
                }
            }
        }
        if let Some(last) = last {
            let count = last - n + 1;
            if count > most {
                long.push((name, n + 1, count));
            }
        }
    }
    long
}

#[test]
fn no_function_is_over_120_lines() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let files: Vec<PathBuf> = [root.join("src"), root.join("crates")].iter().flat_map(|d| rust_files(d)).collect();
    assert!(files.len() > 100, "{} files checked", files.len());
    let mut long = Vec::new();
    for file in files.iter().filter(|f| !f.ends_with("doc_flags_tests.rs")) {
        let code = blank_literals(&std::fs::read_to_string(file).unwrap());
        for (name, line, count) in long_functions(&code, MOST_LINES) {
            long.push(format!("{}:{line} fn {name}: {count} lines", file.display()));
        }
    }
    assert!(long.is_empty(), "over {MOST_LINES} lines:\n{}", long.join("\n"));
}

#[test]
fn functions_are_measured_by_their_braces_not_their_strings() {
    let code = blank_literals(
        "fn short() {\n    let s = \"}}}\";\n    let c = '{';\n    // }\n}\nfn long<'a>(x: &'a str) {\n    if true {\n\n\n    }\n}\nfn decl();\n",
    );
    assert!(long_functions(&code, 6).is_empty(), "{:?}", long_functions(&code, 6));
    // The short one is 5 lines whatever its string, character and comment hold.
    assert_eq!(long_functions(&code, 5), [("long".to_string(), 6, 6)]);
    assert_eq!(long_functions(&blank_literals("fn raw() {\n let r = r#\"}\"#;\n}\n"), 2), [("raw".to_string(), 1, 3)]);
}
