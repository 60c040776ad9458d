//! The revised-affine paper's Appendix A models (to be written).
use crate::shape::Shape;
use arith_core::Real;

/// A model of Appendix A.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PaperModel {}

impl Shape for PaperModel {
    fn eval<R: Real>(&self, _x: R, _y: R, _z: R) -> R {
        match *self {}
    }
}
