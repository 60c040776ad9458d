//! `tracer preview` run from its arguments: headless snapshots per level, refusals, and
//! an image kept where it cannot be written.

use tracer::progressive::SharedImage;
use tracer_cli::args::ModelArgs;
use tracer_cli::preview::run_preview;
use tracer_cli::preview_args::PreviewArgs;

/// An image that cannot be written at the end is kept in the temporary folder, and the
/// error says where.
#[test]
fn a_failed_write_keeps_the_image_and_says_where() {
    let blocker = std::env::temp_dir().join(format!("tracer-blocker-{}", std::process::id()));
    std::fs::write(&blocker, "a file, not a folder").unwrap();
    let img = SharedImage::new(4, 3, [10, 20, 30]);
    let e =
        tracer_cli::preview_args::save_image(&img, &blocker.join("out.png"), "--out").unwrap_err();
    assert!(
        e.starts_with("--out '") && e.contains("the image is kept in "),
        "{e}"
    );
    let kept = std::path::PathBuf::from(e.rsplit("the image is kept in ").next().unwrap());
    let back = image::open(&kept).unwrap().to_rgb8();
    assert_eq!(back.dimensions(), (4, 3));
    assert_eq!(back.get_pixel(2, 1).0, [10, 20, 30]);
    let _ = std::fs::remove_file(&kept);
    let _ = std::fs::remove_file(&blocker);
}

#[test]
fn headless_preview_writes_a_snapshot_per_level() {
    let dir = std::env::temp_dir().join(format!("tracer-preview-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let args = PreviewArgs {
        src: ModelArgs {
            model: Some("mitchell-gm".into()),
            ..ModelArgs::default()
        },
        domain: None,
        size: None,
        view: Default::default(),
        threads: None,
        width: 24,
        height: 16,
        lambda: None,
        eps: 1e-4,
        overshoot: 1.46,
        aa: 1,
        filter: "quadratic".into(),
        paper_child_start: false,
        bound: "local".into(),
        arith: "revaa".into(),
        headless: true,
        snapshots: Some(dir.clone()),
        out: Some(dir.join("out.png")),
        roi: None,
        roi_level: 0,
        fps: 30,
        stop_after: None,
    };
    run_preview(&args).unwrap();
    // 24x16: gcd 8 = 2*2*2, so levels 0, 1, 2 complete before the pixel level 3.
    for l in 0..3 {
        assert!(dir.join(format!("level-{l:02}.png")).exists(), "level {l}");
    }
    assert!(!dir.join("level-03.png").exists());
    let out = image::open(dir.join("out.png")).unwrap();
    assert_eq!((out.width(), out.height()), (24, 16));
    let bad = PreviewArgs {
        src: ModelArgs {
            model: Some("no-such-model".into()),
            ..ModelArgs::default()
        },
        ..args.clone()
    };
    assert!(run_preview(&bad).is_err());
    let bad = PreviewArgs {
        lambda: Some(-1.0),
        ..args
    };
    assert!(run_preview(&bad).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}
