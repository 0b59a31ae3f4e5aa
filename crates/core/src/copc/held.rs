//! The nodes of a LAS/LAZ file held whole ([`super::memory`]): the file's
//! decoded columns and, for each node of its tree, the indices of the points
//! it holds. Loading a node gathers them; nothing is read or decoded again.

use crate::cloud::las_file::Columns;

/// Each node's points, indices into the file's columns (by node of the tree).
pub(crate) struct MemoryNodes {
    columns: Columns,
    points: Vec<Vec<u32>>,
}

impl MemoryNodes {
    /// `points[n]`: the indices into `columns` of node `n`'s points.
    pub(crate) fn new(columns: Columns, points: Vec<Vec<u32>>) -> Self {
        Self { columns, points }
    }

    /// Node `n`'s points, gathered.
    pub(crate) fn node(&self, n: u32) -> Columns {
        self.columns.gather(&self.points[n as usize])
    }
}
