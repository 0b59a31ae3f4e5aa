//! A table of each point's k nearest neighbours and their distances, as
//! [`super::knn`] and [`super::grid_knn`] fill it.

/// `k` neighbours per point, row-major.
#[derive(Debug, Clone)]
pub struct Neighbours {
    pub k: usize,
    /// `indices[i * k + j]`: the j-th nearest neighbour of point i.
    pub indices: Vec<u32>,
    /// Euclidean distances matching `indices`.
    pub distances: Vec<f32>,
}

impl Neighbours {
    /// Points with a row.
    pub fn rows(&self) -> usize {
        self.indices.len() / self.k.max(1)
    }

    pub fn of(&self, i: usize) -> &[u32] {
        &self.indices[i * self.k..(i + 1) * self.k]
    }

    pub fn distances_of(&self, i: usize) -> &[f32] {
        &self.distances[i * self.k..(i + 1) * self.k]
    }
}
