//! Ctrl-C keeps what was computed: `tracer render` and `tracer preview --headless`
//! interrupted by SIGINT exit with code 130 and still write a decodable image holding the
//! finished part.
#![cfg(unix)]

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};
use tracer::render::shade::BACKGROUND;

mod common;
use common::start_xvfb;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracer-interrupt-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Starts `tracer args`, sends SIGINT after `after`, and waits for it to exit (killing it
/// and failing if it has not after 30 s, so a broken handler cannot hang the suite).
fn interrupt(args: &[&str], after: Duration) -> Output {
    interrupt_when(args, &[], after, || true)
}

/// [`interrupt`] with another signal (`"TERM"`).
fn signal(sig: &str, args: &[&str], after: Duration) -> Output {
    signal_when(sig, args, &[], after, || true)
}

/// [`interrupt`] with extra environment variables for the child, signalled once `after`
/// has passed and `ready()` holds (polled for at most 90 s more), so a slow or busy
/// machine cannot make the test interrupt before there is anything to keep.
fn interrupt_when(
    args: &[&str],
    env: &[(&str, &str)],
    after: Duration,
    ready: impl Fn() -> bool,
) -> Output {
    signal_when("INT", args, env, after, ready)
}

fn signal_when(
    sig: &str,
    args: &[&str],
    env: &[(&str, &str)],
    after: Duration,
    ready: impl Fn() -> bool,
) -> Output {
    let child = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .envs(env.iter().copied())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start tracer");
    std::thread::sleep(after);
    let waited = Instant::now();
    while !ready() {
        assert!(
            waited.elapsed() < Duration::from_secs(90),
            "tracer {args:?} was not ready within 90 s"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    let pid = child.id().to_string();
    std::thread::sleep(after);
    let st = Command::new("kill")
        .args([&format!("-{sig}"), &pid])
        .status()
        .expect("run kill");
    assert!(
        st.success(),
        "kill -{sig} {pid} failed: it exited before the signal"
    );
    // Reading the pipes while waiting keeps the child from blocking on a full pipe.
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(child.wait_with_output());
    });
    let start = Instant::now();
    loop {
        if let Ok(out) = rx.try_recv() {
            return out.expect("wait for tracer");
        }
        if start.elapsed() > Duration::from_secs(30) {
            let _ = Command::new("kill").args(["-KILL", &pid]).status();
            panic!("tracer {args:?} did not stop within 30 s of SIG{sig}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Pixels that are not the background colour (shaded surface).
fn shaded_pixels(img: &image::RgbImage) -> usize {
    img.pixels().filter(|p| p.0 != BACKGROUND).count()
}

#[test]
fn render_interrupted_writes_the_finished_tiles() {
    let png = tmp("render.png");
    let npy = tmp("render.npy");
    let _ = std::fs::remove_file(&png);
    let _ = std::fs::remove_file(&npy);
    let (w, h) = (1400u32, 1400u32);
    // A bumpy sphere filling the whole frame: every finished pixel is a hit, so any
    // background pixel comes from a tile the interrupt left unfinished. Tens of CPU
    // seconds in full, far past the signal.
    let size = format!("{w}x{h}");
    let args = [
        "render",
        "--expr",
        "1 - x^2 - y^2 - z^2 + 0.05*sin(30*x)*sin(30*y)*sin(30*z)",
        "--eye",
        "0,0,4",
        "--look-at",
        "0,0,0",
        "--fov",
        "20",
        "--arith",
        "ia",
        "--no-culling",
        "--size",
        &size,
        "--out",
        png.to_str().unwrap(),
        "--depth",
        npy.to_str().unwrap(),
    ];
    let out = interrupt(&args, Duration::from_millis(800));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "stderr: {err}");
    assert!(err.contains("interrupted"), "stderr: {err}");
    assert!(!err.contains("panicked"), "stderr: {err}");

    let img = image::open(&png).expect("partial PNG decodes").to_rgb8();
    assert_eq!(img.dimensions(), (w, h));
    let shaded = shaded_pixels(&img);
    assert!(shaded > 0, "no finished tile in the partial image");
    assert!(
        shaded < (w * h) as usize,
        "the image is complete: the render was not interrupted"
    );

    // Depth: NPY float32 (H, W), row-major: every shaded pixel is a hit (finite depth),
    // and unfinished tiles are +inf although every ray would hit.
    let bytes = std::fs::read(&npy).expect("partial depth written");
    assert!(bytes.starts_with(b"\x93NUMPY"), "not an NPY file");
    let data = &bytes[bytes.len() - 4 * (w * h) as usize..];
    let depth: Vec<f32> = data
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    for (k, p) in img.pixels().enumerate() {
        if p.0 != BACKGROUND {
            assert!(depth[k].is_finite(), "shaded pixel {k} has no depth");
        }
    }
    assert!(
        depth.iter().any(|d| d.is_infinite()),
        "the depth map is complete"
    );
}

#[test]
fn headless_preview_interrupted_writes_the_refined_image() {
    let png = tmp("preview.png");
    let _ = std::fs::remove_file(&png);
    let snaps = tmp("snapshots");
    let _ = std::fs::remove_dir_all(&snaps);
    std::fs::create_dir_all(&snaps).unwrap();
    // Refining this hypertexture takes tens of seconds at this size; its coarse levels
    // cover the whole image within a fraction of a second (signalled once the first
    // level's snapshot is written).
    let args = [
        "preview",
        "hypertexture-3",
        "--headless",
        "--width",
        "900",
        "--height",
        "900",
        "--snapshots",
        snaps.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
    ];
    let first = snaps.join("level-00.png");
    let out = interrupt_when(&args, &[], Duration::from_millis(800), || first.exists());
    let err = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(130), "stderr: {err}");
    assert!(err.contains("interrupted"), "stderr: {err}");
    assert!(
        !stdout.contains("done:"),
        "refinement completed before the signal: {stdout}"
    );
    let img = image::open(&png)
        .expect("refined-so-far PNG decodes")
        .to_rgb8();
    assert_eq!(img.dimensions(), (900, 900));
    assert!(
        shaded_pixels(&img) > 0,
        "nothing refined in the written image"
    );
}

#[test]
fn window_preview_interrupted_writes_the_refined_image() {
    let Some((display, mut xvfb)) = start_xvfb() else {
        println!("skipped: Xvfb is not installed");
        return;
    };
    let png = tmp("window.png");
    let _ = std::fs::remove_file(&png);
    let args = [
        "preview",
        "hypertexture-3",
        "--width",
        "900",
        "--height",
        "900",
        "--out",
        png.to_str().unwrap(),
    ];
    // Signalled once a checkpoint (every few seconds) holds refined pixels; removed then,
    // so the image found afterwards is the one written on the interrupt.
    let refined = || {
        let ok = image::open(&png).is_ok_and(|i| shaded_pixels(&i.to_rgb8()) > 0);
        ok && std::fs::remove_file(&png).is_ok()
    };
    let out = interrupt_when(
        &args,
        &[("DISPLAY", &display)],
        Duration::from_millis(1500),
        refined,
    );
    let _ = xvfb.kill();
    let _ = xvfb.wait();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(130),
        "stdout: {stdout} stderr: {err}"
    );
    assert!(stdout.contains("interrupted:"), "stdout: {stdout}");
    let img = image::open(&png)
        .expect("refined-so-far PNG decodes")
        .to_rgb8();
    assert_eq!(img.dimensions(), (900, 900));
    assert!(
        shaded_pixels(&img) > 0,
        "nothing refined in the written image"
    );
}

/// SIGTERM stops a render like Ctrl-C, with the conventional status 128 + 15.
#[test]
fn sigterm_exits_143_and_keeps_the_image() {
    let png = tmp("term.png");
    let _ = std::fs::remove_file(&png);
    let args = [
        "render",
        "--expr",
        "1 - x^2 - y^2 - z^2 + 0.05*sin(30*x)*sin(30*y)*sin(30*z)",
        "--eye",
        "0,0,4",
        "--look-at",
        "0,0,0",
        "--fov",
        "20",
        "--arith",
        "ia",
        "--no-culling",
        "--size",
        "1400x1400",
        "--out",
        png.to_str().unwrap(),
    ];
    let out = signal("TERM", &args, Duration::from_millis(800));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(143), "stderr: {err}");
    assert!(err.contains("interrupted"), "stderr: {err}");
    assert!(!err.contains("depth"), "no --depth was asked for: {err}");
    image::open(&png).expect("partial PNG decodes");
}

/// `tracer mesh` stopped by Ctrl-C exits with 130 promptly and leaves no file, neither
/// the mesh nor its temporary file.
#[test]
fn mesh_interrupted_leaves_no_file() {
    let dir = tmp("mesh");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let ply = dir.join("gyroid.ply");
    // A gyroid at depth 9: hundreds of thousands of surface cells, far past the signal.
    let args = [
        "mesh",
        "--expr",
        "0.3 - abs(sin(8*x)*cos(8*y) + sin(8*y)*cos(8*z) + sin(8*z)*cos(8*x))",
        "--domain",
        "-1,-1,-1,1,1,1",
        "--depth",
        "9",
        "--out",
        ply.to_str().unwrap(),
    ];
    let out = interrupt(&args, Duration::from_millis(800));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "stderr: {err}");
    assert!(err.contains("interrupted"), "stderr: {err}");
    assert!(!err.contains("panicked"), "stderr: {err}");
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "files left behind: {left:?}");
}
