//! The quadratic error function of dual contouring, minimised *inside the cell*.
//!
//! Each edge crossing `p_i` with unit normal `n_i` gives a plane; the vertex minimises
//! `E(x) = Σ (n_i · (x - p_i))^2 + λ |x - c|^2` over the cell's box, where `c` is the
//! mass point (the crossings' mean). The small Tikhonov term (`λ` = [`REG`] times the
//! trace of `Σ n_i n_iᵀ`) plays the part of the truncated SVD of the classic solvers:
//! where the planes leave a direction free (a flat or cylindrical patch) the vertex
//! stays near the mass point along it, while where three planes meet (a corner, an
//! edge of a CSG shape) the vertex goes to within `REG`-ish of the feature.
//!
//! The peers solve without the box and clamp (or not at all), so their vertices escape
//! their cells and the mesh folds through itself. Here the minimum over the box is
//! exact: `E` is strictly convex, so its minimum over the box lies in the relative
//! interior of exactly one face of the box (the box itself, one of its 6 faces, 12
//! edges or 8 corners), where it is the minimum of `E` restricted to that face's
//! affine hull. [`Qef::solve`] tries the unconstrained minimum first and, if it lies
//! outside, each of the 26 faces, keeping the feasible one with the least `E`.

use glam::DVec3;

/// The Tikhonov weight relative to the trace of the normal matrix.
pub const REG: f64 = 0.01;

/// The accumulated planes of a cell (or of one piece of the surface in it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Qef {
    /// `Σ n nᵀ` (symmetric, row-major).
    ata: [[f64; 3]; 3],
    /// `Σ n (n · p)`.
    atb: [f64; 3],
    /// `Σ (n · p)^2`.
    btb: f64,
    /// `Σ p`.
    sum: DVec3,
    /// Number of planes.
    count: u32,
}

impl Qef {
    /// Adds the plane through `p` with unit normal `n`, and `p` to the mass point.
    pub fn add(&mut self, p: DVec3, n: DVec3) {
        self.add_plane(p, n);
        self.sum += p;
        self.count += 1;
    }

    /// Adds the plane through `q` with unit normal `n` without moving the mass point
    /// (another branch's plane at a crossing: `q` need not lie on the surface).
    pub fn add_plane(&mut self, q: DVec3, n: DVec3) {
        let n = n.to_array();
        let d = n[0] * q.x + n[1] * q.y + n[2] * q.z;
        for i in 0..3 {
            for j in 0..3 {
                self.ata[i][j] += n[i] * n[j];
            }
            self.atb[i] += n[i] * d;
        }
        self.btb += d * d;
    }

    /// Adds the planes and points of `o` (the QEF of a union of cells).
    pub fn merge(&mut self, o: &Qef) {
        for i in 0..3 {
            for j in 0..3 {
                self.ata[i][j] += o.ata[i][j];
            }
            self.atb[i] += o.atb[i];
        }
        self.btb += o.btb;
        self.sum += o.sum;
        self.count += o.count;
    }

    /// `Σ (n · (x - p))^2`: the planes' squared distances from `x` summed (without the
    /// Tikhonov term), at least the square of each plane's distance.
    pub fn residual(&self, x: DVec3) -> f64 {
        let x = x.to_array();
        let mut e = self.btb;
        for i in 0..3 {
            for j in 0..3 {
                e += x[i] * self.ata[i][j] * x[j];
            }
            e -= 2.0 * self.atb[i] * x[i];
        }
        e.max(0.0)
    }

    /// The number of planes added.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// The mass point: the mean of the points added (the box's centre if none).
    pub fn mass_point(&self, lo: DVec3, hi: DVec3) -> DVec3 {
        if self.count == 0 {
            (lo + hi) * 0.5
        } else {
            self.sum / self.count as f64
        }
    }

    /// The minimiser of `E` over the box `[lo, hi]` (always inside it).
    ///
    /// ```
    /// use glam::DVec3;
    /// use tracer_mesh::qef::Qef;
    /// // Three faces of a cube meeting at (0.3, 0.3, 0.3): the vertex finds the corner.
    /// let mut q = Qef::default();
    /// q.add(DVec3::new(0.3, 0.1, 0.2), DVec3::X);
    /// q.add(DVec3::new(0.2, 0.3, 0.1), DVec3::Y);
    /// q.add(DVec3::new(0.1, 0.2, 0.3), DVec3::Z);
    /// let v = q.solve(DVec3::ZERO, DVec3::ONE);
    /// assert!((v - DVec3::splat(0.3)).length() < 0.02);
    /// // Constrained to a box that excludes the corner, it stays in the box.
    /// let w = q.solve(DVec3::ZERO, DVec3::splat(0.25));
    /// assert!(w.cmple(DVec3::splat(0.25)).all());
    /// ```
    pub fn solve(&self, lo: DVec3, hi: DVec3) -> DVec3 {
        let c = self.mass_point(lo, hi).clamp(lo, hi);
        let p = Problem::new(self, c);
        let (lo_y, hi_y) = ((lo - c).to_array(), (hi - c).to_array());
        let mut best: Option<([f64; 3], f64)> = None;
        // Face patterns: each axis free (0), at its low bound (1) or its high bound (2);
        // all free first, so an interior minimum returns at once.
        for pattern in 0..27 {
            let fix: [u8; 3] = [pattern % 3, pattern / 3 % 3, pattern / 9];
            let Some(y) = p.minimise_on(fix, &lo_y, &hi_y) else {
                continue;
            };
            let e = p.energy(&y);
            if best.is_none_or(|(_, b)| e < b) {
                best = Some((y, e));
            }
            if pattern == 0 {
                break;
            }
        }
        let y = best.map_or([0.0; 3], |(y, _)| y);
        (c + DVec3::from(y)).clamp(lo, hi)
    }
}

/// `E` in coordinates `y = x - c`: `yᵀ M y - 2 rᵀ y + const`, `M` positive definite.
struct Problem {
    m: [[f64; 3]; 3],
    r: [f64; 3],
}

impl Problem {
    fn new(q: &Qef, c: DVec3) -> Problem {
        let trace = q.ata[0][0] + q.ata[1][1] + q.ata[2][2];
        // A floor keeps M definite for a cell without planes (then y = 0: the centre).
        let lambda = REG * trace + 1e-12;
        let c = c.to_array();
        let mut m = q.ata;
        let mut r = [0.0; 3];
        for i in 0..3 {
            m[i][i] += lambda;
            // Σ n (n·p) - (Σ n nᵀ) c: the linear term around c (the Tikhonov term is
            // centred there too, so adds nothing to it).
            r[i] = q.atb[i] - (0..3).map(|j| q.ata[i][j] * c[j]).sum::<f64>();
        }
        Problem { m, r }
    }

    fn energy(&self, y: &[f64; 3]) -> f64 {
        let mut e = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                e += y[i] * self.m[i][j] * y[j];
            }
            e -= 2.0 * self.r[i] * y[i];
        }
        e
    }

    /// The minimiser of `E` with the axes of `fix` (1: low bound, 2: high bound) fixed,
    /// if the free coordinates land inside their bounds (within a hair).
    fn minimise_on(&self, fix: [u8; 3], lo: &[f64; 3], hi: &[f64; 3]) -> Option<[f64; 3]> {
        let mut y = [0.0; 3];
        let mut free = Vec::with_capacity(3);
        for k in 0..3 {
            match fix[k] {
                0 => free.push(k),
                1 => y[k] = lo[k],
                _ => y[k] = hi[k],
            }
        }
        // M_ff y_f = r_f - M_fx y_x.
        let n = free.len();
        let mut a = [[0.0; 3]; 3];
        let mut b = [0.0; 3];
        for (i, &fi) in free.iter().enumerate() {
            for (j, &fj) in free.iter().enumerate() {
                a[i][j] = self.m[fi][fj];
            }
            b[i] = self.r[fi]
                - (0..3)
                    .filter(|k| fix[*k] != 0)
                    .map(|k| self.m[fi][k] * y[k])
                    .sum::<f64>();
        }
        let sol = solve_spd(&a, &b, n)?;
        for (i, &fi) in free.iter().enumerate() {
            let slack = 1e-9 * (hi[fi] - lo[fi]);
            if !(sol[i] >= lo[fi] - slack && sol[i] <= hi[fi] + slack) {
                return None;
            }
            y[fi] = sol[i].clamp(lo[fi], hi[fi]);
        }
        Some(y)
    }
}

/// Solves the leading `n x n` block of a symmetric positive definite system (Cholesky).
fn solve_spd(a: &[[f64; 3]; 3], b: &[f64; 3], n: usize) -> Option<[f64; 3]> {
    let mut l = [[0.0; 3]; 3];
    for i in 0..n {
        for j in 0..=i {
            let s = a[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if s.is_nan() || s <= 0.0 {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    let mut z = [0.0; 3];
    for i in 0..n {
        z[i] = (b[i] - (0..i).map(|k| l[i][k] * z[k]).sum::<f64>()) / l[i][i];
    }
    let mut x = [0.0; 3];
    for i in (0..n).rev() {
        x[i] = (z[i] - (i + 1..n).map(|k| l[k][i] * x[k]).sum::<f64>()) / l[i][i];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The box minimum is no worse than any point of a fine lattice of the box.
    #[test]
    fn the_box_minimum_beats_a_lattice() {
        let mut q = Qef::default();
        q.add(
            DVec3::new(0.9, 0.5, 0.5),
            DVec3::new(1.0, 0.2, 0.0).normalize(),
        );
        q.add(
            DVec3::new(0.5, 0.95, 0.5),
            DVec3::new(0.1, 1.0, 0.3).normalize(),
        );
        q.add(
            DVec3::new(0.5, 0.5, 0.2),
            DVec3::new(0.0, 0.4, 1.0).normalize(),
        );
        let (lo, hi) = (DVec3::ZERO, DVec3::splat(0.6));
        let v = q.solve(lo, hi);
        assert!(v.cmpge(lo).all() && v.cmple(hi).all());
        let c = q.mass_point(lo, hi).clamp(lo, hi);
        let p = Problem::new(&q, c);
        let e = |x: DVec3| p.energy(&(x - c).to_array());
        let ev = e(v);
        let k = 12;
        for i in 0..=k {
            for j in 0..=k {
                for l in 0..=k {
                    let x = DVec3::new(i as f64, j as f64, l as f64) * (0.6 / k as f64);
                    assert!(ev <= e(x) + 1e-9, "{v} ({ev}) worse than {x} ({})", e(x));
                }
            }
        }
    }

    #[test]
    fn the_residual_is_the_sum_of_squared_distances() {
        let mut q = Qef::default();
        q.add(DVec3::new(0.3, 0.0, 0.0), DVec3::X);
        let mut r = Qef::default();
        r.add(DVec3::new(0.0, 0.5, 0.0), DVec3::Y);
        q.merge(&r);
        let x = DVec3::new(0.1, 0.1, 7.0);
        assert!((q.residual(x) - (0.04 + 0.16)).abs() < 1e-12);
        assert_eq!(
            q.mass_point(DVec3::ZERO, DVec3::ONE),
            DVec3::new(0.15, 0.25, 0.0)
        );
    }

    #[test]
    fn no_planes_gives_the_centre() {
        let q = Qef::default();
        assert_eq!(q.solve(DVec3::ZERO, DVec3::ONE), DVec3::splat(0.5));
    }
}
