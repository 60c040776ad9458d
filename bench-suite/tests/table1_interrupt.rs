//! Ctrl-C during `bench-suite table1` keeps what was measured: exit code 130, and
//! table1.md/csv are written with the unmeasured cells marked.
#![cfg(unix)]

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[test]
fn table1_interrupted_writes_the_tables() {
    let dir = std::env::temp_dir().join(format!("bench-suite-int-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    // Every model in every arithmetic at this scale takes minutes: far past the signal.
    let child = Command::new(env!("CARGO_BIN_EXE_bench-suite"))
        .args(["table1", "--scale", "0.2", "--repeats", "1", "--out"])
        .arg(&dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start bench-suite");
    let pid = child.id().to_string();
    std::thread::sleep(Duration::from_millis(1500));
    let st = Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .expect("run kill");
    assert!(
        st.success(),
        "kill -INT {pid} failed: it exited before the signal"
    );
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(child.wait_with_output());
    });
    let start = Instant::now();
    let out = loop {
        if let Ok(out) = rx.try_recv() {
            break out.expect("wait for bench-suite");
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = Command::new("kill").args(["-KILL", &pid]).status();
            panic!("bench-suite did not stop within 60 s of SIGINT");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "stderr:\n{stderr}");

    let md = std::fs::read_to_string(dir.join("table1.md")).expect("table1.md written");
    assert!(md.contains("**Interrupted**"), "{md}");
    let csv = std::fs::read_to_string(dir.join("table1.csv")).expect("table1.csv written");
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    // Every model keeps its rows (one per arithmetic), measured or not.
    let n = model_ir::arith::ArithKind::COUNT;
    assert_eq!(rows.len() % n, 0);
    assert!(rows.len() >= n);
    assert!(rows.iter().all(|r| r.len() == head.len()));
    let interrupted = rows.iter().filter(|r| r[col("interrupted")] == "true");
    assert!(
        interrupted.count() > 0,
        "no cell marked interrupted:\n{csv}"
    );
    // A cell is either marked interrupted or has a time (completed runs or the budget).
    for r in &rows {
        assert!(
            r[col("interrupted")] == "true" || !r[col("seconds_median")].is_empty(),
            "{r:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
