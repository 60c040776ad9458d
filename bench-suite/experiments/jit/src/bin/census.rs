//! How many evaluations a render makes per specialised tape: renders fidget's bear in IA
//! through the library with the tape wrapped in a [`Shape`] that counts, per distinct
//! tape (the base and every specialisation the renderer builds), the lanes it
//! evaluates over ranges and over points, and prints the census as JSON lines and a
//! summary.
//!
//! `cargo run --release --bin census -- 256` (image size; the view is the README's bear
//! render: `--ortho 2 --eye 0,0,2 --look-at 0,0,0 --domain=-1,-1,-1,1,1,1`).

use arith_core::{Range, Real};
use arith_ia::{IaArith, Interval, IntervalX4};
use glam::DVec3;
use model_ir::Tape;
use std::any::TypeId;
use std::collections::HashMap;
use std::sync::Mutex;
use tracer::render::{render, RenderOptions};
use tracer::shape::{Aabb, Shape, View};

#[derive(Clone, Copy, Default, Debug)]
struct Count {
    len: usize,
    range_lanes: u64,
    point_lanes: u64,
    other_lanes: u64,
    calls: u64,
}

static CENSUS: Mutex<Option<HashMap<usize, Count>>> = Mutex::new(None);

/// The bear's tape, counting its evaluations.
struct Counted(Tape);

impl Counted {
    fn note<R: Real>(&self, lanes: usize) {
        let (range, point) = if TypeId::of::<R>() == TypeId::of::<f64>() {
            (0, 1)
        } else if TypeId::of::<R>() == TypeId::of::<Interval>() {
            (1, 0)
        } else if TypeId::of::<R>() == TypeId::of::<IntervalX4>() {
            (4, 0)
        } else {
            (0, 0)
        };
        let key = self.0.instructions().as_ptr() as usize;
        let mut g = CENSUS.lock().unwrap();
        let c = g.get_or_insert_with(HashMap::new).entry(key).or_default();
        c.len = self.0.len();
        c.calls += 1;
        c.range_lanes += (range * lanes) as u64;
        c.point_lanes += (point * lanes) as u64;
        if range == 0 && point == 0 {
            c.other_lanes += lanes as u64;
        }
    }
}

impl Shape for Counted {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        self.note::<R>(1);
        self.0.eval(x, y, z)
    }
    fn eval_batch<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        self.note::<R>(x.len());
        self.0.eval_batch(x, y, z, out)
    }
    fn packs(&self) -> bool {
        !self.0.has_branches()
    }
    fn specialises(&self) -> bool {
        self.0.specialises()
    }
    fn specialises_values(&self) -> bool {
        self.0.specialises_values()
    }
    fn tape_len(&self) -> Option<usize> {
        Some(self.0.len())
    }
    fn specialise<R: Range>(&self, regions: &[[R; 3]]) -> Option<Self> {
        self.0.specialise(regions).map(Counted)
    }
    fn specialise_groups<R: Range>(
        &self,
        regions: &[[R; 3]],
        groups: &[(usize, usize)],
    ) -> (Vec<Self>, Vec<Option<usize>>) {
        let (s, w) = self.0.specialise_groups(regions, groups);
        (s.into_iter().map(Counted).collect(), w)
    }
    fn specialise_values<R: Range>(&self, region: &[R; 3], within: f64) -> Option<Self> {
        self.0.specialise_values(region, within).map(Counted)
    }
}

fn main() {
    let size: u32 = std::env::args()
        .nth(1)
        .map(|s| s.parse().expect("an image size"))
        .unwrap_or(256);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../peers/fidget/models/bear.vm"
    );
    let tape = tracer::models::vm::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
    let base = tape.instructions().as_ptr() as usize;
    let view = View {
        eye: DVec3::new(0.0, 0.0, 2.0),
        look_at: DVec3::ZERO,
        up: DVec3::Y,
        fov_deg: 30.0,
        ortho: Some(2.0),
    };
    let opts = RenderOptions::for_view(view, Aabb::cube(1.0), size, size);
    let shape = Counted(tape);
    let r = render::<IaArith, _>(&shape, &opts).expect("renders");
    let s = r.stats;
    let census = CENSUS.lock().unwrap().take().unwrap_or_default();
    let mut tapes: Vec<Count> = census
        .iter()
        .filter(|(k, _)| **k != base)
        .map(|(_, c)| *c)
        .collect();
    tapes.sort_by_key(|c| c.range_lanes + c.point_lanes);
    let b = census.get(&base).copied().unwrap_or_default();
    let lanes = |c: &Count| c.range_lanes + c.point_lanes + c.other_lanes;
    let total_range: u64 = census.values().map(|c| c.range_lanes).sum();
    let total_point: u64 = census.values().map(|c| c.point_lanes).sum();
    let total_other: u64 = census.values().map(|c| c.other_lanes).sum();
    let range_ops: u64 = census.values().map(|c| c.range_lanes * c.len as u64).sum();
    let spec_range_ops: u64 = tapes.iter().map(|c| c.range_lanes * c.len as u64).sum();
    let spec_instr: u64 = tapes.iter().map(|c| c.len as u64).sum();
    let pct = |p: f64| {
        if tapes.is_empty() {
            0
        } else {
            lanes(&tapes[((tapes.len() - 1) as f64 * p) as usize])
        }
    };
    let n = tapes.len().max(1) as f64;
    println!(
        "{{\"size\": {size}, \"tiles\": {}, \"wall_s\": {:.2}, \"range_evals\": {}, \
         \"cell_evals\": {}, \"shade_evals\": {}, \"point_evals\": {}, \"range_ops\": {}, \
         \"base_len\": {}, \"base_range_lanes\": {}, \"base_point_lanes\": {}, \
         \"specialised_tapes\": {}, \"mean_specialised_len\": {:.1}, \
         \"range_lanes\": {total_range}, \"point_lanes\": {total_point}, \
         \"other_lanes\": {total_other}, \"range_lane_instructions\": {range_ops}, \
         \"specialised_range_lane_instructions\": {spec_range_ops}, \
         \"lanes_per_specialised_tape_mean\": {:.1}, \"median\": {}, \"p90\": {}, \"max\": {}, \
         \"range_lane_instructions_per_specialised_instruction\": {:.1}}}",
        s.tiles_total,
        s.wall.as_secs_f64(),
        s.range_evals,
        s.cell_evals,
        s.shade_evals,
        s.point_evals,
        s.range_ops,
        shape.0.len(),
        b.range_lanes,
        b.point_lanes,
        tapes.len(),
        spec_instr as f64 / n,
        tapes.iter().map(lanes).sum::<u64>() as f64 / n,
        pct(0.5),
        pct(0.9),
        pct(1.0),
        spec_range_ops as f64 / spec_instr.max(1) as f64,
    );
}
