//! The previewer benchmark (Gamito and Maddock 2007, Table 1 and Fig. 9): wall time and
//! evaluation counts of the previewer in each bound mode and of the whole-image ray
//! casters on each model, the rows `bench-suite` tabulates against the paper's numbers.
//! Times are measured in rounds, every method once per round in turn, so that a slow
//! spell of the machine hits every method alike; a row keeps its median.

use model_ir::arith::ArithKind;
use model_sources::Model;
use std::time::Instant;
use tracer::progressive::{raycast, Bound, Caster, Engine, Options, Step};
use tracer::search::lipschitz::DEFAULT_OVERSHOOT;

/// One row of the previewer benchmark (the paper's Table 1 and Fig. 9).
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    /// The model's name.
    pub model: String,
    /// The method: see [`bench_methods`].
    pub method: String,
    /// Wall time to the final image, seconds (the median over the rounds).
    pub seconds: f64,
    /// Point evaluations of `f` (tracing only; normals excluded, as for the ray casters).
    pub evals: u64,
    /// Range evaluations (`Dual<Interval>` for local Lipschitz bounds, the arithmetic's
    /// forms for the range test and Algorithm 1).
    pub range_evals: u64,
    /// Previewer only: wall time until every pixel was painted once (first full frame).
    pub first_frame_s: Option<f64>,
    /// Previewer only: samples processed.
    pub iterations: Option<u64>,
}

/// A method of the benchmark.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// The previewer with this bound mode.
    Previewer(Bound),
    /// A conventional whole-image ray caster.
    Caster(Caster),
}

/// The previewer's method name for a bound mode: `previewer` (the paper's global bound),
/// `previewer-local`, `previewer-range-<arith>`.
pub fn previewer_method(b: Bound) -> String {
    match b {
        Bound::Lipschitz => "previewer".into(),
        Bound::Local => "previewer-local".into(),
        Bound::Range(k) => format!("previewer-range-{k}"),
        Bound::Auto => "previewer-auto".into(),
    }
}

/// Every method, in display order: the previewer with the global bound, local bounds,
/// their automatic choice and the range test in each arithmetic of the one list; then the overshooting,
/// standard and local ray casters.
pub fn bench_methods() -> Vec<(String, Method)> {
    let mut v = vec![Bound::Lipschitz, Bound::Local, Bound::Auto];
    v.extend(ArithKind::ALL.map(Bound::Range));
    let mut out: Vec<(String, Method)> = v
        .into_iter()
        .map(|b| (previewer_method(b), Method::Previewer(b)))
        .collect();
    out.push((
        "overshoot-rc".into(),
        Method::Caster(Caster::Overshoot(DEFAULT_OVERSHOOT)),
    ));
    out.push(("standard-rc".into(), Method::Caster(Caster::Standard)));
    out.push((
        "local-rc".into(),
        Method::Caster(Caster::Local(DEFAULT_OVERSHOOT)),
    ));
    out
}

/// One run of `method` on `m`.
fn run_once(m: &Model, method: Method, w: u32, h: u32, lambda: f64) -> Result<BenchRow, String> {
    let start = Instant::now();
    match method {
        Method::Previewer(bound) => {
            let mut opts = Options::new(lambda);
            opts.bound = bound;
            let mut e = Engine::new(m.clone(), m.domain, m.view, w, h, opts)?;
            let mut first = None;
            while e.step() != Step::Done {
                if first.is_none() && e.fully_painted() {
                    first = Some(start.elapsed().as_secs_f64());
                }
            }
            let s = e.stats();
            Ok(BenchRow {
                model: m.name.clone(),
                method: previewer_method(bound),
                seconds: start.elapsed().as_secs_f64(),
                evals: s.evals,
                range_evals: s.range_evals,
                first_frame_s: first,
                iterations: Some(s.iterations),
            })
        }
        Method::Caster(caster) => {
            let eps = Options::new(lambda).eps;
            let (_, c) = raycast(m, m.domain, m.view, w, h, lambda, eps, caster)?;
            Ok(BenchRow {
                model: m.name.clone(),
                method: String::new(),
                seconds: start.elapsed().as_secs_f64(),
                evals: c.evals,
                range_evals: c.range_evals,
                first_frame_s: None,
                iterations: None,
            })
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Times every method of [`bench_methods`] (or those `keep` accepts) on each model at
/// `width x height`, with each model's own bound and precision `1e-4`, `rounds` times
/// in turn. The ray casters shade nothing; the previewer's times include its shading of
/// every sample (its extra cost, as in the paper).
pub fn bench_rounds(
    models: &[Model],
    width: u32,
    height: u32,
    rounds: u32,
    keep: &dyn Fn(&str) -> bool,
) -> Result<Vec<BenchRow>, String> {
    let methods: Vec<(String, Method)> = bench_methods()
        .into_iter()
        .filter(|(n, _)| keep(n))
        .collect();
    let mut rows = Vec::new();
    for m in models {
        let lambda = m
            .lipschitz
            .ok_or_else(|| format!("model '{}' has no Lipschitz bound", m.name))?;
        let mut first: Vec<Option<BenchRow>> = vec![None; methods.len()];
        let mut times = vec![Vec::new(); methods.len()];
        let mut frames = vec![Vec::new(); methods.len()];
        for _ in 0..rounds.max(1) {
            for (k, (name, method)) in methods.iter().enumerate() {
                let mut r = run_once(m, *method, width, height, lambda)?;
                r.method = name.clone();
                times[k].push(r.seconds);
                if let Some(f) = r.first_frame_s {
                    frames[k].push(f);
                }
                first[k].get_or_insert(r);
            }
        }
        for (k, r) in first.into_iter().enumerate() {
            let mut r = r.expect("one round at least");
            r.seconds = median(&mut times[k]);
            if !frames[k].is_empty() {
                r.first_frame_s = Some(median(&mut frames[k]));
            }
            rows.push(r);
        }
    }
    Ok(rows)
}

/// [`bench_rounds`] with one round of every method.
pub fn bench_table(models: &[Model], width: u32, height: u32) -> Result<Vec<BenchRow>, String> {
    bench_rounds(models, width, height, 1, &|_| true)
}
