//! What the `tracer` binary is made of (feature `cli`): the parsing of flag values into
//! the library's types with one-line errors naming the flag, the model a command's
//! flags select, the terminal progress bar, and the previewer's command and window.

pub mod preview;
pub mod window;

use crate::models::Model;
use crate::render::{Progress, RenderStats};
use crate::shape::Aabb;
use glam::DVec3;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// The model that `MODEL`, `--expr` and a domain flag (`(flag, value)`: `--domain`,
/// `--box`) select, from the one registry ([`crate::models`]): a built-in name or a
/// formula (domain `[-2, 2]^3` unless the flag gives one, framed by
/// [`crate::camera::frame_box`]).
pub fn model_source(
    name: Option<&str>,
    expr: Option<&str>,
    domain: Option<(&str, &str)>,
) -> Result<Model, String> {
    let domain = match domain {
        Some((flag, s)) => {
            let b = parse_box(flag, s)?;
            if expr.is_some() {
                crate::camera::frame_box(&b).map_err(|e| format!("{flag} '{s}': {e}"))?;
            }
            Some(b)
        }
        None => None,
    };
    let mut model = match (name, expr) {
        (Some(_), Some(_)) => return Err("give either a MODEL or --expr, not both".into()),
        (None, None) => {
            return Err("give a MODEL name (see `tracer list`) or --expr FORMULA".into())
        }
        (Some(m), None) => crate::models::find(m)?,
        (None, Some(f)) => {
            return Model::formula(f, domain).map_err(|e| format!("--expr: {e}"));
        }
    };
    if let Some(d) = domain {
        model.domain = d;
    }
    Ok(model)
}

/// Parses `n` comma-separated finite numbers for `flag`.
pub fn parse_list(flag: &str, s: &str, n: usize) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != n {
        return Err(format!(
            "{flag} '{s}': expected {n} comma-separated numbers, got {}",
            parts.len()
        ));
    }
    parts
        .iter()
        .map(|p| match p.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("{flag} '{s}': '{p}' is not a finite number")),
        })
        .collect()
}

/// Parses `X,Y,Z` for `flag`.
pub fn parse_vec3(flag: &str, s: &str) -> Result<DVec3, String> {
    let v = parse_list(flag, s, 3)?;
    Ok(DVec3::new(v[0], v[1], v[2]))
}

/// Parses `XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX` for `flag`: a box the renderers can work in.
pub fn parse_box(flag: &str, s: &str) -> Result<Aabb, String> {
    let v = parse_list(flag, s, 6)?;
    let b = Aabb::new(DVec3::new(v[0], v[1], v[2]), DVec3::new(v[3], v[4], v[5]));
    crate::shape::check_domain(&b).map_err(|e| format!("{flag} '{s}': {e}"))?;
    Ok(b)
}

/// Parses `WxH` for `flag`, each side within [`crate::camera::check_size`].
pub fn parse_size(flag: &str, s: &str) -> Result<(u32, u32), String> {
    let max = crate::camera::MAX_SIDE;
    let err =
        || format!("{flag} '{s}': expected WxH with positive integers up to {max}, e.g. 640x480");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(err)?;
    let w: u32 = w.trim().parse().map_err(|_| err())?;
    let h: u32 = h.trim().parse().map_err(|_| err())?;
    crate::camera::check_size(w, h).map_err(|_| err())?;
    Ok((w, h))
}

/// Most worker threads `--threads` accepts.
pub const MAX_THREADS: usize = 1024;

/// Parses `--threads N`, `1 <= N <= MAX_THREADS`.
pub fn parse_threads(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(n) if (1..=MAX_THREADS).contains(&n) => Ok(n),
        _ => Err(format!(
            "--threads '{s}': expected a whole number of threads from 1 to {MAX_THREADS}"
        )),
    }
}

/// Builds rayon's global pool with `--threads` threads, if given (before any parallel
/// work: the pool is built once per process).
pub fn set_threads(threads: Option<&str>) -> Result<(), String> {
    let Some(s) = threads else {
        return Ok(());
    };
    let n = parse_threads(s)?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build_global()
        .map_err(|e| format!("--threads {n}: {e}"))
}

/// `s` as a JSON string.
pub fn json_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The stats of a render as one JSON object on one line: every counter of
/// [`RenderStats`] under its field name, `wall_s` for the wall time, and the render's
/// model, size and arithmetic.
pub fn stats_json(model: &str, width: u32, height: u32, arith: &str, s: &RenderStats) -> String {
    // Destructured so that a new counter cannot be left out.
    let RenderStats {
        wall,
        rays,
        shadow_rays,
        range_evals,
        range_evals_hit,
        cell_evals,
        point_evals,
        cells_culled,
        pixels_culled,
        pruned_empty,
        hits,
        unconfirmed,
        cut,
        tiles_done,
        tiles_total,
    } = *s;
    let counters = [
        ("rays", rays),
        ("shadow_rays", shadow_rays),
        ("range_evals", range_evals),
        ("range_evals_hit", range_evals_hit),
        ("cell_evals", cell_evals),
        ("point_evals", point_evals),
        ("cells_culled", cells_culled),
        ("pixels_culled", pixels_culled),
        ("pruned_empty", pruned_empty),
        ("hits", hits),
        ("unconfirmed", unconfirmed),
        ("tiles_done", tiles_done),
        ("tiles_total", tiles_total),
    ];
    let mut out = format!(
        "{{\"model\": {}, \"width\": {width}, \"height\": {height}, \"arith\": {}, \"wall_s\": {:?}, \"cut\": {cut}",
        json_string(model),
        json_string(arith),
        wall.as_secs_f64(),
    );
    for (k, v) in counters {
        out.push_str(&format!(", \"{k}\": {v}"));
    }
    out.push_str(&format!(
        ", \"mean_evals_per_hit\": {:?}}}",
        s.mean_evals_per_hit()
    ));
    out
}

/// Parses a finite number above 0 for `flag`.
pub fn parse_positive(flag: &str, s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!("{flag} '{s}': expected a positive number")),
    }
}

/// A progress bar of tiles on stderr, drawn only when stderr is a terminal and only once
/// a render has run for a second (short renders stay quiet), with the time left.
#[derive(Debug)]
pub struct Bar {
    bar: ProgressBar,
    start: Instant,
    shown: AtomicBool,
}

impl Bar {
    /// A bar that shows itself where stderr is a terminal.
    pub fn new() -> Bar {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
        if let Ok(style) =
            ProgressStyle::with_template("{bar:40} {pos}/{len} tiles, {elapsed} (left {eta})")
        {
            bar.set_style(style);
        }
        Bar {
            bar,
            start: Instant::now(),
            shown: AtomicBool::new(!std::io::stderr().is_terminal()),
        }
    }
}

impl Default for Bar {
    fn default() -> Self {
        Bar::new()
    }
}

impl Progress for Bar {
    fn start(&self, tiles: u64) {
        self.bar.set_length(tiles);
    }
    fn tile_done(&self) {
        if !self.shown.load(Ordering::Relaxed) && self.start.elapsed() > Duration::from_secs(1) {
            self.shown.store(true, Ordering::Relaxed);
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        self.bar.inc(1);
    }
    fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
