//! The help texts that name file formats, made from the core's format
//! registry ([`pointblend::formats::FORMATS`]) so that a format added there
//! is named in every command's `--help` at once.

use pointblend::formats::{self, Format, Reader};

/// The commands that stream a COPC file or URL node by node; `convert` and
/// `group` read one whole, as LAZ.
pub const STREAMING_COMMANDS: [&str; 6] = ["view", "render", "bench", "info", "pick", "measure"];

fn whole(format: &Format) -> bool {
    pointblend::cloud::formats::opened_whole(format)
}

fn streamed_formats() -> String {
    formats::names_with_extensions(|f| f.streamed)
}

fn scene_files() -> String {
    formats::names_with_extensions(|f| f.reader == Reader::Scene)
}

/// The list of commands that stream, for a sentence.
fn streaming_commands() -> String {
    let (last, rest) = STREAMING_COMMANDS.split_last().expect("commands stream");
    format!("{} and {last}", rest.join(", "))
}

/// A file that `render`, `pick` and `measure` draw.
pub fn drawn_file() -> String {
    format!("{}; or a virtual point cloud (.vpc) of such files, of which those the view reaches are opened", one_file())
}

/// A cloud, a scene file, or a streamed file.
fn one_file() -> String {
    format!(
        "Point cloud ({}), {}, or a {} file or http(s) URL, streamed under the point budget",
        formats::names(whole, "or"),
        scene_files(),
        streamed_formats()
    )
}

/// The file `profile` cuts.
pub fn profiled_file() -> String {
    format!(
        "Point cloud ({}), every point read; a {} file or http(s) URL: every point of the nodes the slab meets",
        formats::names(whole, "or"),
        streamed_formats()
    )
}

/// The files `bench` measures.
pub fn benched_files() -> String {
    format!(
        "Point clouds ({}), {}s or virtual point clouds (.vpc, every file of each together); {} files and http(s) URLs are streamed view by view under the point budget (1M unless --point-budget)",
        formats::names(whole, "or"),
        scene_files(),
        streamed_formats()
    )
}

/// The file `view` opens.
pub fn opened_by_view() -> String {
    format!(
        "{}; or a virtual point cloud (.vpc): every file of it [default: the demo scene, assets/demo.toml]",
        one_file()
    )
}

/// The file `info` describes.
pub fn described_by_info() -> String {
    format!(
        "Point cloud file ({}); of a {} file or http(s) URL, its header and hierarchy, without decoding its points; of a .vpc, what it states of its files",
        formats::names(whole, "or"),
        streamed_formats()
    )
}

/// What `convert` reads.
pub fn converted_input() -> String {
    format!(
        "Input: a mesh or cloud ({}; a COPC file is read whole, as LAZ; of a COPC http(s) URL, the nodes meeting --clip-box), or a {}",
        formats::names(whole, "or"),
        formats::names_with_extensions(|f| f.reader == Reader::Volume)
    )
}

/// What `convert` writes.
pub fn converted_output() -> String {
    format!(
        "Output, by its extension: {}. PLY is binary (x y z nx ny nz radius red green blue, then the attributes); \
         LAS and LAZ keep the attributes in their fields, normals and radii as extra bytes; COPC is an octree of \
         LAZ chunks that {} stream",
        formats::names_with_extensions(|f| f.written),
        streaming_commands()
    )
}

/// The file `group` groups.
pub fn grouped_file() -> String {
    format!("Point cloud file ({}; a COPC file is read whole)", formats::names(whole, "or"))
}

/// `pointblend info`'s one-line description.
pub fn info_about() -> String {
    format!(
        "Show what a file holds ({}; COPC without decoding; a .vpc's files as it lists them) and what loading estimates or repairs",
        formats::names(whole, "or")
    )
}

/// `pointblend render`'s one-line description.
pub fn render_about() -> String {
    format!(
        "Render a point cloud ({}), a COPC stream or a scene file to a PNG or JPEG image",
        formats::names(whole, "or")
    )
}

/// The program's one-line description.
pub fn program_about() -> String {
    format!(
        "Point-based surface splatting with correct transparency: render, inspect and benchmark point clouds ({})",
        formats::names(|f| whole(f) || f.streamed, "and")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_help_that_lists_point_files_names_every_format_of_the_registry() {
        let helps = [
            ("render", drawn_file()),
            ("bench", benched_files()),
            ("view", opened_by_view()),
            ("info", described_by_info()),
            ("convert", converted_input()),
            ("group", grouped_file()),
            ("info's about", info_about()),
            ("render's about", render_about()),
            ("the program", program_about()),
        ];
        for (command, help) in &helps {
            for format in formats::FORMATS.iter().filter(|f| whole(f)) {
                assert!(help.contains(format.name), "{command}'s help does not name {}: {help}", format.name);
            }
        }
        for format in formats::FORMATS.iter().filter(|f| f.written) {
            assert!(converted_output().contains(format.name), "convert's output help: {}", converted_output());
        }
    }
}
