//! Long work with the GIL released, stoppable by Ctrl-C, with optional progress.
//!
//! The work runs on a thread of its own while the calling thread, the GIL released,
//! waits for it in short steps; at each step it takes the GIL for a moment to let
//! Python look at its signals (`PyErr_CheckSignals`: Ctrl-C raises `KeyboardInterrupt`
//! there) and to draw the progress. A pending exception sets the work's cancel flag
//! (the tracer and the mesher poll it per tile, cell subtree or chunk), the worker is
//! joined, and the exception is raised: Ctrl-C stops a render within a tile's time.

use crate::toolkit::render::Progress;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often the waiting thread looks at Python's signals and redraws the progress.
const POLL: Duration = Duration::from_millis(40);

/// Units of work done out of a total (tiles of a render, parts of a meshing): the
/// [`Progress`] handed to the tracer and the mesher.
#[derive(Debug, Default)]
pub struct Counter {
    total: AtomicU64,
    done: AtomicU64,
}

impl Counter {
    fn read(&self) -> (u64, u64) {
        (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }
}

impl Progress for Counter {
    fn start(&self, tiles: u64) {
        self.total.store(tiles, Ordering::Relaxed);
    }
    fn tile_done(&self) {
        self.done.fetch_add(1, Ordering::Relaxed);
    }
    fn finish(&self) {}
}

/// How the progress of a job is shown: nowhere, as a line on `sys.stderr` redrawn in
/// place, or by calling a Python function with `(done, total)`.
pub enum Report {
    /// No progress (the default).
    Quiet,
    /// A line on `sys.stderr`: the label, units done of the total, the time.
    Line(&'static str),
    /// `f(done, total)`; an exception it raises stops the work and is raised.
    Call(Py<PyAny>),
}

impl Report {
    /// The `progress=` argument of a job: `False`/`None` quiet, `True` a line labelled
    /// `label`, or a callable.
    pub fn from_arg(arg: Option<&Bound<'_, PyAny>>, label: &'static str) -> PyResult<Report> {
        let Some(a) = arg else {
            return Ok(Report::Quiet);
        };
        if a.is_none() {
            return Ok(Report::Quiet);
        }
        if a.is_callable() {
            return Ok(Report::Call(a.clone().unbind()));
        }
        match a.extract::<bool>() {
            Ok(true) => Ok(Report::Line(label)),
            Ok(false) => Ok(Report::Quiet),
            Err(_) => Err(pyo3::exceptions::PyTypeError::new_err(
                "progress: expected True, False or a callable f(done, total)",
            )),
        }
    }

    fn show(&self, py: Python<'_>, counter: &Counter, start: Instant, last: bool) -> PyResult<()> {
        let (done, total) = counter.read();
        match self {
            Report::Quiet => Ok(()),
            Report::Call(f) => f.call1(py, (done, total)).map(drop),
            Report::Line(label) => {
                let end = if last { "\n" } else { "" };
                let line = format!(
                    "\r{label}: {done}/{total}, {:.1} s{end}",
                    start.elapsed().as_secs_f64()
                );
                let err = py.import("sys")?.getattr("stderr")?;
                err.call_method1("write", (line,))?;
                err.call_method0("flush").map(drop)
            }
        }
    }
}

/// A rayon pool of `threads` workers, or `None` for the global pool (one worker per
/// core).
pub fn pool(threads: Option<usize>) -> PyResult<Option<rayon::ThreadPool>> {
    let Some(n) = threads else {
        return Ok(None);
    };
    if n == 0 || n > 1024 {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "threads={n}: expected a whole number of threads from 1 to 1024"
        )));
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .map(Some)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("threads={n}: {e}")))
}

/// Runs `work(cancel, counter)` on a thread of its own (in `pool` where given) with the
/// GIL released, as the module doc says: Ctrl-C, or an exception of the progress
/// callback, sets `cancel` and is raised once the work has stopped.
pub fn run<T: Send>(
    py: Python<'_>,
    report: &Report,
    pool: Option<&rayon::ThreadPool>,
    work: impl FnOnce(&Arc<AtomicBool>, &Arc<Counter>) -> T + Send,
) -> PyResult<T> {
    let cancel = Arc::new(AtomicBool::new(false));
    let counter = Arc::new(Counter::default());
    let start = Instant::now();
    let (cancel, counter) = (&cancel, &counter);
    py.detach(|| {
        std::thread::scope(|s| {
            let (tx, rx) = mpsc::channel::<()>();
            let worker = s.spawn(move || {
                let out = match pool {
                    Some(p) => p.install(|| work(cancel, counter)),
                    None => work(cancel, counter),
                };
                // The receiver may be gone (the caller stopped waiting): nothing to do.
                let _ = tx.send(());
                out
            });
            while let Err(mpsc::RecvTimeoutError::Timeout) = rx.recv_timeout(POLL) {
                let checked = Python::attach(|py| {
                    py.check_signals()?;
                    report.show(py, counter, start, false)
                });
                if let Err(e) = checked {
                    cancel.store(true, Ordering::SeqCst);
                    // The work polls the flag; its result is dropped.
                    let _ = worker.join();
                    return Err(e);
                }
            }
            let out = worker
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            Python::attach(|py| report.show(py, counter, start, true))?;
            Ok(out)
        })
    })
}
