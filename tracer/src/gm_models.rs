//! The progressive-refinement paper's models (to be written).
use crate::shape::Shape;
use arith_core::Real;

/// A model of the progressive-refinement paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GmModel {}

impl Shape for GmModel {
    fn eval<R: Real>(&self, _x: R, _y: R, _z: R) -> R {
        match *self {}
    }
}

/// The progressive-refinement paper's models, with domains, views and Lipschitz bounds.
pub fn all() -> Vec<crate::shape::Model> {
    Vec::new()
}
