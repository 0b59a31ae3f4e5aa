//! The nodes of a file held whole ([`super::memory`]): the file's decoded
//! columns and, for each node of its tree, the indices of the points it
//! holds. Loading a node gathers them; nothing is read or decoded again.
//! Beside them, what the file says of itself where no LAS header does (a
//! PLY or E57 file), and how its estimated normals face.

use super::node_estimates::FileFacing;
use crate::cloud::FileInfo;
use crate::cloud::las_file::Columns;

/// What a PLY or E57 file held whole says of itself: its encoding line and
/// what its reader found (format lines, CRS, warnings, which way is up).
pub(crate) struct Described {
    pub(crate) encoding: String,
    pub(crate) info: FileInfo,
}

/// Each node's points, indices into the file's columns (by node of the tree).
pub(crate) struct MemoryNodes {
    columns: Columns,
    points: Vec<Vec<u32>>,
    /// How the nodes' estimated normals face, decided once for the file.
    pub(crate) facing: FileFacing,
    /// `None` for a LAS or LAZ file: its header describes it.
    pub(crate) described: Option<Described>,
}

impl MemoryNodes {
    /// `points[n]`: the indices into `columns` of node `n`'s points.
    pub(crate) fn new(columns: Columns, points: Vec<Vec<u32>>) -> Self {
        Self { columns, points, facing: FileFacing::Up, described: None }
    }

    /// Node `n`'s points, gathered.
    pub(crate) fn node(&self, n: u32) -> Columns {
        self.columns.gather(&self.points[n as usize])
    }
}
