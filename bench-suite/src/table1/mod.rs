//! `bench-suite table1`: the paper's Table 1 regenerated from the tracer.
//!
//! For each Appendix A model (paper order), each arithmetic renders the model's default
//! view; the arithmetics are interleaved per model and the whole round is repeated, so
//! slow drift (thermal, other load) hits all of them alike; the median wall time is
//! reported. A render that runs past the per-cell budget is stopped (the tracer stops
//! its rays within a moment) and shown as `> N s`; it is not repeated.
//!
//! Like the paper's CPU renderer, primary rays only, no shadows, argument pruning on and
//! cell culling off (the paper: "we do not use cell culling in the CPU renderer");
//! `--culling` turns it on.
//!
//! With [`Options::cancel`] set (Ctrl-C in the CLI), the run stops between renders (a
//! render in flight stops within a moment and is discarded), marks the cells it
//! did not measure as interrupted, and still writes the tables with what it measured.

mod masks;
mod report;

pub use masks::ray_changes_sign;
pub use report::{csv, markdown, utc_now};

use crate::counter::{count_ops, Counter, OpCounts};
use crate::paper::{self, PaperRow};
use model_ir::arith::ArithKind;
use model_ir::shape::Shape;
use model_sources::PaperModel;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use tracer::render::{render_kind, RenderOptions, RenderResult, Search};

/// Default fraction of the paper's resolution per axis.
pub const DEFAULT_SCALE: f64 = 0.1;
/// Default per-cell budget in seconds (without `--full`).
pub const DEFAULT_BUDGET: f64 = 10.0;
/// Default per-cell budget in seconds with `--full`.
pub const DEFAULT_BUDGET_FULL: f64 = 600.0;

/// What to run.
#[derive(Clone, Debug)]
pub struct Options {
    /// The paper's resolutions (ignores `scale`).
    pub full: bool,
    /// Fraction of the paper's resolution per axis.
    pub scale: f64,
    /// Models to run (tracer names), in the paper's order whatever the order given.
    pub models: Vec<PaperModel>,
    /// Arithmetics to run, in table order.
    pub kinds: Vec<ArithKind>,
    /// Per-cell budget.
    pub budget: Duration,
    /// Rounds of interleaved renders; the median is reported.
    pub repeats: usize,
    /// Cell culling (Algorithm 2); the paper's CPU timings have none.
    pub culling: bool,
    /// Output directory.
    pub out: PathBuf,
    /// Print progress to stderr.
    pub verbose: bool,
    /// Once set, stop measuring and write what was measured (see the module docs).
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Options {
    /// The defaults, writing into the folder `out`.
    pub fn new(out: impl Into<PathBuf>) -> Options {
        Options {
            full: false,
            scale: DEFAULT_SCALE,
            models: PaperModel::ALL.to_vec(),
            kinds: ArithKind::ALL.to_vec(),
            budget: Duration::from_secs_f64(DEFAULT_BUDGET),
            repeats: 3,
            culling: false,
            out: out.into(),
            verbose: false,
            cancel: None,
        }
    }

    /// Checks user-given values; the message says what is wrong.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.scale > 0.0 && self.scale <= 16.0) {
            return Err(format!("--scale {} must be in (0, 16]", self.scale));
        }
        if self.models.is_empty() {
            return Err("no models selected".into());
        }
        if self.kinds.is_empty() {
            return Err("no arithmetics selected".into());
        }
        if self.budget.is_zero() {
            return Err("--budget must be positive".into());
        }
        if self.repeats == 0 {
            return Err("--repeats must be at least 1".into());
        }
        Ok(())
    }
}

/// Parses a comma-separated model list (tracer names of Appendix A models).
pub fn parse_models(s: &str) -> Result<Vec<PaperModel>, String> {
    let mut out = Vec::new();
    for name in s.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        let m = PaperModel::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(name))
            .ok_or_else(|| {
                let names: Vec<_> = PaperModel::ALL.iter().map(|m| m.name()).collect();
                format!(
                    "unknown model '{name}' (expected one of: {})",
                    names.join(", ")
                )
            })?;
        if !out.contains(&m) {
            out.push(m);
        }
    }
    // The paper's order, whatever order was given.
    out.sort_by_key(|m| PaperModel::ALL.iter().position(|p| p == m));
    Ok(out)
}

/// Parses a comma-separated arithmetic list.
pub fn parse_kinds(s: &str) -> Result<Vec<ArithKind>, String> {
    let mut out = Vec::new();
    for name in s.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        let k: ArithKind = name.parse()?;
        if !out.contains(&k) {
            out.push(k);
        }
    }
    out.sort();
    Ok(out)
}

/// One arithmetic on one model.
#[derive(Clone, Debug)]
pub struct Cell {
    /// The arithmetic.
    pub kind: ArithKind,
    /// Wall time of every completed run, seconds.
    pub runs: Vec<f64>,
    /// CPU seconds (user + system, all threads) of every completed run, where the OS
    /// tells (Linux); robust to other load on a shared machine, unlike wall time.
    pub cpu_runs: Vec<f64>,
    /// Median of `runs` (or the time when stopped).
    pub seconds: f64,
    /// Stopped by the budget: `seconds` is a lower bound.
    pub stopped: bool,
    /// Range evaluations along rays and on culling cells, of one render.
    pub ray_evals: u64,
    /// Range evaluations on cells.
    pub cell_evals: u64,
    /// Pixels that hit the surface.
    pub hits: u64,
    /// Pixels rendered.
    pub pixels: u64,
    /// Pixels whose hit flag differs from the reference arithmetic's.
    pub mask_diff: Option<usize>,
    /// Among pixels where the arithmetics disagree: this one reports a miss although
    /// `f64` samples along the ray change sign (a certain root). A soundness failure.
    pub missed_roots: usize,
    /// Among pixels where the arithmetics disagree: this one reports a (possible) root
    /// that no sign change along the ray confirms, while another arithmetic proved the
    /// ray root-free: a range still holding 0 at the root precision (overestimation).
    pub unconfirmed_hits: usize,
    /// The run was interrupted before this cell had all its runs: `runs` holds those
    /// that completed (none: not measured).
    pub interrupted: bool,
}

impl Cell {
    /// Whether there is a time to show: completed runs, or a stop by the budget.
    pub fn measured(&self) -> bool {
        self.stopped || !self.runs.is_empty()
    }
    /// Whether more than 1% of the pixels are unconfirmed hits (see [`Cell::unconfirmed_hits`]).
    pub fn spurious(&self) -> bool {
        self.unconfirmed_hits as f64 > 0.01 * self.pixels as f64
    }
    /// Range evaluations (rays and cells) per pixel.
    pub fn evals_per_pixel(&self) -> f64 {
        (self.ray_evals + self.cell_evals) as f64 / self.pixels.max(1) as f64
    }
}

/// One model.
#[derive(Clone, Debug)]
pub struct Row {
    /// The model.
    pub model: PaperModel,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Operation counts of the model's function.
    pub ops: OpCounts,
    /// The paper's row, where it has one.
    pub paper: Option<&'static PaperRow>,
    /// One cell per arithmetic run.
    pub cells: Vec<Cell>,
    /// The arithmetic whose hit mask the others are compared with.
    pub reference: Option<ArithKind>,
}

impl Row {
    /// The cell of arithmetic `k`, if it was run.
    pub fn cell(&self, k: ArithKind) -> Option<&Cell> {
        self.cells.iter().find(|c| c.kind == k)
    }
    /// Time ratio to RevAA measured in this run (`None` if either is missing or RevAA
    /// was stopped).
    pub fn ratio_to_revaa(&self, k: ArithKind) -> Option<f64> {
        let r = self.cell(ArithKind::Revaa)?;
        let c = self.cell(k)?;
        (!r.stopped && r.measured() && c.measured() && r.seconds > 0.0)
            .then(|| c.seconds / r.seconds)
    }
    /// Our speed-up over the paper for arithmetic `k`: the paper's seconds divided by ours
    /// scaled linearly in pixel count to the paper's resolution.
    pub fn speedup(&self, k: ArithKind) -> Option<f64> {
        let c = self.cell(k)?;
        if !c.measured() {
            return None;
        }
        self.speedup_of(k, c.seconds)
    }
    /// [`Row::speedup`] with our CPU seconds (all threads) instead of wall seconds: the
    /// paper's Pentium 4 ran one thread, and CPU time is not inflated by other load.
    pub fn speedup_cpu(&self, k: ArithKind) -> Option<f64> {
        let c = self.cell(k)?;
        if c.stopped || c.cpu_runs.is_empty() {
            return None;
        }
        self.speedup_of(k, median(&c.cpu_runs))
    }
    fn speedup_of(&self, k: ArithKind, ours: f64) -> Option<f64> {
        let p = self.paper?;
        let ps = p.seconds_of(k)?;
        let ours_at_paper_res =
            ours * (p.width as f64 * p.height as f64) / (self.width as f64 * self.height as f64);
        (ours_at_paper_res > 0.0).then(|| ps / ours_at_paper_res)
    }
}

/// Everything one `table1` run measured.
#[derive(Clone, Debug)]
pub struct Report {
    /// The rows, in the paper's order.
    pub rows: Vec<Row>,
    /// The arithmetics run, in table order.
    pub kinds: Vec<ArithKind>,
    /// The options it ran with.
    pub opts: Options,
    /// Wall time of the whole run.
    pub total: Duration,
    /// Stopped by [`Options::cancel`]: some cells are not (fully) measured.
    pub interrupted: bool,
}

impl Report {
    /// Every (model, arithmetic, rays) where an arithmetic missed a certain root.
    pub fn missed_roots(&self) -> Vec<(PaperModel, ArithKind, usize)> {
        let mut v = Vec::new();
        for r in &self.rows {
            for c in &r.cells {
                if c.missed_roots > 0 {
                    v.push((r.model, c.kind, c.missed_roots));
                }
            }
        }
        v
    }

    /// Every (model, arithmetic, pixels differing) hit-mask disagreement.
    pub fn disagreements(&self) -> Vec<(PaperModel, ArithKind, ArithKind, usize)> {
        let mut v = Vec::new();
        for r in &self.rows {
            for c in &r.cells {
                if let (Some(n), Some(rk)) = (c.mask_diff, r.reference) {
                    if n > 0 {
                        v.push((r.model, c.kind, rk, n));
                    }
                }
            }
        }
        v
    }
}

/// The counts of one evaluation of `m` over [`Counter`]s.
pub fn op_counts(m: PaperModel) -> OpCounts {
    count_ops(|| m.eval(Counter(0.3), Counter(0.2), Counter(0.1))).1
}

/// User plus system CPU time of this process, all threads, from `/proc/self/stat`
/// (Linux; clock ticks taken as 100 per second, the kernel's `USER_HZ` on every mainstream
/// architecture). `None` elsewhere.
pub fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name in parentheses start at field 3 (state).
    let rest = &stat[stat.rfind(')')? + 1..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = f.get(11)?.parse().ok()?;
    let stime: f64 = f.get(12)?.parse().ok()?;
    Some((utime + stime) / 100.0)
}

/// The median of `v` (the mean of the middle two for an even count; NaN when empty).
pub fn median(v: &[f64]) -> f64 {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    }
}

/// The resolution a model is rendered at.
pub fn resolution(m: PaperModel, full: bool, scale: f64) -> (u32, u32) {
    let (w, h) = m.table1_size();
    if full {
        (w, h)
    } else {
        let s = |v: u32| ((v as f64 * scale).round() as u32).max(4);
        (s(w), s(h))
    }
}

/// Tile side used by every bench render (see [`render_once`]): the renderer's default,
/// so the table times what `tracer render` does (16 measured 5-10% slower with culling,
/// whose narrowing starts afresh in every tile).
pub const RENDER_TILE: u32 = 32;

/// Renders one model in one arithmetic under a budget.
pub fn render_once(
    m: PaperModel,
    kind: ArithKind,
    size: (u32, u32),
    budget: Duration,
    culling: bool,
) -> Result<RenderResult, String> {
    render_cancellable(m, kind, size, budget, culling, None)
}

/// [`render_once`] that also stops starting tiles once `cancel` is set.
pub fn render_cancellable(
    m: PaperModel,
    kind: ArithKind,
    (w, h): (u32, u32),
    budget: Duration,
    culling: bool,
    cancel: Option<Arc<AtomicBool>>,
) -> Result<RenderResult, String> {
    let model = m.model();
    let mut o = RenderOptions::new(&model, w, h);
    // The paper's search: Algorithm 1 per ray, Algorithm 2's culling where asked.
    o.search = Search::Paper;
    o.culling = culling;
    o.pruning = true;
    o.shadows = false;
    o.progress = None;
    o.deadline = Some(Instant::now() + budget);
    // Every render here uses the same tile, so culling on/off comparisons stay fair.
    o.tile = RENDER_TILE;
    o.cancel = cancel;
    // The model's shape, as `tracer render` has it (Virtual Shikki: its tape, which
    // specialises).
    render_kind(kind, &model.shape, &o)
}

/// Runs the table, writes every output file into `opts.out`, returns what it measured.
pub fn run(opts: &Options) -> Result<Report, String> {
    opts.validate()?;
    std::fs::create_dir_all(&opts.out)
        .map_err(|e| format!("cannot create '{}': {e}", opts.out.display()))?;
    let start = Instant::now();
    let cancelled = || {
        opts.cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::SeqCst))
    };
    let mut interrupted = false;
    let mut rows = Vec::new();
    for &m in &opts.models {
        let (w, h) = resolution(m, opts.full, opts.scale);
        interrupted |= cancelled();
        if opts.verbose && !interrupted {
            eprintln!("{} at {w}x{h}", m.name());
        }
        let mut cells: Vec<Cell> = opts
            .kinds
            .iter()
            .map(|&kind| Cell {
                kind,
                runs: Vec::new(),
                cpu_runs: Vec::new(),
                seconds: 0.0,
                stopped: false,
                ray_evals: 0,
                cell_evals: 0,
                hits: 0,
                pixels: w as u64 * h as u64,
                mask_diff: None,
                missed_roots: 0,
                unconfirmed_hits: 0,
                interrupted: false,
            })
            .collect();
        let mut masks: Vec<Option<Vec<bool>>> = vec![None; opts.kinds.len()];
        'rounds: for rep in 0..opts.repeats {
            // Rotate the order each round so no arithmetic always runs first.
            let n = opts.kinds.len();
            for step in 0..n {
                let k = (step + rep) % n;
                let kind = opts.kinds[k];
                if cells[k].stopped {
                    continue;
                }
                if interrupted {
                    break 'rounds;
                }
                let cpu0 = process_cpu_seconds();
                let res = render_cancellable(
                    m,
                    kind,
                    (w, h),
                    opts.budget,
                    opts.culling,
                    opts.cancel.clone(),
                )?;
                let cpu = process_cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
                if res.stats.cut && cancelled() {
                    // Cut by the interrupt, not (only) by the budget: not a measurement.
                    interrupted = true;
                    if opts.verbose {
                        eprintln!("  {:>6} interrupted", kind.label());
                    }
                    break 'rounds;
                }
                let secs = res.stats.wall.as_secs_f64();
                let c = &mut cells[k];
                if res.stats.cut {
                    c.stopped = true;
                    c.runs.clear();
                    c.cpu_runs.clear();
                    c.seconds = secs.max(opts.budget.as_secs_f64());
                } else {
                    c.runs.push(secs);
                    c.cpu_runs.extend(cpu);
                }
                if opts.verbose {
                    eprintln!(
                        "  {:>6} {:8.3} s{}",
                        kind.label(),
                        secs,
                        if res.stats.cut {
                            " (stopped by budget)"
                        } else {
                            ""
                        }
                    );
                }
                if rep == 0 {
                    c.ray_evals = res.stats.range_evals;
                    c.cell_evals = res.stats.cell_evals;
                    c.hits = res.stats.hits;
                    let path = opts.out.join(format!("{}-{}.png", m.name(), kind.name()));
                    tracer_kit::output::write_png(&path, res.width, res.height, &res.rgb)?;
                    if !res.stats.cut {
                        masks[k] = Some(res.hit);
                    }
                }
            }
        }
        for c in &mut cells {
            if interrupted && !c.stopped && c.runs.len() < opts.repeats {
                c.interrupted = true;
            }
            if !c.stopped && !c.runs.is_empty() {
                c.seconds = median(&c.runs);
            }
        }
        // Cross-check hit masks against RevAA (or the first arithmetic that finished).
        let reference = opts
            .kinds
            .iter()
            .position(|&k| k == ArithKind::Revaa)
            .filter(|&i| masks[i].is_some())
            .or_else(|| masks.iter().position(Option::is_some));
        if let Some(r) = reference {
            let rm = masks[r].clone().unwrap_or_default();
            for (k, mask) in masks.iter().enumerate() {
                if let Some(mask) = mask {
                    let diff = mask.iter().zip(&rm).filter(|(a, b)| a != b).count();
                    cells[k].mask_diff = Some(diff);
                    if diff > 0 {
                        eprintln!(
                            "!!! HIT MASK DISAGREEMENT: {} {} vs {}: {diff} of {} pixels differ",
                            m.name(),
                            opts.kinds[k].label(),
                            opts.kinds[r].label(),
                            rm.len()
                        );
                    }
                }
            }
        }
        masks::classify_disagreements(m, (w, h), &masks, &mut cells);
        for c in &cells {
            if c.missed_roots > 0 {
                eprintln!(
                    "!!! MISSED ROOTS: {} {} reports no hit on {} rays where f changes sign",
                    m.name(),
                    c.kind.label(),
                    c.missed_roots
                );
            }
        }
        rows.push(Row {
            model: m,
            width: w,
            height: h,
            ops: op_counts(m),
            paper: paper::find(m.name()),
            cells,
            reference: reference.map(|r| opts.kinds[r]),
        });
    }
    let report = Report {
        rows,
        kinds: opts.kinds.clone(),
        opts: opts.clone(),
        total: start.elapsed(),
        interrupted,
    };
    let md = markdown(&report);
    report::write(&opts.out.join("table1.md"), md.as_bytes())?;
    report::write(&opts.out.join("table1.csv"), csv(&report).as_bytes())?;
    report::draw_chart(&report, &opts.out.join("table1.png"))?;
    Ok(report)
}
