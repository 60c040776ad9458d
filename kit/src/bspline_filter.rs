//! Anti-aliasing by filtering constant-colour rectangles (Gamito and Maddock 2007,
//! Appendix A, eq. A.1): pixel `(i, j)` is `Σ_s I_s ∫∫_s h(x - i - 0.5, y - j - 0.5)`
//! over the samples `s` meeting the filter's support, with `h` a separable uniform
//! B-spline (their reference [38]) of degree 0 (the box filter) to 3. Samples are unions
//! of `aa x aa` sub-pixels, so the integrals are precomputed once per sub-pixel offset
//! into a lookup table ([`Filter`]), exactly from the B-spline's antiderivative (the
//! Irwin-Hall distribution function). Shared by the previewer (which re-filters the
//! pixels a newly painted sample touches) and by `tracer render --aa N` (which filters a
//! render at `N` times the resolution).

use std::fmt;
use std::str::FromStr;

/// The filter's kernel: a uniform B-spline of this degree, one pixel wide per degree
/// plus one (support `[-(n+1)/2, (n+1)/2]` pixels).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Kernel {
    /// Degree 0: the box filter over the pixel.
    Box,
    /// Degree 1: the tent over `[-1, 1]`.
    Tent,
    /// Degree 2: the quadratic B-spline over `[-1.5, 1.5]` (the default).
    #[default]
    Quadratic,
    /// Degree 3: the cubic B-spline over `[-2, 2]`.
    Cubic,
}

impl Kernel {
    /// Every kernel, by degree.
    pub const ALL: [Kernel; 4] = [Kernel::Box, Kernel::Tent, Kernel::Quadratic, Kernel::Cubic];

    /// The B-spline's degree.
    pub fn degree(self) -> u32 {
        self as u32
    }
    /// Command-line name.
    pub fn name(self) -> &'static str {
        ["box", "tent", "quadratic", "cubic"][self as usize]
    }
}

impl fmt::Display for Kernel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Kernel {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Kernel::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| format!("unknown filter '{s}' (expected box, tent, quadratic or cubic)"))
    }
}

/// The distribution function of the centred uniform B-spline of degree `n` (the sum of
/// `n + 1` independent uniforms on `[-1/2, 1/2]`): `0` left of its support, `1` right.
fn bspline_cdf(n: u32, x: f64) -> f64 {
    let m = n + 1;
    let y = x + m as f64 * 0.5;
    if y <= 0.0 {
        return 0.0;
    }
    if y >= m as f64 {
        return 1.0;
    }
    // Irwin-Hall: F(y) = 1/m! Σ_{k <= y} (-1)^k C(m, k) (y - k)^m.
    let mut sum = 0.0;
    let mut binom = 1.0;
    let mut fact = 1.0;
    for k in 1..=m {
        fact *= k as f64;
    }
    for k in 0..=m {
        if k as f64 > y {
            break;
        }
        let term = binom * (y - k as f64).powi(m as i32);
        sum += if k % 2 == 0 { term } else { -term };
        binom = binom * (m - k) as f64 / (k + 1) as f64;
    }
    (sum / fact).clamp(0.0, 1.0)
}

/// Eq. (A.1)'s integrals for one `aa` and kernel: the weight of each sub-pixel of a row
/// (or column) in the pixel it is filtered into, by the sub-pixel's offset from the
/// pixel's first sub-pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Filter {
    aa: u32,
    kernel: Kernel,
    /// Sub-pixel offsets `lo..lo + weights.len()` relative to `i * aa`.
    lo: i64,
    weights: Vec<f64>,
}

impl Filter {
    /// The filter of `kernel` for `aa x aa` sub-pixels per pixel (`aa >= 1`).
    pub fn new(kernel: Kernel, aa: u32) -> Filter {
        let aa = aa.max(1);
        let n = kernel.degree();
        let half = (n + 1) as f64 * 0.5;
        // Sub-pixel `p` (offset `k = p - i aa`) covers `[k/aa, (k+1)/aa]` relative to the
        // pixel's left edge; the filter is centred at 0.5.
        let lo = ((0.5 - half) * aa as f64).floor() as i64;
        let hi = ((0.5 + half) * aa as f64).ceil() as i64;
        let weights = (lo..hi)
            .map(|k| {
                let a = k as f64 / aa as f64 - 0.5;
                let b = (k + 1) as f64 / aa as f64 - 0.5;
                bspline_cdf(n, b) - bspline_cdf(n, a)
            })
            .collect();
        Filter {
            aa,
            kernel,
            lo,
            weights,
        }
    }

    /// Sub-pixels per pixel along each axis.
    pub fn aa(&self) -> u32 {
        self.aa
    }
    /// The kernel.
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// The sub-pixel columns `[a, b)` (of `vw`) filtered into pixel column `i`.
    fn range(&self, i: u32, vw: u32) -> (u32, u32) {
        let a = (i as i64 * self.aa as i64 + self.lo).max(0) as u32;
        let b = (i as i64 * self.aa as i64 + self.lo + self.weights.len() as i64)
            .clamp(0, vw as i64) as u32;
        (a, b)
    }

    /// The pixels `[a, b)` along one axis whose value depends on sub-pixels `[p0, p1)`
    /// (of an image `n` pixels long).
    pub fn affected(&self, p0: u32, p1: u32, n: u32) -> (u32, u32) {
        let aa = self.aa as i64;
        let top = self.lo + self.weights.len() as i64;
        // Pixel i uses sub-pixels i aa + lo .. i aa + top.
        let a = ((p0 as i64 - top).div_euclid(aa) + 1).max(0);
        let b = ((p1 as i64 - 1 - self.lo).div_euclid(aa) + 1).clamp(0, n as i64);
        (a as u32, b.max(a) as u32)
    }

    #[inline]
    fn weight(&self, i: u32, p: u32) -> f64 {
        self.weights[(p as i64 - i as i64 * self.aa as i64 - self.lo) as usize]
    }

    /// Pixel `(i, j)` of the image whose `vw x vh` sub-pixels are `sub` (row-major), by
    /// eq. (A.1); at the image's edges the weights of the sub-pixels inside are
    /// renormalised to sum to one.
    pub fn pixel(&self, sub: &[[u8; 3]], vw: u32, vh: u32, i: u32, j: u32) -> [u8; 3] {
        let (x0, x1) = self.range(i, vw);
        let (y0, y1) = self.range(j, vh);
        let mut acc = [0.0f64; 3];
        let mut total = 0.0;
        for y in y0..y1 {
            let wy = self.weight(j, y);
            if wy == 0.0 {
                continue;
            }
            let row = &sub[(y * vw) as usize..];
            for x in x0..x1 {
                let w = wy * self.weight(i, x);
                let c = row[x as usize];
                for k in 0..3 {
                    acc[k] += w * c[k] as f64;
                }
                total += w;
            }
        }
        if total <= 0.0 {
            return [0; 3];
        }
        acc.map(|v| (v / total).round().clamp(0.0, 255.0) as u8)
    }

    /// The whole `w x h` image from its `w aa x h aa` sub-pixels, RGB bytes row-major.
    pub fn downsample(&self, sub: &[[u8; 3]], w: u32, h: u32) -> Vec<u8> {
        let (vw, vh) = (w * self.aa, h * self.aa);
        let mut out = Vec::with_capacity(w as usize * h as usize * 3);
        for j in 0..h {
            for i in 0..w {
                out.extend_from_slice(&self.pixel(sub, vw, vh, i, j));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_are_the_kernel_integrals_and_sum_to_one() {
        for kernel in Kernel::ALL {
            for aa in 1..=5 {
                let f = Filter::new(kernel, aa);
                let s: f64 = f.weights.iter().sum();
                assert!((s - 1.0).abs() < 1e-12, "{kernel} aa {aa}: {s}");
                // Symmetric about the pixel centre.
                let n = f.weights.len();
                for k in 0..n {
                    assert!((f.weights[k] - f.weights[n - 1 - k]).abs() < 1e-12);
                }
            }
        }
        // The box filter at aa 2 is the plain mean of the pixel's own 2x2 sub-pixels.
        assert_eq!(Filter::new(Kernel::Box, 2).weights, vec![0.5, 0.5]);
        // The tent at aa 1: the pixel's 3/4, each neighbour 1/8.
        let t = Filter::new(Kernel::Tent, 1).weights;
        assert!(
            (t[1] - 0.75).abs() < 1e-15 && (t[0] - 0.125).abs() < 1e-15,
            "{t:?}"
        );
        // Cubic B-spline CDF at its centre and knots: 1/2, and 1/24 at -1.5.
        assert!((bspline_cdf(3, 0.0) - 0.5).abs() < 1e-15);
        assert!((bspline_cdf(3, -1.0) - 1.0 / 24.0).abs() < 1e-15);
    }

    #[test]
    fn a_flat_image_stays_flat_and_an_edge_is_blurred_in_order() {
        let (w, h, aa) = (6u32, 4u32, 3u32);
        let (vw, vh) = (w * aa, h * aa);
        for kernel in Kernel::ALL {
            let f = Filter::new(kernel, aa);
            let flat = vec![[7, 8, 9]; (vw * vh) as usize];
            assert!(f.downsample(&flat, w, h).chunks(3).all(|c| c == [7, 8, 9]));
            // Left half black, right half white: values rise monotonically.
            let edge: Vec<[u8; 3]> = (0..vw * vh)
                .map(|k| if k % vw < vw / 2 { [0; 3] } else { [255; 3] })
                .collect();
            let row: Vec<u8> = (0..w).map(|i| f.pixel(&edge, vw, vh, i, 1)[0]).collect();
            assert!(row.windows(2).all(|p| p[0] <= p[1]), "{kernel}: {row:?}");
            assert_eq!((row[0], row[5]), (0, 255), "{kernel}: {row:?}");
        }
        // `affected` covers every pixel whose support meets a sub-pixel range.
        let f = Filter::new(Kernel::Cubic, aa);
        for p0 in 0..vw {
            for p1 in p0 + 1..=vw {
                let (a, b) = f.affected(p0, p1, w);
                for i in 0..w {
                    let (x0, x1) = f.range(i, vw);
                    let meets = x0 < p1 && p0 < x1;
                    assert_eq!(meets, (a..b).contains(&i), "{p0}..{p1} pixel {i}");
                }
            }
        }
    }
}
