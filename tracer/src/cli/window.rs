//! The live preview (Section 3.5): a refinement thread and a display thread sharing the
//! image buffer ([`crate::progressive::SharedImage`], relaxed atomics, no locks).
//!
//! The display thread (this one: X11 windows belong to the thread that made them) shows
//! the buffer at a steady frame rate and edits the region of interest: drag with the
//! left button to set it, right-click to cancel it. Esc, closing the window or Ctrl-C
//! (see [`crate::interrupt`]) stops the refinement. The image is written to `--out` when
//! refinement completes and when it is stopped early; `--out` is also checkpointed every
//! few seconds, so even a force-quit (a second Ctrl-C) loses at most the last few
//! seconds of refinement.

use super::preview::{save_image, PreviewArgs};
use crate::progressive::{write_png, Engine, Rect, SharedImage, Stats, Step};
use crate::shape::Shape;
use minifb::{Key, MouseButton, MouseMode, Window, WindowOptions};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::Arc;
use std::thread;
use std::time::Instant;

/// Messages from the display thread to the refinement thread.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// Refine this rectangle first.
    SetRoi(Rect),
    /// Refine the whole image again.
    CancelRoi,
}

/// Seconds between checkpoints of `--out` while the window is open.
const CHECKPOINT_S: f64 = 5.0;

/// The refinement thread: steps the engine until done or told to stop, applying ROI
/// commands between samples. Returns the engine's counters and whether it completed.
fn refine<S: Shape>(
    mut engine: Engine<S>,
    stop: Arc<AtomicBool>,
    done: Arc<AtomicBool>,
    roi_active: Arc<AtomicBool>,
    rx: mpsc::Receiver<Command>,
) -> (Stats, bool) {
    while !stop.load(Ordering::Relaxed) {
        while let Ok(c) = rx.try_recv() {
            match c {
                Command::SetRoi(r) => {
                    let _ = engine.set_roi(r);
                }
                Command::CancelRoi => engine.cancel_roi(),
            }
        }
        // A batch of samples between checks keeps the flag and channel overhead small.
        for _ in 0..64 {
            if engine.step() == Step::Done {
                break;
            }
        }
        roi_active.store(engine.roi().is_some(), Ordering::Relaxed);
        if engine.is_done() {
            done.store(true, Ordering::Relaxed);
            return (engine.stats(), true);
        }
    }
    (engine.stats(), false)
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

/// Opens the window and runs the two threads until completion or stop.
/// `initial_roi` (the `--roi` flag) is set at once.
pub fn run_window<S: Shape + 'static>(
    engine: Engine<S>,
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
    let image = engine.image();
    let stop = Arc::new(AtomicBool::new(false));
    let done = Arc::new(AtomicBool::new(false));
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
    let mut right_was_down = false;
    let mut completed_written = false;
    let mut last_checkpoint = Instant::now();
    let mut frames = 0u64;
    let mut checkpoint_failed = false;
    let mouse_px = |win: &Window| {
        win.get_mouse_pos(MouseMode::Clamp)
            .map(|(x, y)| ((x as u32).min(w - 1), (y as u32).min(h - 1)))
    };
    let result = loop {
        if !window.is_open() || window.is_key_down(Key::Escape) || crate::interrupt::requested() {
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
        let right = window.get_mouse_down(MouseButton::Right);
        if right && !right_was_down {
            roi = None;
            let _ = tx.send(Command::CancelRoi);
        }
        right_was_down = right;
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
        if done.load(Ordering::Relaxed) && !completed_written {
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
    crate::say!(
        "{}: {} iterations, {} evaluations, {:.3} s, {} frames",
        if complete {
            "complete"
        } else if crate::interrupt::requested() {
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
