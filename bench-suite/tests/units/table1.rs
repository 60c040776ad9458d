//! Tests of [`bench_suite::table1`].

use bench_suite::table1::*;
use model_ir::arith::ArithKind;
use model_sources::PaperModel;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

#[test]
fn op_counts_match_the_paper_where_the_formula_is_the_papers() {
    // Non-affine and multiplication counts of the algebraic models do not depend on
    // how sums are grouped.
    let m = op_counts(PaperModel::Mitchell);
    assert_eq!((m.non_affine, m.mul), (6, 6));
}

#[test]
fn lists_parse_and_reject_unknown_names() {
    let m = parse_models("sphere-noise, mitchell").unwrap();
    assert_eq!(m, vec![PaperModel::Mitchell, PaperModel::SphereNoise]);
    assert!(parse_models("mitchell,teapot")
        .unwrap_err()
        .contains("teapot"));
    assert_eq!(
        parse_kinds("revaa,ia").unwrap(),
        vec![ArithKind::Ia, ArithKind::Revaa]
    );
    assert!(parse_kinds("ia,xx").is_err());
}

#[test]
fn resolution_scales_and_keeps_a_minimum() {
    assert_eq!(resolution(PaperModel::Mitchell, true, 0.1), (1280, 1024));
    assert_eq!(resolution(PaperModel::Mitchell, false, 0.5), (640, 512));
    assert_eq!(resolution(PaperModel::Csg, false, 0.0001), (4, 4));
}

#[test]
fn bad_options_are_errors() {
    let mut o = Options::new("/tmp/x");
    o.scale = 0.0;
    assert!(o.validate().is_err());
    o.scale = 0.1;
    o.repeats = 0;
    assert!(o.validate().is_err());
}

#[test]
fn utc_date_is_well_formed() {
    let d = utc_now();
    assert_eq!(d.len(), "2026-01-01 00:00 UTC".len());
    assert!(d.starts_with("20"));
}

#[test]
fn cancelled_run_marks_every_cell_and_still_writes_the_tables() {
    let dir = std::env::temp_dir().join(format!("table1-cancel-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let mut o = Options::new(&dir);
    o.scale = 0.02;
    o.models = vec![PaperModel::ALL[0]];
    o.kinds = vec![ArithKind::Ia, ArithKind::Revaa];
    o.repeats = 1;
    o.cancel = Some(Arc::new(AtomicBool::new(true)));
    let r = run(&o).unwrap();
    assert!(r.interrupted);
    assert_eq!(r.rows.len(), 1);
    for c in &r.rows[0].cells {
        assert!(c.interrupted && !c.measured(), "{:?}", c.kind);
        assert!(r.rows[0].ratio_to_revaa(c.kind).is_none());
    }
    let md = std::fs::read_to_string(dir.join("table1.md")).unwrap();
    assert!(md.contains("**Interrupted**") && md.contains("| interrupted |"));
    let csv = std::fs::read_to_string(dir.join("table1.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = head.iter().position(|h| *h == "interrupted").unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2);
    assert!(rows
        .iter()
        .all(|r| r.len() == head.len() && r[col] == "true"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn median_of_even_and_odd() {
    assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
    assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
}
