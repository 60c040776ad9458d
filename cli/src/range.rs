//! `tracer range`: the range of a model over a box in each arithmetic of the one list,
//! as text or JSON (the shortest decimals that read back as the same doubles).

use crate::args::{model_source, ModelArgs};
use crate::stats_json::json_num;
use arith_core::{Arithmetic, Range};
use model_ir::arith::ArithKind;
use model_ir::shape::{Aabb, Shape};
use model_ir::with_arith;
use tracer_kit::out;

/// The `--arith` help text, listing the arithmetics of the one list.
pub fn arith_help(all: bool) -> String {
    let names = ArithKind::names();
    if all {
        format!("Arithmetic: {names}, or all")
    } else {
        format!("Arithmetic: {names}")
    }
}

/// Arguments of `tracer range`.
#[derive(clap::Args, Debug)]
pub struct RangeArgs {
    /// The model: see `tracer render --help`.
    #[command(flatten)]
    pub src: ModelArgs,
    /// The box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX (default: the model's domain; [-2, 2]^3 for
    /// a formula).
    #[arg(long = "box", allow_hyphen_values = true)]
    pub bbox: Option<String>,
    /// Arithmetic.
    #[arg(long, default_value = "all", help = arith_help(true))]
    pub arith: String,
    /// Print JSON: [{"arith": "revaa", "lo": .., "hi": ..}, ...] (null for an infinite bound).
    #[arg(long)]
    pub json: bool,
}

fn range_over<A: Arithmetic, S: Shape>(shape: &S, b: &Aabb) -> (f64, f64) {
    let x = <A::Cell as Range>::input(0, b.min.x, b.max.x);
    let y = <A::Cell as Range>::input(1, b.min.y, b.max.y);
    let z = <A::Cell as Range>::input(2, b.min.z, b.max.z);
    shape.eval(x, y, z).bounds()
}

/// Runs `tracer range`: the range of the model over the box in each arithmetic asked
/// for, as text or JSON.
pub fn run_range(a: &RangeArgs) -> Result<(), String> {
    let model = model_source(&a.src, a.bbox.as_deref().map(|b| ("--box", b)))?;
    let b = model.domain;
    let kinds: Vec<ArithKind> = if a.arith.eq_ignore_ascii_case("all") {
        ArithKind::ALL.to_vec()
    } else {
        vec![a
            .arith
            .parse()
            .map_err(|e| format!("--arith: {e} or all"))?]
    };
    let rows: Vec<(ArithKind, (f64, f64))> = kinds
        .iter()
        .map(|&k| (k, with_arith!(k, A => range_over::<A, _>(&model.shape, &b))))
        .collect();
    if a.json {
        let items: Vec<String> = rows
            .iter()
            .map(|(k, (lo, hi))| {
                format!(
                    "{{\"arith\": \"{}\", \"lo\": {}, \"hi\": {}}}",
                    k.name(),
                    json_num(*lo),
                    json_num(*hi)
                )
            })
            .collect();
        out!("[{}]", items.join(", "));
    } else {
        for (k, (lo, hi)) in rows {
            // Shortest decimals that read back as the same doubles.
            out!("{:<6} [{lo:?}, {hi:?}]", k.name());
        }
    }
    Ok(())
}
