//! Procedural noise for the progressive-refinement paper's models (Perlin's improved
//! gradient noise, Lewis' sparse convolution noise, Worley's cellular noise), evaluable
//! at points, over every [`Range`] and over [`Dual`] numbers.
//!
//! # How noise works over ranges
//!
//! A noise function hashes the integer lattice cell of its input, which only a point can
//! do. Over a box of inputs we use its Lipschitz bound instead: with centre `c` and
//! Euclidean radius `r`, every value lies in `n(c) ± (L r + slack)`, clipped to the
//! function's value bound, and that interval enters the arithmetic through
//! [`Range::from_interval`]. Every `L` and bound below is *derived* in its doc comment
//! (numerical searches only give estimates, not bounds).
//!
//! # How a generic `R: Real` is told apart
//!
//! [`model_ir::shape::Shape::eval`] is generic over [`Real`] only; [`Real::known`] tells a
//! point from a range (and gives its bounds), [`Real::from_bounds`] builds the range.
//! For [`Dual`] numbers, whose gradient needs the field's own gradient bound,
//! [`eval_field`] looks at the concrete type with [`Any`]: `Dual` over `f64` and over the
//! ray and cell forms of every arithmetic in [`model_ir::arith::ArithKind`]. For any other
//! type (an operation counter) it returns `1 / 0`, which is `+inf` for points and the
//! whole line for every sound range: sound, if useless.

use arith_core::dual::Dual;
use arith_core::{Arithmetic, Known, Real};
use glam::DVec3;
use std::any::{Any, TypeId};

/// Absolute slack added to every noise enclosure for the rounding error of its `f64`
/// evaluation at the box centre. The evaluation takes a few dozen operations on values
/// bounded by a few units (relative error about `1e-15` each), far below `1e-9`.
pub const EVAL_SLACK: f64 = 1e-9;

/// `v` as a `B` when `A` and `B` are the same type.
pub(crate) fn cast<A: 'static, B: 'static>(v: A) -> Option<B> {
    let mut slot = Some(v);
    (&mut slot as &mut dyn Any)
        .downcast_mut::<Option<B>>()
        .and_then(Option::take)
}

/// Calls `$m!(T)` for the ray and cell form of every arithmetic in the one list
/// ([`model_ir::arith::ArithKind`]), so a new arithmetic needs no line here.
macro_rules! for_each_range {
    ($m:ident) => {
        for kind in model_ir::arith::ArithKind::ALL {
            model_ir::with_arith!(kind, A => {
                $m!(<A as Arithmetic>::Ray);
                $m!(<A as Arithmetic>::Cell);
            });
        }
    };
}

/// The whole line for sound ranges (`1/0`, by the [`Range`] contract), `+inf` for points.
pub fn unknown_value<R: Real>() -> R {
    R::constant(0.0).recip()
}

/// A smooth-almost-everywhere scalar field on `R^3` with derived bounds.
pub trait Field3: Send + Sync {
    /// The value at a point.
    fn value(&self, p: DVec3) -> f64;
    /// The gradient at a point (a one-sided or any generalised gradient at kinks).
    fn gradient(&self, p: DVec3) -> DVec3;
    /// `(lo, hi)` with `lo <= value(p) <= hi` everywhere.
    fn value_bound(&self) -> (f64, f64);
    /// A bound of the Euclidean norm of the gradient: a Lipschitz bound.
    fn lipschitz(&self) -> f64;
    /// A bound of each partial derivative's absolute value.
    fn partial_bound(&self) -> f64;
}

/// Centre and Euclidean radius (rounded up) of a box given by per-axis bounds, `None`
/// when a bound is not finite.
fn centre_radius(b: [(f64, f64); 3]) -> Option<(DVec3, f64)> {
    let mut c = [0.0; 3];
    let mut r2 = 0.0f64;
    for k in 0..3 {
        let (lo, hi) = b[k];
        if !(lo.is_finite() && hi.is_finite()) {
            return None;
        }
        c[k] = 0.5 * lo + 0.5 * hi;
        // The half-width from the rounded centre to the farther bound, rounded up.
        let h = arith_core::round::up((hi - c[k]).max(c[k] - lo));
        r2 = arith_core::round::add_up(r2, arith_core::round::mul_up(h, h));
    }
    Some((DVec3::from_array(c), arith_core::round::up(r2.sqrt())))
}

/// The enclosure of a field over a box: `value(c) ± (L r + slack)`, clipped.
pub fn field_over_box<F: Field3 + ?Sized>(f: &F, b: [(f64, f64); 3]) -> (f64, f64) {
    let (vlo, vhi) = f.value_bound();
    match centre_radius(b) {
        None => (vlo, vhi),
        Some((c, r)) => {
            let v = f.value(c);
            let w = arith_core::round::up(arith_core::round::mul_up(f.lipschitz(), r) + EVAL_SLACK);
            let lo = arith_core::round::down(v - w).max(vlo);
            let hi = arith_core::round::up(v + w).min(vhi);
            if lo <= hi && !v.is_nan() {
                (lo, hi)
            } else {
                (vlo, vhi)
            }
        }
    }
}

/// A field evaluated over any [`Real`]: points exactly, known ranges by
/// [`field_over_box`], [`Dual`] numbers by the chain rule, unknown types as the whole line.
pub fn eval_field<F: Field3 + ?Sized, R: Real>(f: &F, x: &R, y: &R, z: &R) -> R {
    match (x.known(), y.known(), z.known()) {
        (Known::Point(a), Known::Point(b), Known::Point(c)) => {
            return R::constant(f.value(DVec3::new(a, b, c)));
        }
        (Known::Range(a0, a1), Known::Range(b0, b1), Known::Range(c0, c1)) => {
            let (lo, hi) = field_over_box(f, [(a0, a1), (b0, b1), (c0, c1)]);
            if let Some(v) = R::from_bounds(lo, hi) {
                return v;
            }
        }
        _ => {}
    }
    macro_rules! try_dual {
        ($t:ty) => {
            if TypeId::of::<R>() == TypeId::of::<Dual<$t>>() {
                let d = |v: &R| (v as &dyn Any).downcast_ref::<Dual<$t>>().cloned();
                if let (Some(dx), Some(dy), Some(dz)) = (d(x), d(y), d(z)) {
                    if let Some(out) = cast::<Dual<$t>, R>(dual_field(f, &dx, &dy, &dz)) {
                        return out;
                    }
                }
            }
        };
    }
    try_dual!(f64);
    for_each_range!(try_dual);
    unknown_value()
}

/// The chain rule over [`Dual`]: `d f(x(u)) / du_j = sum_k (df/dx_k) (dx_k/du_j)`, where
/// each partial `df/dx_k` is exact at points and `[-G, G]` (the derived partial bound)
/// over ranges.
fn dual_field<F: Field3 + ?Sized, T: Real>(
    f: &F,
    x: &Dual<T>,
    y: &Dual<T>,
    z: &Dual<T>,
) -> Dual<T> {
    let v = eval_field(f, &x.v, &y.v, &z.v);
    let partials: [T; 3] = match (x.v.known(), y.v.known(), z.v.known()) {
        (Known::Point(a), Known::Point(b), Known::Point(c)) => {
            let g = f.gradient(DVec3::new(a, b, c));
            [T::constant(g.x), T::constant(g.y), T::constant(g.z)]
        }
        _ => {
            let gb = f.partial_bound();
            match T::from_bounds(-gb, gb) {
                Some(p) => [p.clone(), p.clone(), p],
                None => [unknown_value(), unknown_value(), unknown_value()],
            }
        }
    };
    let ins = [x, y, z];
    let g = std::array::from_fn(|j| {
        let mut acc = partials[0].clone() * ins[0].g[j].clone();
        for k in 1..3 {
            acc = acc + partials[k].clone() * ins[k].g[j].clone();
        }
        acc
    });
    Dual { v, g }
}

/// SplitMix64 (Steele, Lea, Flood 2014), the workspace's one seeded generator: the
/// seeded models (the blobby model's basis functions, the noise permutations) and the
/// bench suite's samples depend on this exact sequence, so it is written here rather
/// than taken from a crate whose sequence could change between versions.
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }
}

/// A 256-entry permutation from a seed (Fisher-Yates), doubled to avoid index wrapping.
fn permutation(seed: u64) -> [u8; 512] {
    let mut p: [u8; 256] = std::array::from_fn(|i| i as u8);
    let mut rng = SplitMix64(seed);
    for i in (1..256).rev() {
        let j = (rng.next_u64() % (i as u64 + 1)) as usize;
        p.swap(i, j);
    }
    std::array::from_fn(|i| p[i & 255])
}

/// Perlin's quintic fade `s(t) = 6t^5 - 15t^4 + 10t^3`.
#[inline]
pub fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// `s'(t) = 30 t^2 (1 - t)^2`, at most `30/16 = 1.875` (at `t = 1/2`) on `[0, 1]`.
#[inline]
pub fn fade_deriv(t: f64) -> f64 {
    30.0 * t * t * (1.0 - t) * (1.0 - t)
}

/// The 16 gradient directions of Perlin's improved noise (`grad(hash, x, y, z)` of his
/// reference code): the 12 cube-edge vectors, four of them repeated. Each has exactly two
/// non-zero components, both `±1`.
pub const GRADS: [[f64; 3]; 16] = [
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [-1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, -1.0, 1.0],
    [0.0, 1.0, -1.0],
    [0.0, -1.0, -1.0],
    [1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, -1.0],
];

/// Perlin's improved gradient noise (SIGGRAPH 2002), with a permutation from a seed.
///
/// `n(p) = sum_c w_c(u, v, w) (g_c . (p - c))` over the 8 corners `c` of the lattice cell,
/// with fractional coordinates `(u, v, w)`, weights `w_c = F(u) F(v) F(w)` where each `F`
/// is `s` or `1 - s` (so `w_c >= 0`, `sum_c w_c = 1`) and `g_c` from [`GRADS`].
///
/// # Derived bounds
///
/// *Lemma.* `h(v) = (1 - s(v)) v + s(v)(1 - v) <= 1/2` on `[0, 1]`. `h(1 - v) = h(v)` since
/// `s(1 - v) = 1 - s(v)`. On `[0, 1/2]`, `s'' = 60 t (1 - t)(1 - 2t) >= 0`, so `s` is convex
/// with `s(0) = 0`, `s(1/2) = 1/2`, hence `s(v) <= v`, and `h(v) = v + s(v)(1 - 2v) <=
/// 2v - 2v^2 <= 1/2`. `h` is the `F`-weighted mean of the distances `|δ|` to the two
/// lattice planes along one axis.
///
/// *Value:* `|g_c . δ_c| <= |δx| + |δy| + |δz|` (two unit components), so
/// `|n| <= sum_c w_c (|δx|+|δy|+|δz|) = h(u) + h(v) + h(w) <= 3/2`. **B = 1.5.**
///
/// *Gradient (by hand):* `∂n/∂x = sum_c (∂w_c/∂x)(g_c . δ_c) + sum_c w_c g_c,x`. The second
/// sum is a convex combination of values in `{-1, 0, 1}`: at most 1. In the first,
/// `∂w_c/∂x = ±s'(u) F(v) F(w)`; grouping the corners in x-pairs, it is at most
/// `s'(u) sum_{jk} F(v)F(w) (|g_1jk.δ_1jk| + |g_0jk.δ_0jk|) <= s'(u) (u + (1 - u) + 2h(v) +
/// 2h(w)) <= 1.875 * 3`, so each partial is at most `6.625` and `|grad n| <= √2 + 5.625 √3
/// = 11.157`.
///
/// *Gradient (tighter, computer-assisted):* inside a cell `grad n = sum_c J_c g_c` with
/// `J_c g = (grad w_c)(g . δ_c) + w_c g`, so `|grad n| <= M(u, v, w) = sum_c max_{g ∈ GRADS}
/// |J_c g|`, a function of the fractional coordinates alone (whatever the hash picks);
/// likewise `|∂n/∂x| <= sum_c max_g |(J_c g)_x|`. Reflecting `u -> 1 - u` swaps the corners
/// and flips the sign of `δ_x` and `∂/∂u`, and the gradient set is closed under sign
/// flips, so both functions are symmetric and their maxima over `[0, 1/2]^3` are the
/// maxima over the cell. `n` is C² across cells (`s'` and `s''` vanish at 0 and 1), so
/// the sup of `|grad n|` over cells is the Lipschitz constant. The test
/// `perlin_gradient_bounds_are_verified_by_interval_subdivision` encloses both maxima
/// with outward-rounded interval arithmetic over `24^3` sub-boxes of `[0, 1/2]^3` (a
/// point grid estimates 5.48 and 3.75; the enclosures give 6.15 and 4.13): **L = 6.2**,
/// **G = 4.2**.
#[derive(Clone, Debug)]
pub struct Perlin {
    perm: [u8; 512],
}

impl Perlin {
    /// Value bound `B` (derived above).
    pub const BOUND: f64 = 1.5;
    /// Partial-derivative bound `G` (verified above).
    pub const PARTIAL: f64 = 4.2;
    /// Lipschitz bound `L` (verified above).
    pub const LIPSCHITZ: f64 = 6.2;

    /// Noise with the permutation drawn from `seed`.
    pub fn new(seed: u64) -> Self {
        Perlin {
            perm: permutation(seed),
        }
    }

    /// Value and (optionally) gradient at `p`.
    fn eval(&self, p: DVec3, want_grad: bool) -> (f64, DVec3) {
        let fl = p.floor();
        let (fx, fy, fz) = (p.x - fl.x, p.y - fl.y, p.z - fl.z);
        let xi = (fl.x as i64 & 255) as usize;
        let yi = (fl.y as i64 & 255) as usize;
        let zi = (fl.z as i64 & 255) as usize;
        let f = [fx, fy, fz];
        let s = [fade(fx), fade(fy), fade(fz)];
        let ds = [fade_deriv(fx), fade_deriv(fy), fade_deriv(fz)];
        let perm = &self.perm;
        let mut value = 0.0;
        let mut grad = DVec3::ZERO;
        for c in 0..8usize {
            let (i, j, k) = (c & 1, (c >> 1) & 1, (c >> 2) & 1);
            let h = perm[perm[perm[xi + i] as usize + yi + j] as usize + zi + k] as usize & 15;
            let g = GRADS[h];
            let d = [f[0] - i as f64, f[1] - j as f64, f[2] - k as f64];
            let dot = g[0] * d[0] + g[1] * d[1] + g[2] * d[2];
            let wf = |a: usize, sel: usize| if sel == 1 { s[a] } else { 1.0 - s[a] };
            let (w0, w1, w2) = (wf(0, i), wf(1, j), wf(2, k));
            value += w0 * w1 * w2 * dot;
            if want_grad {
                let sg = |sel: usize| if sel == 1 { 1.0 } else { -1.0 };
                let dw = DVec3::new(
                    sg(i) * ds[0] * w1 * w2,
                    sg(j) * ds[1] * w0 * w2,
                    sg(k) * ds[2] * w0 * w1,
                );
                grad += dw * dot + DVec3::from_array(g) * (w0 * w1 * w2);
            }
        }
        (value, grad)
    }
}

impl Field3 for Perlin {
    fn value(&self, p: DVec3) -> f64 {
        self.eval(p, false).0
    }
    fn gradient(&self, p: DVec3) -> DVec3 {
        self.eval(p, true).1
    }
    fn value_bound(&self) -> (f64, f64) {
        (-Self::BOUND, Self::BOUND)
    }
    fn lipschitz(&self) -> f64 {
        Self::LIPSCHITZ
    }
    fn partial_bound(&self) -> f64 {
        Self::PARTIAL
    }
}

/// Hash of an integer cell and a salt, for the cell-based noises.
#[inline]
fn cell_hash(seed: u64, c: [i64; 3], salt: u64) -> SplitMix64 {
    let mut h = seed ^ salt.wrapping_mul(0xD6E8_FEB8_6659_FD93);
    for v in c {
        h = (h ^ v as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .rotate_left(29);
    }
    SplitMix64(h)
}

/// Lewis' sparse convolution noise: `n(p) = sum_i a_i k(|p - x_i|^2)` over `K` random
/// impulses per unit cell (positions uniform in the cell, weights `a_i ∈ [-1, 1]`), with
/// the compact kernel `k(q) = (1 - q)^2` for `q = r^2 < 1`, else 0.
///
/// # Derived bounds
///
/// An impulse at distance `< 1` from `p` lies in one of the 27 cells around `p`'s cell,
/// so at most `27 K` terms are non-zero. `0 <= k <= 1`, so **B = 27 K**. As a function of
/// `r`, `k = (1 - r^2)^2` has `|k'(r)| = 4 r (1 - r^2)`, maximal at `r = 1/√3`:
/// `8 / (3√3) = 1.53961 <= 1.5397`; so **L = 27 K · 1.5397** and each partial is bounded by
/// the same (`|∂k/∂x| <= |∇k|`).
#[derive(Clone, Debug)]
pub struct SparseConvolution {
    seed: u64,
}

impl SparseConvolution {
    /// Impulses per cell.
    pub const K: usize = 1;
    /// `max |k'(r)|`, rounded up.
    const KERNEL_SLOPE: f64 = 1.5397;

    /// Noise with impulses drawn from `seed`.
    pub fn new(seed: u64) -> Self {
        SparseConvolution { seed }
    }

    fn eval(&self, p: DVec3, want_grad: bool) -> (f64, DVec3) {
        let fl = p.floor();
        let base = [fl.x as i64, fl.y as i64, fl.z as i64];
        let mut value = 0.0;
        let mut grad = DVec3::ZERO;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let c = [base[0] + dx, base[1] + dy, base[2] + dz];
                    let mut rng = cell_hash(self.seed, c, 1);
                    for _ in 0..Self::K {
                        let x = DVec3::new(
                            c[0] as f64 + rng.next_f64(),
                            c[1] as f64 + rng.next_f64(),
                            c[2] as f64 + rng.next_f64(),
                        );
                        let a = rng.range(-1.0, 1.0);
                        let d = p - x;
                        let q = d.length_squared();
                        if q < 1.0 {
                            value += a * (1.0 - q) * (1.0 - q);
                            if want_grad {
                                grad += d * (-4.0 * a * (1.0 - q));
                            }
                        }
                    }
                }
            }
        }
        (value, grad)
    }
}

impl Field3 for SparseConvolution {
    fn value(&self, p: DVec3) -> f64 {
        self.eval(p, false).0
    }
    fn gradient(&self, p: DVec3) -> DVec3 {
        self.eval(p, true).1
    }
    fn value_bound(&self) -> (f64, f64) {
        let b = 27.0 * Self::K as f64;
        (-b, b)
    }
    fn lipschitz(&self) -> f64 {
        27.0 * Self::K as f64 * Self::KERNEL_SLOPE
    }
    fn partial_bound(&self) -> f64 {
        self.lipschitz()
    }
}

/// Worley's cellular noise `F1`: the distance to the nearest of one random feature point
/// per unit cell.
///
/// # Derived bounds
///
/// A minimum of distance functions `|p - x_i|`, each 1-Lipschitz, is 1-Lipschitz: **L = 1**,
/// partials at most 1. The feature point of `p`'s own cell is at most the cell diagonal
/// away: **0 <= F1 <= √3 <= 1.7321**. The search is exact: a cell two or more steps away
/// along some axis is at distance `>= 1` and one three steps away `>= 2 > √3`, so the 5^3
/// cells around `p` (skipping those farther than the best so far) hold the nearest point.
#[derive(Clone, Debug)]
pub struct Cellular {
    seed: u64,
}

impl Cellular {
    /// Upper value bound `√3`, rounded up.
    pub const MAX: f64 = 1.7321;

    /// Noise with feature points drawn from `seed`.
    pub fn new(seed: u64) -> Self {
        Cellular { seed }
    }

    /// The nearest feature point to `p`.
    fn nearest(&self, p: DVec3) -> DVec3 {
        let fl = p.floor();
        let base = [fl.x as i64, fl.y as i64, fl.z as i64];
        let f = p - fl;
        let mut best = f64::INFINITY;
        let mut best_x = p;
        for dx in -2i64..=2 {
            for dy in -2i64..=2 {
                for dz in -2i64..=2 {
                    // Squared distance from p to the cell (a lower bound for its point).
                    let gap = |d: i64, t: f64| match d {
                        0 => 0.0,
                        d if d > 0 => d as f64 - t,
                        d => t - (d + 1) as f64,
                    };
                    let g = DVec3::new(gap(dx, f.x), gap(dy, f.y), gap(dz, f.z));
                    if g.length_squared() >= best {
                        continue;
                    }
                    let c = [base[0] + dx, base[1] + dy, base[2] + dz];
                    let mut rng = cell_hash(self.seed, c, 2);
                    let x = DVec3::new(
                        c[0] as f64 + rng.next_f64(),
                        c[1] as f64 + rng.next_f64(),
                        c[2] as f64 + rng.next_f64(),
                    );
                    let q = (p - x).length_squared();
                    if q < best {
                        best = q;
                        best_x = x;
                    }
                }
            }
        }
        best_x
    }
}

impl Field3 for Cellular {
    fn value(&self, p: DVec3) -> f64 {
        (p - self.nearest(p)).length()
    }
    fn gradient(&self, p: DVec3) -> DVec3 {
        let d = p - self.nearest(p);
        let l = d.length();
        if l > 0.0 {
            d / l
        } else {
            DVec3::ZERO
        }
    }
    fn value_bound(&self) -> (f64, f64) {
        (0.0, Self::MAX)
    }
    fn lipschitz(&self) -> f64 {
        1.0
    }
    fn partial_bound(&self) -> f64 {
        1.0
    }
}

/// Perlin noise at `(x, y, z)` over any [`Real`] (see [`eval_field`]).
pub fn noise3<R: Real>(n: &Perlin, x: &R, y: &R, z: &R) -> R {
    eval_field(n, x, y, z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Range;

    #[test]
    fn uniform_samples_stay_in_range_and_spread() {
        let mut r = SplitMix64(1);
        let v: Vec<f64> = (0..10_000).map(|_| r.next_f64()).collect();
        assert!(v.iter().all(|&x| (0.0..1.0).contains(&x)));
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        assert!((mean - 0.5).abs() < 0.02, "{mean}");
        assert!(v.iter().any(|&x| x < 0.01) && v.iter().any(|&x| x > 0.99));
    }

    #[test]
    fn dispatch_tells_points_from_ranges() {
        assert_eq!(1.5f64.known(), Known::Point(1.5));
        let i = arith_ia::Interval::new(-1.0, 2.0);
        assert_eq!(i.known(), Known::Range(-1.0, 2.0));
        assert!(f64::from_bounds(0.0, 1.0).is_none());
        let r = arith_ia::Interval::from_bounds(0.0, 1.0).unwrap();
        assert_eq!(r.bounds(), (0.0, 1.0));
    }

    #[test]
    fn fade_lemma_holds_on_a_grid() {
        for i in 0..=10_000 {
            let v = i as f64 / 10_000.0;
            let h = (1.0 - fade(v)) * v + fade(v) * (1.0 - v);
            assert!(h <= 0.5 + 1e-15, "h({v}) = {h}");
            assert!(fade_deriv(v) <= 1.875 + 1e-15);
        }
    }
}
