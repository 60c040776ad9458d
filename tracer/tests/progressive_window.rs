//! Smoke test of the live preview window under a virtual X display (Xvfb). Skipped,
//! with a message, on machines without `Xvfb`.

use std::process::{Command, Stdio};
use std::time::Duration;
use tracer::cli::preview::{run_preview, PreviewArgs};
use tracer::cli::ModelArgs;

fn have_xvfb() -> bool {
    Command::new("sh")
        .args(["-c", "command -v Xvfb"])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

#[test]
fn window_refines_for_a_second_then_stops_and_writes_the_image() {
    if !have_xvfb() {
        println!("skipped: Xvfb is not installed");
        return;
    }
    // A free display number: Xvfb exits at once when the number is taken.
    let mut started = None;
    for k in 0..20 {
        let display = format!(":{}", 90 + (std::process::id() + 37 * k) % 900);
        let mut child = Command::new("Xvfb")
            .args([
                display.as_str(),
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start Xvfb");
        std::thread::sleep(Duration::from_millis(700));
        if child.try_wait().expect("poll Xvfb").is_none() {
            started = Some((display, child));
            break;
        }
    }
    let (display, mut xvfb) = started.expect("no free X display for Xvfb");
    // This test binary holds this one test only, so setting the variable races nothing.
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
        ortho: None,
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
