//! Fig. 9's hash table for K groups, and §4.4.2's radius estimate derived
//! from its geometry for every K (Zhang & Pajarola 2007 §4.3, §4.4.2).
//!
//! The table maps Eq. 9's cell (x, y) to group `(x + s·y) mod K`, s the
//! integer nearest √K (s = 3 for K = 8 is Fig. 9 exactly). The cells of one
//! group are then a lattice: the (x, y) with x + s·y ≡ 0 (mod K), shifted.
//! §4.4.2 enlarges every splat so that its group alone covers the surface,
//! and for K = 8 takes the circumradius √50/4 of the lattice's triangle with
//! sides √10, √10 and 2√2 (cell sides, which are one radius). That is the
//! lattice's covering radius: the largest distance from any point of the
//! plane to the nearest cell centre of one group. [`cover_scale`] computes it
//! for any K from the lattice's reduced basis: its two shortest independent
//! vectors b1, b2 with b1·b2 ≥ 0 span a triangle with no obtuse angle, which
//! is one of the lattice's Delaunay triangles, all congruent, so the
//! covering radius is its circumradius. K = 4 gives 1.25, K = 8 √50/4.

/// Fig. 9's table for K groups, in 32-bit steps (the regrouping's hot loop).
#[derive(Debug, Clone, Copy)]
pub struct Table {
    k: i32,
    s: i32,
}

impl Table {
    /// The table for `k` groups (1..=[`super::MAX_GROUPS`]).
    pub fn new(k: usize) -> Self {
        let k = k.clamp(1, super::MAX_GROUPS) as i32;
        Self { k, s: ((k as f64).sqrt().round() as i32).max(1) }
    }

    /// The group of cell `(x, y)`.
    pub fn at(&self, (x, y): (i32, i32)) -> u32 {
        if self.k.count_ones() == 1 {
            // A mask for K a power of two (8, the paper's): no integer division.
            let mask = self.k - 1;
            return ((x & mask) + self.s * (y & mask)) as u32 & mask as u32;
        }
        (x.rem_euclid(self.k) + self.s * y.rem_euclid(self.k)).rem_euclid(self.k) as u32
    }

    pub fn k(&self) -> usize {
        self.k as usize
    }

    /// The lattice of the cells of group 0: a reduced basis (b1, b2), the
    /// shortest vector first and b1·b2 ≥ 0.
    pub fn group_lattice(&self) -> [[i64; 2]; 2] {
        let k = self.k as i64;
        let mut vectors: Vec<[i64; 2]> = (-k..=k)
            .flat_map(|x| (-k..=k).map(move |y| [x, y]))
            .filter(|&[x, y]| (x, y) != (0, 0) && self.at((x as i32, y as i32)) == 0)
            .collect();
        vectors.sort_by_key(|&[x, y]| (x * x + y * y, x, y));
        // (K, 0) and (0, K) are in the lattice, so both minima lie within |x|, |y| <= K.
        let b1 = vectors[0];
        let mut b2 = *vectors.iter().find(|v| v[0] * b1[1] - v[1] * b1[0] != 0).expect("(0, K) is independent of b1");
        if b1[0] * b2[0] + b1[1] * b2[1] < 0 {
            b2 = [-b2[0], -b2[1]];
        }
        [b1, b2]
    }
}

/// §4.4.2's radius scale for a hash grouping of `k` groups: the covering
/// radius of one group's cell centres in cell sides (one cell side is the
/// median radius), never below 1 (a splat is never shrunk).
pub fn cover_scale(k: usize) -> f32 {
    let [a, b] = Table::new(k).group_lattice().map(|[x, y]| [x as f64, y as f64]);
    let c = [b[0] - a[0], b[1] - a[1]];
    let length = |v: [f64; 2]| v[0].hypot(v[1]);
    let doubled_area = (a[0] * b[1] - a[1] * b[0]).abs();
    let circumradius = length(a) * length(b) * length(c) / (2.0 * doubled_area);
    circumradius.max(1.0) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eight_groups_give_the_papers_estimate_and_four_give_one_and_a_quarter() {
        assert!((cover_scale(8) - 50f32.sqrt() / 4.0).abs() < 1e-6, "{}", cover_scale(8));
        assert!((cover_scale(4) - 1.25).abs() < 1e-6, "{}", cover_scale(4));
    }
}
