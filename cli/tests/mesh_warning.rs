//! `tracer mesh` says in one warning line how many cells it left unresolved and where,
//! and still writes its mesh.

use std::process::Command;

#[test]
fn unresolved_cells_give_one_warning_line_with_their_box() {
    let dir = std::env::temp_dir().join(format!("tracer-mesh-warning-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let out_path = dir.join("m.obj");
    // A ball, and a ball a ten-thousandth across that no probe to --max-depth finds.
    let expr = "max(0.25 - x^2 - y^2 - z^2, 1e-8 - (x - 1.1)^2 - (y - 1.1)^2 - (z - 1.1)^2)";
    let out = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args([
            "mesh",
            "--expr",
            expr,
            "--depth",
            "3",
            "--max-depth",
            "5",
            "-q",
        ])
        .args(["--out", out_path.to_str().expect("path")])
        .output()
        .expect("run tracer");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(
        warnings[0].contains("stayed unresolved in [") && warnings[0].contains("--max-depth 5"),
        "{}",
        warnings[0]
    );
    // The box is around the small ball, not the large one.
    let box_text = warnings[0].split(" in ").nth(1).expect("a box");
    let first: f64 = box_text
        .trim_start_matches('[')
        .split(',')
        .next()
        .and_then(|v| v.trim().parse().ok())
        .expect("a number");
    assert!(first > 0.5, "{}", warnings[0]);
    assert!(std::fs::metadata(&out_path).is_ok_and(|m| m.len() > 0));
    let _ = std::fs::remove_dir_all(&dir);
}
