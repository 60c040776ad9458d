//! `bench-suite table1`: the paper's Table 1 regenerated from the tracer.
//!
//! For each Appendix A model (paper order), each arithmetic renders the model's default
//! view; the arithmetics are interleaved per model and the whole round is repeated, so
//! slow drift (thermal, other load) hits all of them alike; the median wall time is
//! reported. A render that runs past the per-cell budget is stopped (the tracer stops
//! starting new tiles; tiles in flight finish) and shown as `> N s`; it is not repeated.
//!
//! Like the paper's CPU renderer, primary rays only, no shadows, argument pruning on and
//! cell culling off (the paper: "we do not use cell culling in the CPU renderer");
//! `--culling` turns it on.
//!
//! With [`Options::cancel`] set (Ctrl-C in the CLI), the run stops between renders (a
//! render in flight stops after its tiles in flight and is discarded), marks the cells it
//! did not measure as interrupted, and still writes the tables with what it measured.

use crate::chart::{self, Bar, Group};
use crate::counter::{count_ops, Counter, OpCounts};
use crate::paper::{self, PaperRow};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};
use tracer::arith::ArithKind;
use tracer::models::PaperModel;
use tracer::render::{render_kind, RenderOptions, RenderResult};
use tracer::shape::Shape;

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

fn median(v: &[f64]) -> f64 {
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
    o.culling = culling;
    o.pruning = true;
    o.shadows = false;
    o.progress = None;
    o.deadline = Some(Instant::now() + budget);
    // The deadline is checked between tiles, so a stopped render overshoots its budget
    // by at most a tile per thread. Every render here uses the same tile, so culling
    // on/off comparisons stay fair.
    o.tile = RENDER_TILE;
    o.cancel = cancel;
    render_kind(kind, &m, &o)
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
                    tracer::render::output::write_png(&path, res.width, res.height, &res.rgb)?;
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
        classify_disagreements(m, (w, h), &masks, &mut cells);
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
    write(&opts.out.join("table1.md"), md.as_bytes())?;
    write(&opts.out.join("table1.csv"), csv(&report).as_bytes())?;
    draw_chart(&report, &opts.out.join("table1.png"))?;
    Ok(report)
}

/// Samples per ray when checking a disputed pixel for a sign change.
const SIGN_SAMPLES: usize = 20_000;

/// Whether `f64` samples of `m` along the pixel's ray (clipped to the domain) change
/// sign: then the ray certainly has a root (the models are continuous).
pub fn ray_changes_sign(m: PaperModel, (w, h): (u32, u32), i: u32, j: u32) -> bool {
    let model = m.model();
    let cam = tracer::camera::Camera::new(model.view, w, h);
    let (o, d) = cam.ray(i, j);
    let Some((t0, t1)) = tracer::search::ray::clip(o, d, &model.domain, 0.0) else {
        return false;
    };
    let (mut pos, mut neg) = (false, false);
    for k in 0..=SIGN_SAMPLES {
        let t = t0 + (t1 - t0) * k as f64 / SIGN_SAMPLES as f64;
        let p = o + d * t;
        let v = m.eval(p.x, p.y, p.z);
        pos |= v > 0.0;
        neg |= v < 0.0;
        if pos && neg {
            return true;
        }
    }
    false
}

/// For every pixel where the finished arithmetics disagree, checks the ray for a sign
/// change and counts, per arithmetic, missed certain roots and unconfirmed hits.
fn classify_disagreements(
    m: PaperModel,
    size: (u32, u32),
    masks: &[Option<Vec<bool>>],
    cells: &mut [Cell],
) {
    let done: Vec<(usize, &Vec<bool>)> = masks
        .iter()
        .enumerate()
        .filter_map(|(k, v)| v.as_ref().map(|v| (k, v)))
        .collect();
    let Some(&(_, first)) = done.first() else {
        return;
    };
    for p in 0..first.len() {
        let hit = |k: &(usize, &Vec<bool>)| k.1[p];
        if done.iter().all(hit) || !done.iter().any(hit) {
            continue;
        }
        let (i, j) = ((p % size.0 as usize) as u32, (p / size.0 as usize) as u32);
        let root = ray_changes_sign(m, size, i, j);
        for &(k, mask) in &done {
            if root && !mask[p] {
                cells[k].missed_roots += 1;
            } else if !root && mask[p] {
                cells[k].unconfirmed_hits += 1;
            }
        }
    }
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
    std::fs::write(path, bytes).map_err(|e| format!("cannot write '{}': {e}", path.display()))
}

fn fmt_secs(c: &Cell) -> String {
    if !c.measured() {
        "interrupted".into()
    } else if c.interrupted {
        // A median of fewer runs than asked.
        format!("{} ‡", fmt_secs_value(c.seconds))
    } else if c.stopped {
        format!("> {:.0} s", c.seconds.floor().max(1.0))
    } else {
        fmt_secs_value(c.seconds)
    }
}

fn fmt_secs_value(seconds: f64) -> String {
    if seconds >= 100.0 {
        format!("{seconds:.0}")
    } else if seconds >= 1.0 {
        format!("{seconds:.2}")
    } else {
        format!("{seconds:.3}")
    }
}

fn fmt_paper_secs(p: Option<f64>) -> String {
    match p {
        Some(s) => format!("{s}"),
        None => ">50000".into(),
    }
}

/// Seconds since the Unix epoch as `YYYY-MM-DD HH:MM UTC` (no date crate needed).
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Howard Hinnant's civil-from-days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let mo = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(mo <= 2);
    format!(
        "{y:04}-{mo:02}-{d:02} {:02}:{:02} UTC",
        rem / 3600,
        rem % 3600 / 60
    )
}

/// The report as Markdown: the table, range evaluations, and the paper beside us.
pub fn markdown(r: &Report) -> String {
    let o = &r.opts;
    let mut s = String::new();
    let cores = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1);
    let _ = writeln!(s, "## Table 1: ray-tracing time per arithmetic\n");
    let _ = writeln!(
        s,
        "{} · {cores} cores · {} · budget {:.0} s per cell · median of {} interleaved runs · \
         cell culling {} · primary rays, argument pruning on · total {:.0} s\n",
        utc_now(),
        if o.full {
            "paper resolutions (--full)".to_string()
        } else {
            format!("scale {}", o.scale)
        },
        o.budget.as_secs_f64(),
        o.repeats,
        if o.culling {
            "on"
        } else {
            "off (as the paper's CPU renderer)"
        },
        r.total.as_secs_f64()
    );
    // Main table.
    let mut head = String::from("| Model | Resolution | Ops ours (All / NA / Mul) | Ops paper |");
    let mut rule = String::from("|---|---|---|---|");
    for k in &r.kinds {
        let _ = write!(head, " {} s |", k.label());
        rule.push_str("---:|");
    }
    if r.kinds.contains(&ArithKind::Revaa) {
        for k in r.kinds.iter().filter(|&&k| k != ArithKind::Revaa) {
            let _ = write!(head, " {}/RevAA |", k.label());
            rule.push_str("---:|");
        }
    }
    head.push_str(" Hit masks |");
    rule.push_str("---|");
    let _ = writeln!(s, "{head}\n{rule}");
    for row in &r.rows {
        let label = row.paper.map_or(row.model.name(), |p| p.label);
        let paper_ops = row.paper.map_or("n/a".to_string(), |p| p.ops.to_string());
        let _ = write!(
            s,
            "| {label} | {}x{} | {} | {paper_ops} |",
            row.width, row.height, row.ops
        );
        for c in &row.cells {
            let mark = if c.spurious() { " †" } else { "" };
            let _ = write!(s, " {}{mark} |", fmt_secs(c));
        }
        if r.kinds.contains(&ArithKind::Revaa) {
            for k in r.kinds.iter().filter(|&&k| k != ArithKind::Revaa) {
                match (row.ratio_to_revaa(*k), row.cell(*k)) {
                    (Some(x), Some(c)) if c.stopped => {
                        let _ = write!(s, " > {x:.2} |");
                    }
                    (Some(x), _) => {
                        let _ = write!(s, " {x:.2} |");
                    }
                    _ => s.push_str(" n/a |"),
                }
            }
        }
        let _ = writeln!(s, " {} |", mask_summary(row));
    }
    if !o.models.is_empty() && o.models.len() == PaperModel::ALL.len() {
        if let Some(p) = paper::TABLE1.iter().find(|p| p.label == "Virtual Shikki") {
            let _ = write!(s, "| {} | n/a | n/a | {} |", p.label, p.ops);
            for _ in &r.kinds {
                s.push_str(" n/a |");
            }
            if r.kinds.contains(&ArithKind::Revaa) {
                for _ in 1..r.kinds.len() {
                    s.push_str(" n/a |");
                }
            }
            let _ = writeln!(s, " source not available |");
        }
    }
    if r.interrupted {
        let _ = writeln!(
            s,
            "\n**Interrupted** (Ctrl-C) after {:.0} s: cells marked `interrupted` were not \
             measured; ‡ marks a median of fewer runs than the {} asked.",
            r.total.as_secs_f64(),
            o.repeats
        );
    }
    if r.rows
        .iter()
        .any(|row| row.cells.iter().any(Cell::spurious))
    {
        let _ = writeln!(
            s,
            "\n† More than 1% of the pixels are unconfirmed hits: this arithmetic reported a \
             possible root (a segment at the root precision whose range still holds 0) on rays \
             that another arithmetic proved root-free, and stopped there. Its image is wrong \
             there and its time is not comparable: it did less work, not better work."
        );
    }
    let wall: f64 = r
        .rows
        .iter()
        .flat_map(|row| row.cells.iter().flat_map(|c| c.runs.iter()))
        .sum();
    let cpu: f64 = r
        .rows
        .iter()
        .flat_map(|row| row.cells.iter().flat_map(|c| c.cpu_runs.iter()))
        .sum();
    if wall > 0.0 && cpu > 0.0 {
        let _ = writeln!(
            s,
            "\nCPU use during the completed renders: {:.2} cores on average of {cores} \
             (CPU seconds / wall seconds; below {cores} means the machine was shared or the work \
             did not parallelise). The CSV has each cell's median CPU seconds.",
            cpu / wall
        );
    }
    // Range evaluations.
    let _ = writeln!(
        s,
        "\n### Range evaluations per pixel (rays + culling cells)\n"
    );
    let mut head = String::from("| Model |");
    let mut rule = String::from("|---|");
    for k in &r.kinds {
        let _ = write!(head, " {} |", k.label());
        rule.push_str("---:|");
    }
    let _ = writeln!(s, "{head}\n{rule}");
    for row in &r.rows {
        let _ = write!(s, "| {} |", row.model.name());
        for c in &row.cells {
            if !c.measured() {
                s.push_str(" n/a |");
                continue;
            }
            let stop = if c.stopped { " (stopped)" } else { "" };
            let _ = write!(s, " {:.1}{stop} |", c.evals_per_pixel());
        }
        s.push('\n');
    }
    // The paper beside us.
    let _ = writeln!(
        s,
        "\n### The paper beside us (Pentium 4 3.2 GHz, POV-Ray, paper resolution)\n\n\
         Speed-up = paper seconds / our seconds scaled linearly in pixel count to the paper's \
         resolution{}; once with our wall seconds, once with our CPU seconds (all threads; \
         the paper's renderer ran one thread, and CPU time is not inflated by other load).\n",
        if o.full {
            " (here the same resolution)"
        } else {
            ""
        }
    );
    let mut head = String::from("| Model | Paper resolution |");
    let mut rule = String::from("|---|---|");
    for k in &r.kinds {
        let _ = write!(
            head,
            " {} paper s | {} speed-up wall / CPU |",
            k.label(),
            k.label()
        );
        rule.push_str("---:|---:|");
    }
    let _ = writeln!(s, "{head}\n{rule}");
    for row in &r.rows {
        let Some(p) = row.paper else {
            continue;
        };
        let _ = write!(s, "| {} | {}x{} |", p.label, p.width, p.height);
        for k in &r.kinds {
            let sp = match (row.speedup(*k), row.cell(*k)) {
                (Some(x), Some(c)) if c.stopped => format!("< {x:.0}x"),
                (Some(x), _) if x >= 10.0 => format!("{x:.0}x"),
                (Some(x), _) => format!("{x:.1}x"),
                _ => "n/a".into(),
            };
            let cpu = match row.speedup_cpu(*k) {
                Some(x) if x >= 10.0 => format!("{x:.0}x"),
                Some(x) => format!("{x:.1}x"),
                None => "n/a".into(),
            };
            let _ = write!(s, " {} | {sp} / {cpu} |", fmt_paper_secs(p.seconds_of(*k)));
        }
        s.push('\n');
    }
    let dis = r.disagreements();
    let missed = r.missed_roots();
    if dis.is_empty() && missed.is_empty() {
        let _ = writeln!(
            s,
            "\nHit masks: every arithmetic that finished agrees pixel for pixel."
        );
    } else {
        let _ = writeln!(
            s,
            "\n**HIT MASK DISAGREEMENTS** (vs the reference arithmetic). Each disputed ray is \
             sampled at {SIGN_SAMPLES} points in f64: a sign change proves a root, so a miss there \
             is a *missed root* (a soundness failure); a hit with no sign change while another \
             arithmetic proved the ray root-free is an *unconfirmed hit*: a range that still \
             holds 0 on a segment at the root precision, which reliable methods report as a \
             possible root.\n"
        );
        for (m, k, rk, n) in dis {
            let _ = writeln!(
                s,
                "- {}: {} vs {}: {n} pixels",
                m.name(),
                k.label(),
                rk.label()
            );
        }
        for (m, k, n) in missed {
            let _ = writeln!(
                s,
                "- **{}: {} MISSED {n} CERTAIN ROOTS**",
                m.name(),
                k.label()
            );
        }
    }
    s
}

fn mask_summary(row: &Row) -> String {
    let Some(rk) = row.reference else {
        return if row.cells.iter().any(|c| c.interrupted) {
            "not checked (interrupted)".into()
        } else {
            "not checked (all stopped)".into()
        };
    };
    let differ: Vec<String> = row
        .cells
        .iter()
        .filter_map(|c| match c.mask_diff {
            Some(n) if n > 0 => Some(format!("{} {n}", c.kind.label())),
            _ => None,
        })
        .collect();
    let unconfirmed: Vec<String> = row
        .cells
        .iter()
        .filter(|c| c.unconfirmed_hits > 0)
        .map(|c| format!("{} {}", c.kind.label(), c.unconfirmed_hits))
        .collect();
    let missed: Vec<String> = row
        .cells
        .iter()
        .filter(|c| c.missed_roots > 0)
        .map(|c| format!("{} {}", c.kind.label(), c.missed_roots))
        .collect();
    let mut out = if differ.is_empty() {
        format!("agree (vs {})", rk.label())
    } else {
        format!("**DIFFER** px vs {}: {}", rk.label(), differ.join(", "))
    };
    if !unconfirmed.is_empty() {
        let _ = write!(out, "; unconfirmed hits: {}", unconfirmed.join(", "));
    }
    if !missed.is_empty() {
        let _ = write!(out, "; **MISSED ROOTS: {}**", missed.join(", "));
    }
    let unchecked = |interrupted: bool| {
        row.cells
            .iter()
            .filter(|c| c.mask_diff.is_none() && c.interrupted == interrupted)
            .count()
    };
    if unchecked(false) > 0 {
        let _ = write!(out, "; {} stopped, unchecked", unchecked(false));
    }
    if unchecked(true) > 0 {
        let _ = write!(out, "; {} interrupted, unchecked", unchecked(true));
    }
    out
}

/// The report as CSV, one line per (model, arithmetic).
pub fn csv(r: &Report) -> String {
    let mut s = String::from(
        "model,arith,width,height,ops_all,ops_nonaffine,ops_mul,paper_ops_all,paper_ops_nonaffine,\
         paper_ops_mul,seconds_median,runs,stopped,budget_s,range_evals_per_pixel,ray_evals,cell_evals,\
         hits,ratio_to_revaa,paper_width,paper_height,paper_seconds,speedup_vs_paper,mask_reference,\
         mask_diff_pixels,missed_roots,unconfirmed_hits,cpu_seconds_median,speedup_vs_paper_cpu,interrupted\n",
    );
    for row in &r.rows {
        for c in &row.cells {
            let p = row.paper;
            let opt = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x}"));
            let runs: Vec<String> = c.runs.iter().map(|x| format!("{x:.6}")).collect();
            // Counts of a cell never measured (interrupted) are left empty, not 0.
            let if_measured = |v: String| if c.measured() { v } else { String::new() };
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                row.model.name(),
                c.kind.name(),
                row.width,
                row.height,
                row.ops.all,
                row.ops.non_affine,
                row.ops.mul,
                p.map_or(String::new(), |p| p.ops.all.to_string()),
                p.map_or(String::new(), |p| p.ops.non_affine.to_string()),
                p.map_or(String::new(), |p| p.ops.mul.to_string()),
                if c.measured() { format!("{:.6}", c.seconds) } else { String::new() },
                runs.join(" "),
                c.stopped,
                r.opts.budget.as_secs_f64(),
                if_measured(format!("{:.3}", c.evals_per_pixel())),
                if_measured(c.ray_evals.to_string()),
                if_measured(c.cell_evals.to_string()),
                if_measured(c.hits.to_string()),
                opt(row.ratio_to_revaa(c.kind)),
                p.map_or(String::new(), |p| p.width.to_string()),
                p.map_or(String::new(), |p| p.height.to_string()),
                opt(p.and_then(|p| p.seconds_of(c.kind))),
                opt(row.speedup(c.kind)),
                row.reference.map_or("", |k| k.name()),
                c.mask_diff.map_or(String::new(), |n| n.to_string()),
                c.missed_roots,
                c.unconfirmed_hits,
                if c.cpu_runs.is_empty() { String::new() } else { format!("{:.2}", median(&c.cpu_runs)) },
                opt(row.speedup_cpu(c.kind)),
                c.interrupted,
            );
        }
    }
    s
}

fn draw_chart(r: &Report, path: &Path) -> Result<(), String> {
    let labels: Vec<&str> = r.kinds.iter().map(|k| k.label()).collect();
    let groups: Vec<Group> = r
        .rows
        .iter()
        .map(|row| Group {
            label: row.model.name().to_string(),
            bars: row
                .cells
                .iter()
                .map(|c| {
                    c.measured().then_some(Bar {
                        seconds: c.seconds,
                        stopped: c.stopped,
                    })
                })
                .collect(),
        })
        .collect();
    let title = format!(
        "Ray-tracing time per model and arithmetic ({}; hollow = stopped by budget)",
        if r.opts.full {
            "paper resolutions".to_string()
        } else {
            format!("scale {}", r.opts.scale)
        }
    );
    chart::bar_chart(path, &title, &labels, &groups).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn op_counts_match_the_paper_where_the_formula_is_the_papers() {
        // Non-affine and multiplication counts of the algebraic models do not depend on
        // how sums are grouped.
        let m = op_counts(PaperModel::Mitchell);
        assert_eq!((m.non_affine, m.mul), (6, 6));
    }

    #[test]
    fn lists_parse_and_reject_unknown_names() {
        let m = parse_models("sphere-noise, mitchell").unwrap();
        assert_eq!(m, vec![PaperModel::Mitchell, PaperModel::SphereNoise]);
        assert!(parse_models("mitchell,teapot")
            .unwrap_err()
            .contains("teapot"));
        assert_eq!(
            parse_kinds("revaa,ia").unwrap(),
            vec![ArithKind::Ia, ArithKind::Revaa]
        );
        assert!(parse_kinds("ia,xx").is_err());
    }

    #[test]
    fn resolution_scales_and_keeps_a_minimum() {
        assert_eq!(resolution(PaperModel::Mitchell, true, 0.1), (1280, 1024));
        assert_eq!(resolution(PaperModel::Mitchell, false, 0.5), (640, 512));
        assert_eq!(resolution(PaperModel::Csg, false, 0.0001), (4, 4));
    }

    #[test]
    fn bad_options_are_errors() {
        let mut o = Options::new("/tmp/x");
        o.scale = 0.0;
        assert!(o.validate().is_err());
        o.scale = 0.1;
        o.repeats = 0;
        assert!(o.validate().is_err());
    }

    #[test]
    fn utc_date_is_well_formed() {
        let d = utc_now();
        assert_eq!(d.len(), "2026-01-01 00:00 UTC".len());
        assert!(d.starts_with("20"));
    }

    #[test]
    fn cancelled_run_marks_every_cell_and_still_writes_the_tables() {
        let dir = std::env::temp_dir().join(format!("table1-cancel-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut o = Options::new(&dir);
        o.scale = 0.02;
        o.models = vec![PaperModel::ALL[0]];
        o.kinds = vec![ArithKind::Ia, ArithKind::Revaa];
        o.repeats = 1;
        o.cancel = Some(Arc::new(AtomicBool::new(true)));
        let r = run(&o).unwrap();
        assert!(r.interrupted);
        assert_eq!(r.rows.len(), 1);
        for c in &r.rows[0].cells {
            assert!(c.interrupted && !c.measured(), "{:?}", c.kind);
            assert!(r.rows[0].ratio_to_revaa(c.kind).is_none());
        }
        let md = std::fs::read_to_string(dir.join("table1.md")).unwrap();
        assert!(md.contains("**Interrupted**") && md.contains("| interrupted |"));
        let csv = std::fs::read_to_string(dir.join("table1.csv")).unwrap();
        let mut lines = csv.lines();
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = head.iter().position(|h| *h == "interrupted").unwrap();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len(), 2);
        assert!(rows
            .iter()
            .all(|r| r.len() == head.len() && r[col] == "true"));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn median_of_even_and_odd() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}
