//! The octree search: from the cube down to the leaf level, a cell whose range of `f`
//! (the arithmetic's cell form, three independent symbols as culling's cells) excludes
//! 0 is proved empty or full and dropped; the others are split. A leaf with a sign
//! change among its corners is kept for dual contouring.
//!
//! A leaf whose range still holds 0 while its 8 corners agree is *not* assumed empty
//! (the peers' mistake: features thinner than a cell vanish). Unless the
//! Plantinga–Vegter test certifies it (then any surface in it is one sheet that its
//! neighbours' sign changes account for: a bulge of the surface through a face, not a
//! feature of its own), it is probed below the leaf level, down to the maximum depth,
//! until every sub-cell is excluded by one of the tighter tests of
//! [`super::exclusion`] (interval arithmetic, the mean value form) or certified, or a
//! sub-cell shows a sign change among its corners. A sign change at level `d` says
//! that the leaf level must be at least `d` for that part of the surface to be meshed;
//! the caller then searches again at that level ([`Descent::needs`]). Probes that reach
//! the maximum depth with a range that still holds 0 and no sign change are counted
//! ([`Descent::unresolved`]): a tangency, a feature thinner than the finest cell, or
//! the arithmetic's overestimation.
//!
//! Probing is held to a budget proportional to the mesh: each task (a subtree handed
//! to a thread) may evaluate [`PROBE_FLOOR`] sub-cells plus [`PROBE_PER_CELL`] per
//! surface cell it has found so far, and one leaf at most [`PROBE_BUDGET`]. A task's
//! cells are visited in a fixed order, so what the budget leaves is the same on every
//! run; it is counted as unresolved, with the box around it ([`Descent::unresolved_box`]).
//!
//! A leaf with a sign change that is not certified, nor monotone along every axis
//! ([`monotone`]: then no lattice in it can show another topology), is checked on a
//! finer lattice of points ([`super::consistency`]): where the lattice shows another topology than the
//! corners (a thin shell through a corner), the leaf level must rise too. Each such
//! leaf is checked once, at most `9^3` points in one batch evaluation of its own tape,
//! so these checks are bounded by the mesh's size on their own and take nothing from
//! the probes' budget (nor leave cells unresolved).
//!
//! The shape is specialised to every cell (sign-only): the cube by
//! [`Shape::specialise`], every cell below from the interval evaluation of its
//! parent's eight sub-cells in one batch ([`Shape::eval_boxes_traced`], then
//! [`Shape::specialise_traced`] per sub-cell, without evaluating it again); the
//! shorter shape serves the cell's subtree's range tests. The levels above the tasks'
//! (level 3) are searched once ([`Octree::tops`]), so each task starts from its own
//! cell's tape. Point values (corner signs, finer lattices) use each cell's
//! value-exact tape ([`super::cell_tape`]), specialised at every level from its
//! parent's, which each leaf kept for contouring hands on ([`Descent::tapes`]).

use super::cell_tape::{specialise_to, tape, CellTape};
use super::certificate::{cell_gradient, certifies, meet};
use super::consistency::finer_topology;
use super::exclusion::{gradient_verdict, interval_excludes, Test, Verdict};
use super::grid::{
    cell_inputs, corner_mask, corner_of, corner_offset, crosses, inside_batch, Clipped, Grid,
};
use arith_core::{Arithmetic, Range};
use glam::DVec3;
use model_ir::arith::arith_ia::{IaArith, Interval};
use model_ir::shape::{Aabb, Shape};
use model_ir::shape_batch::Batch;
use model_ir::Trace;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Sub-cells a probe evaluates at most per leaf.
pub const PROBE_BUDGET: u32 = 256;

/// Sub-cells each task may probe whatever it finds.
pub const PROBE_FLOOR: u64 = 64;

/// Sub-cells a task may probe per surface cell it has found.
pub const PROBE_PER_CELL: u64 = 4;

/// Cells are handed to threads as the subtrees below this level.
const TASK_LEVEL: u32 = 3;

/// A task's buffers for [`Octree::kid_tapes`], kept from cell to cell.
#[derive(Default)]
struct Scratch {
    /// The sub-cells' boxes, per axis.
    boxes: [Vec<Interval>; 3],
    /// Their ranges.
    out: Vec<Interval>,
    /// What their evaluation recorded for specialisation.
    trace: Trace,
}

/// A cell where a task starts ([`Octree::tops`]).
struct Top<S> {
    c: [u32; 3],
    /// Its sign tape: an index into the tapes built above it, `None` for the shape.
    tape: Option<usize>,
    value: CellTape<S>,
}

/// What the search found.
#[derive(Clone, Debug)]
pub struct Descent<S> {
    /// Leaves at the leaf level with a sign change among their corners.
    pub cells: Vec<[u32; 3]>,
    /// Each leaf's value-exact tape ([`super::cell_tape`]), in the order of `cells`.
    pub tapes: Vec<CellTape<S>>,
    /// Whether the Plantinga–Vegter test certifies each leaf (on its sign tape, whose
    /// zero set is the shape's there), in the order of `cells`.
    pub certified: Vec<bool>,
    /// The deepest level at which a probe below the leaf level found a sign change
    /// (the leaf level itself when none did).
    pub needs: u32,
    /// Probes at the maximum depth whose range still held 0 with no sign change, and
    /// sub-cells and lattices the budget left unexamined.
    pub unresolved: u64,
    /// The box around the unresolved cells (`None` when there are none).
    pub unresolved_box: Option<Aabb>,
    /// Leaves where a probe or a finer lattice found a feature, each with the leaf
    /// level it needs (deeper than the search's).
    pub deeper: Vec<(u32, [u32; 3])>,
    /// Cells that interval arithmetic or the mean value form excluded while the
    /// arithmetic's range did not.
    pub excluded: u64,
    /// Budget units spent (sub-cells probed).
    pub spent: u64,
    /// Cells whose range was evaluated.
    pub visited: u64,
    /// Cells dropped because their range excluded 0.
    pub pruned: u64,
    /// Cells below the leaf level that probes evaluated.
    pub probed: u64,
    /// Point evaluations (corner signs).
    pub point_evals: u64,
    /// Cells whose shape was specialised.
    pub specialised: u64,
    /// Plantinga–Vegter tests of probed cells.
    pub certificates: u64,
    /// Leaves with a sign change whose finer lattice showed another topology.
    pub finer: u64,
    /// Whether the search was cancelled (the result is then incomplete).
    pub cancelled: bool,
}

impl<S> Default for Descent<S> {
    fn default() -> Self {
        Descent {
            cells: Vec::new(),
            tapes: Vec::new(),
            certified: Vec::new(),
            needs: 0,
            unresolved: 0,
            unresolved_box: None,
            deeper: Vec::new(),
            excluded: 0,
            spent: 0,
            visited: 0,
            pruned: 0,
            probed: 0,
            point_evals: 0,
            specialised: 0,
            certificates: 0,
            finer: 0,
            cancelled: false,
        }
    }
}

impl<S> Descent<S> {
    /// Counts the cell `b` as unresolved.
    fn unresolved(&mut self, b: &Aabb) {
        if std::env::var_os("MESH_DEBUG_UNRESOLVED").is_some() {
            eprintln!(
                "UNRES {} {} {} {}",
                b.min.x,
                b.min.y,
                b.min.z,
                b.max.x - b.min.x
            );
        }
        self.unresolved += 1;
        self.unresolved_box = union(self.unresolved_box, Some(*b));
    }

    /// What is left of this task's budget: [`PROBE_FLOOR`] plus [`PROBE_PER_CELL`] per
    /// surface cell found, less what was spent.
    fn allowance(&self) -> u64 {
        (PROBE_FLOOR + PROBE_PER_CELL * self.cells.len() as u64).saturating_sub(self.spent)
    }

    fn merge(&mut self, o: Descent<S>) {
        self.cells.extend(o.cells);
        self.tapes.extend(o.tapes);
        self.certified.extend(o.certified);
        self.needs = self.needs.max(o.needs);
        self.unresolved += o.unresolved;
        self.unresolved_box = union(self.unresolved_box, o.unresolved_box);
        self.deeper.extend(o.deeper);
        self.excluded += o.excluded;
        self.spent += o.spent;
        self.visited += o.visited;
        self.pruned += o.pruned;
        self.probed += o.probed;
        self.point_evals += o.point_evals;
        self.specialised += o.specialised;
        self.certificates += o.certificates;
        self.finer += o.finer;
        self.cancelled |= o.cancelled;
    }
}

/// The search's fixed inputs.
pub struct Octree<'a, S> {
    /// The shape (unclipped; the search clips it to `domain`).
    pub shape: &'a S,
    /// The domain the shape is clipped to.
    pub domain: Aabb,
    /// The cube.
    pub grid: Grid,
    /// The leaf level.
    pub level: u32,
    /// The deepest level probes go to.
    pub max_depth: u32,
    /// Stops the search when set.
    pub cancel: Option<&'a AtomicBool>,
}

impl<S: Shape> Octree<'_, S> {
    /// Searches the cube: the leaves with sign changes and what the probes found.
    /// `done(1)` is called once per finished subtree below level `min(level, 3)` (there
    /// are [`Octree::tasks`] of them).
    pub fn search<A: Arithmetic>(&self, done: &(dyn Fn(u64) + Sync)) -> Descent<S> {
        let top = self.level.min(TASK_LEVEL);
        let mut all = Descent {
            needs: self.level,
            ..Descent::default()
        };
        let (tapes, tasks) = self.tops::<A>(top, &mut all, done);
        let parts: Vec<Descent<S>> = tasks
            .par_iter()
            .map(|t| {
                let mut d = Descent::default();
                if !self.cancelled() {
                    let shape = t.tape.map_or(self.shape, |i| &tapes[i]);
                    let mut sc = Scratch::default();
                    self.crossing::<A>(shape, &t.value, top, t.c, &mut d, &mut sc);
                } else {
                    d.cancelled = true;
                }
                done(1);
                d
            })
            .collect();
        for p in parts {
            all.merge(p);
        }
        all.cancelled |= self.cancelled();
        all
    }

    /// The cells at level `top` whose range holds 0, with their tapes, from the cube
    /// down as below it (each level's sign tapes from its parent's batch), in the
    /// order of their index `x + n y + n^2 z`; the tapes built on the way (which the
    /// cells' `tape` indexes). `done` is told of the tasks pruned above `top`.
    fn tops<A: Arithmetic>(
        &self,
        top: u32,
        d: &mut Descent<S>,
        done: &(dyn Fn(u64) + Sync),
    ) -> (Vec<S>, Vec<Top<S>>) {
        let mut tapes = Vec::new();
        d.visited += 1;
        let b = self.grid.cell_box(0, [0; 3]);
        if !self.may_cross::<A>(self.shape, &b) {
            d.pruned += 1;
            done(1 << (3 * top));
            return (tapes, Vec::new());
        }
        let special = self
            .shape
            .specialises()
            .then(|| self.shape.specialise(&[cell_inputs::<A::Cell>(&b)]))
            .flatten();
        d.specialised += special.is_some() as u64;
        let tape = special.map(|s| {
            tapes.push(s);
            tapes.len() - 1
        });
        let value = specialise_to(self.shape, &None, &b);
        let mut cells = vec![Top {
            c: [0; 3],
            tape,
            value,
        }];
        let mut sc = Scratch::default();
        for level in 0..top {
            let mut next = Vec::new();
            for cell in cells {
                let shape = cell.tape.map_or(self.shape, |i| &tapes[i]);
                let kids = self.kids::<A>(shape, level, cell.c, d, &mut sc);
                done((8 - kids.len() as u64) << (3 * (top - level - 1)));
                let mut built = Vec::new();
                for (k, t) in kids {
                    let kv = if level + 1 == self.level {
                        cell.value.clone()
                    } else {
                        specialise_to(self.shape, &cell.value, &self.grid.cell_box(level + 1, k))
                    };
                    built.push((k, t, kv));
                }
                for (k, t, value) in built {
                    let tape = match t {
                        Some(t) => {
                            tapes.push(t);
                            Some(tapes.len() - 1)
                        }
                        None => cell.tape,
                    };
                    next.push(Top { c: k, tape, value });
                }
            }
            cells = next;
        }
        cells.sort_unstable_by_key(|t| [t.c[2], t.c[1], t.c[0]]);
        (tapes, cells)
    }

    /// How many subtrees [`Octree::search`] hands to threads.
    pub fn tasks(&self) -> u64 {
        1 << (3 * self.level.min(TASK_LEVEL))
    }

    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// The range of `shape` (clipped) over cell `c` at `level` holds 0.
    fn may_cross<A: Arithmetic>(&self, shape: &S, b: &Aabb) -> bool {
        let clipped = Clipped {
            inner: shape,
            domain: self.domain,
        };
        let [x, y, z] = cell_inputs::<A::Cell>(b);
        clipped.eval(x, y, z).contains_zero()
    }

    /// The corners' signs of cell `c` at `level` from the value tape `value` (one
    /// valid over the cell): a mask with bit `i` set where corner `i` is inside
    /// (`f >= 0`).
    fn corner_mask(&self, value: &S, level: u32, c: [u32; 3], d: &mut Descent<S>) -> u8 {
        d.point_evals += 8;
        corner_mask(value, &self.domain, &self.grid, level, c)
    }

    /// A cell whose range holds 0, with its sign tape `shape` (specialised to it, for
    /// range tests) and its value tape `value`: a leaf is kept or probed, any other
    /// cell's eight children are evaluated in one batch ([`Batch`]) and those whose
    /// range holds 0 visited in turn, each with its own sign tape ([`Octree::kid_tapes`])
    /// and value tape.
    fn crossing<A: Arithmetic>(
        &self,
        shape: &S,
        value: &CellTape<S>,
        level: u32,
        c: [u32; 3],
        d: &mut Descent<S>,
        sc: &mut Scratch,
    ) {
        if level == self.level {
            self.leaf::<A>(shape, value, c, d);
            return;
        }
        let kids = self.kids::<A>(shape, level, c, d, sc);
        for (k, t) in kids {
            if d.cancelled || self.cancelled() {
                d.cancelled = true;
                return;
            }
            // A leaf specialises its value tape only once its corners show a sign
            // change.
            let kv = if level + 1 == self.level {
                value.clone()
            } else {
                specialise_to(self.shape, value, &self.grid.cell_box(level + 1, k))
            };
            self.crossing::<A>(t.as_ref().unwrap_or(shape), &kv, level + 1, k, d, sc);
        }
    }

    /// The sub-cells of cell `c` at `level` (sign tape `shape`) whose range holds 0,
    /// each with its own sign tape (`None`: `shape`'s): the eight evaluated in one
    /// interval batch first (traced for their tapes, [`Octree::kid_tapes`]), the
    /// cheapest, then in the arithmetic's cell form ([`Batch`]) where that holds 0.
    fn kids<A: Arithmetic>(
        &self,
        shape: &S,
        level: u32,
        c: [u32; 3],
        d: &mut Descent<S>,
        sc: &mut Scratch,
    ) -> Vec<([u32; 3], Option<S>)> {
        let kids: [[u32; 3]; 8] = core::array::from_fn(|i| child(c, i));
        let boxes: [Aabb; 8] = kids.map(|k| self.grid.cell_box(level + 1, k));
        let near = self.interval_batch(shape, &boxes, sc);
        let group: Vec<usize> = (0..8).filter(|&i| near[i]).collect();
        let clipped = Clipped {
            inner: shape,
            domain: self.domain,
        };
        let mut ranges: [Option<A::Cell>; 8] = Default::default();
        Batch::<A::CellPack>::default().eval(
            &clipped,
            &group,
            |i| cell_inputs(&boxes[i]),
            &mut ranges,
        );
        d.visited += 8;
        let live: Vec<usize> = group
            .into_iter()
            .filter(|&i| ranges[i].as_ref().is_some_and(|f| f.contains_zero()))
            .collect();
        d.pruned += 8 - live.len() as u64;
        let tapes = self.kid_tapes(shape, &live, d, sc);
        live.iter().map(|&i| kids[i]).zip(tapes).collect()
    }

    /// Whether the interval range of `shape` clipped to the domain holds 0 over each of
    /// `boxes`: one batch ([`Shape::eval_boxes_traced`]), whose trace
    /// [`Octree::kid_tapes`] reads.
    fn interval_batch(&self, shape: &S, boxes: &[Aabb; 8], sc: &mut Scratch) -> [bool; 8] {
        let inputs = boxes.map(|b| cell_inputs::<Interval>(&b));
        for (a, v) in sc.boxes.iter_mut().enumerate() {
            v.clear();
            v.extend(inputs.iter().map(|r| r[a]));
        }
        let [x, y, z] = &sc.boxes;
        shape.eval_boxes_traced(x, y, z, &mut sc.out, &mut sc.trace);
        let clipped = Clipped {
            inner: shape,
            domain: self.domain,
        };
        core::array::from_fn(|i| {
            let [x, y, z] = &inputs[i];
            clipped.clip(sc.out[i], x, y, z).contains_zero()
        })
    }

    /// The sign tapes of the sub-cells `kids` (indices of the batch
    /// [`Octree::interval_batch`] evaluated last with `shape`): each specialised from
    /// that evaluation's trace ([`Shape::specialise_traced`]: the decisions
    /// [`Shape::specialise`] takes over that box alone, without evaluating it again).
    /// `None` where nothing shortens `shape`.
    fn kid_tapes(
        &self,
        shape: &S,
        kids: &[usize],
        d: &mut Descent<S>,
        sc: &mut Scratch,
    ) -> [Option<S>; 8] {
        let mut tapes: [Option<S>; 8] = Default::default();
        for (t, &i) in tapes.iter_mut().zip(kids) {
            *t = shape.specialise_traced(&mut sc.trace, i);
            d.specialised += t.is_some() as u64;
        }
        tapes
    }

    /// A leaf whose range holds 0 (`value`: a value tape valid over it): kept, with its
    /// own value tape, where its corners differ in sign, else excluded or probed.
    fn leaf<A: Arithmetic>(&self, shape: &S, value: &CellTape<S>, c: [u32; 3], d: &mut Descent<S>) {
        let level = self.level;
        let v = tape(self.shape, value);
        let m = self.corner_mask(v, level, c, d);
        if crosses(m) {
            // The certificate and the lattice read the sign tape: they ask about the
            // zero set only, which it shares with the shape, and it is the shortest.
            let b = self.grid.cell_box(level, c);
            d.certificates += 1;
            // Interval arithmetic first, the cheapest: where it certifies the cell, so
            // would any enclosure it holds. Else the arithmetic's tighter one, and the
            // two ranges' intersection for the monotone test.
            let ia = cell_gradient::<IaArith, S>(shape, &self.domain, &b);
            let gi = ia.g.map(|r| r.bounds());
            let mut sure = certifies(&ia.v, &gi);
            if !sure {
                let grad = cell_gradient::<A, S>(shape, &self.domain, &b);
                let g = grad.g.map(|r| r.bounds());
                sure = certifies(&grad.v, &g);
                if !sure && !monotone(&meet(&gi, &g)) {
                    self.check_pieces(shape, level, c, d);
                }
            }
            d.cells.push(c);
            d.tapes.push(specialise_to(self.shape, value, &b));
            d.certified.push(sure);
        } else if interval_excludes(shape, &self.domain, &self.grid.cell_box(level, c)) {
            d.excluded += 1;
        } else {
            let before = d.needs;
            d.needs = level;
            let mut budget = d.allowance().min(PROBE_BUDGET as u64) as u32;
            let start = budget;
            if self.probe::<A>(shape, v, level, c, d, &mut budget) {
                d.deeper.push((d.needs, c));
            }
            d.spent += (start - budget) as u64;
            d.needs = d.needs.max(before);
        }
    }

    /// Looks below cell `c` at `level` (its range holds 0, its corners agree) for sign
    /// changes, down to the maximum depth, unless a tighter range test excludes it
    /// ([`super::exclusion`]) or the Plantinga–Vegter test certifies it: then whatever
    /// surface it holds is a single sheet, a graph over one direction, that cannot
    /// close on itself inside the cell (a small component or both sheets of a thin
    /// shell would need gradients of opposite directions), so the sign changes of its
    /// neighbours already account for it.
    ///
    /// Depth first, at most `budget` sub-cells (a layer of sub-cells along a surface
    /// that only touches the leaf keeps 0 in its ranges down to the maximum depth,
    /// `4^k` of them `k` levels down, unless the mean value form excludes them); the
    /// first sign change ends the probe (the leaf level is raised and the search runs
    /// again). Returns whether it found one. Sub-cells left when the budget runs out
    /// count as unresolved.
    /// `shape` serves the range tests, `value` (valid over the cell) the corner signs.
    fn probe<A: Arithmetic>(
        &self,
        shape: &S,
        value: &S,
        level: u32,
        c: [u32; 3],
        d: &mut Descent<S>,
        budget: &mut u32,
    ) -> bool {
        let b = self.grid.cell_box(level, c);
        d.certificates += 1;
        match gradient_verdict::<A, S>(shape, &self.domain, &b) {
            Verdict::Excluded(t) => {
                d.excluded += (t != Test::Range) as u64;
                return false;
            }
            Verdict::Certified => return false,
            Verdict::Open => {}
        }
        if level >= self.max_depth || *budget == 0 {
            d.unresolved(&b);
            return false;
        }
        let l = level + 1;
        let kids: [[u32; 3]; 8] = core::array::from_fn(|i| child(c, i));
        let boxes: [Aabb; 8] = kids.map(|k| self.grid.cell_box(l, k));
        // The cheapest test first, over the eight in one batch; the arithmetic's range
        // comes with the gradient's ranges in a sub-cell's own probe. The corner signs
        // of the eight, a 3^3 lattice, once one is needed.
        let near = interval_holds_zero(shape, &self.domain, &boxes);
        let mut signs = None;
        for i in 0..8 {
            if *budget == 0 {
                d.unresolved(&boxes[i]);
                continue;
            }
            *budget -= 1;
            d.probed += 1;
            if !near[i] {
                d.excluded += 1;
                continue;
            }
            let s = signs.get_or_insert_with(|| {
                d.point_evals += 27;
                sub_lattice(value, &self.domain, &self.grid, l, c)
            });
            let m = (0..8).fold(0u8, |m, j| {
                let [x, y, z] = corner_of(corner_offset(i), j);
                m | (s[(x + 3 * y + 9 * z) as usize] as u8) << j
            });
            if crosses(m) || self.probe::<A>(shape, value, l, kids[i], d, budget) {
                d.needs = d.needs.max(l);
                return true;
            }
        }
        false
    }

    /// For a leaf with a sign change that the Plantinga–Vegter test does not certify:
    /// whether a finer lattice (of `shape`, valid over the cell) shows another topology
    /// than its corners ([`finer_topology`]); if so the leaf level must reach that
    /// sub-level.
    fn check_pieces(&self, shape: &S, level: u32, c: [u32; 3], d: &mut Descent<S>) {
        if level >= self.max_depth {
            return;
        }
        let levels = self.max_depth - level;
        let (k, evals) = finer_topology(shape, &self.domain, &self.grid, level, c, levels);
        d.point_evals += evals;
        if let Some(k) = k {
            d.finer += 1;
            d.needs = d.needs.max(level + k);
            d.deeper.push((level + k, c));
        }
    }
}

/// Whether the interval range of `shape` clipped to `domain` holds 0 over each of
/// `boxes` (one batch evaluation).
fn interval_holds_zero<S: Shape>(shape: &S, domain: &Aabb, boxes: &[Aabb; 8]) -> [bool; 8] {
    let clipped = Clipped {
        inner: shape,
        domain: *domain,
    };
    let inputs = boxes.map(|b| cell_inputs::<Interval>(&b));
    let [x, y, z]: [Vec<Interval>; 3] =
        core::array::from_fn(|a| inputs.iter().map(|r| r[a]).collect());
    let mut out = Vec::with_capacity(8);
    clipped.eval_batch(&x, &y, &z, &mut out);
    core::array::from_fn(|i| out[i].contains_zero())
}

/// The signs (inside: `f >= 0`) of `shape` clipped to `domain` at the `3^3` corners of
/// the eight sub-cells at `level` of cell `c` (one level up), `x + 3 y + 9 z`: one
/// batch, the values [`corner_mask`] gives each sub-cell.
fn sub_lattice<S: Shape>(
    shape: &S,
    domain: &Aabb,
    grid: &Grid,
    level: u32,
    c: [u32; 3],
) -> [bool; 27] {
    let points: [DVec3; 27] = core::array::from_fn(|i| {
        let o = [i % 3, i / 3 % 3, i / 9].map(|v| v as u32);
        grid.point(level, [0, 1, 2].map(|a| 2 * c[a] + o[a]))
    });
    let mut signs = Vec::with_capacity(27);
    inside_batch(shape, domain, &points, &mut signs);
    core::array::from_fn(|i| signs[i])
}

/// Whether `g` (the gradient's ranges over a cell) has one sign on every axis, with
/// 0 allowed: then no finer lattice can show another topology than the cell's
/// corners.
///
/// Why: where `g_i` lies within `[0, ∞)`, `f` does not fall along axis `i` in the cell
/// (the mean value theorem, as in [`super::exclusion`]), and where it lies within
/// `(-∞, 0]` it does not rise. Flip the axes of the second kind: `f` is then
/// non-decreasing along every axis, so a point inside (`f >= 0`) stays inside when
/// any coordinate grows. On any lattice of the cell the inside points are an upper
/// set: each is joined to the lattice's top corner by steps along the axes through
/// inside points, so they are one 6-connected component (or none), and the outside
/// points, a lower set, likewise. The corners' counts are the same: one component of
/// each where both kinds of point occur. NaN has no sign and is never monotone.
pub fn monotone(g: &[(f64, f64); 3]) -> bool {
    g.iter().all(|&(lo, hi)| lo >= 0.0 || hi <= 0.0)
}

/// The box around both boxes (either may be missing).
pub fn union(a: Option<Aabb>, b: Option<Aabb>) -> Option<Aabb> {
    match (a, b) {
        (Some(a), Some(b)) => Some(Aabb::new(a.min.min(b.min), a.max.max(b.max))),
        (a, b) => a.or(b),
    }
}

/// Child `i` (0..8, bits x, y, z) of cell `c`: coordinates one level down.
pub fn child(c: [u32; 3], i: usize) -> [u32; 3] {
    corner_of([2 * c[0], 2 * c[1], 2 * c[2]], i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::Real;
    use glam::DVec3;

    /// A ball of radius `.0` centred at `(.1, .1, .1)`.
    struct Ball(f64, f64);
    impl Shape for Ball {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            let c = self.1;
            ((x - c).sqr() + (y - c).sqr() + (z - c).sqr()).rsub(self.0 * self.0)
        }
    }

    fn search(shape: &Ball, level: u32, max_depth: u32) -> Descent<Ball> {
        let domain = Aabb::cube(1.0);
        let o = Octree {
            shape,
            domain,
            grid: Grid::new(&domain, level),
            level,
            max_depth,
            cancel: None,
        };
        o.search::<IaArith>(&|_| {})
    }

    #[test]
    fn a_ball_keeps_its_surface_cells_only() {
        let d = search(&Ball(0.6, 0.0), 4, 6);
        assert!(!d.cells.is_empty());
        assert!(d.pruned > 0);
        let g = Grid::new(&Aabb::cube(1.0), 4);
        for c in &d.cells {
            let b = g.cell_box(4, *c);
            let (near, far) = (
                b.min.max(-b.max).max(DVec3::ZERO),
                b.min.abs().max(b.max.abs()),
            );
            assert!(near.length() <= 0.6 && far.length() >= 0.6, "{c:?}");
        }
        assert_eq!(d.needs, 4);
    }

    #[test]
    fn a_monotone_cell_shows_its_corners_topology_on_every_lattice() {
        // A corner of three tilted planes (inside where all three are), and a slab a
        // fifth of a cell thick through a plane of corners: where the gradient's ranges are monotone, the finer
        // lattice agrees with the corners; across the slab they are not monotone.
        struct Corner;
        impl Shape for Corner {
            fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
                let a = x.clone().rsub(0.1);
                let b = z.clone() * 0.3 - y * 0.5 + 0.05;
                let c = (z + x * 0.2).rsub(0.02);
                a.min(&b).min(&c)
            }
        }
        struct Slab;
        impl Shape for Slab {
            fn eval<R: Real>(&self, x: R, _y: R, _z: R) -> R {
                (x - 0.01).abs().rsub(0.03)
            }
        }
        let domain = Aabb::cube(1.0);
        let g = Grid::new(&domain, 3);
        let (mut monotone_cells, mut slab_cells) = (0, 0);
        for i in 0..512u32 {
            let c = [i % 8, i / 8 % 8, i / 64];
            let b = g.cell_box(3, c);
            if crosses(corner_mask(&Corner, &domain, &g, 3, c)) {
                let grad = cell_gradient::<IaArith, _>(&Corner, &domain, &b);
                if monotone(&grad.g.map(|r| r.bounds())) {
                    monotone_cells += 1;
                    let (k, _) = finer_topology(&Corner, &domain, &g, 3, c, 3);
                    assert_eq!(k, None, "{c:?}");
                }
            }
            // The cells that hold the slab's middle (x = 0.01; the slab holds the
            // corners at x = 0), away from the domain's walls (whose clip makes sign
            // changes of its own): the cells beside, x < 0, hold one of its sheets.
            let inner = c[1..].iter().all(|&k| (1..7).contains(&k));
            if c[0] == 4 && inner && crosses(corner_mask(&Slab, &domain, &g, 3, c)) {
                slab_cells += 1;
                let grad = cell_gradient::<IaArith, _>(&Slab, &domain, &b);
                assert!(!monotone(&grad.g.map(|r| r.bounds())), "{c:?}");
            }
        }
        assert!(
            monotone_cells > 10 && slab_cells > 0,
            "{monotone_cells} {slab_cells}"
        );
    }

    #[test]
    fn a_ball_inside_one_cell_is_found_below_it() {
        // Radius 0.02 at 0.07: inside one cell of side 2/7, no corner of it inside.
        let d = search(&Ball(0.02, 0.07), 3, 7);
        assert!(d.cells.is_empty());
        assert!(d.needs > 3 && d.needs <= 7, "needs {}", d.needs);
    }
}
