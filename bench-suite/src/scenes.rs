//! `bench-suite scenes`: cost against model size, with and without region
//! specialisation ([`model_sources::formula::Tape::specialise`]).
//!
//! A scene is `N` balls scattered in `[-1, 1]^3` (seeded), joined by `max` or by the
//! R-function union `|` in a balanced tree, as a formula tape. The balls' radii shrink as
//! `N^(-1/3)`, so every scene fills about the same share of the domain and the image
//! shows about as much surface: what grows with `N` is the model, not the picture.
//! Each configuration is rendered alternately with specialisation on and off, the
//! median time of the rounds reported with range evaluations (rays and cells), the mean
//! tape length per evaluation, hits and unconfirmed hits, and the pixels whose hit
//! differs between on and off (must be 0). The Appendix A R-function models, as their
//! formula tapes, follow.

use model_ir::arith::ArithKind;
use model_ir::shape::Aabb;
use model_sources::noise::SplitMix64;
use model_sources::{Model, PaperModel};
use std::fmt::Write as _;
use std::time::{Duration, Instant};
use tracer::render::{render_kind, RenderOptions, RenderResult};

/// What to run.
#[derive(Clone, Debug)]
pub struct Options {
    /// Numbers of balls.
    pub sizes: Vec<usize>,
    /// Image side in pixels.
    pub pixels: u32,
    /// How the balls are joined (each join runs every size).
    pub joins: Vec<Join>,
    /// Image side for the paper models (0: leave them out).
    pub paper_pixels: u32,
    /// The arithmetic.
    pub kind: ArithKind,
    /// Interleaved rounds; the median is reported.
    pub rounds: usize,
    /// Stop a render after this long (reported as cut).
    pub budget: Duration,
    /// Seed of the scenes.
    pub seed: u64,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            sizes: vec![10, 100, 1000, 10000],
            pixels: 1024,
            joins: vec![Join::Max, Join::RUnion],
            paper_pixels: 320,
            kind: ArithKind::Revaa,
            rounds: 3,
            budget: Duration::from_secs(300),
            seed: 16,
        }
    }
}

/// How the balls are joined.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Join {
    /// `max(a, b)`: exact union.
    Max,
    /// The R-function union `a | b`.
    RUnion,
}

impl Join {
    /// Its name in `--joins` and in file names.
    pub fn name(self) -> &'static str {
        match self {
            Join::Max => "max",
            Join::RUnion => "union",
        }
    }
}

/// The formula of `n` balls joined by `join` (see the module doc).
pub fn scene(n: usize, join: Join, seed: u64) -> String {
    let mut rng = SplitMix64(seed);
    let r0 = 0.3 * (10.0 / n.max(1) as f64).cbrt();
    let terms: Vec<String> = (0..n.max(1))
        .map(|_| {
            let c: [f64; 3] = core::array::from_fn(|_| rng.range(-0.85, 0.85));
            let r = r0 * rng.range(0.6, 1.0);
            format!(
                "{:.6} - (x - {:.5})^2 - (y - {:.5})^2 - (z - {:.5})^2",
                r * r,
                c[0],
                c[1],
                c[2]
            )
        })
        .collect();
    fn tree(t: &[String], join: Join) -> String {
        if t.len() == 1 {
            return format!("({})", t[0]);
        }
        let (a, b) = t.split_at(t.len() / 2);
        match join {
            Join::Max => format!("max({}, {})", tree(a, join), tree(b, join)),
            Join::RUnion => format!("({} | {})", tree(a, join), tree(b, join)),
        }
    }
    tree(&terms, join)
}

/// [`scene`] as a formula file (`.expr`) that renders as the study does, its domain
/// in the header.
pub fn scene_file(n: usize, join: Join, seed: u64) -> String {
    format!(
        "# {n} balls joined by {}, seed {seed} (bench-suite scenes)\n# domain: -1,-1,-1,1,1,1\n{}\n",
        join.name(),
        scene(n, join, seed)
    )
}

/// One configuration's medians.
#[derive(Clone, Debug)]
pub struct Point {
    /// Scene or model name.
    pub name: String,
    /// Instructions of the whole tape.
    pub tape_len: usize,
    /// Median wall times, off and on.
    pub secs: [f64; 2],
    /// Whether a render was cut by the budget, off and on.
    pub cut: [bool; 2],
    /// Range evaluations (rays and cells), off and on.
    pub evals: [u64; 2],
    /// Mean tape length per range evaluation, off and on.
    pub mean_len: [f64; 2],
    /// Hit pixels and unconfirmed hits (with specialisation).
    pub hits: u64,
    /// Unconfirmed hits, off and on.
    pub unconfirmed: [u64; 2],
    /// Pixels whose hit differs between off and on (0 expected; counted only when
    /// neither render was cut, "n/a" in the table otherwise).
    pub differ: usize,
}

fn measure_model(name: &str, model: &Model, side: u32, o: &Options) -> Result<Point, String> {
    let model_sources::AnyShape::Expr(tape) = &model.shape else {
        return Err(format!("{name}: not a tape"));
    };
    let mut times = [Vec::new(), Vec::new()];
    let mut last: [Option<RenderResult>; 2] = [None, None];
    for round in 0..o.rounds.max(1) {
        // Alternate which goes first; a configuration cut by the budget is not run again.
        let order = if round % 2 == 0 { [0, 1] } else { [1, 0] };
        for on in order {
            if last[on].as_ref().is_some_and(|r| r.stats.cut) {
                continue;
            }
            let mut r = RenderOptions::for_view(model.view, model.domain, side, side);
            r.specialise = on == 1;
            r.deadline = Some(Instant::now() + o.budget);
            let res = render_kind(o.kind, &model.shape, &r)?;
            times[on].push(res.stats.wall.as_secs_f64());
            last[on] = Some(res);
        }
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let [Some(off), Some(on)] = last else {
        return Err(format!("{name}: no render"));
    };
    let differ = if off.stats.cut || on.stats.cut {
        0
    } else {
        off.hit.iter().zip(&on.hit).filter(|(a, b)| a != b).count()
    };
    let ev = |r: &RenderResult| r.stats.range_evals + r.stats.cell_evals + r.stats.shade_evals;
    Ok(Point {
        name: name.to_string(),
        tape_len: tape.len(),
        secs: [median(&mut times[0]), median(&mut times[1])],
        cut: [off.stats.cut, on.stats.cut],
        evals: [ev(&off), ev(&on)],
        mean_len: [off.stats.mean_tape_len(), on.stats.mean_tape_len()],
        hits: on.stats.hits,
        unconfirmed: [off.stats.unconfirmed, on.stats.unconfirmed],
        differ,
    })
}

/// Runs the scenes (both joins) and the paper's R-function models; `progress` is told
/// each finished point.
pub fn run(o: &Options, mut progress: impl FnMut(&Point)) -> Result<Vec<Point>, String> {
    let domain = Aabb::cube(1.0);
    let mut pts = Vec::new();
    for &join in &o.joins {
        for &n in &o.sizes {
            let text = scene(n, join, o.seed);
            let model = Model::formula(&text, Some(domain))?;
            let tag = match join {
                Join::Max => "max",
                Join::RUnion => "union",
            };
            let p = measure_model(&format!("{n} balls, {tag}"), &model, o.pixels, o)?;
            progress(&p);
            pts.push(p);
        }
    }
    let paper = if o.paper_pixels == 0 {
        &[][..]
    } else {
        &[
            PaperModel::Csg,
            PaperModel::CsgBlendingPrinted,
            PaperModel::Hair,
            PaperModel::SphereMicrostructure,
            PaperModel::Shikki,
        ][..]
    };
    for &m in paper {
        let base = m.model();
        // A model with a formula is rendered from it; Virtual Shikki is a tape already.
        let model = match m.formula() {
            Some(text) => {
                let mut model = Model::formula(text, Some(base.domain))?;
                model.view = base.view;
                model
            }
            None if matches!(base.shape, model_sources::AnyShape::Expr(_)) => base,
            None => continue,
        };
        let p = measure_model(m.name(), &model, o.paper_pixels, o)?;
        progress(&p);
        pts.push(p);
    }
    Ok(pts)
}

/// The table as markdown.
pub fn markdown(o: &Options, pts: &[Point]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Scenes at {0}x{0}, paper models at {1}x{1}, {2}, median of {3} alternating rounds \
         (budget {4:.0} s per render; `>` marks a render cut by it).\n",
        o.pixels,
        o.paper_pixels,
        o.kind,
        o.rounds,
        o.budget.as_secs_f64()
    );
    s.push_str(
        "| model | tape | time off (s) | time on (s) | off/on | evals off | evals on | \
         mean tape off | mean tape on | hits | unconfirmed off/on | hits differ |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for p in pts {
        let t = |k: usize| format!("{}{:.3}", if p.cut[k] { ">" } else { "" }, p.secs[k]);
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {}{:.2} | {} | {} | {:.1} | {:.1} | {} | {}/{} | {} |",
            p.name,
            p.tape_len,
            t(0),
            t(1),
            if p.cut[0] { ">" } else { "" },
            p.secs[0] / p.secs[1].max(1e-9),
            p.evals[0],
            p.evals[1],
            p.mean_len[0],
            p.mean_len[1],
            p.hits,
            p.unconfirmed[0],
            p.unconfirmed[1],
            if p.cut[0] || p.cut[1] {
                "n/a".to_string()
            } else {
                p.differ.to_string()
            }
        );
    }
    s
}
