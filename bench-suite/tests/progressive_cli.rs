//! Runs the built `bench-suite progressive` binary at a tiny size and checks that every
//! output file is written, every method counted point evaluations, and bad input is a
//! clear error.

use std::path::PathBuf;
use std::process::Command;

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("bench-suite-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn progressive_tiny_writes_every_file_with_positive_counts() {
    let dir = out_dir("prog");
    let out = Command::new(env!("CARGO_BIN_EXE_bench-suite"))
        .args(["progressive", "--size", "48", "--models"])
        .args(["mitchell-gm,hypertexture-1", "--layers", "2", "--out"])
        .arg(&dir)
        .output()
        .expect("run bench-suite");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "stdout:\n{stdout}\nstderr:\n{stderr}");

    for f in [
        "progressive.md",
        "progressive.csv",
        "fig9.csv",
        "fig9.png",
        "fig9-evals.png",
    ] {
        let p = dir.join(f);
        let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
        assert!(len > 0, "{} missing or empty", p.display());
    }
    let img = image::open(dir.join("fig9.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (1200, 600));
    // The previewer's bars (first palette colour) were drawn.
    let red = image::Rgb([0xd6, 0x27, 0x28]);
    assert!(img.pixels().filter(|p| **p == red).count() > 100);

    let md = std::fs::read_to_string(dir.join("progressive.md")).unwrap();
    assert!(
        stdout.contains(md.lines().nth(4).unwrap()),
        "stdout lacks the table"
    );
    assert!(md.contains("first full-frame preview of mitchell-gm"));

    let check = |file: &str, expect_rows: usize| {
        let csv = std::fs::read_to_string(dir.join(file)).unwrap();
        let mut lines = csv.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len(), expect_rows, "{file}");
        for r in &rows {
            assert_eq!(r.len(), header.len(), "{file}");
            let who = format!("{file}: {} {}", r[col("model")], r[col("method")]);
            let evals: u64 = r[col("point_evals")].parse().unwrap();
            assert!(evals > 0, "{who}: no point evaluations");
            assert_eq!(r[col("width")], "48", "{who}");
            // Paper numbers are only shown at the paper's size.
            assert!(r[col("paper_evals")].is_empty(), "{who}");
            if r[col("method")] == "previewer" {
                assert!(!r[col("first_frame_s")].is_empty(), "{who}: no first frame");
            }
        }
    };
    // Two models, and L = 1, 2, each x every method (the range test once per arithmetic
    // of the one list).
    let n = bench_suite::gm_table1::methods().len();
    check("progressive.csv", 2 * n);
    check("fig9.csv", 2 * n);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_is_a_clear_error() {
    for (args, needle) in [
        (vec!["--models", "teapot"], "unknown model 'teapot'"),
        (vec!["--size", "0"], "--size 0"),
        (vec!["--layers", "9"], "--layers 9"),
    ] {
        let dir = out_dir("prog-bad");
        let out = Command::new(env!("CARGO_BIN_EXE_bench-suite"))
            .arg("progressive")
            .args(&args)
            .arg("--out")
            .arg(&dir)
            .output()
            .expect("run bench-suite");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?} succeeded");
        assert!(stderr.contains(needle), "{args:?}: {stderr}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
