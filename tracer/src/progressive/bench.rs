//! The previewer benchmark (Gamito and Maddock 2007, Table 1 and Fig. 9): wall time and
//! evaluation counts of the previewer and of the whole-image ray casters on each model,
//! the rows `bench-suite` tabulates against the paper's numbers.

use super::{raycast, Caster, Engine, Options, Step};
use crate::models::Model;
use std::time::Instant;

/// One row of the previewer benchmark (the paper's Table 1 and Fig. 9).
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    /// The model's name.
    pub model: String,
    /// `previewer`, `previewer-local`, `overshoot-rc`, `standard-rc`, `local-rc`.
    pub method: &'static str,
    /// Wall time to the final image, seconds.
    pub seconds: f64,
    /// Point evaluations of `f` (tracing only; normals excluded, as for the ray casters).
    pub evals: u64,
    /// Range evaluations (`Dual<Interval>`) for local Lipschitz bounds.
    pub range_evals: u64,
    /// Previewer only: wall time until every pixel was painted once (first full frame).
    pub first_frame_s: Option<f64>,
    /// Previewer only: samples processed.
    pub iterations: Option<u64>,
}

/// Times the previewer (global and local Lipschitz bounds) and the overshooting,
/// standard and local ray casters on each model at `width x height`, with each model's
/// own bound and precision `1e-4`. The ray casters shade nothing; the previewer's times
/// include its shading of every sample (its extra cost, as in the paper).
pub fn bench_table(models: &[Model], width: u32, height: u32) -> Result<Vec<BenchRow>, String> {
    let mut rows = Vec::new();
    for m in models {
        let lambda = m
            .lipschitz
            .ok_or_else(|| format!("model '{}' has no Lipschitz bound", m.name))?;
        for (method, local) in [("previewer", false), ("previewer-local", true)] {
            let mut opts = Options::new(lambda);
            opts.local = local;
            let start = Instant::now();
            let mut e = Engine::new(m.clone(), m.domain, m.view, width, height, opts)?;
            let mut first = None;
            while e.step() != Step::Done {
                if first.is_none() && e.fully_painted() {
                    first = Some(start.elapsed().as_secs_f64());
                }
            }
            let s = e.stats();
            rows.push(BenchRow {
                model: m.name.clone(),
                method,
                seconds: start.elapsed().as_secs_f64(),
                evals: s.evals,
                range_evals: s.range_evals,
                first_frame_s: first,
                iterations: Some(s.iterations),
            });
        }
        let eps = Options::new(lambda).eps;
        for (method, caster) in [
            (
                "overshoot-rc",
                Caster::Overshoot(crate::search::lipschitz::DEFAULT_OVERSHOOT),
            ),
            ("standard-rc", Caster::Standard),
            (
                "local-rc",
                Caster::Local(crate::search::lipschitz::DEFAULT_OVERSHOOT),
            ),
        ] {
            let start = Instant::now();
            let (_, c) = raycast(m, m.domain, m.view, width, height, lambda, eps, caster)?;
            rows.push(BenchRow {
                model: m.name.clone(),
                method,
                seconds: start.elapsed().as_secs_f64(),
                evals: c.evals,
                range_evals: c.range_evals,
                first_frame_s: None,
                iterations: None,
            });
        }
    }
    Ok(rows)
}
