//! `bench-suite kernel`: the cost of one tape instruction per lane of batched
//! evaluation ([`Tape::eval_batch_on`]), by arithmetic and lane path, on fidget's bear
//! and colonnade tapes, as one JSON object.
//!
//! Points, intervals, forward-mode gradients (a value and three partials per point,
//! [`Tape::eval_gradient_batch_on`]) and RevAA (four-ray packs) run the lane kernels,
//! once on each path this processor has (`avx512`, `avx2`, `emulated`); RAA* and Hull
//! (four-ray SIMD packs) run the generic batch loop, which has no lane path
//! (`generic`). Within a round every configuration runs, in turn, for `millis`
//! milliseconds, one batch per call, and keeps its fastest call: on a machine shared
//! with other work the fastest call is the one least disturbed by it, where a mean
//! over the round measures the load as much as the code. Each figure is the median over
//! `rounds` rounds of those fastest calls.

use arith_core::lanes::Path;
use arith_core::pack::{Pack, LANES};
use arith_core::{Arithmetic, Range};
use arith_hull::HullArith;
use arith_ia::Interval;
use arith_raa::RaaArith;
use arith_revaa::RevAaArith;
use model_ir::Tape;
use std::fmt::Write as _;
use std::hint::black_box;
use std::path::{Path as FsPath, PathBuf};
use std::time::{Duration, Instant};

/// What to measure.
#[derive(Clone, Debug)]
pub struct Options {
    /// Models: a name and its `.vm` file.
    pub models: Vec<(String, PathBuf)>,
    /// Lanes per batch.
    pub batches: Vec<usize>,
    /// Time per configuration and round.
    pub millis: u64,
    /// Rounds; the median is reported.
    pub rounds: usize,
    /// The arithmetics measured, among [`ARITHS`].
    pub ariths: Vec<String>,
}

/// The arithmetics measured, in the order the JSON lists them.
pub const ARITHS: [&str; 6] = ["point", "ia", "revaa", "raa", "hull", "gradient"];

impl Options {
    /// The bear and the colonnade from `models_dir`, batches of 64 and 512 lanes.
    pub fn new(models_dir: &FsPath) -> Options {
        let models = ["bear", "colonnade"]
            .map(|m| (m.to_string(), models_dir.join(format!("{m}.vm"))))
            .to_vec();
        Options {
            models,
            batches: vec![64, 512],
            millis: 100,
            rounds: 3,
            ariths: ARITHS.map(String::from).to_vec(),
        }
    }
}

/// The default folder of fidget's models in this repository.
pub fn default_models_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/peers/fidget/models"))
}

/// Short segments of rays from a ring of eyes through the middle of the model's box
/// (as the ray search evaluates them): origin, direction, `t0`, `t1`.
fn segments(n: usize) -> Vec<([f64; 3], [f64; 3], f64, f64)> {
    (0..n)
        .map(|k| {
            let a = k as f64 * 0.37;
            let o = [2.0 * a.cos(), 0.3 * a.sin(), 2.0 * a.sin()];
            let r = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
            let d = o.map(|c| -c / r);
            let t0 = 1.4 + 0.01 * (k % 7) as f64;
            (o, d, t0, t0 + 0.02)
        })
        .collect()
}

/// The inputs `t d + o` of a segment in `R` (one input symbol, `t`).
fn ray<R: Range>((o, d, t0, t1): ([f64; 3], [f64; 3], f64, f64)) -> [R; 3] {
    let t = R::input(0, t0, t1);
    core::array::from_fn(|i| t.clone() * d[i] + o[i])
}

fn columns<R: Clone>(v: &[[R; 3]]) -> [Vec<R>; 3] {
    core::array::from_fn(|i| v.iter().map(|x| x[i].clone()).collect())
}

/// One timed configuration: its labels and the evaluation it repeats.
struct Case<'a> {
    model: usize,
    lanes: usize,
    arith: &'static str,
    path: &'static str,
    run: Box<dyn FnMut() + 'a>,
    samples: Vec<f64>,
}

/// A batch of `n` ray segments of arithmetic `A` as four-ray packs.
fn packs<A: Arithmetic>(n: usize) -> [Vec<A::RayPack>; 3] {
    let rays: Vec<[A::Ray; 3]> = segments(n).into_iter().map(ray).collect();
    core::array::from_fn(|i| {
        rays.chunks(LANES)
            .map(|c| A::RayPack::pack(core::array::from_fn(|l| c[l][i].clone())))
            .collect()
    })
}

/// Packs of arithmetic `A` on `path` (`None`: the generic loop, which has no path).
fn pack_case<'a, A: Arithmetic>(
    t: &'a Tape,
    model: usize,
    lanes: usize,
    path: Option<Path>,
) -> Case<'a> {
    let p = packs::<A>(lanes);
    let mut out = Vec::new();
    Case {
        model,
        lanes,
        arith: A::NAME,
        path: path.map_or("generic", Path::name),
        run: Box::new(move || {
            t.eval_batch_on(
                path.unwrap_or_else(Path::current),
                &p[0],
                &p[1],
                &p[2],
                &mut out,
            );
            black_box(&out);
        }),
        samples: Vec::new(),
    }
}

/// Every configuration of one model and batch size.
fn cases(t: &Tape, model: usize, lanes: usize) -> Vec<Case<'_>> {
    let segs = segments(lanes);
    let mut v = Vec::new();
    for path in Path::available_paths() {
        let pts: Vec<[f64; 3]> = segs
            .iter()
            .map(|&(o, d, t0, t1)| {
                let m = 0.5 * (t0 + t1);
                core::array::from_fn(|i| o[i] + m * d[i])
            })
            .collect();
        let [x, y, z] = columns(&pts);
        let [px, py, pz] = [x.clone(), y.clone(), z.clone()];
        let mut out = Vec::new();
        v.push(Case {
            model,
            lanes,
            arith: "point",
            path: path.name(),
            run: Box::new(move || {
                t.eval_batch_on(path, &px, &py, &pz, &mut out);
                black_box(&out);
            }),
            samples: Vec::new(),
        });
        let mut out = Vec::new();
        v.push(Case {
            model,
            lanes,
            arith: "gradient",
            path: path.name(),
            run: Box::new(move || {
                t.eval_gradient_batch_on(path, &x, &y, &z, &mut out);
                black_box(&out);
            }),
            samples: Vec::new(),
        });
        v.push(pack_case::<RevAaArith>(t, model, lanes, Some(path)));
        let ia: Vec<[Interval; 3]> = segs.iter().map(|&s| ray(s)).collect();
        let [x, y, z] = columns(&ia);
        let mut out = Vec::new();
        v.push(Case {
            model,
            lanes,
            arith: "ia",
            path: path.name(),
            run: Box::new(move || {
                t.eval_batch_on(path, &x, &y, &z, &mut out);
                black_box(&out);
            }),
            samples: Vec::new(),
        });
    }
    v.push(pack_case::<RaaArith>(t, model, lanes, None));
    v.push(pack_case::<HullArith>(t, model, lanes, None));
    v
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The processor's model name (`/proc/cpuinfo`), where it can be read.
fn cpu_name() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// Runs the measurements; returns the JSON object.
pub fn run(o: &Options) -> Result<String, String> {
    if o.rounds == 0 || o.millis == 0 || o.batches.is_empty() {
        return Err("--rounds, --millis and --batches must be positive".into());
    }
    if let Some(b) = o.batches.iter().find(|&&b| b == 0 || b % LANES != 0) {
        return Err(format!(
            "--batches: {b} is not a positive multiple of {LANES}"
        ));
    }
    if let Some(a) = o.ariths.iter().find(|a| !ARITHS.contains(&a.as_str())) {
        return Err(format!(
            "--arith: '{a}' is not one of {}",
            ARITHS.join(", ")
        ));
    }
    let mut tapes = Vec::new();
    for (name, path) in &o.models {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("model {name}: cannot read {}: {e}", path.display()))?;
        let t = model_sources::vm::parse(&text)
            .map_err(|e| format!("model {name} ({}): {e}", path.display()))?;
        tapes.push(t);
    }
    let mut all: Vec<Case> = Vec::new();
    for (m, t) in tapes.iter().enumerate() {
        for &lanes in &o.batches {
            all.extend(
                cases(t, m, lanes)
                    .into_iter()
                    .filter(|c| o.ariths.iter().any(|a| a == c.arith)),
            );
        }
    }
    let budget = Duration::from_millis(o.millis);
    for _ in 0..o.rounds {
        for c in &mut all {
            (c.run)();
            let start = Instant::now();
            let mut best = f64::INFINITY;
            while start.elapsed() < budget {
                let call = Instant::now();
                (c.run)();
                best = best.min(call.elapsed().as_nanos() as f64);
            }
            let work = (tapes[c.model].len() * c.lanes) as f64;
            c.samples.push(best / work);
        }
    }
    Ok(json(o, &tapes, &mut all))
}

fn json(o: &Options, tapes: &[Tape], all: &mut [Case]) -> String {
    let mut s = String::new();
    let paths: Vec<String> = Path::available_paths()
        .iter()
        .map(|p| format!("\"{p}\""))
        .collect();
    let missing: Vec<String> = Path::ALL
        .iter()
        .filter(|p| !p.available())
        .map(|p| format!("\"{p}\""))
        .collect();
    let _ = write!(
        s,
        "{{\"unit\": \"ns per instruction per lane\", \"statistic\": \"median over rounds of each \
         round's fastest batch\", \"cpu\": \"{}\", \"default_path\": \"{}\", \
         \"paths\": [{}], \"paths_not_run\": [{}], \"rounds\": {}, \"millis\": {}, \"models\": [",
        cpu_name().replace('"', "'"),
        Path::current(),
        paths.join(", "),
        missing.join(", "),
        o.rounds,
        o.millis
    );
    for (m, (name, _)) in o.models.iter().enumerate() {
        if m > 0 {
            s.push_str(", ");
        }
        let _ = write!(
            s,
            "{{\"name\": \"{name}\", \"instructions\": {}, \"batches\": [",
            tapes[m].len()
        );
        for (b, &lanes) in o.batches.iter().enumerate() {
            if b > 0 {
                s.push_str(", ");
            }
            let _ = write!(s, "{{\"lanes\": {lanes}");
            for arith in ARITHS {
                let mut entries = Vec::new();
                for c in all.iter_mut() {
                    if c.model == m && c.lanes == lanes && c.arith == arith {
                        entries.push(format!("\"{}\": {:.3}", c.path, median(&mut c.samples)));
                    }
                }
                let _ = write!(s, ", \"{arith}\": {{{}}}", entries.join(", "));
            }
            s.push('}');
        }
        s.push_str("]}");
    }
    s.push_str("]}");
    s
}
