//! The tape as a [`Shape`]: what the searches, renderers and the mesher ask of a shape,
//! answered by the tape's own evaluators (one value, a batch of lanes) and by its region
//! specialisation (a shorter tape that agrees with it over a region).

use crate::shape::Shape;
use crate::specialise::Trace;
use crate::tape::Tape;
use arith_core::{Range, Real};
use arith_ia::Interval;

impl Shape for Tape {
    fn eval<R: Real>(&self, x: R, y: R, z: R) -> R {
        Tape::eval(self, x, y, z)
    }

    fn eval_batch<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        Tape::eval_batch(self, x, y, z, out)
    }

    /// Steps and selections look at their values ([`arith_core::Real::known`]), which
    /// packs do not answer: a tape with them evaluates its forms one at a time.
    fn packs(&self) -> bool {
        !self.has_branches()
    }

    fn specialises(&self) -> bool {
        Tape::specialises(self)
    }

    fn specialises_values(&self) -> bool {
        Tape::specialises_values(self)
    }

    fn tape_len(&self) -> Option<usize> {
        Some(self.len())
    }

    fn specialise<R: Range>(&self, regions: &[[R; 3]]) -> Option<Self> {
        Tape::specialise(self, regions)
    }

    fn specialise_groups<R: Range>(
        &self,
        regions: &[[R; 3]],
        groups: &[(usize, usize)],
    ) -> (Vec<Self>, Vec<Option<usize>>) {
        Tape::specialise_groups(self, regions, groups)
    }

    fn specialise_values<R: Range>(&self, region: &[R; 3], within: f64) -> Option<Self> {
        Tape::specialise_values(self, region, within)
    }

    fn eval_boxes_traced(
        &self,
        x: &[Interval],
        y: &[Interval],
        z: &[Interval],
        out: &mut Vec<Interval>,
        trace: &mut Trace,
    ) {
        Tape::eval_boxes_traced(self, x, y, z, out, trace)
    }

    fn specialise_traced(&self, trace: &mut Trace, lane: usize) -> Option<Self> {
        Tape::specialise_traced(self, trace, lane)
    }
}
