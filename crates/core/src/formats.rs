//! Every file format pointblend reads or writes, one row each: its name,
//! its extensions, the reader that opens it, whether it is streamed (read
//! node by node under a point budget, from disk or over HTTP) rather than
//! opened whole, and whether `convert` writes it.
//!
//! Readers dispatch on this table ([`format_of`]; `cloud::formats::reader_of`
//! gives each kind of file its reader), and the command line's help and
//! errors list formats from it ([`names`]), so that a format added here is
//! read, written and named everywhere at once.

use std::path::Path;

/// The code that reads a format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reader {
    /// [`crate::cloud::ply`]: clouds, meshes, strips, 3D Gaussian splats.
    Ply,
    /// [`crate::cloud::las_file`], through the `las` and `laz` crates.
    Las,
    /// [`crate::cloud::e57_file`], through the `e57` crate.
    E57,
    /// [`crate::copc`]: node by node, from disk or over HTTP.
    Copc,
    /// [`crate::scene::file`]: objects, materials, lights, camera.
    Scene,
    /// [`crate::cloud::volume`]: a scalar volume, made into points by `convert`.
    Volume,
}

/// One format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Format {
    pub name: &'static str,
    /// Lower-case file name endings, with their dot; the longest match wins
    /// (`.copc.laz` over `.laz`).
    pub extensions: &'static [&'static str],
    /// What a file of it holds, for help texts.
    pub holds: &'static str,
    pub reader: Reader,
    /// Read node by node under the point budget (and from http(s) URLs).
    pub streamed: bool,
    /// `convert` writes it.
    pub written: bool,
}

/// The formats, in the order help texts list them.
pub const FORMATS: [Format; 7] = [
    Format {
        name: "PLY",
        extensions: &[".ply"],
        holds: "clouds, meshes, strips, 3D Gaussian splats",
        reader: Reader::Ply,
        streamed: false,
        written: true,
    },
    Format {
        name: "LAS",
        extensions: &[".las"],
        holds: "lidar points with their attributes",
        reader: Reader::Las,
        streamed: false,
        written: true,
    },
    Format {
        name: "LAZ",
        extensions: &[".laz"],
        holds: "compressed LAS",
        reader: Reader::Las,
        streamed: false,
        written: true,
    },
    Format {
        name: "E57",
        extensions: &[".e57"],
        holds: "terrestrial scans",
        reader: Reader::E57,
        streamed: false,
        written: false,
    },
    Format {
        name: "COPC",
        extensions: &[".copc.laz"],
        holds: "a LAZ octree, streamed from disk or an http(s) URL",
        reader: Reader::Copc,
        streamed: true,
        written: true,
    },
    Format {
        name: "scene file",
        extensions: &[".toml"],
        holds: "objects, materials, lights and a camera",
        reader: Reader::Scene,
        streamed: false,
        written: false,
    },
    Format {
        name: "NIfTI-1 volume",
        extensions: &[".nii", ".nii.gz"],
        holds: "a scalar volume, made into points by convert",
        reader: Reader::Volume,
        streamed: false,
        written: false,
    },
];

/// Whether `name` is an http(s) URL.
pub fn is_url(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.starts_with("http://") || lower.starts_with("https://")
}

/// The format whose extension ends `name` (a URL's query and fragment left out).
pub fn by_extension(name: &str) -> Option<&'static Format> {
    let path = name.split(['?', '#']).next().unwrap_or(name).to_ascii_lowercase();
    FORMATS
        .iter()
        .flat_map(|f| f.extensions.iter().map(move |e| (f, *e)))
        .filter(|(_, e)| path.ends_with(e))
        .max_by_key(|(_, e)| e.len())
        .map(|(f, _)| f)
}

/// The format a path or URL names: by its extension, and every URL is
/// streamed, so a URL with no known extension is COPC.
pub fn format_of_name(name: &str) -> Option<&'static Format> {
    match by_extension(name) {
        Some(f) => Some(f),
        None if is_url(name) => FORMATS.iter().find(|f| f.streamed),
        None => None,
    }
}

/// The format of `path` by its extension.
pub fn format_of(path: &Path) -> Option<&'static Format> {
    format_of_name(&path.to_string_lossy())
}

/// The formats `keep` selects, named for a sentence: "PLY, LAS, LAZ or E57"
/// (with `and` when `conjunction` says so).
pub fn names(keep: impl Fn(&Format) -> bool, conjunction: &str) -> String {
    let names: Vec<&str> = FORMATS.iter().filter(|f| keep(f)).map(|f| f.name).collect();
    match names.as_slice() {
        [] => String::new(),
        [one] => one.to_string(),
        [rest @ .., last] => format!("{} {conjunction} {last}", rest.join(", ")),
    }
}

/// The formats `keep` selects with their extensions: "PLY (.ply), LAS (.las)".
pub fn names_with_extensions(keep: impl Fn(&Format) -> bool) -> String {
    FORMATS
        .iter()
        .filter(|f| keep(f))
        .map(|f| format!("{} ({})", f.name, f.extensions.join(", ")))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_longest_extension_wins_and_case_is_ignored() {
        assert_eq!(format_of(Path::new("a/b.COPC.LAZ")).unwrap().name, "COPC");
        assert_eq!(format_of(Path::new("a/b.laz")).unwrap().name, "LAZ");
        assert_eq!(format_of(Path::new("head.nii.gz")).unwrap().reader, Reader::Volume);
        assert_eq!(format_of(Path::new("demo.toml")).unwrap().reader, Reader::Scene);
        assert!(format_of(Path::new("points.xyz")).is_none());
        assert!(format_of(Path::new("no-extension")).is_none());
    }

    #[test]
    fn a_url_is_streamed_whatever_it_ends_with() {
        assert!(format_of_name("https://example.org/scan.copc.laz?sig=1#x").unwrap().streamed);
        assert!(format_of_name("http://example.org/data").unwrap().streamed);
        assert_eq!(format_of_name("http://example.org/x.copc.laz").unwrap().name, "COPC");
    }

    #[test]
    fn names_read_as_a_list() {
        assert_eq!(names(|f| f.written, "and"), "PLY, LAS, LAZ and COPC");
        assert_eq!(names(|f| f.streamed, "or"), "COPC");
        assert!(names_with_extensions(|f| f.written).contains("COPC (.copc.laz)"));
    }

    #[test]
    fn every_extension_names_one_format() {
        let mut seen = std::collections::HashSet::new();
        for format in &FORMATS {
            for extension in format.extensions {
                assert!(extension.starts_with('.') && *extension == extension.to_lowercase(), "{extension}");
                assert!(seen.insert(*extension), "{extension} is in two rows");
            }
        }
    }
}
