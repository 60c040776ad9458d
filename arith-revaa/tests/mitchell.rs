//! Range widths of Mitchell's quartic over a few boxes: RevAA (`RevAa<3>`) against AF1
//! (`Raa<3>`). Run with `--nocapture` to see the table.

use arith_core::{Range, Real};
use arith_raa::Raa;
use arith_revaa::RevAa;

/// Mitchell's polynomial `20(x²+y²+z²) - 4(x⁴+(y²+z²)²) - 17x²(y²+z²) - 17`, written
/// once for points and ranges.
fn mitchell<R: Real>(x: R, y: R, z: R) -> R {
    let (x2, y2, z2) = (x.sqr(), y.sqr(), z.sqr());
    let yz = y2 + z2;
    (x2.clone() + yz.clone()) * 20.0 - (x2.sqr() + yz.sqr()) * 4.0 - x2 * yz * 17.0 - 17.0
}

fn over_box<R: Range>(b: [(f64, f64); 3]) -> (f64, f64) {
    mitchell(
        R::input(0, b[0].0, b[0].1),
        R::input(1, b[1].0, b[1].1),
        R::input(2, b[2].0, b[2].1),
    )
    .bounds()
}

const BOXES: [[(f64, f64); 3]; 6] = [
    [(0.5, 0.625), (-0.125, 0.125), (0.875, 1.0)],
    [(-1.0, 1.0), (-1.0, 1.0), (-1.0, 1.0)],
    [(0.25, 0.5), (0.25, 0.5), (0.5, 0.75)],
    [(-0.5, -0.25), (0.5, 0.75), (-1.0, -0.75)],
    [(1.0, 1.125), (0.0, 0.125), (0.0, 0.125)],
    [(0.0, 2.0), (-0.5, 0.5), (0.0, 0.25)],
];

/// Rays `o + t d`, `t ∈ [t0, t1]`: one input symbol shared by `x`, `y`, `z`.
type Ray = ([f64; 3], [f64; 3], (f64, f64));

const RAYS: [Ray; 4] = [
    ([-2.0, 0.25, 0.5], [1.0, 0.25, -0.5], (0.5, 1.5)),
    ([-2.0, -2.0, -2.0], [0.5, 0.5, 0.5], (2.0, 4.0)),
    ([0.0, 0.0, -3.0], [0.125, 0.25, 1.0], (1.75, 2.25)),
    ([1.5, -1.5, 0.0], [-0.5, 0.5, 0.25], (0.0, 4.0)),
];

fn along_ray<R: Range>((o, d, (t0, t1)): Ray) -> (f64, f64) {
    let t = R::input(0, t0, t1);
    let c = |i: usize| t.clone() * d[i] + o[i];
    mitchell(c(0), c(1), c(2)).bounds()
}

/// Grid points with 1/4 steps of dyadic boxes: every f64 operation of the model is exact
/// there (few significant bits), so the point value is the real value.
fn grid(lo: f64, hi: f64, s: i32) -> f64 {
    lo + (hi - lo) * s as f64 / 4.0
}

#[test]
fn mitchell_widths_revaa_vs_raa_on_boxes() {
    // On a cell the only product, x² * (y² + z²), multiplies forms over disjoint symbols:
    // no diagonal terms and no paired off-diagonal terms, so RevAA's product equals
    // AF1's in exact arithmetic, and so do the ranges. Only the rounding-error
    // bookkeeping differs (RevAA's product bounds a few more roundings): allowance 16
    // ulps of the larger end.
    println!("| box | RevAA width | RAA* width | RevAA/RAA* |");
    println!("|---|---|---|---|");
    for b in BOXES {
        let rev = over_box::<RevAa<3>>(b);
        let raa = over_box::<Raa<3>>(b);
        let (wr, wa) = (rev.1 - rev.0, raa.1 - raa.0);
        println!("| {b:?} | {wr:.6} | {wa:.6} | {:.6} |", wr / wa);
        let tol = 16.0 * f64::EPSILON * raa.0.abs().max(raa.1.abs());
        assert!(wr <= wa + 2.0 * tol, "box {b:?}: revaa {rev:?} raa {raa:?}");
        for i in 0..=4 {
            for j in 0..=4 {
                for k in 0..=4 {
                    let v = mitchell(
                        grid(b[0].0, b[0].1, i),
                        grid(b[1].0, b[1].1, j),
                        grid(b[2].0, b[2].1, k),
                    );
                    assert!(rev.0 <= v && v <= rev.1, "revaa {rev:?} misses {v}");
                    assert!(raa.0 <= v && v <= raa.1, "raa {raa:?} misses {v}");
                }
            }
        }
    }
}

#[test]
fn mitchell_widths_revaa_vs_raa_on_rays() {
    // On a ray x, y, z share the symbol of t: the product has a diagonal term and
    // RevAA's tight product is strictly narrower.
    println!("| ray (o, d, t) | RevAA width | RAA* width | RevAA/RAA* |");
    println!("|---|---|---|---|");
    for ray in RAYS {
        let rev = along_ray::<RevAa<1>>(ray);
        let raa = along_ray::<Raa<1>>(ray);
        let (wr, wa) = (rev.1 - rev.0, raa.1 - raa.0);
        println!("| {ray:?} | {wr:.6} | {wa:.6} | {:.6} |", wr / wa);
        assert!(wr < wa, "ray {ray:?}: revaa {rev:?} raa {raa:?}");
        let (o, d, (t0, t1)) = ray;
        for s in 0..=4 {
            let t = grid(t0, t1, s);
            let v = mitchell(o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]);
            assert!(rev.0 <= v && v <= rev.1, "revaa {rev:?} misses {v}");
            assert!(raa.0 <= v && v <= raa.1, "raa {raa:?} misses {v}");
        }
    }
}
