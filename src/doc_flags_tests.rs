//! The docs and the parsers name the same flags, both ways:
//!
//! - every `--flag` the README or docs/*.md shows beside a subcommand exists
//!   in that subcommand's parser: in a command line (`pointblend render …`,
//!   `scripts/run render …`, in a code block or inline), in an inline span
//!   that starts with the subcommand (`render --camera SHOT.json`), or in a
//!   section of the user guide's "Command line" whose heading names the
//!   subcommand in backticks (every flag of that section is that command's);
//! - every flag of every subcommand's parser, hidden or not, is described in
//!   such a section of the guide.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use clap::CommandFactory;

use super::Cli;

/// Each subcommand's long flags (`help` aside), hidden ones included.
fn parser_flags() -> BTreeMap<String, BTreeSet<String>> {
    let cli = Cli::command();
    cli.get_subcommands()
        .map(|sub| {
            let flags = sub.get_arguments().filter_map(|a| a.get_long()).filter(|l| *l != "help");
            let mut flags: BTreeSet<String> = flags.map(str::to_string).collect();
            // Every subcommand has clap's `--help`, which need not be described.
            flags.insert("help".into());
            (sub.get_name().to_string(), flags)
        })
        .collect()
}

/// The `--flag` names in `text`.
fn flags_in(text: &str) -> Vec<String> {
    let mut flags = Vec::new();
    let mut rest = text;
    while let Some(at) = rest.find("--") {
        let before = rest[..at].chars().last();
        let name: String = rest[at + 2..].chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '-').collect();
        // `--x` starts a flag only after a space, a quote, a bracket or the start of the text.
        let starts = before.is_none_or(|c| c.is_whitespace() || "`'\"([|,".contains(c));
        if starts && name.starts_with(|c: char| c.is_ascii_lowercase()) {
            flags.push(name.trim_end_matches('-').to_string());
        }
        rest = &rest[at + 2..];
    }
    flags
}

/// The code of a Markdown text: each line of its fenced blocks, and each inline code span.
fn code_texts(markdown: &str) -> Vec<String> {
    let mut texts = Vec::new();
    for (i, part) in markdown.split("```").enumerate() {
        if i % 2 == 1 {
            texts.extend(part.lines().skip(1).map(str::to_string));
        } else {
            texts.extend(part.split('`').skip(1).step_by(2).map(str::to_string));
        }
    }
    texts
}

/// (subcommand, flag) pairs a code text names: after `pointblend SUB` or
/// `scripts/run SUB` up to a comment or a pipe, or after a leading `SUB`.
fn attributed(text: &str, commands: &BTreeSet<String>) -> Vec<(String, String)> {
    let command_text = text.split(" # ").next().unwrap_or(text).split(" | ").next().unwrap_or(text);
    let words: Vec<&str> = command_text.split_whitespace().collect();
    let mut pairs = Vec::new();
    for (i, word) in words.iter().enumerate() {
        let leads = i == 0 || words[i - 1].ends_with("pointblend") || words[i - 1] == "scripts/run";
        if leads && commands.contains(*word) && (i > 0 || words.get(1).is_some_and(|w| w.starts_with("--"))) {
            let rest = words[i + 1..].join(" ");
            let until_next = rest.split("pointblend ").next().unwrap_or(&rest);
            pairs.extend(flags_in(until_next).into_iter().map(|f| (word.to_string(), f)));
        }
    }
    pairs
}

/// The sections of the guide's "Command line": the subcommands each
/// heading names in backticks, and the flags of its text.
fn guide_sections(guide: &str, commands: &BTreeSet<String>) -> Vec<(String, BTreeSet<String>, Vec<String>)> {
    let part = guide.split("\n## Command line").nth(1).expect("the guide has a '## Command line' part");
    let part = part.split("\n## ").next().unwrap_or(part);
    part.split("\n### ")
        .skip(1)
        .map(|section| {
            let heading = section.lines().next().unwrap_or("");
            let named: BTreeSet<String> =
                heading.split('`').skip(1).step_by(2).filter(|w| commands.contains(*w)).map(str::to_string).collect();
            (heading.to_string(), named, flags_in(section))
        })
        .collect()
}

fn docs() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut paths = vec![root.join("README.md")];
    let mut in_docs: Vec<_> = std::fs::read_dir(root.join("docs")).unwrap().flatten().map(|e| e.path()).collect();
    in_docs.sort();
    paths.extend(in_docs.into_iter().filter(|p| p.extension().is_some_and(|e| e == "md")));
    paths
        .into_iter()
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read_to_string(&p).unwrap()))
        .collect()
}

#[test]
fn every_flag_the_docs_show_beside_a_subcommand_is_in_its_parser() {
    let parsers = parser_flags();
    let commands: BTreeSet<String> = parsers.keys().cloned().collect();
    let mut wrong = Vec::new();
    let mut checked = 0;
    for (doc, text) in docs() {
        for code in code_texts(&text) {
            for (command, flag) in attributed(&code, &commands) {
                checked += 1;
                if !parsers[&command].contains(&flag) {
                    wrong.push(format!("{doc}: `{code}` gives {command} --{flag}"));
                }
            }
        }
        if doc == "USER_GUIDE.md" {
            for (heading, named, flags) in guide_sections(&text, &commands) {
                for command in &named {
                    for flag in &flags {
                        checked += 1;
                        if !parsers[command].contains(flag) {
                            wrong.push(format!("{doc}: the section '{heading}' gives {command} --{flag}"));
                        }
                    }
                }
            }
        }
    }
    assert!(checked > 200, "the docs name flags beside their commands: {checked}");
    assert!(wrong.is_empty(), "flags the parsers do not have:\n{}", wrong.join("\n"));
}

#[test]
fn every_flag_of_every_subcommand_is_described_in_the_guide_under_it() {
    let parsers = parser_flags();
    let commands: BTreeSet<String> = parsers.keys().cloned().collect();
    let guide = docs().into_iter().find(|(doc, _)| doc == "USER_GUIDE.md").expect("the user guide").1;
    let mut described: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (_, named, flags) in guide_sections(&guide, &commands) {
        for command in named {
            described.entry(command).or_default().extend(flags.iter().cloned());
        }
    }
    let mut missing = Vec::new();
    for (command, flags) in &parsers {
        for flag in flags.iter().filter(|f| *f != "help") {
            if !described.get(command).is_some_and(|d| d.contains(flag)) {
                missing.push(format!("{command} --{flag}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "flags no section of the guide's Command line describes under their command:\n{}",
        missing.join("\n")
    );
}

#[test]
fn flags_are_found_and_attributed_as_written() {
    let commands: BTreeSet<String> = ["render", "bench", "view"].map(String::from).into();
    assert_eq!(flags_in("a --size 5 --no-cull, (--edl) x--y --Z"), ["size", "no-cull", "edl"]);
    let pairs = attributed("pointblend render a.ply --out b.png   # then --ignored", &commands);
    assert_eq!(pairs, [("render".to_string(), "out".to_string())]);
    let pairs = attributed("render --camera SHOT.json", &commands);
    assert_eq!(pairs, [("render".to_string(), "camera".to_string())]);
    assert!(attributed("bench renders views", &commands).is_empty());
    assert_eq!(attributed("scripts/run view --mode alg1", &commands), [("view".into(), "mode".into())]);
    let guide =
        "x\n## Command line\n### Camera: `render` and `view`\n`--fov` and `--up`\n### `bench`\n--frames\n## Next\n--no";
    let sections = guide_sections(guide, &commands);
    assert_eq!(sections.len(), 2);
    assert_eq!(sections[0].1, ["render", "view"].map(String::from).into());
    assert_eq!(sections[0].2, ["fov", "up"]);
    assert_eq!(sections[1].2, ["frames"]);
}
