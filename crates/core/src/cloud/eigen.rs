//! A neighbourhood's covariance and the eigenvector of its smallest
//! eigenvalue: the normal of principal component analysis (Hoppe et al.
//! 1992), for [`super::estimate`]. The eigenvalue by Newton's method on the
//! characteristic polynomial where the smallest stands far below the others
//! (a surface), else by the cubic's trigonometric solution; the eigenvector
//! as the largest cross product of two rows of A - λI; where the two
//! smallest eigenvalues nearly coincide, by cyclic Jacobi rotations. No
//! linear-algebra crate for one call.

use glam::{DVec3, Mat3, Vec3};

/// The sum of (p - centre)(p - centre)ᵀ over `points`: its six distinct
/// entries accumulated once each (a product and its mirror are the same
/// f32, so the matrix is the one a full outer product per point makes).
pub(crate) fn covariance(points: &[Vec3], centre: Vec3) -> Mat3 {
    let (mut xx, mut xy, mut xz, mut yy, mut yz, mut zz) = (0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for p in points {
        let d = *p - centre;
        xx += d.x * d.x;
        xy += d.y * d.x;
        xz += d.z * d.x;
        yy += d.y * d.y;
        yz += d.z * d.y;
        zz += d.z * d.z;
    }
    Mat3::from_cols(Vec3::new(xx, xy, xz), Vec3::new(xy, yy, yz), Vec3::new(xz, yz, zz))
}

/// Unit eigenvector of the smallest eigenvalue of a symmetric 3x3 matrix.
///
/// In closed form where the smallest eigenvalue stands apart (a surface's
/// neighbourhood: the common case, a third of the time of the sweeps), else
/// by cyclic Jacobi rotations ([`jacobi_smallest_eigenvector`]).
pub fn smallest_eigenvector(m: Mat3) -> Option<Vec3> {
    closed_form_smallest_eigenvector(m).or_else(|| jacobi_smallest_eigenvector(m))
}

/// The smallest eigenvalue by Newton's method where it settles
/// ([`newton_smallest_eigenvalues`]), else by the trigonometric solution of
/// the characteristic cubic, in f64 on the matrix scaled to unit
/// size; its eigenvector as the largest cross product of two rows of
/// A - λI. `None` where the two smallest eigenvalues are within 1e-6 of the
/// spread, or the cross products vanish: the sweeps decide there.
fn closed_form_smallest_eigenvector(m: Mat3) -> Option<Vec3> {
    let (a, q, p) = unit_scaled(m)?;
    let (smallest, middle) = newton_smallest_eigenvalues(&a).unwrap_or_else(|| trigonometric_eigenvalues(&a, q, p));
    if middle - smallest < 1e-6 * p {
        return None;
    }
    let rows: [DVec3; 3] = std::array::from_fn(|i| DVec3::new(a[0][i], a[1][i], a[2][i]) - smallest * DVec3::AXES[i]);
    let best = [rows[0].cross(rows[1]), rows[0].cross(rows[2]), rows[1].cross(rows[2])]
        .into_iter()
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))?;
    let len = best.length();
    (len > 1e-9 && len.is_finite()).then(|| (best / len).as_vec3())
}

/// `m` in f64 divided by its largest entry, with a third of its trace `q`
/// and its spread `p` = √(|A - qI|²/6); `None` where it is zero, not
/// finite, or a multiple of the identity (every direction is an eigenvector).
fn unit_scaled(m: Mat3) -> Option<([[f64; 3]; 3], f64, f64)> {
    let a = m.to_cols_array_2d().map(|c| c.map(|v| v as f64));
    let scale = a.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let a = a.map(|c| c.map(|v| v / scale));
    let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    let q = (a[0][0] + a[1][1] + a[2][2]) / 3.0;
    let p2 = (a[0][0] - q).powi(2) + (a[1][1] - q).powi(2) + (a[2][2] - q).powi(2) + 2.0 * off;
    let p = (p2 / 6.0).sqrt();
    (p >= 1e-12).then_some((a, q, p))
}

/// Newton steps at most, from 0 to the smallest eigenvalue: a surface's
/// takes 2-4; more means the two smallest nearly coincide.
const NEWTON_STEPS: usize = 12;

/// The two smallest eigenvalues of the symmetric `a` (entries at most 1,
/// positive semi-definite: a covariance) by Newton's method on its
/// characteristic polynomial g(λ) = det(A - λI) from λ = 0, where the
/// smallest is far below the others (a surface's neighbourhood). g is
/// positive, decreasing and convex below its smallest root, so the steps
/// rise to it and never pass it; the other two are the roots of what is
/// left. With it the eigenvector takes about half the time it took with
/// the trigonometric solution alone (its acos and two cos; `perf` on a 2M
/// terrain's load); `None` where 0 is not below the root (rounding) or the
/// steps do not settle, and that solution decides.
fn newton_smallest_eigenvalues(a: &[[f64; 3]; 3]) -> Option<(f64, f64)> {
    let c2 = a[0][0] + a[1][1] + a[2][2];
    let c1 = a[0][0] * a[1][1] - a[0][1] * a[0][1] + a[0][0] * a[2][2] - a[0][2] * a[0][2] + a[1][1] * a[2][2]
        - a[1][2] * a[1][2];
    let c0 = determinant(a);
    let g = |l: f64| ((c2 - l) * l - c1) * l + c0;
    let slope = |l: f64| (2.0 * c2 - 3.0 * l) * l - c1;
    if !(c0 > 0.0 && c2 > 0.0) {
        return None;
    }
    let tolerance = 1e-15 * c2;
    let mut smallest = 0.0;
    for _ in 0..NEWTON_STEPS {
        let step = -g(smallest) / slope(smallest);
        if !(step.is_finite() && step > -tolerance) {
            return None;
        }
        smallest += step.max(0.0);
        if step <= tolerance {
            // The other two sum to c2 - λ, and their product is c1 - λ (c2 - λ).
            let sum = c2 - smallest;
            let product = c1 - smallest * sum;
            let root = (sum * sum - 4.0 * product).max(0.0).sqrt();
            let middle = if sum + root > 0.0 { 2.0 * product / (sum + root) } else { return None };
            return Some((smallest, middle));
        }
    }
    None
}

/// The two smallest eigenvalues of the symmetric `a` by the trigonometric
/// solution of its characteristic cubic (Smith 1961); `q` is a third of its
/// trace and `p` its spread, √(|A - qI|²/6).
fn trigonometric_eigenvalues(a: &[[f64; 3]; 3], q: f64, p: f64) -> (f64, f64) {
    let b = a.map(|c| c.map(|v| v / p));
    let b =
        [[b[0][0] - q / p, b[0][1], b[0][2]], [b[1][0], b[1][1] - q / p, b[1][2]], [b[2][0], b[2][1], b[2][2] - q / p]];
    let phi = (determinant(&b) / 2.0).clamp(-1.0, 1.0).acos() / 3.0;
    let third = 2.0 * std::f64::consts::PI / 3.0;
    (q + 2.0 * p * (phi + third).cos(), q + 2.0 * p * (phi - third).cos())
}

/// The determinant of `m`, by its first row.
fn determinant(m: &[[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Unit eigenvector of the smallest eigenvalue by cyclic Jacobi rotations:
/// exact for any symmetric matrix, also where eigenvalues repeat.
pub fn jacobi_smallest_eigenvector(m: Mat3) -> Option<Vec3> {
    let mut a = m.to_cols_array_2d().map(|c| c.map(|v| v as f64));
    let mut v = [[1.0f64, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..24 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off < 1e-30 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (row_p, row_q) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * row_p[k] - s * row_q[k]);
            a[q] = std::array::from_fn(|k| s * row_p[k] + c * row_q[k]);
            for row in v.iter_mut() {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let smallest = (0..3).min_by(|&x, &y| a[x][x].total_cmp(&a[y][y]))?;
    let e = Vec3::new(v[0][smallest] as f32, v[1][smallest] as f32, v[2][smallest] as f32);
    let len = e.length();
    (len.is_finite() && len > 1e-6).then(|| e / len)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [0, 1) with 24 random bits (exact in f32 too), from `seed`.
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 40) as f64 / (1u64 << 24) as f64
        }
    }

    /// The covariance of `points` about their mean, as the estimation makes it.
    fn centred_covariance(points: &[Vec3]) -> Mat3 {
        covariance(points, points.iter().sum::<Vec3>() / points.len() as f32)
    }

    #[test]
    fn the_smallest_eigenvector_of_a_flat_covariance_is_its_normal() {
        // Points spread in a plane with normal n: covariance = I - n n^T (scaled).
        for n in [Vec3::X, Vec3::new(1.0, 2.0, -0.5).normalize(), Vec3::new(-0.3, 0.1, 0.9).normalize()] {
            let cov = Mat3::IDENTITY - Mat3::from_cols(n * n.x, n * n.y, n * n.z);
            let e = smallest_eigenvector(cov).unwrap();
            assert!(e.dot(n).abs() > 1.0 - 1e-5, "{e} vs {n}");
        }
    }

    #[test]
    fn the_covariance_is_the_sum_of_full_outer_products_bit_for_bit() {
        let mut random = uniform(11);
        let mut next = || random() as f32 * 7.0 - 3.0;
        for _ in 0..200 {
            let points: Vec<Vec3> = (0..17).map(|_| Vec3::new(next(), next(), next() * 0.01)).collect();
            let centre = points.iter().sum::<Vec3>() / 17.0;
            let mut full = Mat3::ZERO;
            for d in points.iter().map(|p| *p - centre) {
                full += Mat3::from_cols(d * d.x, d * d.y, d * d.z);
            }
            let bits = |m: Mat3| m.to_cols_array().map(f32::to_bits);
            assert_eq!(bits(covariance(&points, centre)), bits(full));
        }
    }

    #[test]
    fn the_closed_form_agrees_with_the_sweeps_on_random_neighbourhoods() {
        let mut random = uniform(3);
        let mut next = || random() as f32 - 0.5;
        let mut closed = 0;
        for round in 0..2000 {
            // A noisy patch of 17 points: flat, thick, or a blob.
            let thickness = [0.01, 0.2, 1.0][round % 3];
            let (u, v) = (Vec3::new(next(), next(), next()).normalize(), Vec3::new(next(), next(), next()).normalize());
            let n = u.cross(v).normalize();
            let points: Vec<Vec3> = (0..17).map(|_| u * next() + v * next() + n * next() * thickness).collect();
            let cov = centred_covariance(&points);
            let (Some(a), Some(b)) = (closed_form_smallest_eigenvector(cov), jacobi_smallest_eigenvector(cov)) else {
                continue;
            };
            closed += 1;
            assert!(a.dot(b).abs() > 1.0 - 1e-4, "{a} vs {b} for {cov}");
        }
        assert!(closed > 1900, "the closed form decided only {closed} of 2000");
    }

    #[test]
    fn newtons_eigenvalues_are_the_trigonometric_ones_on_flat_and_thick_patches() {
        let mut random = uniform(9);
        let mut next = || random() as f32 - 0.5;
        let mut settled = 0;
        for round in 0..3000 {
            // A patch of 17 points, from flat to a blob.
            let thickness = [0.001, 0.01, 0.2, 1.0][round % 4];
            let points: Vec<Vec3> = (0..17).map(|_| Vec3::new(next(), next() * 0.7, next() * thickness)).collect();
            let Some((a, q, p)) = unit_scaled(centred_covariance(&points)) else { continue };
            let (smallest, middle) = trigonometric_eigenvalues(&a, q, p);
            if let Some((newton_smallest, newton_middle)) = newton_smallest_eigenvalues(&a) {
                settled += 1;
                assert!((newton_smallest - smallest).abs() <= 1e-12, "{newton_smallest} vs {smallest} for {a:?}");
                assert!((newton_middle - middle).abs() <= 1e-9, "{newton_middle} vs {middle} for {a:?}");
            }
        }
        // Flat and thin patches settle; blobs may leave it to the trigonometric solution.
        assert!(settled >= 1500, "Newton's method settled on only {settled} of 3000");
    }

    #[test]
    fn a_zero_matrix_has_no_preferred_direction_but_gives_a_unit_vector() {
        let e = smallest_eigenvector(Mat3::ZERO).unwrap();
        assert!((e.length() - 1.0).abs() < 1e-6);
    }
}
