//! `bench-suite formulas`: every arithmetic's range of random formulas over random boxes,
//! against intervals and revised affine forms.
//!
//! A seeded generator writes formulas in the formula language (every operation it has:
//! `+ - * /`, integer powers, `sqrt sqr exp ln sin cos abs min max` and the R-functions
//! `& | \`), as `tracer range --expr` reads them, and boxes whose sides are from `1e-4`
//! to `1` wide, placed in `[-2, 2]^3`. For each arithmetic it counts the formulas whose
//! range is wider than intervals' (IA), wider than revised affine arithmetic's (RevAA),
//! and unbounded where intervals are bounded.
//!
//! # What "wider" means
//!
//! A range is wider than a reference when one of its bounds lies outside the reference's
//! by more than 8 ulps of the larger magnitude of the two ranges' finite bounds. Sound
//! arithmetics that agree in exact arithmetic still round differently: an affine form
//! bounds its rounding errors relative to its centre, and intervals round each bound,
//! so equal ranges differ by a few ulps of the magnitude, never by more on one
//! operation; an unbounded side where the reference is bounded is always wider. The
//! share wider by more than 1% of the reference's width is printed beside it.

use arith_core::{Arithmetic, Range};
use model_ir::arith::ArithKind;
use model_sources::formula::{self, Tape};
use model_sources::noise::SplitMix64 as Rng;

/// Settings of the study.
#[derive(Clone, Copy, Debug)]
pub struct Settings {
    /// Number of formulas (one box each).
    pub formulas: usize,
    /// Nesting depth of the generated formulas.
    pub depth: u32,
    /// Seed of the generator.
    pub seed: u64,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            formulas: 400,
            depth: 5,
            seed: 13,
        }
    }
}

/// A random formula of depth at most `depth`.
pub fn random_formula(rng: &mut Rng, depth: u32) -> String {
    if depth == 0 || rng.next_f64() < 0.15 {
        return leaf(rng);
    }
    let a = random_formula(rng, depth - 1);
    match (rng.next_f64() * 21.0) as u32 {
        0..=1 => format!("({a} + {})", random_formula(rng, depth - 1)),
        2..=3 => format!("({a} - {})", random_formula(rng, depth - 1)),
        4..=5 => format!("({a} * {})", random_formula(rng, depth - 1)),
        6 => format!("({a} / {})", random_formula(rng, depth - 1)),
        7 => format!(
            "({a})^{}",
            [2, 3, 4, -1, -2][(rng.next_f64() * 5.0) as usize]
        ),
        8 => format!("sqrt({a})"),
        9 => format!("sqr({a})"),
        10 => format!("exp({a})"),
        11 => format!("ln({a})"),
        12 => format!("sin({a})"),
        13 => format!("cos({a})"),
        14 => format!("abs({a})"),
        15 => format!("min({a}, {})", random_formula(rng, depth - 1)),
        16 => format!("max({a}, {})", random_formula(rng, depth - 1)),
        17 => format!("({a} & {})", random_formula(rng, depth - 1)),
        18 => format!("({a} | {})", random_formula(rng, depth - 1)),
        19 => format!("({a} \\ {})", random_formula(rng, depth - 1)),
        _ => format!("({a} * {} + {})", constant(rng), constant(rng)),
    }
}

fn leaf(rng: &mut Rng) -> String {
    if rng.next_f64() < 0.7 {
        ["x", "y", "z"][(rng.next_f64() * 3.0) as usize].to_string()
    } else {
        constant(rng)
    }
}

/// A constant in `[-3, 3]` with three decimals (never a bare `-`: the formula language
/// reads `-0.5` as a negation, which is the same value).
fn constant(rng: &mut Rng) -> String {
    let c = (rng.range(-3.0, 3.0) * 1000.0).round() / 1000.0;
    if c < 0.0 {
        format!("({c})")
    } else {
        format!("{c}")
    }
}

/// A box with sides `10^U(-4, 0)` wide, centred in `[-2, 2]^3`.
pub fn random_box(rng: &mut Rng) -> [(f64, f64); 3] {
    core::array::from_fn(|_| {
        let c = rng.range(-2.0, 2.0);
        let w = 10f64.powf(rng.range(-4.0, 0.0));
        (c - w / 2.0, c + w / 2.0)
    })
}

fn range_of<A: Arithmetic>(tape: &Tape, b: &[(f64, f64); 3]) -> (f64, f64) {
    let v = |i: usize| <A::Cell as Range>::input(i, b[i].0, b[i].1);
    tape.eval(v(0), v(1), v(2)).bounds()
}

/// Whether `(bl, bh)` lies outside `(cl, ch)` by more than rounding (module doc).
pub fn wider((bl, bh): (f64, f64), (cl, ch): (f64, f64)) -> bool {
    let scale = [bl, bh, cl, ch]
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let slack = 8.0 * f64::EPSILON * scale + 1e-300;
    !((cl == f64::NEG_INFINITY || bl >= cl - slack) && (ch == f64::INFINITY || bh <= ch + slack))
}

/// Whether `b` is more than 1% wider than a bounded `c` (or unbounded where `c` is not).
fn wider_by_a_percent(b: (f64, f64), c: (f64, f64)) -> bool {
    let (wb, wc) = (b.1 - b.0, c.1 - c.0);
    if !wc.is_finite() {
        return false;
    }
    wb.is_nan() || wb > wc * 1.01 + 1e-300
}

/// Counts for one arithmetic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Shares {
    /// Formulas evaluated.
    pub formulas: usize,
    /// Wider than intervals, beyond rounding.
    pub wider_than_ia: usize,
    /// More than 1% wider than intervals.
    pub wider_than_ia_1pc: usize,
    /// Wider than revised affine arithmetic, beyond rounding.
    pub wider_than_revaa: usize,
    /// More than 1% wider than revised affine arithmetic.
    pub wider_than_revaa_1pc: usize,
    /// Unbounded where intervals are bounded.
    pub unbounded_where_ia_is_not: usize,
}

/// The study's counts per arithmetic, and the formulas that made each arithmetic wider
/// than intervals or revised affine forms (text and box, at most 3 each).
pub fn study(kinds: &[ArithKind], s: &Settings) -> (Vec<(ArithKind, Shares)>, Vec<String>) {
    let mut rng = Rng(s.seed);
    let mut shares = vec![Shares::default(); kinds.len()];
    let mut examples = Vec::new();
    let mut shown = vec![0usize; kinds.len()];
    let mut made = 0;
    while made < s.formulas {
        let text = random_formula(&mut rng, s.depth);
        let b = random_box(&mut rng);
        // Formulas the language refuses (`ln` of a constant <= 0, `1/0`) are drawn again.
        let Ok(tape) = formula::parse(&text) else {
            continue;
        };
        made += 1;
        let ia = model_ir::with_arith!(ArithKind::Ia, A => range_of::<A>(&tape, &b));
        let rev = model_ir::with_arith!(ArithKind::Revaa, A => range_of::<A>(&tape, &b));
        for (k, (kind, sh)) in kinds.iter().zip(&mut shares).enumerate() {
            let r = model_ir::with_arith!(*kind, A => range_of::<A>(&tape, &b));
            sh.formulas += 1;
            let (wi, wr) = (wider(r, ia), wider(r, rev));
            sh.wider_than_ia += usize::from(wi);
            sh.wider_than_revaa += usize::from(wr);
            sh.wider_than_ia_1pc += usize::from(wider_by_a_percent(r, ia));
            sh.wider_than_revaa_1pc += usize::from(wider_by_a_percent(r, rev));
            let unbounded = !(r.0.is_finite() && r.1.is_finite());
            let ia_bounded = ia.0.is_finite() && ia.1.is_finite();
            sh.unbounded_where_ia_is_not += usize::from(unbounded && ia_bounded);
            if (wi || wr) && shown[k] < 3 {
                shown[k] += 1;
                examples.push(format!(
                    "{}: {r:?} (ia {ia:?}, revaa {rev:?}) for `{text}` over {b:?}",
                    kind.name()
                ));
            }
        }
    }
    (kinds.iter().copied().zip(shares).collect(), examples)
}

/// The study as a Markdown table (percentages of the formulas).
pub fn report(rows: &[(ArithKind, Shares)], examples: &[String], s: &Settings) -> String {
    let pc = |n: usize, of: usize| 100.0 * n as f64 / of.max(1) as f64;
    let mut md = format!(
        "Random formulas over random boxes: {} formulas of depth <= {}, seed {}, sides \
         1e-4 to 1.\nWider = a bound outside the reference's by more than 8 ulps of the \
         ranges' magnitude.\n\n| arithmetic | wider than IA | > 1% wider than IA | wider \
         than RevAA | > 1% wider than RevAA | unbounded, IA bounded |\n|---|---|---|---|---|---|\n",
        s.formulas, s.depth, s.seed
    );
    for (k, sh) in rows {
        let n = sh.formulas;
        md += &format!(
            "| {} | {:.1}% | {:.1}% | {:.1}% | {:.1}% | {:.1}% |\n",
            k.label(),
            pc(sh.wider_than_ia, n),
            pc(sh.wider_than_ia_1pc, n),
            pc(sh.wider_than_revaa, n),
            pc(sh.wider_than_revaa_1pc, n),
            pc(sh.unbounded_where_ia_is_not, n),
        );
    }
    if !examples.is_empty() {
        md += "\nExamples:\n\n";
        for e in examples {
            md += &format!("- {e}\n");
        }
    }
    md
}
