//! The terminal progress bar of long commands (`render`, `mesh`).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use tracer_kit::progress::Progress;

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
        Bar::with_unit("tiles")
    }

    /// [`Bar::new`] counting `unit` (`tiles`, `parts`) instead of tiles.
    pub fn with_unit(unit: &str) -> Bar {
        Bar::with_template(&format!(
            "{{bar:40}} {{pos}}/{{len}} {unit}, {{elapsed}} (left {{eta}})"
        ))
    }

    /// A bar over a whole job of named phases, in per cent (the phase's name first).
    pub fn phased() -> Bar {
        Bar::with_template("{msg:18} {bar:40} {percent:>3}%, {elapsed} (left {eta})")
    }

    fn with_template(template: &str) -> Bar {
        let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
        if let Ok(style) = ProgressStyle::with_template(template) {
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
    fn phase(&self, name: &str) {
        self.bar.set_message(name.to_string());
    }
}
