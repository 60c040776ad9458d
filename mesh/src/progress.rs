//! One progress measure over the whole meshing, so that a bar never starts over: the
//! job is a line of phases (the octree search at each leaf level, the contouring, the
//! certificate, the checks), each taking a share of what is left of the bar when it
//! starts, and each advancing by the units of work it counts (subtrees of the octree,
//! chunks of edges and cells). Work found in the middle of a phase (another chunk, or
//! a search again at a finer level) spreads over what is left of it, so the position
//! only ever moves forward. The bar is [`STEPS`] long; [`Progress::phase`] names the
//! phase beside it.

use std::sync::{Arc, Mutex};
use tracer_kit::progress::Progress;

/// The bar's length: the whole job in thousandths.
pub const STEPS: u64 = 1000;

/// The progress of one meshing, reported to a [`Progress`].
pub struct Meter {
    progress: Option<Arc<dyn Progress>>,
    state: Mutex<State>,
}

/// Where the bar is, and the current phase.
#[derive(Default)]
struct State {
    /// Steps reported so far.
    drawn: u64,
    /// The current phase's start and end, as fractions of the job.
    from: f64,
    to: f64,
    /// The phase's units of work, and those done.
    units: u64,
    done: u64,
}

impl State {
    /// The position in the job, from 0 to 1.
    fn position(&self) -> f64 {
        if self.units == 0 {
            self.from
        } else {
            self.from + (self.to - self.from) * (self.done as f64 / self.units as f64)
        }
    }
}

impl Meter {
    /// A meter reporting to `progress`, if any.
    pub fn new(progress: Option<Arc<dyn Progress>>) -> Meter {
        if let Some(p) = &progress {
            p.start(STEPS);
        }
        Meter {
            progress,
            state: Mutex::new(State::default()),
        }
    }

    /// Enters the phase `name`, which takes `share` (0 to 1) of what is left of the job
    /// and has `units` units of work (more may come with [`Meter::add_total`]).
    pub fn phase(&self, name: &str, share: f64, units: u64) {
        let mut s = self.lock();
        let pos = s.position();
        s.from = pos;
        s.to = pos + (1.0 - pos) * share.clamp(0.0, 1.0);
        s.units = units;
        s.done = 0;
        drop(s);
        if let Some(p) = &self.progress {
            p.phase(name);
        }
    }

    /// `n` more units of work in the current phase: what is left of the phase is
    /// spread over the units left.
    pub fn add_total(&self, n: u64) {
        let mut s = self.lock();
        s.from = s.position();
        s.units = s.units - s.done + n;
        s.done = 0;
    }

    /// `n` units of the current phase done.
    pub fn tick(&self, n: u64) {
        let mut s = self.lock();
        s.done = (s.done + n).min(s.units);
        let target = ((s.position() * STEPS as f64) as u64).min(STEPS);
        if let Some(p) = &self.progress {
            while s.drawn < target {
                p.tile_done();
                s.drawn += 1;
            }
        }
        s.drawn = s.drawn.max(target);
    }

    /// The job is over (done or stopped).
    pub fn finish(&self) {
        if let Some(p) = &self.progress {
            p.finish();
        }
    }

    /// The position reported so far, in steps.
    pub fn drawn(&self) -> u64 {
        self.lock().drawn
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_position_never_moves_back_when_work_is_found() {
        let m = Meter::new(None);
        m.phase("search", 0.4, 8);
        let mut last = 0;
        for _ in 0..6 {
            m.tick(1);
            assert!(m.drawn() >= last);
            last = m.drawn();
        }
        assert_eq!(last, 300);
        // The search runs again at a finer level: more work, the position stays.
        m.phase("search again", 0.4, 64);
        assert_eq!(m.drawn(), last);
        m.add_total(10);
        for _ in 0..74 {
            m.tick(1);
            assert!(m.drawn() >= last);
            last = m.drawn();
        }
        m.phase("rest", 1.0, 2);
        m.tick(2);
        assert_eq!(m.drawn(), STEPS);
    }
}
