//! The previewer's benchmark rows: one per model and method, in the listed order.

use tracer::model_sources::Model;

fn model(name: &str) -> Model {
    tracer::model_sources::gamito_maddock::all()
        .into_iter()
        .find(|m| m.name == name)
        .unwrap()
}

#[test]
fn bench_table_has_a_row_per_model_and_method() {
    let models = vec![model("mitchell-gm")];
    let rows = bench_suite::gm_rows::bench_table(&models, 16, 16).unwrap();
    let methods: Vec<String> = rows.iter().map(|r| r.method.clone()).collect();
    let mut expected: Vec<String> = ["previewer", "previewer-local", "previewer-auto"]
        .map(String::from)
        .to_vec();
    expected.extend(tracer::arith::ArithKind::ALL.map(|k| format!("previewer-range-{k}")));
    expected.extend(["overshoot-rc", "standard-rc", "local-rc"].map(String::from));
    assert_eq!(methods, expected);
    let at = |name: &str| rows.iter().find(|r| r.method == name).unwrap();
    // The range test needs no point evaluation for its cones, only range evaluations.
    assert!(rows
        .iter()
        .all(|r| r.evals + r.range_evals > 0 && r.seconds >= 0.0));
    assert!(rows
        .iter()
        .filter(|r| r.method.starts_with("previewer-range"))
        .all(|r| r.range_evals > 0));
    // The overshooting caster needs fewer evaluations than the standard one.
    assert!(at("overshoot-rc").evals < at("standard-rc").evals);
    let p = at("previewer");
    assert!(p.first_frame_s.is_some() && p.iterations.is_some());
}

#[test]
#[ignore = "timing report at 800x800; run with --ignored --nocapture"]
fn bench_report_800() {
    let models: Vec<Model> = ["mitchell-gm", "hypertexture-1", "blobby"]
        .iter()
        .map(|n| model(n))
        .collect();
    for r in bench_suite::gm_rows::bench_table(&models, 800, 800).unwrap() {
        println!(
            "{:16} {:16} {:9.3} s  evals {:>11}  ranges {:>9}  first frame {:?}  iterations {:?}",
            r.model, r.method, r.seconds, r.evals, r.range_evals, r.first_frame_s, r.iterations
        );
    }
}
