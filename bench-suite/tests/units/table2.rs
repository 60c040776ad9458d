//! Tests of [`bench_suite::table2`].

use bench_suite::table2::*;

fn row(model: &str, size: (u32, u32)) -> Row {
    Row {
        model: model.into(),
        size,
        fps: vec![[1.0, 2.0]; 3],
        hits: vec![0; 3],
    }
}

#[test]
fn the_papers_figures_stand_beside_their_rows_at_512() {
    let md = markdown(
        "dev",
        &[
            row("mitchell", (512, 512)),
            row("shikki", (512, 512)),
            row("hair", (512, 512)),
            row("mitchell", (1920, 1080)),
        ],
    );
    let lines: Vec<&str> = md.lines().filter(|l| l.starts_with("| ")).collect();
    assert!(
        lines[1].ends_with("| 28.1 / 90.1 / 92.2 / 97.4 |"),
        "{}",
        lines[1]
    );
    assert!(
        lines[2].ends_with("| 0.56 / 5.12 / 5.95 / 6.1 (Cup) |"),
        "{}",
        lines[2]
    );
    assert!(lines[3].ends_with("| - |"), "{}", lines[3]);
    assert!(lines[4].ends_with("| - |"), "{}", lines[4]);
    assert!(lines[1].contains("| 1.00 | 2.00 |"));
}
