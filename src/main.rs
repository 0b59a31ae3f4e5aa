//! The `pointblend` command line: view | info | render | pick | measure | profile | convert | bench | group.
//!
//! With no subcommand it is `pointblend view`, parsed by the same clap
//! arguments (so the two cannot differ): the viewer on the demo scene in alg2,
//! or, with no display, the opaque modes on the bundled lion and the
//! transparent ones on the demo scene rendered to `./out/`.

mod commands;
#[cfg(test)]
mod doc_flags_tests;
mod interrupt;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "pointblend",
    version,
    about = commands::formats_help::program_about(),
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// With no subcommand: the arguments of `view`, with its defaults.
    #[command(flatten)]
    view: commands::view::Args,
}

#[derive(Subcommand)]
enum Command {
    /// Open the interactive viewer (the default); headless, render every mode to ./out/.
    View(commands::view::Args),
    #[command(about = commands::formats_help::info_about())]
    Info(commands::info::Args),
    #[command(about = commands::formats_help::render_about())]
    Render(commands::render::Args),
    /// List the surface layers a pixel's ray passes (the exact reference's), with their attributes.
    Pick(commands::pick::Args),
    /// Measure distances, angles and heights between the surfaces under pixels.
    Measure(commands::measure::Args),
    /// A cross-section: the points within a slab along a line, drawn from the side and written out.
    Profile(commands::profile::Args),
    /// Convert a mesh, cloud or volume into splats: PLY with normals, radii and colours, LAS/LAZ, or COPC.
    Convert(commands::convert::Args),
    /// Time every mode and measure its error against the exact reference.
    Bench(commands::bench::Args),
    /// Split the splats into groups (MGC, WGC or hashing) and report their quality.
    Group(commands::group::Args),
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn,pointblend=info"))
        .format_timestamp(None)
        .format_target(false)
        // The las crate's "upgrading las version" names no file; the reader logs its own line that does.
        .filter_module("las::header", log::LevelFilter::Error)
        .init();
    interrupt::end_quietly_on_a_closed_pipe();
    interrupt::install();
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::View(args)) => commands::view::run(&args),
        Some(Command::Info(args)) => commands::info::run(&args),
        Some(Command::Render(args)) => commands::render::run(&args),
        Some(Command::Pick(args)) => commands::pick::run(&args),
        Some(Command::Measure(args)) => commands::measure::run(&args),
        Some(Command::Profile(args)) => commands::profile::run(&args),
        Some(Command::Convert(args)) => commands::convert::run(&args),
        Some(Command::Bench(args)) => commands::bench::run(&args),
        Some(Command::Group(args)) => commands::group::run(&args),
        None => commands::view::run(&cli.view),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            // Whatever the error quotes, a URL's credentials are not shown.
            eprintln!("error: {}", pointblend::copc::shown(&one_line(&error)));
            ExitCode::FAILURE
        }
    }
}

/// The error and its causes on one line.
fn one_line(error: &anyhow::Error) -> String {
    let mut parts: Vec<String> = Vec::new();
    for cause in error.chain() {
        let text = cause.to_string();
        if !parts.iter().any(|p| p.contains(&text)) {
            parts.push(text);
        }
    }
    parts.join(": ").split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::{Cli, Command};

    /// The view arguments `pointblend ARGS` parses to, as text.
    fn view_args(args: &[&str]) -> String {
        let cli = Cli::try_parse_from(args).expect("parses");
        match cli.command {
            Some(Command::View(view)) => format!("{view:?}"),
            None => format!("{:?}", cli.view),
            Some(_) => panic!("{args:?} is not the viewer"),
        }
    }

    #[test]
    fn no_subcommand_parses_exactly_as_view() {
        assert_eq!(view_args(&["pointblend"]), view_args(&["pointblend", "view"]));
        let flags = ["--size", "96x64", "--out", "o", "--mode", "alg1"];
        let bare: Vec<&str> = ["pointblend"].into_iter().chain(flags).collect();
        let view: Vec<&str> = ["pointblend", "view"].into_iter().chain(flags).collect();
        assert_eq!(view_args(&bare), view_args(&view));
        assert!(view_args(&["pointblend"]).contains("size: (512, 512)"), "clap's defaults, not Default's");
    }

    /// The long flags of a subcommand.
    fn long_flags(name: &str) -> std::collections::BTreeSet<String> {
        use clap::CommandFactory;
        let cli = Cli::command();
        let command = cli.find_subcommand(name).unwrap_or_else(|| panic!("no subcommand {name}"));
        command.get_arguments().filter_map(|a| a.get_long()).map(str::to_string).collect()
    }

    /// The rendering parameters among each front end's flags, keys and
    /// settings are exactly the descriptor table's rows: a parameter added by
    /// hand to one of them (or a row one of them leaves out) fails here.
    #[test]
    fn every_front_ends_rendering_parameters_are_exactly_the_descriptor_tables() {
        use pointblend::frame::parameters::TABLE;
        use pointblend::frame::{RenderSettings, Sidecar};
        let table: std::collections::BTreeSet<String> =
            TABLE.iter().flat_map(|row| [row.flag].into_iter().chain(row.off_switch)).map(str::to_string).collect();
        // View, camera, scene and output flags, and each command's own job: outside the table.
        let view_and_camera = [
            "mode",
            "size",
            "azimuth",
            "elevation",
            "distance",
            "fov",
            "up",
            "projection",
            "view",
            "camera",
            "cache-mb",
            "disk-cache",
        ];
        let scene = [
            "opacity",
            "color",
            "light",
            "env",
            "color-by",
            "colormap",
            "range",
            "classes",
            "filter",
            "returns",
            "class-opacity",
            "opacity-by",
            "clip-box",
            "clip-hide",
            "clip-plane",
        ];
        let own: [(&str, &[&str]); 4] = [
            ("render", &["out", "explain", "diff", "flat-background", "time", "path", "path-frames"]),
            (
                "bench",
                &[
                    "modes",
                    "ruler",
                    "no-reference",
                    "frames",
                    "warm-up",
                    "views",
                    "loads",
                    "orders",
                    "out",
                    "animate",
                    "path",
                    "together",
                ],
            ),
            ("view", &["screenshot", "exit-after-frames", "screenshot-dir", "out", "time"]),
            ("profile", &["line", "width", "out", "csv", "points"]),
        ];
        for (name, own) in own {
            let outside: std::collections::BTreeSet<String> =
                view_and_camera.iter().chain(&scene).chain(own).chain(&["help"]).map(|f| f.to_string()).collect();
            let parameters: std::collections::BTreeSet<String> =
                long_flags(name).into_iter().filter(|f| !outside.contains(f)).collect();
            assert_eq!(parameters, table, "`pointblend {name}`'s rendering flags");
        }
        // Bench variants take every row's key, and no other.
        for row in &TABLE {
            let mode = row.parameter.used_by().next().expect("a mode reads it");
            let value = row.parameter.shown_text(&RenderSettings { mode, ..Default::default() });
            let variant = format!("{mode}:{}={value}", row.key);
            assert!(pointblend::bench::variants::expand(&variant).is_ok(), "bench refuses {variant}");
        }
        assert!(pointblend::bench::variants::expand("two-pass:no-such-key=1").is_err());
        // A sidecar records every row that holds a value, and reads it back.
        let settings = RenderSettings { peel_layers: 4, ..Default::default() };
        let model = pointblend::frame::sidecar::SidecarModel {
            name: String::new(),
            path: String::new(),
            hash: String::new(),
            splats: 1,
            nodes: false,
            layers: Vec::new(),
        };
        let camera = pointblend::frame::Camera::framing(glam::Vec3::ZERO, 1.0, 1.0);
        let sidecar = Sidecar::new(model, &camera, &settings, (8, 8));
        let keys: Vec<&str> = sidecar.parameters.keys().map(String::as_str).collect();
        let mut rows: Vec<&str> = TABLE.iter().map(|row| row.key).collect();
        rows.sort();
        assert_eq!(keys, rows, "the sidecar's settings");
        assert_eq!(sidecar.settings(), Ok(settings));
    }

    /// No subcommand has two flags of one name (say a command's own flag and
    /// a flattened parameter's): clap checks that only in debug builds, and a
    /// release build silently gives the value to one of them.
    #[test]
    fn no_subcommand_has_two_flags_or_arguments_of_one_name() {
        use clap::CommandFactory;
        for sub in Cli::command().get_subcommands() {
            let mut seen = std::collections::BTreeSet::new();
            for long in sub.get_arguments().filter_map(|a| a.get_long()) {
                assert!(seen.insert(long), "`pointblend {}` has two --{long} flags", sub.get_name());
            }
            // Nor two arguments of one id: clap would give both one value (as the MORE files
            // once took the --layers parameter's).
            let mut ids = std::collections::BTreeSet::new();
            for id in sub.get_arguments().map(|a| a.get_id().as_str()) {
                assert!(ids.insert(id), "`pointblend {}` has two arguments of id {id}", sub.get_name());
            }
        }
    }

    /// The window takes every camera, streaming and time flag that `render` takes.
    #[test]
    fn view_takes_renders_camera_streaming_and_time_flags() {
        let (view, render) = (long_flags("view"), long_flags("render"));
        let wanted = ["azimuth", "elevation", "distance", "fov", "up", "cache-mb", "disk-cache", "time", "mode", "env"];
        for flag in wanted {
            assert!(render.contains(flag), "render --{flag}");
            assert!(view.contains(flag), "view lacks render's --{flag}");
        }
        // And the commands that do not read a flag do not show it.
        assert!(!long_flags("bench").contains("mode") && !long_flags("bench").contains("azimuth"));
        assert!(!long_flags("pick").contains("mode") && !long_flags("measure").contains("mode"));
    }

    /// Shell words of one command line: quotes group, `#` outside quotes ends it.
    fn shell_words(line: &str) -> Vec<String> {
        let (mut words, mut word, mut quote, mut in_word) = (Vec::new(), String::new(), None, false);
        for c in line.chars() {
            match (quote, c) {
                (Some(q), c) if c == q => quote = None,
                (Some(_), c) => word.push(c),
                (None, '"' | '\'') => (quote, in_word) = (Some(c), true),
                (None, '#') if !in_word => break,
                (None, c) if c.is_whitespace() => {
                    if in_word {
                        words.push(std::mem::take(&mut word));
                    }
                    in_word = false;
                }
                (None, c) => {
                    word.push(c);
                    in_word = true;
                }
            }
        }
        if in_word {
            words.push(word);
        }
        words
    }

    /// Every `pointblend …` line of the shell blocks of the README and docs/.
    fn documented_commands() -> Vec<(String, String)> {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let mut docs = vec![root.join("README.md")];
        let mut in_docs: Vec<_> = std::fs::read_dir(root.join("docs")).unwrap().flatten().map(|e| e.path()).collect();
        in_docs.sort();
        docs.extend(in_docs.into_iter().filter(|p| p.extension().is_some_and(|e| e == "md")));
        let mut commands = Vec::new();
        for doc in docs {
            let text = std::fs::read_to_string(&doc).unwrap();
            let blocks = text.split("```").enumerate().filter(|(i, _)| i % 2 == 1).map(|(_, b)| b);
            for block in blocks.filter(|b| b.starts_with("sh") || b.starts_with("bash")) {
                for line in block.lines().map(str::trim).filter(|l| l.starts_with("pointblend ")) {
                    commands.push((doc.file_name().unwrap().to_string_lossy().into_owned(), line.to_string()));
                }
            }
        }
        commands
    }

    #[test]
    fn every_command_the_docs_show_parses_and_names_bundled_files_that_exist() {
        let commands = documented_commands();
        assert!(commands.len() >= 20, "the docs show the command line: {}", commands.len());
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        for (doc, line) in &commands {
            let words = shell_words(line);
            if let Err(error) = Cli::try_parse_from(&words) {
                panic!("{doc}: `{line}` does not parse:\n{error}");
            }
            // BENCHMARKS.md records past runs with the files of their day.
            let current = doc != "BENCHMARKS.md";
            for word in words.iter().filter(|w| current && w.starts_with("assets/")) {
                let file = word.split(',').next().unwrap();
                assert!(root.join(file).exists(), "{doc}: `{line}` names {file}, which does not exist");
            }
        }
    }

    #[test]
    fn shell_words_follow_quotes_and_comments() {
        let words = shell_words(r#"pointblend convert a.nii b.ply --transfer "9000:1/2/3/0,1:2/3/4/0.7"   # a volume"#);
        assert_eq!(words, ["pointblend", "convert", "a.nii", "b.ply", "--transfer", "9000:1/2/3/0,1:2/3/4/0.7"]);
    }
}
