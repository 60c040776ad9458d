//! Tests of [`bench_suite::progressive`].

use bench_suite::gm_rows::BenchRow;
use bench_suite::gm_table1::*;

fn row(model: &str, method: &str, evals: u64) -> BenchRow {
    BenchRow {
        model: model.into(),
        method: method.into(),
        seconds: 1.0,
        evals,
        range_evals: 0,
        first_frame_s: None,
        iterations: None,
    }
}

#[test]
fn table_models_exist_and_carry_a_lipschitz_bound() {
    let ms = parse_models(&TABLE_MODELS.join(",")).unwrap();
    assert_eq!(ms.len(), 3);
    assert!(ms.iter().all(|m| m.lipschitz.is_some()));
    for l in 1..=FIG9_LAYERS {
        parse_models(&format!("hypertexture-{l}")).unwrap();
    }
}

#[test]
fn unknown_or_empty_models_are_errors() {
    let e = parse_models("mitchell-gm,teapot").unwrap_err();
    assert!(e.contains("teapot") && e.contains("blobby"), "{e}");
    assert!(parse_models(" , ").is_err());
    assert_eq!(parse_models("blobby,BLOBBY").unwrap().len(), 1);
}

#[test]
fn goal_misses_name_the_model_and_the_caster() {
    let rows = vec![
        row("a", &goal_previewer(), 5),
        row("a", "overshoot-rc", 6),
        row("a", "standard-rc", 9),
        row("b", &goal_previewer(), 7),
        row("b", "overshoot-rc", 7),
        row("b", "standard-rc", 9),
    ];
    let m = eval_goal_misses(&rows);
    assert_eq!(m.len(), 1, "{m:?}");
    assert!(m[0].contains("on b ") && m[0].contains("overshoot-rc"));
}

#[test]
fn paper_cells_only_at_the_paper_size() {
    let c = paper_cell("blobby", "standard-rc", 800).unwrap();
    assert_eq!(c.evals, 84_760_569);
    assert!(paper_cell("blobby", "standard-rc", 64).is_none());
    assert!(paper_cell("blobby", "local-rc", 800).is_none());
    // The paper's own rows satisfy the goal on counts (its claim in Section 4).
    for r in PAPER_TABLE1 {
        assert!(r.previewer.evals < r.overshoot.evals.min(r.standard.evals));
    }
}
