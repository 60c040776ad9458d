//! What the `tracer` binary is made of (feature `cli`): the parsing of flag values into
//! the library's types with one-line errors naming the flag, the model a command's
//! flags select, the terminal progress bar, and the previewer's command and window.

pub mod preview;
pub mod window;

use crate::models::Model;
use crate::render::Progress;
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
