//! Progress reporting of long work: the [`Progress`] a caller hands in (a progress bar,
//! say) and the [`Ticker`] of work whose total grows as it is discovered.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Follows long work's progress: told the number of units (a render's tiles, say), then
/// each finished unit (from any of the worker threads), then the end.
pub trait Progress: Send + Sync + std::fmt::Debug {
    /// The work has `tiles` units (tiles of a render, say) to do.
    fn start(&self, tiles: u64);
    /// One more unit is done.
    fn tile_done(&self);
    /// No more units will be done (all of them, or the work was stopped).
    fn finish(&self);
    /// The work entered the phase `name` (shown beside the bar); none by default.
    fn phase(&self, name: &str) {
        let _ = name;
    }
}

/// Progress in units whose total grows as the work is discovered.
pub struct Ticker {
    progress: Option<Arc<dyn Progress>>,
    total: AtomicU64,
}

impl Ticker {
    /// Reports to `progress`, if any; the total starts at 0.
    pub fn new(progress: Option<Arc<dyn Progress>>) -> Ticker {
        Ticker {
            progress,
            total: AtomicU64::new(0),
        }
    }

    /// `n` more units to do.
    pub fn add_total(&self, n: u64) {
        let t = self.total.fetch_add(n, Ordering::Relaxed) + n;
        if let Some(p) = &self.progress {
            p.start(t);
        }
    }

    /// `n` units done.
    pub fn tick(&self, n: u64) {
        if let Some(p) = &self.progress {
            for _ in 0..n {
                p.tile_done();
            }
        }
    }

    /// No more units will be done.
    pub fn finish(&self) {
        if let Some(p) = &self.progress {
            p.finish();
        }
    }
}
