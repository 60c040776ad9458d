//! R-functions (Rvachev): set operations on FRep functions (`f >= 0` inside), and the
//! blending union and intersection of the paper's "CSG with blending" model. Written
//! once, generic over [`Real`], so points and every arithmetic share them.

use crate::Real;

/// Intersection `f1 & f2 = f1 + f2 - sqrt(f1^2 + f2^2)`.
pub fn intersect<R: Real>(f1: R, f2: R) -> R {
    let r = f1.hypot(&f2);
    f1 + f2 - r
}

/// Union `f1 | f2 = f1 + f2 + sqrt(f1^2 + f2^2)`.
pub fn union<R: Real>(f1: R, f2: R) -> R {
    let r = f1.hypot(&f2);
    f1 + f2 + r
}

/// Subtraction `f1 \ f2 = f1 & (-f2) = f1 - f2 - sqrt(f1^2 + f2^2)`.
pub fn subtract<R: Real>(f1: R, f2: R) -> R {
    let r = f1.hypot(&f2);
    f1 - f2 - r
}

/// The blend term `sqrt(f1^2 + f2^2 + 0.5 / (1 + f1^2 + f2^2))` shared by both blends.
fn blend_root<R: Real>(f1: &R, f2: &R) -> R {
    let s = f1.sqr() + f2.sqr();
    let bump = (s.clone() + 1.0).recip() * 0.5;
    (s + bump).sqrt()
}

/// The paper's "blending intersection" `f1 ∨b f2 = f1 + f2 - sqrt(f1^2 + f2^2 + 0.5/(1 + f1^2 + f2^2))`.
///
/// The paper's Appendix A names this one `∨b` ("blending intersection") and the `+`
/// form `∧b` ("blending union"); the minus sign is what makes it an intersection in
/// FRep (`f >= 0` inside), so the names here follow the formula, as the paper's text does.
pub fn blend_intersect<R: Real>(f1: R, f2: R) -> R {
    let r = blend_root(&f1, &f2);
    f1 + f2 - r
}

/// The paper's "blending union" `f1 ∧b f2 = f1 + f2 + sqrt(f1^2 + f2^2 + 0.5/(1 + f1^2 + f2^2))`.
pub fn blend_union<R: Real>(f1: R, f2: R) -> R {
    let r = blend_root(&f1, &f2);
    f1 + f2 + r
}

/// HyperFun's `hfBlendUni(f1, f2, a0, a1, a2)`: the union plus the displacement
/// `a0 / (1 + (f1/a1)^2 + (f2/a2)^2)`, in the library's order of operations.
pub fn hf_blend_union<R: Real>(f1: R, f2: R, a0: f64, a1: f64, a2: f64) -> R {
    let d = hf_blend_displacement(&f1, &f2, a0, a1, a2);
    union(f1, f2) + d
}

/// HyperFun's `hfBlendInt(f1, f2, a0, a1, a2)`: the intersection plus the same
/// displacement as [`hf_blend_union`].
pub fn hf_blend_intersect<R: Real>(f1: R, f2: R, a0: f64, a1: f64, a2: f64) -> R {
    let d = hf_blend_displacement(&f1, &f2, a0, a1, a2);
    intersect(f1, f2) + d
}

fn hf_blend_displacement<R: Real>(f1: &R, f2: &R, a0: f64, a1: f64, a2: f64) -> R {
    let s = (f1.clone() / a1).sqr() + 1.0 + (f2.clone() / a2).sqr();
    s.rdiv(a0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signs_follow_set_membership() {
        // inside both, inside one, inside none
        assert!(intersect(1.0, 2.0) > 0.0);
        assert!(intersect(1.0, -2.0) < 0.0);
        assert!(union(1.0, -2.0) > 0.0);
        assert!(union(-1.0, -2.0) < 0.0);
        assert!(subtract(1.0, -2.0) > 0.0);
        assert!(subtract(1.0, 2.0) < 0.0);
        assert!(blend_intersect(1.0, 2.0) > 0.0);
        assert!(blend_union(-1.0, 2.0) > 0.0);
        assert!(blend_union(-3.0, -3.0) < 0.0);
    }
}
