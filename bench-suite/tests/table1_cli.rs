//! Runs the built `bench-suite table1` binary at a tiny scale and checks that every
//! output file is written and that the arithmetics' hit masks agree up to the root
//! precision: no arithmetic misses a ray on which `f64` samples of the model change sign.

use std::path::PathBuf;
use std::process::Command;

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("bench-suite-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn table1_tiny_writes_every_file_and_masks_agree() {
    let dir = out_dir("t1");
    let out = Command::new(env!("CARGO_BIN_EXE_bench-suite"))
        .args([
            "table1",
            "--scale",
            "0.02",
            "--models",
            "mitchell,sphere-noise",
            "--budget",
            "5",
        ])
        .args(["--repeats", "1", "--out"])
        .arg(&dir)
        .output()
        .expect("run bench-suite");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "stdout:\n{stdout}\nstderr:\n{stderr}");

    for f in ["table1.md", "table1.csv", "table1.png"] {
        let p = dir.join(f);
        let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
        assert!(len > 0, "{} missing or empty", p.display());
    }
    for m in ["mitchell", "sphere-noise"] {
        for a in model_ir::arith::ArithKind::ALL.map(|k| k.name()) {
            let p = dir.join(format!("{m}-{a}.png"));
            let img = image::open(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            assert!(img.width() > 0 && img.height() > 0);
        }
    }
    // The table on stdout is the file's content.
    let md = std::fs::read_to_string(dir.join("table1.md")).unwrap();
    assert!(
        stdout.contains(md.lines().nth(4).unwrap()),
        "stdout lacks the table"
    );
    assert!(md.contains("| Mitchell |") && md.contains("| Sphere with noise |"));

    // CSV: one line per (model, arithmetic); every render finished within the budget,
    // every mask was compared, and no arithmetic missed a certain root.
    let csv = std::fs::read_to_string(dir.join("table1.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2 * model_ir::arith::ArithKind::COUNT);
    for r in &rows {
        assert_eq!(r.len(), header.len());
        let who = format!("{} {}", r[col("model")], r[col("arith")]);
        assert_eq!(r[col("stopped")], "false", "{who}");
        assert!(
            !r[col("mask_diff_pixels")].is_empty(),
            "{who}: mask not compared"
        );
        assert_eq!(r[col("missed_roots")], "0", "{who} missed a certain root");
        // Every pixel that differs from the reference is a hit no sign change confirms.
        let diff: usize = r[col("mask_diff_pixels")].parse().unwrap();
        let unconfirmed: usize = r[col("unconfirmed_hits")].parse().unwrap();
        if r[col("arith")] != r[col("mask_reference")] {
            assert!(
                diff <= unconfirmed + rows_unconfirmed_of_ref(&rows, &header, r),
                "{who}"
            );
        }
        assert!(
            r[col("hits")].parse::<u64>().unwrap() > 0,
            "{who}: empty image"
        );
        assert!(!stderr.contains("MISSED ROOTS"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Unconfirmed hits of the reference arithmetic on the same model (a pixel where the
/// reference reports a possible root and another arithmetic proved none).
fn rows_unconfirmed_of_ref(rows: &[Vec<&str>], header: &[&str], r: &[&str]) -> usize {
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    rows.iter()
        .find(|o| o[col("model")] == r[col("model")] && o[col("arith")] == r[col("mask_reference")])
        .map_or(0, |o| o[col("unconfirmed_hits")].parse().unwrap())
}

#[test]
fn bad_arguments_are_clear_errors() {
    for args in [
        &["table1", "--models", "teapot"][..],
        &["table1", "--arith", "ia,foo"],
        &["table1", "--scale", "-1"],
        &["table1", "--budget", "0"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_bench-suite"))
            .args(args)
            .args(["--out"])
            .arg(out_dir("bad"))
            .output()
            .unwrap();
        assert!(!out.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("error"), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}
