//! `tracer view`'s window under a virtual X display (Xvfb): it opens, shows the GPU's
//! frame and writes it to `--out` on closing, the same image `tracer render --device
//! gpu` gives. Skipped, with a message, where Xvfb or (outside CI) an adapter is missing.
#![cfg(feature = "gpu")]

#[path = "../../tracer-gpu/tests/common/mod.rs"]
mod gpu_device;
#[path = "common/mod.rs"]
mod x11;

use tracer::render::RenderOptions;
use tracer_cli::args::ModelArgs;
use tracer_cli::view::{run_view, ViewWindowArgs};

#[test]
fn window_shows_the_gpu_render_and_writes_it_on_closing() {
    let Some(gpu) = gpu_device::gpu() else { return };
    let Some((display, mut xvfb)) = x11::start_xvfb() else {
        println!("skipped: Xvfb is not installed");
        return;
    };
    std::env::set_var("DISPLAY", &display);
    let dir = std::env::temp_dir().join(format!("tracer-gpu-window-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("view.png");
    let args = ViewWindowArgs {
        src: ModelArgs {
            model: Some("bretzel".into()),
            ..ModelArgs::default()
        },
        view: Default::default(),
        arith: "revaa".into(),
        size: "64x48".into(),
        domain: None,
        no_culling: false,
        no_pruning: false,
        out: Some(out.clone()),
        fps: 30,
        stop_after: Some(0.5),
    };
    let r = run_view(&args);
    let _ = xvfb.kill();
    let _ = xvfb.wait();
    r.expect("view window");
    let shown = image::open(&out).expect("last frame written").to_rgb8();
    let model = model_sources::find("bretzel").unwrap();
    let opts = RenderOptions::new(&model, 64, 48);
    let want =
        tracer_gpu::render::render(gpu, model_ir::arith::ArithKind::Revaa, &model, &opts).unwrap();
    assert!(want.stats.hits > 100, "{} hits", want.stats.hits);
    assert_eq!(shown.dimensions(), (64, 48));
    assert_eq!(
        shown.as_raw(),
        &want.rgb,
        "the window's frame is the render"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
