//! The `pointblend` command line: view | info | render | convert | bench | group.
//!
//! With no subcommand it opens the viewer on the demo scene in alg2 (or, with
//! no display, renders the opaque modes on the bundled bunny and the
//! transparent ones on the demo scene to `./out/`).

mod commands;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "pointblend",
    version,
    about = "Point-based surface splatting: render, inspect and benchmark PLY scans"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Open the interactive viewer (the default); headless, render every mode to ./out/.
    View(commands::view::Args),
    /// Show what a PLY file holds and what loading it estimates or repairs.
    Info(commands::info::Args),
    /// Render a PLY file to a PNG image.
    Render(commands::render::Args),
    /// Convert a mesh or cloud into a splat cloud (binary PLY with normals, radii, colours).
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
        .init();
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::View(args)) => commands::view::run(&args),
        Some(Command::Info(args)) => commands::info::run(&args),
        Some(Command::Render(args)) => commands::render::run(&args),
        Some(Command::Convert(args)) => commands::convert::run(&args),
        Some(Command::Bench(args)) => commands::bench::run(&args),
        Some(Command::Group(args)) => commands::group::run(&args),
        None => commands::view::run(&commands::view::Args {
            screenshot_dir: "screenshots".into(),
            out: "out".into(),
            ..Default::default()
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {}", one_line(&error));
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
