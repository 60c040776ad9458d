//! `f64` to `f32` rounded outward: every number the host hands the GPU (constants,
//! the eye, ray directions, segment ends) becomes an `f32` bound or a midpoint with a
//! radius rounded up, so the `f32` data enclose the `f64` data exactly.

/// The largest `f32` at or below `x` (`x` finite; `-f32::MAX` below its range).
pub fn down(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) > x {
        next_down(y)
    } else {
        y
    }
}

/// The smallest `f32` at or above `x` (`x` finite; `f32::MAX` above its range).
pub fn up(x: f64) -> f32 {
    -down(-x)
}

/// The next `f32` below `y` (finite `y`).
pub fn next_down(y: f32) -> f32 {
    if y == 0.0 {
        return -f32::from_bits(1);
    }
    let b = y.to_bits();
    if y > 0.0 {
        f32::from_bits(b - 1)
    } else {
        f32::from_bits(b + 1)
    }
}

/// `x` as the nearest `f32` `m` and a radius `r` (rounded up) with `|x - m| <= r`.
pub fn mid_rad(x: f64) -> (f32, f32) {
    let m = x as f32;
    // Both are f64; their difference is exact (`m` is within half an f32 ulp of `x`).
    let d = (x - m as f64).abs();
    (m, up(d))
}

/// Magnitudes at or above this are "unbounded" on the GPU (the shaders' `LIM`).
pub const LIM: f64 = (1u64 << 60) as f64;

/// An `f32` interval enclosing the constant `c`, as the shaders' constant operands take
/// it: nonzero bounds below `2^-124` in magnitude (near the subnormal range, which the GPU
/// may flush) widen to `0` or `+-2^-124`. `None` for `|c| >= LIM` or a non-finite `c`
/// (the operand is then the whole line).
pub fn constant(c: f64) -> Option<(f32, f32)> {
    const TINY: f64 = 1.0 / (1u128 << 124) as f64;
    if c.is_nan() || c.abs() >= LIM {
        return None;
    }
    if c == 0.0 {
        return Some((0.0, 0.0));
    }
    if c.abs() < TINY {
        return Some(if c > 0.0 {
            (0.0, TINY as f32)
        } else {
            (-TINY as f32, 0.0)
        });
    }
    Some((down(c), up(c)))
}

/// [`mid_rad`] for a coordinate: beyond [`LIM`] (or not finite) the radius is `2^100`,
/// which the shaders read as unbounded.
pub fn coord(x: f64) -> (f32, f32) {
    if x.abs() < LIM {
        mid_rad(x)
    } else {
        (0.0, (2.0f64).powi(100) as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_enclose() {
        for &x in &[
            0.1,
            -0.1,
            1.0,
            1e-30,
            -3.3e7,
            std::f64::consts::PI,
            1e18,
            -1e-39,
        ] {
            assert!((down(x) as f64) <= x && x <= (up(x) as f64), "{x}");
            let (m, r) = mid_rad(x);
            assert!(((m as f64) - x).abs() <= r as f64);
            let (lo, hi) = constant(x).unwrap();
            assert!((lo as f64) <= x && x <= hi as f64, "{x}: {lo} {hi}");
        }
        assert_eq!(down(1.0), 1.0);
        assert_eq!(up(0.5), 0.5);
        assert!(down(0.1) < up(0.1));
    }
}
