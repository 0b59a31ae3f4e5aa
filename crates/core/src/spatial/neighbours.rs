//! A table of each point's k nearest neighbours, as [`super::knn`] and
//! [`super::grid_knn`] fill it: one row per point, in the points' order or,
//! from the grid, in its cell order with each point's row looked up
//! (putting 2M rows back in the points' order took a third of the search's
//! time, on one thread). It holds no distances: a row's are the distances
//! to its points, which its user computes as the search did (the table is
//! the largest allocation of a load, and they were half of it).

use rayon::prelude::*;

/// `k` neighbours per point.
#[derive(Debug, Clone)]
pub struct Neighbours {
    pub k: usize,
    /// Row after row of `k` point indices, nearest first.
    indices: Vec<u32>,
    /// The row of point i, and the point of each row, when row i is not point i's.
    row_of: Option<(Vec<u32>, Vec<u32>)>,
    /// Points with a row: the first `queries`.
    queries: usize,
}

impl Neighbours {
    /// Row i is point i's.
    pub fn in_point_order(k: usize, indices: Vec<u32>) -> Self {
        let queries = indices.len() / k.max(1);
        Neighbours { k, indices, row_of: None, queries }
    }

    /// Row r is point `point_of[r]`'s, for the first `queries` points (the
    /// rows of the others are not read).
    pub fn in_row_order(k: usize, indices: Vec<u32>, point_of: Vec<u32>, queries: usize) -> Self {
        let mut row_of = vec![0u32; point_of.len()];
        for (row, &i) in point_of.iter().enumerate() {
            row_of[i as usize] = row as u32;
        }
        Neighbours { k, indices, row_of: Some((row_of, point_of)), queries }
    }

    /// Points with a row.
    pub fn rows(&self) -> usize {
        self.queries
    }

    fn row(&self, i: usize) -> std::ops::Range<usize> {
        let row = self.row_of.as_ref().map_or(i, |(rows, _)| rows[i] as usize);
        row * self.k..(row + 1) * self.k
    }

    /// The j-th nearest neighbour of point i is `of(i)[j]`.
    pub fn of(&self, i: usize) -> &[u32] {
        &self.indices[self.row(i)]
    }

    /// `f(i, neighbours)` for each point i with a row, in point
    /// order, computed in parallel in the rows' order: read point by point,
    /// the rows of a grid's table are a cache miss each (the radii of 2M
    /// points took 0.12 s so), read row by row they stream.
    pub fn map_rows<T: Send + Sync + Copy>(&self, f: impl Fn(usize, &[u32]) -> T + Sync) -> Vec<T> {
        let k = self.k;
        let row = |r: usize| &self.indices[r * k..(r + 1) * k];
        match &self.row_of {
            None => (0..self.queries).into_par_iter().map(|i| f(i, row(i))).collect(),
            Some((row_of, point_of)) => {
                let by_row: Vec<Option<T>> = (0..point_of.len())
                    .into_par_iter()
                    .map(|r| {
                        let i = point_of[r] as usize;
                        (i < self.queries).then(|| f(i, row(r)))
                    })
                    .collect();
                (0..self.queries).into_par_iter().map(|i| by_row[row_of[i] as usize].expect("a query's row")).collect()
            }
        }
    }

    /// Point i's row, to fill.
    pub fn row_mut(&mut self, i: usize) -> &mut [u32] {
        let row = self.row(i);
        &mut self.indices[row]
    }
}
