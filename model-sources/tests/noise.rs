//! The noise functions' and the models' derived bounds against sampled values and
//! gradients (finite differences at many random points): no sample may exceed a bound.

use arith_core::dual::Dual;
use arith_core::{Range, Real};
use arith_ia::Interval;
use glam::DVec3;
use model_ir::shape::Shape;
use model_sources::noise::{eval_field, Cellular, Field3, Perlin, SparseConvolution, SplitMix64};

fn fields() -> Vec<(&'static str, Box<dyn Field3>)> {
    vec![
        ("perlin", Box::new(Perlin::new(7))),
        ("sparse", Box::new(SparseConvolution::new(8))),
        ("cellular", Box::new(Cellular::new(9))),
    ]
}

fn random_point(rng: &mut SplitMix64, r: f64) -> DVec3 {
    DVec3::new(rng.range(-r, r), rng.range(-r, r), rng.range(-r, r))
}

/// Central differences with step `h`, and the analytic gradient, both within the bounds;
/// the analytic gradient agrees with the differences (it feeds the Dual evaluation).
#[test]
fn sampled_noise_values_and_gradients_stay_within_the_derived_bounds() {
    let mut rng = SplitMix64(42);
    let h = 1e-6;
    for (name, f) in fields() {
        let (lo, hi) = f.value_bound();
        let (mut max_v, mut max_g, mut max_p) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..20_000 {
            let p = random_point(&mut rng, 20.0);
            let v = f.value(p);
            assert!(lo <= v && v <= hi, "{name}: value {v} at {p:?}");
            let fd = DVec3::new(
                f.value(p + DVec3::X * h) - f.value(p - DVec3::X * h),
                f.value(p + DVec3::Y * h) - f.value(p - DVec3::Y * h),
                f.value(p + DVec3::Z * h) - f.value(p - DVec3::Z * h),
            ) / (2.0 * h);
            let g = f.gradient(p);
            // Cellular noise has kinks (Voronoi faces) where differences straddle two cells.
            if name != "cellular" {
                assert!(
                    (fd - g).length() <= 1e-4 * (1.0 + g.length()),
                    "{name}: gradient {g:?} vs differences {fd:?} at {p:?}"
                );
            }
            for d in [fd, g] {
                assert!(
                    d.length() <= f.lipschitz() * (1.0 + 1e-6),
                    "{name}: |grad| {} > L {} at {p:?}",
                    d.length(),
                    f.lipschitz()
                );
                assert!(
                    d.abs().max_element() <= f.partial_bound() * (1.0 + 1e-6),
                    "{name}: partial {d:?} at {p:?}"
                );
            }
            max_v = max_v.max(v.abs());
            max_g = max_g.max(g.length());
            max_p = max_p.max(g.abs().max_element());
        }
        println!("{name}: sampled max |n| {max_v:.3} (bound {hi}), |grad| {max_g:.3} (L {}), partial {max_p:.3} (G {})", f.lipschitz(), f.partial_bound());
        // The samples are not degenerate.
        assert!(max_v > 0.1 && max_g > 0.1);
    }
}

/// Over interval boxes, the enclosure holds every sampled point value.
#[test]
fn noise_over_intervals_encloses_sampled_points() {
    let mut rng = SplitMix64(43);
    for (name, f) in fields() {
        for _ in 0..2_000 {
            let c = random_point(&mut rng, 10.0);
            let r = rng.range(0.0, 0.3);
            let iv = |a: f64| Interval::input(0, a - r, a + r);
            let e = eval_field(f.as_ref(), &iv(c.x), &iv(c.y), &iv(c.z));
            let (lo, hi) = e.bounds();
            for _ in 0..10 {
                let p = c + DVec3::new(rng.range(-r, r), rng.range(-r, r), rng.range(-r, r));
                let v = f.value(p);
                assert!(lo <= v && v <= hi, "{name}: {v} outside [{lo}, {hi}]");
            }
        }
    }
}

/// Each model's Lipschitz bound is not exceeded by sampled difference quotients, and its
/// Dual gradient at points matches finite differences.
#[test]
fn model_lipschitz_bounds_hold_on_samples() {
    let mut rng = SplitMix64(44);
    let h = 1e-6;
    for m in model_sources::gamito_maddock::all() {
        let l = m.lipschitz.unwrap();
        let (lo, hi) = (m.domain.min, m.domain.max);
        let f = |p: DVec3| m.eval(p.x, p.y, p.z);
        let mut worst = 0.0f64;
        let n = if m.name == "blobby" { 1500 } else { 4000 };
        for _ in 0..n {
            let p = DVec3::new(
                rng.range(lo.x + h, hi.x - h),
                rng.range(lo.y + h, hi.y - h),
                rng.range(lo.z + h, hi.z - h),
            );
            let fd = DVec3::new(
                f(p + DVec3::X * h) - f(p - DVec3::X * h),
                f(p + DVec3::Y * h) - f(p - DVec3::Y * h),
                f(p + DVec3::Z * h) - f(p - DVec3::Z * h),
            ) / (2.0 * h);
            assert!(
                fd.length() <= l * (1.0 + 1e-6),
                "{}: |grad| {} > {l} at {p:?}",
                m.name,
                fd.length()
            );
            worst = worst.max(fd.length());
            let d = m.eval(Dual::var(p.x, 0), Dual::var(p.y, 1), Dual::var(p.z, 2));
            let g = DVec3::from_array(d.g);
            // Away from kinks (the blobby model's support boundaries, cellular faces).
            if (g - fd).length() > 1e-3 * (1.0 + g.length())
                && !matches!(m.name.as_str(), "blobby" | "landscape")
            {
                panic!("{}: dual gradient {g:?} vs differences {fd:?}", m.name);
            }
        }
        println!("{}: lambda {l:.3}, sampled max |grad| {worst:.3}", m.name);
    }
}

/// The gradient enclosure over an interval box holds sampled gradients.
#[test]
fn dual_interval_gradients_enclose_sampled_gradients() {
    let mut rng = SplitMix64(45);
    // Mitchell's quartic, and the blobby model whose range evaluation skips the basis
    // functions that cannot matter in the box.
    for (name, r_max) in [("mitchell-gm", 0.2), ("blobby", 0.4), ("blobby", 0.05)] {
        let m = model_sources::gamito_maddock::all()
            .into_iter()
            .find(|m| m.name == name)
            .unwrap();
        for _ in 0..300 {
            let c = random_point(&mut rng, 1.5);
            let r = rng.range(0.0, r_max);
            let v = |a: f64, k| Dual::var(Interval::input(k, a - r, a + r), k);
            let e = m.eval(v(c.x, 0), v(c.y, 1), v(c.z, 2));
            let iv = |a: f64, k| Interval::input(k, a - r, a + r);
            let (ilo, ihi) = m.eval(iv(c.x, 0), iv(c.y, 1), iv(c.z, 2)).bounds();
            for _ in 0..10 {
                let p = c + DVec3::new(rng.range(-r, r), rng.range(-r, r), rng.range(-r, r));
                let d = m.eval(Dual::var(p.x, 0), Dual::var(p.y, 1), Dual::var(p.z, 2));
                for k in 0..3 {
                    let (lo, hi) = e.g[k].bounds();
                    assert!(
                        lo <= d.g[k] && d.g[k] <= hi,
                        "{name}: gradient {} outside [{lo}, {hi}]",
                        d.g[k]
                    );
                }
                let (lo, hi) = e.v.bounds();
                assert!(
                    lo <= d.v && d.v <= hi,
                    "{name}: {} outside [{lo}, {hi}]",
                    d.v
                );
                assert!(
                    ilo <= d.v && d.v <= ihi,
                    "{name}: {} outside the interval [{ilo}, {ihi}]",
                    d.v
                );
            }
        }
    }
    let _ = <f64 as Real>::constant(0.0);
}

/// Verifies Perlin's `L` and `G` (see the doc of `Perlin`): encloses
/// `M = sum_c max_g |J_c g|` and `sum_c max_g |(J_c g)_x|` with outward-rounded interval
/// arithmetic over `24^3` sub-boxes of `[0, 1/2]^3` (enough by the reflection symmetry).
#[test]
fn perlin_gradient_bounds_are_verified_by_interval_subdivision() {
    use model_sources::noise::GRADS;
    let iv = |lo: f64, hi: f64| Interval::input(0, lo, hi);
    let c = Interval::constant;
    // s and s' are increasing on [0, 1/2] (s' >= 0, s'' = 60 t (1 - t)(1 - 2t) >= 0), so
    // over [a, b] they range over their end values, widened for the rounding of the f64
    // evaluation (a few ulps of values <= 2).
    let mono = |f: fn(f64) -> f64, t: Interval| {
        let (a, b) = t.bounds();
        Interval::new(f(a) - 1e-14, f(b) + 1e-14)
    };
    let fade = |t: Interval| mono(model_sources::noise::fade, t);
    let dfade = |t: Interval| mono(model_sources::noise::fade_deriv, t);
    let mag = |v: Interval| {
        let (lo, hi) = v.bounds();
        lo.abs().max(hi.abs())
    };
    let n = 24;
    let h = 0.5 / n as f64;
    let (mut worst_l, mut worst_g) = (0.0f64, 0.0f64);
    for a in 0..n {
        for b in 0..n {
            for k in 0..n {
                let f = [
                    iv(a as f64 * h, (a + 1) as f64 * h),
                    iv(b as f64 * h, (b + 1) as f64 * h),
                    iv(k as f64 * h, (k + 1) as f64 * h),
                ];
                let s = f.map(fade);
                let ds = f.map(dfade);
                let (mut tot_l, mut tot_g) = (0.0f64, 0.0f64);
                for corner in 0..8usize {
                    let sel = [corner & 1, (corner >> 1) & 1, (corner >> 2) & 1];
                    let w: Vec<Interval> = (0..3)
                        .map(|q| if sel[q] == 1 { s[q] } else { c(1.0) - s[q] })
                        .collect();
                    let dw: Vec<Interval> = (0..3)
                        .map(|q| if sel[q] == 1 { ds[q] } else { -ds[q] })
                        .collect();
                    let d: Vec<Interval> = (0..3).map(|q| f[q] - sel[q] as f64).collect();
                    let (mut m_l, mut m_g) = (0.0f64, 0.0f64);
                    for g in GRADS {
                        let dot = d[0] * g[0] + d[1] * g[1] + d[2] * g[2];
                        // (J g)_q = (prod of the other two weights) (s'_q-term dot + w_q g_q):
                        // factored so the shared weights are not counted twice.
                        let v: Vec<f64> = (0..3)
                            .map(|q| {
                                let others = w[(q + 1) % 3] * w[(q + 2) % 3];
                                mag(others * (dw[q] * dot + w[q] * g[q]))
                            })
                            .collect();
                        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() * (1.0 + 1e-12);
                        m_l = m_l.max(norm);
                        m_g = m_g.max(v[0]);
                    }
                    tot_l += m_l;
                    tot_g += m_g;
                }
                worst_l = worst_l.max(tot_l * (1.0 + 1e-12));
                worst_g = worst_g.max(tot_g * (1.0 + 1e-12));
            }
        }
    }
    println!("verified: |grad n| <= {worst_l}, |dn/dx| <= {worst_g}");
    assert!(worst_l <= Perlin::LIPSCHITZ, "{worst_l} > L");
    assert!(worst_g <= Perlin::PARTIAL, "{worst_g} > G");
}
