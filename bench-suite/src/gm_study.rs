//! Why our Mitchell counts differ from the progressive-refinement paper's Table 1: the
//! same three methods (previewer with the global bound, overshooting and standard
//! Lipschitz ray casters) with one set-up factor changed at a time: the Lipschitz
//! bound, the hit precision, the camera distance. The paper gives none of them for
//! Fig. 5 except the domain `[-2, 2]^3` and the size 800x800; the factor that moves all
//! three counts by the same ratio is the one that explains a uniform gap.
//!
//! A bound below the Lipschitz constant over the domain (about 867, at its corners) is
//! not guaranteed over the whole box; those rows only measure what the counts would be.

use model_sources::Model;
use std::fmt::Write as _;
use tracer::progressive::{raycast, Bound, Caster, Engine, Options};
use tracer::search::lipschitz::DEFAULT_OVERSHOOT;

/// One set-up: a label, the bound's factor, the precision and the eye's distance factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setup {
    /// What was changed.
    pub label: &'static str,
    /// Multiplies the model's Lipschitz bound.
    pub lambda_factor: f64,
    /// Hit precision.
    pub eps: f64,
    /// Multiplies the eye's distance from the point looked at.
    pub eye_factor: f64,
}

/// The set-ups: ours, then one factor at a time.
pub const SETUPS: [Setup; 7] = [
    Setup {
        label: "ours",
        lambda_factor: 1.0,
        eps: 1e-4,
        eye_factor: 1.0,
    },
    Setup {
        label: "bound / 2",
        lambda_factor: 0.5,
        eps: 1e-4,
        eye_factor: 1.0,
    },
    Setup {
        label: "bound / 2.5",
        lambda_factor: 0.4,
        eps: 1e-4,
        eye_factor: 1.0,
    },
    Setup {
        label: "bound / 4",
        lambda_factor: 0.25,
        eps: 1e-4,
        eye_factor: 1.0,
    },
    Setup {
        label: "eps 1e-3",
        lambda_factor: 1.0,
        eps: 1e-3,
        eye_factor: 1.0,
    },
    Setup {
        label: "eps 1e-2",
        lambda_factor: 1.0,
        eps: 1e-2,
        eye_factor: 1.0,
    },
    Setup {
        label: "eye 1.5x farther",
        lambda_factor: 1.0,
        eps: 1e-4,
        eye_factor: 1.5,
    },
];

/// Point evaluations of the previewer, the overshooting and the standard caster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StudyRow {
    /// The set-up.
    pub setup: Setup,
    /// The bound used.
    pub lambda: f64,
    /// Previewer (global bound), overshooting caster, standard caster.
    pub evals: [u64; 3],
}

/// Runs every set-up on `m` at `size x size`.
pub fn run(m: &Model, size: u32) -> Result<Vec<StudyRow>, String> {
    let base = m.lipschitz.ok_or("the model has no Lipschitz bound")?;
    let mut rows = Vec::new();
    for setup in SETUPS {
        let lambda = base * setup.lambda_factor;
        let mut view = m.view;
        view.eye = view.look_at + (view.eye - view.look_at) * setup.eye_factor;
        let mut opts = Options::new(lambda);
        opts.eps = setup.eps;
        opts.bound = Bound::Lipschitz;
        let mut e = Engine::new(m.clone(), m.domain, view, size, size, opts)?;
        e.run();
        let cast = |c| raycast(m, m.domain, view, size, size, lambda, setup.eps, c);
        let (_, o) = cast(Caster::Overshoot(DEFAULT_OVERSHOOT))?;
        let (_, s) = cast(Caster::Standard)?;
        rows.push(StudyRow {
            setup,
            lambda,
            evals: [e.stats().evals, o.evals, s.evals],
        });
    }
    Ok(rows)
}

/// The study as Markdown, each count over the paper's (scaled to this size by pixels).
pub fn markdown(rows: &[StudyRow], size: u32) -> String {
    let paper = [26_803_413.0, 30_701_240.0, 44_895_932.0];
    let scale = (size as f64 / 800.0).powi(2);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "## Mitchell's surface: our counts over the paper's (Table 1, Fig. 5), {size}x{size}\n\n\
         Point evaluations; `/ paper` divides by the paper's count scaled by pixels \
         ({scale:.4} of 800x800). One factor changed at a time.\n"
    );
    s.push_str("| set-up | lambda | previewer | / paper | overshoot-rc | / paper | standard-rc | / paper |\n");
    s.push_str("|---|--:|--:|--:|--:|--:|--:|--:|\n");
    for r in rows {
        let _ = write!(s, "| {} | {:.1} |", r.setup.label, r.lambda);
        for (e, p) in r.evals.iter().zip(paper) {
            let _ = write!(s, " {e} | {:.2} |", *e as f64 / (p * scale));
        }
        s.push('\n');
    }
    s
}
