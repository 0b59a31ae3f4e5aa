//! Errors raised while reading, writing or converting point clouds.
//!
//! Every variant names the file it concerns and renders as one line, so the
//! CLI can print it as is.

use std::path::PathBuf;

/// A failure to read or write a point cloud file.
#[derive(Debug, thiserror::Error)]
pub enum CloudError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path}: not a valid PLY file: {reason}")]
    Format { path: PathBuf, reason: String },
    #[error("{path}: {reason}")]
    Content { path: PathBuf, reason: String },
}

impl CloudError {
    pub(crate) fn format(path: &std::path::Path, reason: impl Into<String>) -> Self {
        CloudError::Format { path: path.to_path_buf(), reason: one_line(&reason.into()) }
    }

    pub(crate) fn content(path: &std::path::Path, reason: impl Into<String>) -> Self {
        CloudError::Content { path: path.to_path_buf(), reason: one_line(&reason.into()) }
    }

    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        CloudError::Io { path: path.to_path_buf(), source }
    }
}

/// Collapses a multi-line message (ply-rs reports several lines) into one.
pub(crate) fn one_line(text: &str) -> String {
    let words: Vec<&str> = text.split_whitespace().collect();
    let mut line = words.join(" ");
    const MAX_LEN: usize = 300;
    if line.len() > MAX_LEN {
        let mut cut = MAX_LEN;
        while !line.is_char_boundary(cut) {
            cut -= 1;
        }
        line.truncate(cut);
        line.push('…');
    }
    line
}
