//! `bench-suite tightness`: how much wider than the true range each arithmetic's range is.
//!
//! For each model and arithmetic, over random 3-D cells and random ray segments of a few
//! sizes, the ratio `computed width / true width`, averaged. This is the figure behind
//! the timings: a wider range means more subdivision and more range evaluations.
//!
//! # How the true range is estimated
//!
//! The true range over a cell is estimated by evaluating the model in `f64` at every
//! point of a regular `k x k x k` grid spanning the cell (corners included) plus `r`
//! uniformly random points in it; over a ray segment, at `n` evenly spaced parameters
//! (both ends included). The minimum and maximum of those samples are an *inner* bound of
//! the true range (the true extrema may fall between samples), so the true width is
//! under-estimated and every ratio printed is an *upper* estimate of the real ratio;
//! sound arithmetics give ratios `>= 1` up to that sampling error.
//!
//! Samples whose estimated true width is 0 (the function is constant there, e.g. a
//! region where a `min`/`max` clamps) are skipped; computed ranges that are unbounded
//! are counted apart (`inf`) and left out of the mean.

use arith_core::{Arithmetic, Range};
use model_ir::arith::ArithKind;
use model_ir::shape::{Aabb, Shape};
use model_sources::noise::SplitMix64 as Rng;

/// Sampling settings.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Random cells (and random ray segments) per model and size.
    pub samples: usize,
    /// Cell and segment sizes, as fractions of the domain's extent per axis (cells) or
    /// of its diagonal (segments).
    pub sizes: [f64; 3],
    /// Grid points per axis in a cell.
    pub grid: usize,
    /// Extra random points per cell.
    pub random: usize,
    /// Points per ray segment.
    pub ray_points: usize,
    /// Seed of the sample generator.
    pub seed: u64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            samples: 100,
            sizes: [0.25, 1.0 / 16.0, 1.0 / 64.0],
            grid: 9,
            random: 256,
            ray_points: 2049,
            seed: 7,
        }
    }
}

/// Statistics of one (model, arithmetic, geometry, size) cell of the tightness table.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ratio {
    /// Mean of `computed / true` width over the samples with finite computed width.
    pub mean: f64,
    /// Median of the same.
    pub median: f64,
    /// Samples with a finite computed width.
    pub finite: usize,
    /// Samples whose computed range was unbounded.
    pub unbounded: usize,
    /// Samples skipped because the estimated true width was 0.
    pub flat: usize,
}

fn summarise(ratios: &mut [f64], unbounded: usize, flat: usize) -> Ratio {
    if ratios.is_empty() {
        return Ratio {
            mean: f64::NAN,
            median: f64::NAN,
            finite: 0,
            unbounded,
            flat,
        };
    }
    ratios.sort_by(f64::total_cmp);
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let m = ratios.len();
    let median = if m % 2 == 1 {
        ratios[m / 2]
    } else {
        0.5 * (ratios[m / 2 - 1] + ratios[m / 2])
    };
    Ratio {
        mean,
        median,
        finite: m,
        unbounded,
        flat,
    }
}

/// A random axis-aligned cell inside `domain`, each side `frac` of the domain's side.
pub fn random_cell(rng: &mut Rng, domain: &Aabb, frac: f64) -> [(f64, f64); 3] {
    let lo = domain.min.to_array();
    let hi = domain.max.to_array();
    core::array::from_fn(|i| {
        let side = (hi[i] - lo[i]) * frac;
        let a = rng.range(lo[i], hi[i] - side);
        (a, a + side)
    })
}

/// A random segment `o + t d`, `t ∈ [0, len]`, with both ends inside `domain`; `len` is
/// `frac` of the domain's diagonal.
pub fn random_segment(rng: &mut Rng, domain: &Aabb, frac: f64) -> ([f64; 3], [f64; 3], f64) {
    let lo = domain.min.to_array();
    let hi = domain.max.to_array();
    let diag = (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
    let len = diag * frac;
    loop {
        let o: [f64; 3] = core::array::from_fn(|i| rng.range(lo[i], hi[i]));
        // uniform direction on the sphere
        let z = rng.range(-1.0, 1.0);
        let phi = rng.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).sqrt();
        let d = [r * phi.cos(), r * phi.sin(), z];
        let inside = (0..3).all(|i| (lo[i]..=hi[i]).contains(&(o[i] + d[i] * len)));
        if inside {
            return (o, d, len);
        }
    }
}

/// Min and max of `f64` samples of `shape` over a cell (grid plus random points).
pub fn sampled_cell_range<S: Shape + ?Sized>(
    shape: &S,
    cell: &[(f64, f64); 3],
    grid: usize,
    random: usize,
    rng: &mut Rng,
) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    let mut see = |v: f64| {
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    };
    let g = grid.max(2);
    let at = |i: usize, k: usize| cell[i].0 + (cell[i].1 - cell[i].0) * k as f64 / (g - 1) as f64;
    for a in 0..g {
        for b in 0..g {
            for c in 0..g {
                see(shape.eval(at(0, a), at(1, b), at(2, c)));
            }
        }
    }
    for _ in 0..random {
        let p: [f64; 3] = core::array::from_fn(|i| rng.range(cell[i].0, cell[i].1));
        see(shape.eval(p[0], p[1], p[2]));
    }
    (lo, hi)
}

/// Min and max of `f64` samples of `shape` along a segment.
pub fn sampled_segment_range<S: Shape + ?Sized>(
    shape: &S,
    o: [f64; 3],
    d: [f64; 3],
    len: f64,
    n: usize,
) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    let n = n.max(2);
    for k in 0..n {
        let t = len * k as f64 / (n - 1) as f64;
        let v = shape.eval(o[0] + d[0] * t, o[1] + d[1] * t, o[2] + d[2] * t);
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    (lo, hi)
}

/// The computed range of `shape` over a cell in the cell form of `A`.
pub fn cell_range<A: Arithmetic, S: Shape + ?Sized>(
    shape: &S,
    cell: &[(f64, f64); 3],
) -> (f64, f64) {
    let x = A::Cell::input(0, cell[0].0, cell[0].1);
    let y = A::Cell::input(1, cell[1].0, cell[1].1);
    let z = A::Cell::input(2, cell[2].0, cell[2].1);
    shape.eval(x, y, z).bounds()
}

/// The computed range of `shape` along a segment in the ray form of `A`.
pub fn segment_range<A: Arithmetic, S: Shape + ?Sized>(
    shape: &S,
    o: [f64; 3],
    d: [f64; 3],
    len: f64,
) -> (f64, f64) {
    let t = A::Ray::input(0, 0.0, len);
    let x = t.clone() * d[0] + o[0];
    let y = t.clone() * d[1] + o[1];
    let z = t * d[2] + o[2];
    shape.eval(x, y, z).bounds()
}

/// Whether a point sample set is degenerate (no spread to compare against).
fn flat(lo: f64, hi: f64) -> bool {
    // Written so that NaN spreads count as flat.
    (hi - lo).partial_cmp(&(1e-12 * (1.0 + lo.abs().max(hi.abs()))))
        != Some(core::cmp::Ordering::Greater)
}

/// Ratios of one model over `kinds`, for cells (`.0`) and segments (`.1`) of each size.
/// The same cells and segments are used for every arithmetic.
pub fn measure_model<S: Shape + ?Sized>(
    shape: &S,
    domain: &Aabb,
    kinds: &[ArithKind],
    s: &Settings,
) -> Vec<(ArithKind, [Ratio; 3], [Ratio; 3])> {
    let mut rng = Rng(s.seed);
    // ratios[k][size] for cells and segments
    let mut cell_r = vec![vec![Vec::new(); 3]; kinds.len()];
    let mut seg_r = vec![vec![Vec::new(); 3]; kinds.len()];
    let mut cell_u = vec![[0usize; 3]; kinds.len()];
    let mut seg_u = vec![[0usize; 3]; kinds.len()];
    let mut cell_flat = [0usize; 3];
    let mut seg_flat = [0usize; 3];
    for (si, &frac) in s.sizes.iter().enumerate() {
        for _ in 0..s.samples {
            let cell = random_cell(&mut rng, domain, frac);
            let (tlo, thi) = sampled_cell_range(shape, &cell, s.grid, s.random, &mut rng);
            if flat(tlo, thi) {
                cell_flat[si] += 1;
            } else {
                for (k, &kind) in kinds.iter().enumerate() {
                    let (lo, hi) =
                        model_ir::with_arith!(kind, A => cell_range::<A, S>(shape, &cell));
                    let w = hi - lo;
                    if w.is_finite() {
                        cell_r[k][si].push(w / (thi - tlo));
                    } else {
                        cell_u[k][si] += 1;
                    }
                }
            }
            let (o, d, len) = random_segment(&mut rng, domain, frac);
            let (tlo, thi) = sampled_segment_range(shape, o, d, len, s.ray_points);
            if flat(tlo, thi) {
                seg_flat[si] += 1;
            } else {
                for (k, &kind) in kinds.iter().enumerate() {
                    let (lo, hi) =
                        model_ir::with_arith!(kind, A => segment_range::<A, S>(shape, o, d, len));
                    let w = hi - lo;
                    if w.is_finite() {
                        seg_r[k][si].push(w / (thi - tlo));
                    } else {
                        seg_u[k][si] += 1;
                    }
                }
            }
        }
    }
    kinds
        .iter()
        .enumerate()
        .map(|(k, &kind)| {
            let c = core::array::from_fn(|si| {
                summarise(&mut cell_r[k][si], cell_u[k][si], cell_flat[si])
            });
            let g =
                core::array::from_fn(|si| summarise(&mut seg_r[k][si], seg_u[k][si], seg_flat[si]));
            (kind, c, g)
        })
        .collect()
}

/// Three significant digits, without exponent noise for the usual range.
fn sig(x: f64) -> String {
    if x >= 100.0 {
        format!("{x:.0}")
    } else if x >= 10.0 {
        format!("{x:.1}")
    } else {
        format!("{x:.2}")
    }
}

fn fmt_ratio(r: &Ratio) -> String {
    if r.finite == 0 {
        if r.unbounded > 0 {
            return "inf".into();
        }
        return "n/a".into();
    }
    let mut s = format!("{} ({})", sig(r.mean), sig(r.median));
    if r.unbounded > 0 {
        s.push_str(&format!(" ({} inf)", r.unbounded));
    }
    s
}

/// Runs the tightness study over `models` and renders it as Markdown.
pub fn run(models: &[model_sources::Model], kinds: &[ArithKind], s: &Settings) -> String {
    let mut out = String::new();
    out.push_str("## Range tightness: computed width / sampled true width, mean (median)\n\n");
    out.push_str(&format!(
        "True range per sample: min/max of f64 evaluations on a {g}x{g}x{g} grid plus {r} random \
         points (cells), or {n} evenly spaced points (ray segments). This is an inner bound of the \
         true range, so every ratio is an upper estimate. {m} random cells and {m} random segments \
         per model and size (seed {seed}); cell side = fraction of the domain side, segment length \
         = fraction of the domain diagonal. `(k inf)`: k samples had an unbounded computed range \
         and are left out of the mean.\n\n",
        g = s.grid,
        r = s.random,
        n = s.ray_points,
        m = s.samples,
        seed = s.seed
    ));
    let mut header = String::from("| Model | Arithmetic |");
    let mut rule = String::from("|---|---|");
    for geom in ["cell", "ray"] {
        for f in s.sizes {
            header.push_str(&format!(" {geom} 1/{:.0} |", 1.0 / f));
            rule.push_str("---:|");
        }
    }
    out.push_str(&header);
    out.push('\n');
    out.push_str(&rule);
    out.push('\n');
    for m in models {
        let rows = measure_model(m, &m.domain, kinds, s);
        for (kind, c, g) in rows {
            let mut line = format!("| {} | {} |", m.name, kind.label());
            for r in c.iter().chain(g.iter()) {
                line.push_str(&format!(" {} |", fmt_ratio(r)));
            }
            out.push_str(&line);
            out.push('\n');
        }
    }
    out
}
