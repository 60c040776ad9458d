//! Table 1's outputs: the Markdown table beside the paper's figures, the CSV of every
//! cell, and the bar chart.

use super::masks::SIGN_SAMPLES;
use super::{median, Cell, Report, Row};
use crate::chart::{self, Bar, Group};
use model_ir::arith::ArithKind;
use std::fmt::Write as _;
use std::path::Path;

pub(super) fn write(path: &Path, bytes: &[u8]) -> Result<(), String> {
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
    // Only the arithmetics the paper has a column for.
    let paper_kinds: Vec<ArithKind> = r
        .kinds
        .iter()
        .copied()
        .filter(|k| crate::paper::PAPER_COLUMNS.contains(&k.name()))
        .collect();
    for k in &paper_kinds {
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
        for k in &paper_kinds {
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

pub(super) fn draw_chart(r: &Report, path: &Path) -> Result<(), String> {
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
