//! Batches: the ranges of many inputs of one shape in one call, for the drivers that
//! run many searches in lock-step (the rays of a tile in `tracer::search::ray`, the cells of a
//! tile's culling in `tracer::search::cull`). A driver groups its searches by the shape they
//! are on; each group is evaluated here through [`Shape::eval_batch`] (for a tape, each
//! instruction over every lane before the next: the interpreter's dispatch is paid once
//! per instruction per batch, not per input), in [packs](Pack) of [`LANES`] forms where
//! the shape packs, else form by form. Every lane is exactly what [`Shape::eval`] gives
//! on its own input; no lane sees another's. The buffers live as long as the driver, so
//! a step allocates nothing once they have grown.

use crate::shape::Shape;
use arith_core::pack::{Pack, LANES};

/// Reusable buffers for batched evaluations in the pack type `P` (and its lanes).
pub struct Batch<P: Pack> {
    packs: [Vec<P>; 3],
    packed: Vec<P>,
    lanes: [Vec<P::Lane>; 3],
    ranges: Vec<P::Lane>,
}

impl<P: Pack> Default for Batch<P> {
    fn default() -> Self {
        Batch {
            packs: Default::default(),
            packed: Vec::new(),
            lanes: Default::default(),
            ranges: Vec::new(),
        }
    }
}

impl<P: Pack> Batch<P> {
    /// The range of `shape` over `inputs(k)` into `out[k]`, for every `k` of `group`
    /// (indices into `out`, any order, each at most once). In packs, the last pack
    /// repeats its first lane where the group has no more (those results are dropped).
    pub fn eval<S: Shape + ?Sized>(
        &mut self,
        shape: &S,
        group: &[usize],
        inputs: impl Fn(usize) -> [P::Lane; 3],
        out: &mut [Option<P::Lane>],
    ) {
        if group.is_empty() {
            return;
        }
        // A tape runs plain lanes on its lane kernels: packing them would only be
        // undone lane by lane.
        let kernel = shape.tape_len().is_some() && crate::batch::lane_kernel::<P::Lane>();
        if shape.packs() && group.len() > 1 && !kernel {
            for v in &mut self.packs {
                v.clear();
            }
            for chunk in group.chunks(LANES) {
                let mut forms: [[Option<P::Lane>; 3]; LANES] =
                    core::array::from_fn(|l| inputs(*chunk.get(l).unwrap_or(&chunk[0])).map(Some));
                for (i, v) in self.packs.iter_mut().enumerate() {
                    v.push(P::pack(core::array::from_fn(|l| {
                        forms[l][i].take().expect("each form is packed once")
                    })));
                }
            }
            let [x, y, z] = &self.packs;
            shape.eval_batch(x, y, z, &mut self.packed);
            for (chunk, pack) in group.chunks(LANES).zip(self.packed.drain(..)) {
                for (&k, f) in chunk.iter().zip(pack.unpack()) {
                    out[k] = Some(f);
                }
            }
        } else {
            for v in &mut self.lanes {
                v.clear();
            }
            for &k in group {
                for (v, c) in self.lanes.iter_mut().zip(inputs(k)) {
                    v.push(c);
                }
            }
            let [x, y, z] = &self.lanes;
            shape.eval_batch(x, y, z, &mut self.ranges);
            for (&k, f) in group.iter().zip(self.ranges.drain(..)) {
                out[k] = Some(f);
            }
        }
    }
}

/// A driver's slots grouped by the shape they are on (by address), each group's slots
/// in increasing order. The vectors are reused from one step to the next; the groups
/// hold no borrow of the shapes, so the driver may change its slots between steps.
#[derive(Default)]
pub struct Groups(Vec<(usize, Vec<usize>)>);

impl Groups {
    /// Regroups the slots: slot `k` goes with the others on `shapes[k]`; slots without
    /// a shape are left out.
    pub fn regroup<S: ?Sized>(&mut self, shapes: &[Option<&S>]) {
        for g in &mut self.0 {
            g.1.clear();
        }
        for (k, sh) in shapes.iter().enumerate() {
            let Some(sh) = *sh else { continue };
            let key = sh as *const S as *const () as usize;
            match self.0.iter_mut().find(|g| g.0 == key) {
                Some(g) => g.1.push(k),
                None => self.0.push((key, vec![k])),
            }
        }
        // Shapes no slot is on any more (a window left behind) are forgotten.
        self.0.retain(|g| !g.1.is_empty());
    }

    /// Whether no slot has a shape.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The groups, each a non-empty list of slots on one shape.
    pub fn iter(&self) -> impl Iterator<Item = &[usize]> {
        self.0.iter().map(|g| &g.1[..])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::pack::Lanes;
    use arith_core::Real;
    use arith_ia::Interval;

    struct Ball(f64);
    impl Shape for Ball {
        fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
            -(x.clone() * x + y.clone() * y + z.clone() * z) + self.0
        }
    }

    /// Every grouped slot gets exactly its own input's range, packed or not, whatever
    /// the group's size and order; slots outside the group are left alone.
    #[test]
    fn each_slot_gets_its_own_range() {
        let input = |k: usize| {
            let a = k as f64 * 0.1 - 1.0;
            [
                Interval::new(a, a + 0.05),
                Interval::new(-a.abs(), 0.3 + a.abs()),
                Interval::new(0.0, a.abs()),
            ]
        };
        let mut batch = Batch::<Lanes<Interval>>::default();
        for group in [
            vec![3],
            vec![0, 1],
            vec![5, 2, 7, 1, 0],
            (0..13).rev().collect(),
        ] {
            let mut out: Vec<Option<Interval>> = vec![None; 16];
            batch.eval(&Ball(1.0), &group, input, &mut out);
            for (k, f) in out.iter().enumerate() {
                if group.contains(&k) {
                    let [x, y, z] = input(k);
                    assert_eq!(f.as_ref(), Some(&Ball(1.0).eval(x, y, z)), "slot {k}");
                } else {
                    assert!(f.is_none(), "slot {k} is not in the group");
                }
            }
        }
    }

    #[test]
    fn groups_follow_the_shapes() {
        let (a, b) = (Ball(1.0), Ball(2.0));
        let mut groups = Groups::default();
        groups.regroup(&[Some(&a), None, Some(&b), Some(&a)]);
        assert_eq!(groups.iter().collect::<Vec<_>>(), [&[0, 3][..], &[2][..]]);
        groups.regroup(&[None, Some(&b)]);
        assert_eq!(groups.iter().collect::<Vec<_>>(), [&[1][..]]);
        groups.regroup::<Ball>(&[None, None]);
        assert!(groups.is_empty());
    }
}
