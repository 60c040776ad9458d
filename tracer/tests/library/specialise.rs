//! Region specialisation ([`Tape::specialise`]) keeps the sign of the function at every
//! point of the region and never lengthens a tape (random formulas over random boxes),
//! does shorten scenes of separate parts, and renders with it on and off agree: with
//! the analytic hits of a scene of balls (no missed root, hit points on the surface,
//! depths within the precision) and, on every Appendix A model written as a formula, in
//! their hit masks.

use arith_core::Range;
use arith_ia::Interval;
use arith_revaa::RevAa;
use glam::DVec3;
use model_ir::arith::arith_aa::Aa;
use model_ir::arith::arith_hull::Hull;
use model_ir::arith::ArithKind;
use model_ir::camera::Camera;
use model_ir::shape::{Aabb, View};
use model_sources::formula::{parse, Tape, ToFormula, MIN_SPECIALISE_LEN};
use model_sources::{Model, PaperModel};
use proptest::prelude::*;
use tracer::render::{render_kind, RenderOptions};
use tracer::search::ray::clip;

/// Leaves: balls, slabs and the coordinates, so that ranges over small boxes decide.
fn leaf() -> impl Strategy<Value = String> {
    prop_oneof![
        (-2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64, 0.05..1.0f64)
            .prop_map(|(a, b, c, r)| format!("({r} - (x - {a})^2 - (y - {b})^2 - (z - {c})^2)")),
        (-1.5..1.5f64).prop_map(|c| format!("({c} - x)")),
        (-1.5..1.5f64).prop_map(|c| format!("(y - {c})")),
        Just("z".to_string()),
        (-2.0..2.0f64).prop_map(|c| format!("{c}")),
    ]
}

/// Random trees of [`leaf`]s under `ops` (templates in `{a}` and `{b}`).
fn trees_of(ops: &'static [&'static str], depth: u32, size: u32) -> impl Strategy<Value = String> {
    leaf().prop_recursive(depth, size, 2, move |inner| {
        (prop::sample::select(ops), inner.clone(), inner)
            .prop_map(|(op, a, b)| op.replace("{a}", &a).replace("{b}", &b))
    })
}

/// Trees over the operations specialisation looks through, and others it must not.
fn tree() -> impl Strategy<Value = String> {
    trees_of(
        &[
            "min({a}, {b})",
            "max({a}, {b})",
            "({a} & {b})",
            "({a} | {b})",
            "({a} \\ {b})",
            "-({a})",
            "(3 * {a})",
            "({a} / -2)",
            "({a} + {b})",
            "({a} * {b})",
            "if({a} > 0, {b}, {a})",
            "if({a} <= {b}, {a}, -1)",
            "({a} > 0)",
            "exp({a}) - 1",
            "blend_union({a}, {b})",
            "min({a}, {a})",
        ],
        6,
        48,
    )
}

/// Trees of balls under `min`, `max` and negation only: every register is folded by
/// level where it can be, which the mixed trees of [`tree`] seldom reach.
fn lattice() -> impl Strategy<Value = String> {
    trees_of(
        &[
            "min({a}, {b})",
            "max({a}, {b})",
            "-max({a}, {b})",
            "max(-{a}, {b})",
        ],
        5,
        32,
    )
}

/// The box `centre ± half`.
fn region() -> impl Strategy<Value = [(f64, f64); 3]> {
    (
        prop::array::uniform3(-2.0..2.0f64),
        prop::array::uniform3(0.01..1.5f64),
    )
        .prop_map(|(c, h)| core::array::from_fn(|k| (c[k] - h[k], c[k] + h[k])))
}

/// `t` specialised over `b` in the arithmetic `R` (cell form, three symbols).
fn specialised<R: Range>(t: &Tape, b: &[(f64, f64); 3]) -> Option<Tape> {
    let region: [R; 3] = core::array::from_fn(|k| R::input(k, b[k].0, b[k].1));
    t.specialise(&[region])
}

/// Whether the signs of `t` and `s` at `p` are certainly different: their interval
/// enclosures at the point lie strictly on opposite sides of 0.
fn signs_differ(t: &Tape, s: &Tape, p: [f64; 3]) -> bool {
    let at = |t: &Tape| {
        let [x, y, z] = p.map(|c| Interval::from_interval(c, c));
        t.eval(x, y, z).bounds()
    };
    let (a, b) = (at(t), at(s));
    (a.0 > 0.0 && b.1 < 0.0) || (a.1 < 0.0 && b.0 > 0.0)
}

fn check_signs(t: &Tape, s: &Tape, b: &[(f64, f64); 3], seed: u64) -> Result<(), String> {
    // Not shorter only with R-functions turned into `min` and `max` (and `a \ b` into
    // `min(a, -b)`, one more instruction).
    let count = |t: &Tape, ops: &[char]| t.to_formula().matches(ops).count();
    let r_functions = |t: &Tape| count(t, &['&', '|', '\\']);
    if s.len() > t.len() + count(t, &['\\'])
        || (s.len() >= t.len() && r_functions(s) >= r_functions(t))
    {
        return Err(format!(
            "neither shorter nor with fewer R-functions: {} >= {}",
            s.len(),
            t.len()
        ));
    }
    let mut state = seed | 1;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for n in 0..64 {
        // Corners and faces first: the region is closed.
        let p: [f64; 3] = core::array::from_fn(|k| {
            let u = if n < 8 {
                f64::from((n >> k) & 1)
            } else {
                rnd()
            };
            b[k].0 + (b[k].1 - b[k].0) * u
        });
        if signs_differ(t, s, p) {
            return Err(format!(
                "signs differ at {p:?}\nwhole:\n{t}\nspecialised:\n{s}"
            ));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// In IA, AA, RevAA and Hull: a specialised tape is shorter (or has fewer
    /// R-functions, turned into `min` and `max`) and nowhere in the region
    /// of the opposite sign.
    #[test]
    fn specialised_tapes_keep_the_sign(f in tree(), b in region(), seed in any::<u64>()) {
        let t = parse(&f).unwrap();
        for s in [
            specialised::<Interval>(&t, &b),
            specialised::<Aa>(&t, &b),
            specialised::<RevAa<3>>(&t, &b),
            specialised::<Hull<3>>(&t, &b),
        ]
        .into_iter()
        .flatten()
        {
            check_signs(&t, &s, &b, seed).map_err(TestCaseError::fail)?;
            // Specialising again over the same region is sound too.
            if let Some(s2) = specialised::<RevAa<3>>(&s, &b) {
                check_signs(&t, &s2, &b, seed ^ 0x5555).map_err(TestCaseError::fail)?;
            }
        }
    }
}

/// Points of the box `b`: its corners, then pseudo-random ones.
fn points_in(b: &[(f64, f64); 3], seed: u64) -> impl Iterator<Item = [f64; 3]> + '_ {
    let mut state = seed | 1;
    (0..64).map(move |n| {
        core::array::from_fn(|k| {
            let u = if n < 8 {
                f64::from((n >> k) & 1)
            } else {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            (b[k].0 + (b[k].1 - b[k].0) * u).clamp(b[k].0, b[k].1)
        })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// A tape specialised for shading has the whole tape's value, to the bit, at every
    /// point of its box where its own value lies inside `(-within, within)` (every
    /// point for `within = inf`), but for the sign of a zero: where a `min` or `max` is
    /// decided because its operands' ranges meet only at 0, the whole tape's
    /// `min(0, -0)` may take either zero (IEEE 754 leaves it open), and the value tape
    /// the other.
    #[test]
    fn value_tapes_keep_the_value(
        f in tree(),
        b in region(),
        seed in any::<u64>(),
        within in prop_oneof![Just(f64::INFINITY), (-4i32..2).prop_map(|k| 10f64.powi(k))],
    ) {
        let t = parse(&f).unwrap();
        let region: [Interval; 3] = core::array::from_fn(|k| Interval::from_interval(b[k].0, b[k].1));
        if let Some(v) = t.specialise_values(&region, within) {
            prop_assert!(v.len() < t.len());
            for p in points_in(&b, seed) {
                let (a, c): (f64, f64) = (t.eval(p[0], p[1], p[2]), v.eval(p[0], p[1], p[2]));
                if within.is_finite() && (c.is_nan() || c.abs() >= within) {
                    continue;
                }
                prop_assert!(
                    a.to_bits() == c.to_bits() || (a == 0.0 && c == 0.0) || (a.is_nan() && c.is_nan()),
                    "{a} != {c} at {p:?} (within {within})\nwhole:\n{t}\nvalues:\n{v}"
                );
            }
        }
    }

    /// The same for trees of `min`, `max` and negation folded by level, at points
    /// where the folded tape's value lies inside the level.
    #[test]
    fn level_tapes_keep_the_value(
        f in lattice(),
        b in region(),
        seed in any::<u64>(),
        within in prop_oneof![(0.05..3.0f64)],
    ) {
        let t = parse(&f).unwrap();
        let region: [Interval; 3] = core::array::from_fn(|k| Interval::from_interval(b[k].0, b[k].1));
        if let Some(v) = t.specialise_values(&region, within) {
            prop_assert!(v.len() < t.len());
            for p in points_in(&b, seed) {
                let (a, c): (f64, f64) = (t.eval(p[0], p[1], p[2]), v.eval(p[0], p[1], p[2]));
                if c.is_nan() || c.abs() >= within {
                    continue;
                }
                prop_assert!(
                    a.to_bits() == c.to_bits() || (a == 0.0 && c == 0.0),
                    "{a} != {c} at {p:?} (within {within})\nwhole:\n{t}\nvalues:\n{v}"
                );
            }
        }
    }

    /// Specialised over several regions at once (the depth windows): each group's tape
    /// keeps the sign over every region of the group.
    #[test]
    fn grouped_tapes_keep_the_sign(f in tree(), b in region(), seed in any::<u64>()) {
        let t = parse(&f).unwrap();
        // The box cut in two along z: the halves and their union.
        let mid = 0.5 * (b[2].0 + b[2].1);
        let halves = [[b[0], b[1], (b[2].0, mid)], [b[0], b[1], (mid, b[2].1)]];
        let regions: Vec<[RevAa<3>; 3]> = halves
            .iter()
            .map(|h| core::array::from_fn(|k| RevAa::<3>::input(k, h[k].0, h[k].1)))
            .collect();
        let groups = [(0, 1), (1, 2), (0, 2)];
        let (tapes, which) = t.specialise_groups(&regions, &groups);
        prop_assert_eq!(which.len(), groups.len());
        for (g, w) in which.iter().enumerate() {
            let Some(k) = *w else { continue };
            let (i, j) = groups[g];
            for h in &halves[i..j] {
                check_signs(&t, &tapes[k], h, seed ^ g as u64).map_err(TestCaseError::fail)?;
            }
        }
    }
}

/// `n` balls of radius 0.2 at the points of a 3-D grid, joined by `max` or by `|`.
fn balls(n: usize, join: &str) -> (String, Vec<DVec3>) {
    let mut centres = Vec::new();
    let mut terms = Vec::new();
    for k in 0..n {
        let c = DVec3::new(
            -0.9 + 0.6 * (k % 4) as f64,
            -0.9 + 0.6 * ((k / 4) % 4) as f64,
            -0.9 + 0.6 * (k / 16) as f64,
        );
        terms.push(format!(
            "(0.04 - (x - {})^2 - (y - {})^2 - (z - {})^2)",
            c.x, c.y, c.z
        ));
        centres.push(c);
    }
    let text = if join == "max" {
        terms
            .iter()
            .skip(1)
            .fold(terms[0].clone(), |a, t| format!("max({a}, {t})"))
    } else {
        terms.join(" | ")
    };
    (text, centres)
}

/// The exact rule drops an operand of an n-ary `max` that another leaf dominates even
/// where its own node's other operand does not: `F2` lies below the small ball `A`
/// over the box, but not below the big ball `M` it is paired with.
#[test]
fn dominated_leaves_of_a_max_tree_are_dropped() {
    let ball = |c: f64, r2: f64| format!("({r2} - (x - {c})^2 - y^2 - z^2)");
    let (a, m, f1, f2) = (
        ball(0.0, 0.04),
        ball(1.0, 1.0),
        ball(3.0, 0.04),
        ball(0.6, 0.04),
    );
    let t = parse(&format!("max(max({a}, {f1}), max({m}, {f2}))")).unwrap();
    assert!(t.len() >= MIN_SPECIALISE_LEN);
    let region: [Interval; 3] = [(-0.1, 0.1); 3].map(|(lo, hi)| Interval::from_interval(lo, hi));
    let s = t
        .specialise_values(&region, f64::INFINITY)
        .expect("shorter");
    let f = s.to_formula();
    assert!(
        f.contains("x - 1.0") && f.contains("0.04 - (x - 0.0)^2"),
        "{f}"
    );
    assert!(!f.contains("0.6") && !f.contains("x - 3"), "{f}");
}

/// Over a box where every ball reaches, nothing is decided, but the R-functions, which
/// only pass signs, become `min` and `max`, with the same sign everywhere.
#[test]
fn sign_only_r_functions_become_min_and_max() {
    let ball = |c: f64| format!("(0.25 - (x - {c})^2 - y^2 - z^2)");
    let balls: Vec<String> = (0..6).map(|k| ball(k as f64 * 0.1)).collect();
    let text = format!(
        "(({} | {}) & ({} | {})) \\ ({} & {})",
        balls[0], balls[1], balls[2], balls[3], balls[4], balls[5]
    );
    let t = parse(&text).unwrap();
    assert!(t.len() >= MIN_SPECIALISE_LEN);
    let b = [(-0.6, 0.9), (-0.6, 0.6), (-0.6, 0.6)];
    let s = specialised::<RevAa<3>>(&t, &b).expect("rebuilt");
    let f = s.to_formula();
    assert!(f.contains("max(") && f.contains("min("), "{f}");
    assert!(!f.contains(['&', '|', '\\']), "{f}");
    check_signs(&t, &s, &b, 7).unwrap();
}

#[test]
fn a_box_around_one_ball_keeps_that_ball() {
    let (text, _) = balls(16, "max");
    let t = parse(&text).unwrap();
    assert!(t.len() >= MIN_SPECIALISE_LEN);
    // The ball at (-0.9, -0.9, -0.9) and its surface; its neighbours are 0.6 away.
    let b = [(-1.15, -0.65), (-1.15, -0.65), (-1.15, -0.65)];
    let s = specialised::<RevAa<3>>(&t, &b).expect("shorter");
    assert_eq!(
        s.to_formula(),
        "0.04 - (x - (-0.9))^2 - (y - (-0.9))^2 - (z - (-0.9))^2"
    );
    // With R-function unions, the same.
    let (text, _) = balls(16, "|");
    let t = parse(&text).unwrap();
    let s = specialised::<Interval>(&t, &b).expect("shorter");
    assert_eq!(
        s.to_formula(),
        "0.04 - (x - (-0.9))^2 - (y - (-0.9))^2 - (z - (-0.9))^2"
    );
    // A box far from every ball: the constant -1 (no surface).
    let far = [(1.2, 1.4), (1.2, 1.4), (1.2, 1.4)];
    let s = specialised::<RevAa<3>>(&t, &far).expect("shorter");
    assert_eq!(s.to_formula(), "(-1.0)");
}

/// The ray against the balls: `(margin, t, clean)`; it meets one iff `margin > 0` (the
/// largest discriminant), `t` is its first entry, and `clean` says that it crosses that
/// ball well inside its outline and grazes no ball in front of it.
fn balls_hit(o: DVec3, d: DVec3, centres: &[DVec3]) -> (f64, f64, bool) {
    let rays: Vec<(f64, f64)> = centres
        .iter()
        .map(|c| {
            let q = o - *c;
            let b = q.dot(d);
            let disc = b * b - (q.length_squared() - 0.04);
            (disc, -b - disc.max(0.0).sqrt())
        })
        .collect();
    let margin = rays.iter().map(|r| r.0).fold(f64::NEG_INFINITY, f64::max);
    let (disc, t) = rays
        .iter()
        .filter(|r| r.0 > 1e-9)
        .fold((0.0, f64::INFINITY), |a, &r| if r.1 < a.1 { r } else { a });
    let grazed = rays.iter().any(|r| r.0 > -1e-9 && r.0 <= 1e-2 && r.1 <= t);
    (margin, t, disc > 1e-2 && !grazed)
}

#[test]
fn scenes_of_balls_match_the_analytic_hits_with_and_without_specialisation() {
    let (w, h) = (40, 32);
    let view = View {
        eye: DVec3::new(1.9, 1.4, 4.2),
        look_at: DVec3::new(0.0, 0.0, -0.2),
        up: DVec3::Y,
        fov_deg: 40.0,
        ortho: None,
    };
    let domain = Aabb::cube(1.3);
    let cam = Camera::new(view, w, h);
    for join in ["max", "|"] {
        let (text, centres) = balls(12, join);
        let model = Model::formula(&text, Some(domain)).unwrap();
        for k in ArithKind::ALL {
            let mut masks = Vec::new();
            // Small tiles: the tile shapes come down a quadtree of several levels.
            for (specialise, tile) in [(true, 64), (true, 8), (false, 64)] {
                let mut o = RenderOptions::for_view(view, domain, w, h);
                o.specialise = specialise;
                o.tile = tile;
                o.eps = Some(1e-4);
                let r = render_kind(k, &model.shape, &o).unwrap();
                let prec = o.precision(&cam);
                let mut analytic = 0;
                for j in 0..h {
                    for i in 0..w {
                        let idx = (j * w + i) as usize;
                        let (ro, rd) = cam.ray(i, j);
                        let tag = format!(
                            "{join} {k} specialise={specialise} tile {tile} pixel ({i},{j})"
                        );
                        let (margin, t_true, clean) = balls_hit(ro, rd, &centres);
                        if margin > 1e-9 && clip(ro, rd, &domain, 0.0).is_some() {
                            analytic += 1;
                            assert!(r.hit[idx], "{tag}: analytic hit at {t_true} missed");
                            if clean && k != ArithKind::Ia {
                                let t = r.depth[idx] as f64;
                                let tol = 2.0 * prec.at(t_true) + 1e-6 * t_true;
                                assert!((t - t_true).abs() <= tol, "{tag}: {t} vs {t_true}");
                            }
                        }
                        if r.hit[idx] {
                            let p = ro + rd * r.depth[idx] as f64;
                            let e = centres
                                .iter()
                                .map(|c| ((p - *c).length() - 0.2).abs())
                                .fold(f64::INFINITY, f64::min);
                            assert!(e <= 1e-3, "{tag}: hit {e} from every ball");
                        }
                    }
                }
                assert!(analytic > 50, "{join}: {analytic} analytic hits");
                masks.push(r.hit);
            }
            assert_eq!(masks[0], masks[2], "{join} {k}: masks differ");
            assert_eq!(masks[1], masks[2], "{join} {k}: masks differ (small tiles)");
        }
    }
}

/// Every Appendix A model that has a formula, as a tape: the same hit mask with
/// specialisation on and off, in RevAA and Hull.
#[test]
fn paper_formulas_hit_the_same_pixels_with_and_without_specialisation() {
    let mut specialising = 0;
    for m in PaperModel::ALL {
        let Some(text) = m.formula() else { continue };
        let base = m.model();
        let model = Model::formula(text, Some(base.domain)).unwrap();
        let model_sources::AnyShape::Expr(tape) = &model.shape else {
            unreachable!("a formula model is a tape")
        };
        specialising += usize::from(tape.specialises());
        for k in [ArithKind::Revaa, ArithKind::Hull] {
            let masks: Vec<Vec<bool>> = [(true, 64), (true, 8), (false, 64)]
                .into_iter()
                .map(|(on, tile)| {
                    let mut o = RenderOptions::for_view(base.view, base.domain, 32, 24);
                    o.specialise = on;
                    o.tile = tile;
                    render_kind(k, &model.shape, &o).unwrap().hit
                })
                .collect();
            let diff: Vec<usize> = (0..masks[0].len())
                .filter(|&i| masks[0][i] != masks[2][i] || masks[1][i] != masks[2][i])
                .collect();
            assert!(diff.is_empty(), "{} {k}: pixels {diff:?} differ", m.name());
        }
    }
    assert!(
        specialising >= 3,
        "only {specialising} paper tapes specialise"
    );
}
