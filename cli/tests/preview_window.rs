//! The live preview window under a virtual X display (Xvfb): it refines and writes its
//! image, and reads a model file again when it changes. Skipped, with a message, on
//! machines without `Xvfb`.

use std::process::{Command, Stdio};
use std::time::Duration;

mod common;
use common::start_xvfb;
use std::sync::{Mutex, MutexGuard};
use tracer_cli::args::ModelArgs;
use tracer_cli::preview::run_preview;
use tracer_cli::preview_args::PreviewArgs;

/// One test at a time: two Xvfb servers started at once can race for one display.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

/// A virtual display for this test alone (held until the guard drops), or `None`
/// with a message where Xvfb is not installed.
fn display_alone() -> Option<(MutexGuard<'static, ()>, String, std::process::Child)> {
    let one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let Some((display, xvfb)) = start_xvfb() else {
        println!("skipped: Xvfb is not installed");
        return None;
    };
    Some((one, display, xvfb))
}

#[test]
fn window_refines_for_a_second_then_stops_and_writes_the_image() {
    let Some((_one, display, mut xvfb)) = display_alone() else {
        return;
    };
    // The other test here passes DISPLAY to a child process; none reads it in-process.
    std::env::set_var("DISPLAY", &display);
    let dir = std::env::temp_dir().join(format!("tracer-window-{}", std::process::id()));
    // --out's folder must exist, as for `tracer render`.
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("stopped.png");
    let args = PreviewArgs {
        src: ModelArgs {
            model: Some("hypertexture-5".into()),
            ..ModelArgs::default()
        },
        domain: None,
        size: None,
        view: Default::default(),
        threads: None,
        width: 200,
        height: 160,
        lambda: None,
        eps: 1e-4,
        overshoot: 1.46,
        aa: 1,
        filter: "quadratic".into(),
        paper_child_start: false,
        bound: "local".into(),
        arith: "revaa".into(),
        headless: false,
        snapshots: None,
        out: Some(out.clone()),
        roi: None,
        roi_level: 0,
        fps: 30,
        stop_after: Some(1.0),
    };
    let r = run_preview(&args);
    let _ = xvfb.kill();
    let _ = xvfb.wait();
    r.expect("window preview");
    // Stopped after one second, before completion: the refined part is in the file.
    let img = image::open(&out)
        .expect("image written when stopped")
        .to_rgb8();
    assert_eq!(img.dimensions(), (200, 160));
    let bg = tracer::render::shade::BACKGROUND;
    let shaded = img.pixels().filter(|p| p.0 != bg).count();
    assert!(shaded > 1000, "only {shaded} shaded pixels");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A model file changed while the window is open is read again: a file that does not
/// read keeps the last model (the error on stderr), one that does replaces it.
#[test]
fn window_reloads_a_changed_model_file() {
    let Some((_one, display, mut xvfb)) = display_alone() else {
        return;
    };
    let dir = std::env::temp_dir().join(format!("tracer-reload-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (model, out) = (dir.join("ball.expr"), dir.join("reloaded.png"));
    std::fs::write(&model, "1 - x^2 - y^2 - z^2\n").unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args([
            "preview",
            model.to_str().unwrap(),
            "--size",
            "48x48",
            "--out",
        ])
        .arg(&out)
        .args(["--stop-after", "6"])
        .env("DISPLAY", &display)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start tracer");
    // Edits a second apart (the window looks every half second): a broken one, then
    // a function with no surface at all.
    std::thread::sleep(Duration::from_millis(2000));
    std::fs::write(&model, "1 - x^\n").unwrap();
    std::thread::sleep(Duration::from_millis(1500));
    std::fs::write(&model, "-1 - x^2\n").unwrap();
    let waited = std::time::Instant::now();
    while child.try_wait().expect("poll tracer").is_none() {
        if waited.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("the preview did not stop");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let res = child.wait_with_output().expect("tracer output");
    let _ = xvfb.kill();
    let _ = xvfb.wait();
    let err = String::from_utf8_lossy(&res.stderr);
    assert!(res.status.success(), "stderr: {err}");
    assert!(
        err.contains("reload of") && err.contains("failed"),
        "stderr: {err}"
    );
    let said = String::from_utf8_lossy(&res.stdout);
    assert!(said.contains("reloaded"), "stdout: {said}");
    // The last model has no surface: the image written at the end is all background.
    let img = image::open(&out).expect("image written").to_rgb8();
    let bg = tracer::render::shade::BACKGROUND;
    assert!(
        img.pixels().all(|p| p.0 == bg),
        "the first model is still drawn"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
