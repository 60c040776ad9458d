//! `tracer preview`: the headless run (every level's snapshot, Ctrl-C keeping the image
//! refined so far) or the window ([`crate::preview_window`]); [`run_preview`] picks one
//! of the two. The arguments and the engine they set up are in [`crate::preview_args`].

use crate::preview_args::{prepare, save_image, PreviewArgs};
use std::time::Instant;
use tracer::progressive::{Bound, Engine, Rect, Step};

/// Runs `tracer preview`: headless ([`run_headless`]) or in a window
/// ([`crate::preview_window::run_window`]).
pub fn run_preview(args: &PreviewArgs) -> Result<(), String> {
    let (engine, model, roi) = prepare(args)?;
    if args.headless {
        run_headless(engine, args, roi)
    } else {
        crate::preview_window::run_window(engine, model, args, roi)
    }
}

/// Refines to completion without a window, writing a snapshot at every level transition.
pub fn run_headless<S: model_ir::shape::Shape>(
    mut engine: Engine<S>,
    args: &PreviewArgs,
    mut roi: Option<Rect>,
) -> Result<(), String> {
    let start = Instant::now();
    let plan = engine.plan().clone();
    tracer_kit::say!(
        "plan: {}x{} top-level samples of {} px{}, splits {:?}, bound {}, lambda {}",
        plan.u,
        plan.v,
        plan.size,
        if plan.padded {
            " (padded, cropped)"
        } else {
            ""
        },
        plan.splits,
        match engine.options().bound {
            Bound::Range(k) => format!("range --arith {k}"),
            b => b.name().to_string(),
        },
        engine.options().lambda
    );
    // Wall time of refinement only: the snapshots' PNG writing is left out.
    let io = std::cell::Cell::new(std::time::Duration::ZERO);
    let snap = |engine: &Engine<S>, level: usize| -> Result<(), String> {
        let s = engine.stats();
        tracer_kit::say!(
            "level {level} complete: {} iterations, {} evaluations, {:.3} s",
            s.iterations,
            s.evals,
            (start.elapsed() - io.get()).as_secs_f64()
        );
        if let Some(dir) = &args.snapshots {
            let t = Instant::now();
            let p = dir.join(format!("level-{level:02}.png"));
            save_image(&engine.image(), &p, "--snapshots")?;
            io.set(io.get() + t.elapsed());
        }
        Ok(())
    };
    // A snapshot is taken when every sample of a level is processed and before any of
    // the next, as the paper's Figs. 5-7.
    let mut level = 0;
    // Ctrl-C (see [`tracer_kit::interrupt`], installed by the CLI) stops refinement; the image
    // refined so far is still written to `--out` below.
    let mut interrupted = false;
    while !engine.is_done() {
        if tracer_kit::interrupt::requested() {
            interrupted = true;
            break;
        }
        if let Some(l) = engine.next_level() {
            if l > level {
                snap(&engine, level)?;
                level = l;
            }
            if l >= args.roi_level {
                if let Some(r) = roi.take() {
                    engine.set_roi(r)?;
                    let s = engine.stats();
                    tracer_kit::say!(
                        "roi set at level {l}: {} iterations, {:.3} s",
                        s.iterations,
                        (start.elapsed() - io.get()).as_secs_f64()
                    );
                    if let Some(dir) = &args.snapshots {
                        save_image(&engine.image(), &dir.join("roi-set.png"), "--snapshots")?;
                    }
                }
            }
        }
        if let Step::Processed {
            roi_finished: true, ..
        } = engine.step()
        {
            let s = engine.stats();
            tracer_kit::say!(
                "roi done: {} iterations, {:.3} s",
                s.iterations,
                (start.elapsed() - io.get()).as_secs_f64()
            );
            if let Some(dir) = &args.snapshots {
                save_image(&engine.image(), &dir.join("roi-done.png"), "--snapshots")?;
            }
        }
    }
    let s = engine.stats();
    if interrupted {
        eprintln!(
            "interrupted: {} iterations, {} evaluations, {:.3} s; writing the image refined so far",
            s.iterations,
            s.evals,
            (start.elapsed() - io.get()).as_secs_f64()
        );
        if let Some(out) = &args.out {
            save_image(&engine.image(), out, "--out")?;
        }
        return Ok(());
    }
    tracer_kit::say!(
        "done: {} iterations, {} evaluations (+{} for normals, {} range), {:.3} s",
        s.iterations,
        s.evals,
        s.shading_evals,
        s.range_evals,
        (start.elapsed() - io.get()).as_secs_f64()
    );
    // `--out` first: a failing snapshot folder must not cost the final image.
    let out = args
        .out
        .as_ref()
        .map_or(Ok(()), |out| save_image(&engine.image(), out, "--out"));
    if let Some(dir) = &args.snapshots {
        save_image(&engine.image(), &dir.join("final.png"), "--snapshots")?;
    }
    out?;
    Ok(())
}
