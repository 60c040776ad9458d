//! Formulas parsed from text into a tape (to be written).
use crate::shape::Shape;
use arith_core::Real;

/// A compiled formula.
#[derive(Clone, Debug)]
pub struct Tape {}

impl Shape for Tape {
    fn eval<R: Real>(&self, _x: R, _y: R, _z: R) -> R {
        unimplemented!("expr::Tape::eval")
    }
}
