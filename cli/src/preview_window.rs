//! The live preview (Section 3.5): a refinement thread and a display thread sharing the
//! image buffer ([`tracer::progressive::SharedImage`], relaxed atomics, no locks).
//!
//! The display thread (this one: X11 windows belong to the thread that made them) shows
//! the buffer at a steady frame rate and edits the region of interest: drag with the
//! left button to set it, right-click to cancel it. Dragging with the right button
//! orbits the view about the point looked at ([`model_ir::camera::orbit`]), the mouse wheel
//! zooms ([`model_ir::camera::zoom`]), and a model file that changes on disk is read again
//! (a file that does not read keeps the last model, with the error on stderr); each of
//! these starts the refinement over with a new engine. Esc, closing the window or Ctrl-C
//! (see [`tracer_kit::interrupt`]) stops the refinement. The image is written to `--out` when
//! refinement completes and when it is stopped early; `--out` is also checkpointed every
//! few seconds, so even a force-quit (a second Ctrl-C) loses at most the last few
//! seconds of refinement.

use crate::preview_args::{options_for, save_image, PreviewArgs};
use minifb::{Key, MouseButton, MouseMode, Window, WindowOptions};
use model_ir::shape::{Shape, View};
use model_sources::Model;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::sync::Arc;
use std::thread;
use std::time::{Duration, Instant, SystemTime};
use tracer::progressive::{write_png, Engine, Options, Rect, SharedImage, Stats, Step};

/// Messages from the display thread to the refinement thread.
pub enum Command<S: Shape> {
    /// Refine this rectangle first.
    SetRoi(Rect),
    /// Refine the whole image again.
    CancelRoi,
    /// Start over with this engine (a new view or a reloaded model).
    Restart(Box<Engine<S>>),
}

/// Seconds between checkpoints of `--out` while the window is open.
const CHECKPOINT_S: f64 = 5.0;

/// Seconds between looks at the model file's modification time.
const RELOAD_POLL_S: f64 = 0.5;

/// Orbit per pixel of a right-button drag, in radians.
pub(super) const ORBIT_PER_PIXEL: f64 = 0.01;

/// Distance factor per step of the mouse wheel (towards the point looked at).
pub(super) const ZOOM_PER_STEP: f64 = 0.9;

/// The refinement thread: steps its engine until done, then waits, applying commands
/// between batches of samples, until told to stop. `done` holds the number of the last
/// engine that completed (the first is 1; 0: none yet). Returns the last engine's
/// counters and whether it completed.
fn refine<S: Shape>(
    mut engine: Engine<S>,
    stop: Arc<AtomicBool>,
    done: Arc<AtomicU64>,
    roi_active: Arc<AtomicBool>,
    rx: mpsc::Receiver<Command<S>>,
) -> (Stats, bool) {
    let (mut number, mut complete) = (1u64, false);
    while !stop.load(Ordering::Relaxed) {
        while let Ok(c) = rx.try_recv() {
            match c {
                Command::SetRoi(r) => {
                    let _ = engine.set_roi(r);
                }
                Command::CancelRoi => engine.cancel_roi(),
                Command::Restart(e) => {
                    engine = *e;
                    number += 1;
                    complete = false;
                }
            }
        }
        if complete {
            thread::sleep(Duration::from_millis(10));
            continue;
        }
        // A batch of samples between checks keeps the flag and channel overhead small.
        for _ in 0..64 {
            if engine.step() == Step::Done {
                break;
            }
        }
        roi_active.store(engine.roi().is_some(), Ordering::Relaxed);
        if engine.is_done() {
            complete = true;
            done.store(number, Ordering::Relaxed);
        }
    }
    (engine.stats(), complete)
}

/// The model file that `args` reads, if one (a path, not a built-in name or stdin).
fn watched_file(args: &PreviewArgs) -> Option<PathBuf> {
    let p = args
        .src
        .model
        .as_deref()
        .or(args.src.expr_file.as_deref())?;
    let p = Path::new(p);
    (p.is_file()).then(|| p.to_path_buf())
}

fn modified(p: &Path) -> Option<SystemTime> {
    std::fs::metadata(p).and_then(|m| m.modified()).ok()
}

/// Writes `out` by way of a temporary file beside it, so a reader never sees half a PNG.
fn write_atomically(img: &SharedImage, out: &Path) -> Result<(), String> {
    let ext = out.extension().and_then(|e| e.to_str()).unwrap_or("png");
    let tmp = out.with_extension(format!("partial.{ext}"));
    write_png(img, &tmp)?;
    std::fs::rename(&tmp, out).map_err(|e| format!("cannot write {}: {e}", out.display()))
}

/// A checkpoint of `--out` while the window is open: a failure is reported once on
/// stderr and refinement goes on (the final write keeps the image somewhere, see
/// [`save_image`]).
fn checkpoint(img: &SharedImage, out: &Path, failed: &mut bool) {
    if let Err(e) = write_atomically(img, out) {
        if !*failed {
            eprintln!("warning: --out checkpoint: {e}");
        }
        *failed = true;
    }
}

/// Draws a one-pixel white outline of `r` into `buf`.
fn outline(buf: &mut [u32], w: u32, h: u32, r: Rect) {
    let white = 0x00ff_ffff;
    let (x1, y1) = (r.x1.min(w) - 1, r.y1.min(h) - 1);
    for x in r.x0..=x1 {
        buf[(r.y0 * w + x) as usize] = white;
        buf[(y1 * w + x) as usize] = white;
    }
    for y in r.y0..=y1 {
        buf[(y * w + r.x0) as usize] = white;
        buf[(y * w + x1) as usize] = white;
    }
}

/// Opens the window and runs the two threads until stopped. `engine` renders `model`
/// from its view; `initial_roi` (the `--roi` flag) is set at once.
pub fn run_window(
    engine: Engine<Model>,
    model: Model,
    args: &PreviewArgs,
    initial_roi: Option<Rect>,
) -> Result<(), String> {
    if args.fps == 0 || args.fps > 240 {
        return Err(format!("--fps must be in 1..=240, got {}", args.fps));
    }
    let (w, h) = engine.size();
    let mut window = Window::new(
        &format!("tracer preview: {}", args.title()),
        w as usize,
        h as usize,
        WindowOptions::default(),
    )
    .map_err(|e| format!("cannot open a window ({e}); use --headless"))?;
    window.set_target_fps(args.fps as usize);
    let mut image = engine.image();
    let mut opts: Options = *engine.options();
    let mut view = model.view;
    let mut model = model;
    let stop = Arc::new(AtomicBool::new(false));
    let done = Arc::new(AtomicU64::new(0));
    let roi_active = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel();
    let start = Instant::now();
    let worker = {
        let (stop, done, roi_active) = (
            Arc::clone(&stop),
            Arc::clone(&done),
            Arc::clone(&roi_active),
        );
        thread::spawn(move || refine(engine, stop, done, roi_active, rx))
    };
    let mut drag: Option<(u32, u32)> = None;
    let mut roi: Option<Rect> = initial_roi;
    if let Some(r) = initial_roi {
        roi_active.store(true, Ordering::Relaxed);
        let _ = tx.send(Command::SetRoi(r));
    }
    // The engine's number (as `refine` counts them).
    let mut number = 1u64;
    // A right-button press: where, the view then, and whether it has moved (an orbit).
    let mut orbit_from: Option<((u32, u32), View, bool)> = None;
    let watched = watched_file(args);
    let mut stamp = watched.as_deref().and_then(modified);
    let mut last_poll = Instant::now();
    let mut completed_written = false;
    let mut last_checkpoint = Instant::now();
    let mut frames = 0u64;
    let mut checkpoint_failed = false;
    let mouse_px = |win: &Window| {
        win.get_mouse_pos(MouseMode::Clamp)
            .map(|(x, y)| ((x as u32).min(w - 1), (y as u32).min(h - 1)))
    };
    let result = loop {
        if !window.is_open()
            || window.is_key_down(Key::Escape)
            || tracer_kit::interrupt::requested()
        {
            break Ok(());
        }
        if args
            .stop_after
            .is_some_and(|s| start.elapsed().as_secs_f64() >= s)
        {
            break Ok(());
        }
        // Region of interest editing.
        let left = window.get_mouse_down(MouseButton::Left);
        match (left, drag, mouse_px(&window)) {
            (true, None, Some(p)) => drag = Some(p),
            (false, Some(a), Some(b)) => {
                drag = None;
                let r = Rect::from_corners(a, b);
                if r.x1 - r.x0 >= 2 && r.y1 - r.y0 >= 2 {
                    roi = Some(r);
                    roi_active.store(true, Ordering::Relaxed);
                    let _ = tx.send(Command::SetRoi(r));
                }
            }
            _ => {}
        }
        // A right click cancels the region; a right drag orbits, the wheel zooms, a
        // changed file reloads: each restarts the refinement.
        let mut restart: Option<(Option<(Model, Options)>, View)> = None;
        let right = window.get_mouse_down(MouseButton::Right);
        match (right, orbit_from, mouse_px(&window)) {
            (true, None, Some(p)) => orbit_from = Some((p, view, false)),
            (true, Some((p0, v0, moved)), Some(p)) => {
                let (dx, dy) = (p.0 as f64 - p0.0 as f64, p.1 as f64 - p0.1 as f64);
                if moved || dx.abs() + dy.abs() > 2.0 {
                    orbit_from = Some((p0, v0, true));
                    let v =
                        model_ir::camera::orbit(&v0, -dx * ORBIT_PER_PIXEL, dy * ORBIT_PER_PIXEL);
                    if v != view {
                        restart = Some((None, v));
                    }
                }
            }
            (false, Some((_, _, moved)), _) => {
                orbit_from = None;
                if !moved {
                    roi = None;
                    let _ = tx.send(Command::CancelRoi);
                }
            }
            _ => {}
        }
        if let Some((_, steps)) = window.get_scroll_wheel() {
            if steps != 0.0 {
                let v = model_ir::camera::zoom(&view, ZOOM_PER_STEP.powf(steps as f64));
                restart = Some((None, v));
            }
        }
        if let Some(path) = &watched {
            if last_poll.elapsed().as_secs_f64() >= RELOAD_POLL_S {
                last_poll = Instant::now();
                let now = modified(path);
                if now != stamp {
                    stamp = now;
                    let domain = args.domain.as_deref().map(|d| ("--domain", d));
                    match crate::args::model_source(&args.src, domain)
                        .and_then(|m| options_for(args, &m).map(|o| (m, o)))
                    {
                        Ok(mo) => {
                            tracer_kit::say!("reloaded {}", path.display());
                            restart = Some((Some(mo), view));
                        }
                        Err(e) => eprintln!("reload of {} failed: {e}", path.display()),
                    }
                }
            }
        }
        if let Some((new_model, v)) = restart {
            let (m, o) = new_model.unwrap_or_else(|| (model.clone(), opts));
            match Engine::new(m.clone(), m.domain, v, w, h, o) {
                Ok(e) => {
                    (model, opts, view) = (m, o, v);
                    image = e.image();
                    number += 1;
                    let _ = tx.send(Command::Restart(Box::new(e)));
                    roi = None;
                    drag = None;
                    roi_active.store(false, Ordering::Relaxed);
                    if completed_written {
                        completed_written = false;
                        window.set_title(&format!("tracer preview: {}", args.title()));
                    }
                }
                Err(e) => eprintln!("cannot restart the preview: {e}"),
            }
        }
        if roi.is_some() && !roi_active.load(Ordering::Relaxed) && drag.is_none() && frames % 8 == 7
        {
            // The refinement thread finished the region.
            roi = None;
        }
        let mut buf = image.snapshot();
        if let Some(r) = roi {
            outline(&mut buf, w, h, r);
        }
        if let (Some(a), Some(b)) = (drag, mouse_px(&window)) {
            outline(&mut buf, w, h, Rect::from_corners(a, b));
        }
        if let Err(e) = window.update_with_buffer(&buf, w as usize, h as usize) {
            break Err(format!("window update failed: {e}"));
        }
        frames += 1;
        if done.load(Ordering::Relaxed) == number && !completed_written {
            completed_written = true;
            window.set_title(&format!(
                "tracer preview: {} (complete, {:.2} s)",
                args.title(),
                start.elapsed().as_secs_f64()
            ));
            if let Some(out) = &args.out {
                checkpoint(&image, out, &mut checkpoint_failed);
            }
        } else if !completed_written && last_checkpoint.elapsed().as_secs_f64() >= CHECKPOINT_S {
            last_checkpoint = Instant::now();
            if let Some(out) = &args.out {
                checkpoint(&image, out, &mut checkpoint_failed);
            }
        }
    };
    stop.store(true, Ordering::Relaxed);
    let (stats, complete) = worker
        .join()
        .map_err(|_| "the refinement thread panicked".to_string())?;
    // Stopped early or complete: the latest image is written either way, and kept in
    // the temporary folder when `--out` cannot be written.
    if let Some(out) = &args.out {
        if write_atomically(&image, out).is_err() {
            save_image(&image, out, "--out")?;
        }
    }
    tracer_kit::say!(
        "{}: {} iterations, {} evaluations, {:.3} s, {} frames",
        if complete {
            "complete"
        } else if tracer_kit::interrupt::requested() {
            "interrupted"
        } else {
            "stopped"
        },
        stats.iterations,
        stats.evals,
        start.elapsed().as_secs_f64(),
        frames
    );
    result
}
