//! `tracer view`: a real-time window on the GPU renderer ([`tracer_gpu::render`]). The model is
//! compiled to a shader once; every frame whose view changed is searched again on the
//! device, as `tracer render --device gpu` would, and shown. Drag with either mouse
//! button (or press the arrow keys) to orbit about the point looked at, turn the wheel
//! (or press `+` / `-`) to zoom, `R` to return to the starting view; Esc, closing the
//! window or Ctrl-C stops, writing the last frame to `--out` if given. The title shows
//! each frame's time and its hit and unconfirmed pixel counts.

use crate::args::{ModelArgs, ViewArgs};
use std::path::PathBuf;

/// Arguments of `tracer view`.
#[derive(clap::Args, Debug, Clone)]
pub struct ViewWindowArgs {
    /// The model: see `tracer render --help`.
    #[command(flatten)]
    pub src: ModelArgs,
    /// The starting camera: as for `tracer render`.
    #[command(flatten)]
    pub view: ViewArgs,
    /// Arithmetic: ia, raa or revaa (the GPU's).
    #[arg(long, default_value = "revaa")]
    pub arith: String,
    /// Window size WxH.
    #[arg(long, default_value = "800x600", allow_hyphen_values = true)]
    pub size: String,
    /// Domain box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX.
    #[arg(long, allow_hyphen_values = true)]
    pub domain: Option<String>,
    /// Disable the culling pass over screen cells.
    #[arg(long)]
    pub no_culling: bool,
    /// Disable argument pruning.
    #[arg(long)]
    pub no_pruning: bool,
    /// Write the last frame here (PNG) when the window closes.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Window frame rate (the GPU renders only when the view changes).
    #[arg(long, default_value_t = 60)]
    pub fps: u32,
    /// Close the window by itself after this many seconds (for tests and demos).
    #[arg(long)]
    pub stop_after: Option<f64>,
}

/// Opens the window and renders until stopped. Everything the flags name is checked
/// (model, arithmetic, size, `--out`'s folder, the adapter, the shader) before the
/// window opens.
pub fn run_view(args: &ViewWindowArgs) -> Result<(), String> {
    #[cfg(feature = "gpu")]
    return on_gpu::run(args);
    #[cfg(not(feature = "gpu"))]
    {
        let _ = args;
        Err(
            "tracer view: this tracer was built without the GPU renderer; build it with \
             `cargo build --release -p tracer-cli --features gpu`"
                .into(),
        )
    }
}

#[cfg(feature = "gpu")]
mod on_gpu {
    use super::ViewWindowArgs;
    use crate::args::{model_source, parse_size};
    use crate::preview_window::{ORBIT_PER_PIXEL, ZOOM_PER_STEP};
    use minifb::{Key, KeyRepeat, MouseButton, MouseMode, Window, WindowOptions};
    use model_ir::arith::ArithKind;
    use model_ir::camera::{orbit, zoom};
    use model_ir::shape::View;
    use std::time::Instant;
    use tracer::progressive::pack;
    use tracer::render::{RenderOptions, RenderResult};
    use tracer_gpu::{Gpu, Tracer};
    use tracer_kit::output::{check_outputs, write_png};

    /// Orbit per press of an arrow key, in radians (a drag and the wheel move as in
    /// the previewer's window).
    const ORBIT_PER_KEY: f64 = 0.1;

    /// The window's image: `rgb` as minifb's `0RGB` words.
    fn to_words(rgb: &[u8]) -> Vec<u32> {
        rgb.chunks_exact(3)
            .map(|p| pack([p[0], p[1], p[2]]))
            .collect()
    }

    /// Renders `view` with `tracer`, or says why not.
    fn frame(tracer: &Tracer, base: &RenderOptions, view: View) -> Result<RenderResult, String> {
        let opts = RenderOptions {
            view,
            ..base.clone()
        };
        tracer_gpu::render::render_with(tracer, &opts)
    }

    pub fn run(args: &ViewWindowArgs) -> Result<(), String> {
        let kind: ArithKind = args.arith.parse().map_err(|e| format!("--arith: {e}"))?;
        let arith = tracer_gpu::render::gpu_arith(kind).map_err(|e| format!("--arith: {e}"))?;
        let (w, h) = parse_size("--size", &args.size)?;
        if args.fps == 0 || args.fps > 240 {
            return Err(format!("--fps must be in 1..=240, got {}", args.fps));
        }
        if let Some(s) = args.stop_after {
            if !(s.is_finite() && s >= 0.0) {
                return Err(format!(
                    "--stop-after {s}: must be a number of seconds >= 0"
                ));
            }
        }
        if let Some(out) = &args.out {
            check_outputs(out, None)?;
        }
        let model = model_source(&args.src, args.domain.as_deref().map(|d| ("--domain", d)))?;
        let start_view = args.view.apply(model.view)?;
        model_ir::camera::Camera::try_new(start_view, w, h).map_err(|e| format!("camera: {e}"))?;
        let program = model.tape()?;
        let gpu = Gpu::new()?;
        let tracer = Tracer::new(&gpu, &program, arith)?;
        let mut base = RenderOptions::for_view(start_view, model.domain, w, h);
        base.culling = !args.no_culling;
        base.pruning = !args.no_pruning;
        let mut last = frame(&tracer, &base, start_view)?;
        let mut view = start_view;

        let title = |res: &RenderResult| {
            format!(
                "tracer view: {} ({kind}, {:.0} ms, {} hits, {} unconfirmed)",
                args.src.title(),
                res.stats.wall.as_secs_f64() * 1e3,
                res.stats.hits,
                res.stats.unconfirmed
            )
        };
        let mut window = Window::new(&title(&last), w as usize, h as usize, {
            WindowOptions::default()
        })
        .map_err(|e| format!("cannot open a window ({e}); use `tracer render --device gpu`"))?;
        window.set_target_fps(args.fps as usize);
        let mut buf = to_words(&last.rgb);
        let started = Instant::now();
        let mut frames = 0u64;
        // A drag: where it started and the view then.
        let mut drag: Option<((f32, f32), View)> = None;
        let result = loop {
            if !window.is_open()
                || window.is_key_down(Key::Escape)
                || tracer_kit::interrupt::requested()
            {
                break Ok(());
            }
            if args
                .stop_after
                .is_some_and(|s| started.elapsed().as_secs_f64() >= s)
            {
                break Ok(());
            }
            let mut next = view;
            let down = window.get_mouse_down(MouseButton::Left)
                || window.get_mouse_down(MouseButton::Right);
            match (down, drag, window.get_mouse_pos(MouseMode::Pass)) {
                (true, None, Some(p)) => drag = Some((p, view)),
                (true, Some((p0, v0)), Some(p)) => {
                    let (dx, dy) = (f64::from(p.0 - p0.0), f64::from(p.1 - p0.1));
                    next = orbit(&v0, -dx * ORBIT_PER_PIXEL, dy * ORBIT_PER_PIXEL);
                }
                (false, Some(_), _) => drag = None,
                _ => {}
            }
            for (key, yaw, pitch) in [
                (Key::Left, ORBIT_PER_KEY, 0.0),
                (Key::Right, -ORBIT_PER_KEY, 0.0),
                (Key::Up, 0.0, -ORBIT_PER_KEY),
                (Key::Down, 0.0, ORBIT_PER_KEY),
            ] {
                if window.is_key_pressed(key, KeyRepeat::Yes) {
                    next = orbit(&next, yaw, pitch);
                }
            }
            let mut steps = window.get_scroll_wheel().map_or(0.0, |(_, s)| f64::from(s));
            if window.is_key_pressed(Key::Equal, KeyRepeat::Yes)
                || window.is_key_pressed(Key::NumPadPlus, KeyRepeat::Yes)
            {
                steps += 1.0;
            }
            if window.is_key_pressed(Key::Minus, KeyRepeat::Yes)
                || window.is_key_pressed(Key::NumPadMinus, KeyRepeat::Yes)
            {
                steps -= 1.0;
            }
            if steps != 0.0 {
                next = zoom(&next, ZOOM_PER_STEP.powf(steps));
            }
            if window.is_key_pressed(Key::R, KeyRepeat::No) {
                next = start_view;
            }
            if next != view {
                // A view the camera refuses (zoomed onto the point looked at) keeps the last.
                match frame(&tracer, &base, next) {
                    Ok(res) => {
                        window.set_title(&title(&res));
                        buf = to_words(&res.rgb);
                        (last, view) = (res, next);
                    }
                    Err(e) => eprintln!("view not rendered: {e}"),
                }
            }
            if let Err(e) = window.update_with_buffer(&buf, w as usize, h as usize) {
                break Err(format!("window update failed: {e}"));
            }
            frames += 1;
        };
        if let Some(out) = &args.out {
            write_png(out, w, h, &last.rgb).map_err(|e| format!("--out: {e}"))?;
            tracer_kit::say!("wrote {}", out.display());
        }
        tracer_kit::say!(
            "{} frames in {:.2} s",
            frames,
            started.elapsed().as_secs_f64()
        );
        result
    }
}
