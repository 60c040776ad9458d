//! The progressive-refinement paper's Table 1 and Fig. 9 (Gamito and Maddock 2007),
//! measured with [`crate::gm_rows::bench_table`]: wall time and point evaluations of
//! the previewer, the overshooting and the standard Lipschitz ray casters (plus the
//! local-bound variants, past the paper), with the paper's numbers beside ours.
//!
//! The paper's timings are from a Pentium 4 at 1.2 GHz, so only the evaluation counts
//! and the ordering of the methods are comparable, not the seconds.

use crate::chart::{self, Bar, Group};
use crate::gm_rows::BenchRow;
use model_sources::Model;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The paper's resolution for Table 1 and Figs. 5-7 (Section 4: "800x800 pixels").
pub const DEFAULT_SIZE: u32 = 800;
/// Table 1's models: Fig. 5 (Mitchell), Fig. 6 (blobby), Fig. 7 (hypertexture, L = 1).
pub const TABLE_MODELS: [&str; 3] = ["mitchell-gm", "blobby", "hypertexture-1"];
/// Fig. 9's layer counts run from 1 to this.
pub const FIG9_LAYERS: u32 = 5;
/// The model whose first full-frame preview has a time goal.
pub const GOAL_MODEL: &str = "mitchell-gm";
/// The goal for that first full frame at 800x800, in seconds.
pub const FIRST_FRAME_GOAL_S: f64 = 0.1;
/// The two ray casters the previewer must beat on point evaluations.
pub const RAY_CASTERS: [&str; 2] = ["overshoot-rc", "standard-rc"];
/// Every method `bench_table` reports, in display order.
pub fn methods() -> Vec<String> {
    crate::gm_rows::bench_methods()
        .into_iter()
        .map(|(n, _)| n)
        .collect()
}
/// The methods the paper's Fig. 9 plots, in its legend's order.
pub const FIG9_METHODS: [&str; 3] = ["previewer", "overshoot-rc", "standard-rc"];

/// One method's cell of the paper's Table 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperCell {
    /// Seconds for the final image.
    pub seconds: f64,
    /// Point evaluations of `f`.
    pub evals: u64,
}

/// One row of the paper's Table 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperRow {
    /// The paper's label (the figure the row describes).
    pub label: &'static str,
    /// Our model for that figure.
    pub model: &'static str,
    /// The previewer's cell.
    pub previewer: PaperCell,
    /// The overshooting ray caster's cell.
    pub overshoot: PaperCell,
    /// The standard ray caster's cell.
    pub standard: PaperCell,
}

const fn cell(seconds: f64, evals: u64) -> PaperCell {
    PaperCell { seconds, evals }
}

/// The paper's Table 1, typed in from the text ("Previewer / Optimised R.C. / Standard
/// R.C.", time and number of evaluations, 800x800, Pentium 4 at 1.2 GHz).
pub const PAPER_TABLE1: [PaperRow; 3] = [
    PaperRow {
        label: "Fig. 5",
        model: "mitchell-gm",
        previewer: cell(19.18, 26_803_413),
        overshoot: cell(14.03, 30_701_240),
        standard: cell(19.87, 44_895_932),
    },
    PaperRow {
        label: "Fig. 6",
        model: "blobby",
        previewer: cell(159.48, 30_563_596),
        overshoot: cell(287.56, 58_132_753),
        standard: cell(419.27, 84_760_569),
    },
    PaperRow {
        label: "Fig. 7",
        model: "hypertexture-1",
        previewer: cell(23.22, 12_641_154),
        overshoot: cell(29.69, 21_425_128),
        standard: cell(36.69, 27_504_354),
    },
];

/// The paper's cell for a model and method, where the paper gives one (only at its
/// resolution, 800x800: counts at other sizes are not comparable).
pub fn paper_cell(model: &str, method: &str, size: u32) -> Option<PaperCell> {
    if size != DEFAULT_SIZE {
        return None;
    }
    let r = PAPER_TABLE1.iter().find(|r| r.model == model)?;
    match method {
        "previewer" => Some(r.previewer),
        "overshoot-rc" => Some(r.overshoot),
        "standard-rc" => Some(r.standard),
        _ => None,
    }
}

/// Fig. 9's methods by default: the paper's three and the previewer's default mode.
pub fn fig9_default_methods() -> Vec<String> {
    let mut v: Vec<String> = FIG9_METHODS.iter().map(|s| s.to_string()).collect();
    v.insert(1, goal_previewer());
    v
}

/// The previewer whose counts the goals judge: the default bound mode of `tracer
/// preview` ([`tracer::progressive::DEFAULT_BOUND`]).
pub fn goal_previewer() -> String {
    crate::gm_rows::previewer_method(tracer::progressive::DEFAULT_BOUND)
}

/// Checks comma-separated method names against [`methods`].
pub fn parse_methods(s: &str) -> Result<Vec<String>, String> {
    let all = methods();
    let v: Vec<String> = s
        .split(',')
        .map(str::trim)
        .filter(|n| !n.is_empty())
        .map(String::from)
        .collect();
    for n in &v {
        if !all.contains(n) {
            return Err(format!(
                "--methods: unknown method '{n}' (expected one of: {})",
                all.join(", ")
            ));
        }
    }
    if v.is_empty() {
        return Err("--methods names no method".into());
    }
    Ok(v)
}

/// Looks up comma-separated model names among [`model_sources::gamito_maddock::all`], keeping the
/// given order and dropping repeats.
pub fn parse_models(s: &str) -> Result<Vec<Model>, String> {
    let all = model_sources::gamito_maddock::all();
    let mut out: Vec<Model> = Vec::new();
    for name in s.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        let m = all
            .iter()
            .find(|m| m.name.eq_ignore_ascii_case(name))
            .ok_or_else(|| {
                let names: Vec<_> = all.iter().map(|m| m.name.as_str()).collect();
                format!(
                    "unknown model '{name}' (expected one of: {})",
                    names.join(", ")
                )
            })?;
        if !out.iter().any(|o| o.name == m.name) {
            out.push(m.clone());
        }
    }
    if out.is_empty() {
        return Err("--models names no model".into());
    }
    Ok(out)
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct Options {
    /// Image width and height in pixels.
    pub size: u32,
    /// Table 1's models.
    pub models: Vec<Model>,
    /// Fig. 9 runs the hypertexture with `L = 1..=layers` (0: no Fig. 9).
    pub layers: u32,
    /// Folder the tables and plots are written to.
    pub out: PathBuf,
    /// Print each model's progress on stderr.
    pub verbose: bool,
    /// Timing rounds: every method once per round, in turn; rows keep the median.
    pub rounds: u32,
    /// Only the methods with these names (empty: all of [`methods`]).
    pub methods: Vec<String>,
}

impl Options {
    /// The paper's setup: 800x800, Table 1's three models, `L = 1..5`.
    pub fn new(out: PathBuf) -> Self {
        Options {
            size: DEFAULT_SIZE,
            models: parse_models(&TABLE_MODELS.join(",")).expect("Table 1's models exist"),
            layers: FIG9_LAYERS,
            out,
            verbose: false,
            rounds: 1,
            methods: Vec::new(),
        }
    }
}

/// The measurements.
#[derive(Clone, Debug)]
pub struct Report {
    /// Image side in pixels.
    pub size: u32,
    /// Table 1: every method for each model.
    pub table: Vec<BenchRow>,
    /// Fig. 9: every method for `hypertexture-1..=L`, in order of `L`.
    pub fig9: Vec<(u32, Vec<BenchRow>)>,
}

fn bench(m: &Model, o: &Options) -> Result<Vec<BenchRow>, String> {
    let (size, verbose) = (o.size, o.verbose);
    if verbose {
        eprintln!("progressive: {} at {size}x{size} ...", m.name);
    }
    let keep = |name: &str| o.methods.is_empty() || o.methods.iter().any(|k| k == name);
    let rows = crate::gm_rows::bench_rounds(std::slice::from_ref(m), size, size, o.rounds, &keep)?;
    if verbose {
        for r in &rows {
            eprintln!(
                "  {:<22} {:>9.3} s {:>12} point {:>10} range evals",
                r.method, r.seconds, r.evals, r.range_evals
            );
        }
    }
    Ok(rows)
}

/// Runs Table 1 and Fig. 9 (reusing a Table 1 model that Fig. 9 also needs) and writes
/// `progressive.md`, `progressive.csv`, `fig9.csv`, `fig9.png` and `fig9-evals.png`.
pub fn run(o: &Options) -> Result<Report, String> {
    let max = model_ir::camera::MAX_SIDE;
    if o.size == 0 || o.size > max {
        return Err(format!("--size {} must be between 1 and {max}", o.size));
    }
    if o.layers > u32::from(model_sources::gamito_maddock::MAX_LAYERS) {
        return Err(format!(
            "--layers {} must be at most {}",
            o.layers,
            model_sources::gamito_maddock::MAX_LAYERS
        ));
    }
    std::fs::create_dir_all(&o.out)
        .map_err(|e| format!("cannot create '{}': {e}", o.out.display()))?;
    let mut table = Vec::new();
    for m in &o.models {
        table.extend(bench(m, o)?);
    }
    let mut fig9 = Vec::new();
    for l in 1..=o.layers {
        let name = format!("hypertexture-{l}");
        let done: Vec<BenchRow> = table.iter().filter(|r| r.model == name).cloned().collect();
        let rows = if done.is_empty() {
            bench(&parse_models(&name)?[0], o)?
        } else {
            done
        };
        fig9.push((l, rows));
    }
    let report = Report {
        size: o.size,
        table,
        fig9,
    };
    let write = |name: &str, text: &str| {
        let p = o.out.join(name);
        std::fs::write(&p, text).map_err(|e| format!("cannot write '{}': {e}", p.display()))
    };
    if o.models.is_empty() {
        // Fig. 9 alone (`bench-suite fig9`).
        write("fig9.md", &markdown(&report))?;
    } else {
        write("progressive.md", &markdown(&report))?;
        write("progressive.csv", &csv(&report))?;
    }
    if !report.fig9.is_empty() {
        write("fig9.csv", &fig9_csv(&report))?;
        fig9_charts(&report, &o.out)?;
    }
    Ok(report)
}

fn find<'a>(rows: &'a [BenchRow], model: &str, method: &str) -> Option<&'a BenchRow> {
    rows.iter().find(|r| r.model == model && r.method == method)
}

/// `a / b` as a ratio string, or `n/a` when `b` is zero.
fn ratio(a: u64, b: u64) -> String {
    if b == 0 {
        "n/a".into()
    } else {
        format!("{:.3}", a as f64 / b as f64)
    }
}

/// Seconds as milliseconds with one decimal (first frames are far below a second).
fn opt_ms(v: Option<f64>) -> String {
    v.map_or(String::new(), |s| format!("{:.1}", s * 1e3))
}

/// Model names in first-seen order.
fn model_names(rows: &[BenchRow]) -> Vec<&str> {
    let mut v: Vec<&str> = Vec::new();
    for r in rows {
        if !v.contains(&r.model.as_str()) {
            v.push(&r.model);
        }
    }
    v
}

/// Models on which the previewer does NOT need fewer point evaluations than both ray
/// casters, each with a sentence saying why (empty: the goal is met everywhere).
pub fn eval_goal_misses(rows: &[BenchRow]) -> Vec<String> {
    let mut out = Vec::new();
    for m in model_names(rows) {
        let gp = goal_previewer();
        let Some(p) = find(rows, m, &gp) else {
            continue;
        };
        for rc in RAY_CASTERS {
            if let Some(r) = find(rows, m, rc) {
                if p.evals + p.range_evals >= r.evals {
                    out.push(format!(
                        "on {m} {gp} needs {} point and {} range evaluations, not fewer in \
                         all than {rc}'s {} point evaluations",
                        p.evals, p.range_evals, r.evals
                    ));
                }
            }
        }
    }
    out
}

/// The first full-frame time of [`GOAL_MODEL`]'s previewer, if it was measured.
pub fn first_frame_s(rows: &[BenchRow]) -> Option<f64> {
    find(rows, GOAL_MODEL, &goal_previewer()).and_then(|r| r.first_frame_s)
}

/// The goal lines: one per model for the evaluation goal, one for the first-frame goal.
/// Misses start with `!!!` so they stand out.
pub fn goal_lines(r: &Report) -> Vec<String> {
    let mut out = Vec::new();
    let misses = eval_goal_misses(&r.table);
    for m in model_names(&r.table) {
        let Some(p) = find(&r.table, m, &goal_previewer()) else {
            continue;
        };
        if misses.iter().any(|s| s.starts_with(&format!("on {m} "))) {
            continue;
        }
        let parts: Vec<String> = RAY_CASTERS
            .iter()
            .filter_map(|rc| {
                find(&r.table, m, rc)
                    .map(|x| format!("{}x {rc}", ratio(p.evals + p.range_evals, x.evals)))
            })
            .collect();
        out.push(format!(
            "goal met on {m}: {} needs fewer point and range evaluations in all than both ray casters' point evaluations ({})",
            goal_previewer(),
            parts.join(", ")
        ));
    }
    for s in &misses {
        out.push(format!("!!! GOAL MISSED: {s}"));
    }
    let at = if r.size == DEFAULT_SIZE {
        String::new()
    } else {
        format!(" (the goal is stated at {DEFAULT_SIZE}x{DEFAULT_SIZE}; this run is not)")
    };
    match first_frame_s(&r.table) {
        Some(s) if s < FIRST_FRAME_GOAL_S => out.push(format!(
            "goal met: first full-frame preview of {GOAL_MODEL} at {0}x{0} after {1:.1} ms (goal < {2:.0} ms){at}",
            r.size,
            s * 1e3,
            FIRST_FRAME_GOAL_S * 1e3
        )),
        Some(s) => out.push(format!(
            "!!! GOAL MISSED: first full-frame preview of {GOAL_MODEL} at {0}x{0} after {1:.1} ms (goal < {2:.0} ms){at}",
            r.size,
            s * 1e3,
            FIRST_FRAME_GOAL_S * 1e3
        )),
        None => {
            if find(&r.table, GOAL_MODEL, &goal_previewer()).is_some() {
                out.push(format!(
                    "!!! GOAL MISSED: the previewer of {GOAL_MODEL} never painted a full frame"
                ));
            }
        }
    }
    out
}

/// Table 1 and Fig. 9 as Markdown.
pub fn markdown(r: &Report) -> String {
    let mut s = String::new();
    let n = r.size;
    if !r.table.is_empty() {
        let _ = writeln!(
            s,
            "## Table 1 (Gamito and Maddock 2007) at {n}x{n}\n\n\
             Point evaluations of `f` while tracing (normals excluded, as for the ray casters); \
             the `-local` methods also pay the range evaluations (`Dual<Interval>`) of their local \
             Lipschitz bounds. `/ overshoot-rc` and `/ standard-rc` are this method's point \
             evaluations over that ray caster's. The paper's columns are from its Table 1 \
             (800x800, Pentium 4 at 1.2 GHz: compare counts, not seconds).\n"
        );
        s.push_str(
            "| model | method | seconds | point evals | range evals | / overshoot-rc | / standard-rc \
             | first frame ms | iterations | paper seconds | paper evals |\n",
        );
        s.push_str("|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
        for m in model_names(&r.table) {
            let label = PAPER_TABLE1
                .iter()
                .find(|p| p.model == m)
                .map_or(m.to_string(), |p| format!("{m} ({})", p.label));
            for method in methods() {
                let method = method.as_str();
                let Some(row) = find(&r.table, m, method) else {
                    continue;
                };
                let rel = |rc: &str| {
                    find(&r.table, m, rc).map_or("".into(), |x| ratio(row.evals, x.evals))
                };
                let paper = paper_cell(m, method, n);
                let _ = writeln!(
                    s,
                    "| {label} | {method} | {:.3} | {} | {} | {} | {} | {} | {} | {} | {} |",
                    row.seconds,
                    row.evals,
                    row.range_evals,
                    rel("overshoot-rc"),
                    rel("standard-rc"),
                    opt_ms(row.first_frame_s),
                    row.iterations.map_or(String::new(), |i| i.to_string()),
                    paper.map_or(String::new(), |p| format!("{:.2}", p.seconds)),
                    paper.map_or(String::new(), |p| p.evals.to_string()),
                );
            }
        }
        s.push('\n');
        for line in goal_lines(r) {
            let _ = writeln!(s, "- {line}");
        }
    }
    if !r.fig9.is_empty() {
        let _ = writeln!(
            s,
            "\n## Fig. 9: total rendering time of the hypertexture with L layers (eq. 12) at {n}x{n}\n\n\
             The paper's Fig. 9 plots total rendering time per method for L = 1..5 as bars \
             (`fig9.png`; evaluations in `fig9-evals.png`). The paper gives no numbers for its \
             bars; its L = 1 is Table 1's Fig. 7 row.\n"
        );
        s.push_str("| L | method | seconds | point evals | range evals | / overshoot-rc | / standard-rc |\n");
        s.push_str("|--:|---|--:|--:|--:|--:|--:|\n");
        for (l, rows) in &r.fig9 {
            for method in methods() {
                let method = method.as_str();
                let Some(row) = rows.iter().find(|x| x.method == method) else {
                    continue;
                };
                let rel = |rc: &str| {
                    rows.iter()
                        .find(|x| x.method == rc)
                        .map_or("".into(), |x| ratio(row.evals, x.evals))
                };
                let _ = writeln!(
                    s,
                    "| {l} | {method} | {:.3} | {} | {} | {} | {} |",
                    row.seconds,
                    row.evals,
                    row.range_evals,
                    rel("overshoot-rc"),
                    rel("standard-rc"),
                );
            }
        }
        let all: Vec<BenchRow> = r.fig9.iter().flat_map(|(_, v)| v.clone()).collect();
        let misses = eval_goal_misses(&all);
        s.push('\n');
        if misses.is_empty() {
            s.push_str(
                "- for every L the previewer needs fewer point evaluations than both ray casters\n",
            );
        }
        for m in misses {
            let _ = writeln!(s, "- !!! GOAL MISSED: {m}");
        }
    }
    s
}

const CSV_HEADER: &str = "model,method,width,height,seconds,point_evals,range_evals,\
ratio_overshoot_rc,ratio_standard_rc,first_frame_s,iterations,paper_seconds,paper_evals";

fn csv_rows(s: &mut String, rows: &[BenchRow], size: u32, prefix: Option<u32>) {
    for row in rows {
        let rel = |rc: &str| {
            rows.iter()
                .find(|x| x.model == row.model && x.method == rc)
                .map_or(String::new(), |x| ratio(row.evals, x.evals))
        };
        let paper = paper_cell(&row.model, &row.method, size);
        if let Some(l) = prefix {
            let _ = write!(s, "{l},");
        }
        let _ = writeln!(
            s,
            "{},{},{size},{size},{},{},{},{},{},{},{},{},{}",
            row.model,
            row.method,
            row.seconds,
            row.evals,
            row.range_evals,
            rel("overshoot-rc"),
            rel("standard-rc"),
            row.first_frame_s.map_or(String::new(), |f| f.to_string()),
            row.iterations.map_or(String::new(), |i| i.to_string()),
            paper.map_or(String::new(), |p| p.seconds.to_string()),
            paper.map_or(String::new(), |p| p.evals.to_string()),
        );
    }
}

/// Table 1 as CSV: one line per (model, method).
pub fn csv(r: &Report) -> String {
    let mut s = format!("{CSV_HEADER}\n");
    csv_rows(&mut s, &r.table, r.size, None);
    s
}

/// Fig. 9 as CSV: one line per (L, method), with the layer count first.
pub fn fig9_csv(r: &Report) -> String {
    let mut s = format!("layers,{CSV_HEADER}\n");
    for (l, rows) in &r.fig9 {
        csv_rows(&mut s, rows, r.size, Some(*l));
    }
    s
}

/// Fig. 9's bar charts: seconds (what the paper plots) and point evaluations, one group
/// per L, one bar per method of the paper.
fn fig9_charts(r: &Report, dir: &Path) -> Result<(), String> {
    let names: Vec<String> = fig9_default_methods()
        .into_iter()
        .filter(|m| {
            r.fig9
                .iter()
                .any(|(_, rows)| rows.iter().any(|x| &x.method == m))
        })
        .collect();
    let labels: Vec<&str> = names.iter().map(String::as_str).collect();
    let groups = |value: &dyn Fn(&BenchRow) -> f64| -> Vec<Group> {
        r.fig9
            .iter()
            .map(|(l, rows)| Group {
                label: format!("L = {l}"),
                bars: labels
                    .iter()
                    .map(|m| {
                        rows.iter().find(|x| x.method == *m).map(|x| Bar {
                            seconds: value(x),
                            stopped: false,
                        })
                    })
                    .collect(),
            })
            .collect()
    };
    let n = r.size;
    chart::bar_chart(
        &dir.join("fig9.png"),
        &format!("Fig. 9: total rendering time, hypertexture with L layers, {n}x{n}"),
        &labels,
        &groups(&|x| x.seconds),
    )?;
    chart::bar_chart_with_axis(
        &dir.join("fig9-evals.png"),
        &format!("Point evaluations, hypertexture with L layers, {n}x{n}"),
        "point evaluations (log scale)",
        &labels,
        &groups(&|x| x.evals as f64),
    )?;
    Ok(())
}
