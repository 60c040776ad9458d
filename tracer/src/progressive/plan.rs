//! The prime-factor subdivision plan (Gamito and Maddock 2007, eq. 7): a
//! `w x h` image is tiled by `u x v` square samples of side `gcd(w, h)`, and each level
//! splits every sample `p x p`, `p` running over the prime factors of that side, largest
//! first, so any image size reaches single pixels without partial samples.
//!
//! A prime or awkward size (797x797, 37x24: `gcd` prime or 1) gets no levels at all from
//! eq. (7). [`Plan::for_image`] then pads the sample grid: square samples of a side with
//! prime factors 2, 3 and 5 only, `ceil(w / side) x ceil(h / side)` of them, covering at
//! most [`MAX_PADDING`] more pixels than the image; the samples are cropped to the image
//! (a sample wholly outside it is never queued, one across its edge is traced as a whole
//! cone and painted inside only). Eq. (7) is kept wherever it gives a few levels of
//! small splits (800x800, 800x600, 800x400 all keep it).

/// Prime factors of `n`, largest first.
pub fn prime_factors_desc(mut n: u32) -> Vec<u32> {
    let mut f = Vec::new();
    let mut p = 2;
    while p * p <= n {
        while n.is_multiple_of(p) {
            f.push(p);
            n /= p;
        }
        p += 1;
    }
    if n > 1 {
        f.push(n);
    }
    f.reverse();
    f
}

fn gcd(a: u32, b: u32) -> u32 {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

/// How much larger (in pixels) than the image a padded sample grid may be.
pub const MAX_PADDING: f64 = 0.25;
/// Eq. (7) is kept when it has at least this many levels ...
pub const MIN_LEVELS: usize = 3;
/// ... and none of its splits is above this.
pub const MAX_SPLIT: u32 = 7;

/// The subdivision plan of eq. (7): `u x v` top-level square samples of `size` pixels,
/// then a `p x p` split per level, `p` the prime factors of `gcd(w, h)`, largest first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    /// Top-level samples across.
    pub u: u32,
    /// Top-level samples down.
    pub v: u32,
    /// Side of a top-level sample in pixels.
    pub size: u32,
    /// The split per level, largest prime first.
    pub splits: Vec<u32>,
    /// Whether the grid of `u x v` samples of `size` overhangs the image (the samples are
    /// cropped to it); false for the plan of eq. (7).
    pub padded: bool,
}

impl Plan {
    /// The plan for a `w x h` image.
    pub fn new(w: u32, h: u32) -> Plan {
        let g = gcd(w, h);
        Plan {
            u: w / g,
            v: h / g,
            size: g,
            splits: prime_factors_desc(g),
            padded: false,
        }
    }

    /// The plan the previewer uses: eq. (7) when it has [`MIN_LEVELS`] levels or more,
    /// none of them splitting above [`MAX_SPLIT`]; otherwise, where a padded grid of
    /// square samples of a side `2^a 3^b 5^c` covering at most [`MAX_PADDING`] more
    /// pixels has more levels, the padded grid with the most levels (ties: the least
    /// padding, then the larger side).
    pub fn for_image(w: u32, h: u32) -> Plan {
        let exact = Plan::new(w, h);
        if exact.splits.len() >= MIN_LEVELS && exact.splits.iter().all(|&p| p <= MAX_SPLIT) {
            return exact;
        }
        let area = w as f64 * h as f64;
        let limit = w.max(h) as u64 * 2;
        // (levels, padding, side) of the best padded grid so far.
        let mut best: Option<(usize, f64, u32)> = None;
        let mut p2 = 1u64;
        while p2 <= limit {
            let mut p3 = p2;
            while p3 <= limit {
                let mut g = p3;
                while g <= limit {
                    let side = g as u32;
                    let (u, v) = (w.div_ceil(side), h.div_ceil(side));
                    let pad = (u as f64 * v as f64 * g as f64 * g as f64) / area - 1.0;
                    if pad <= MAX_PADDING {
                        let levels = prime_factors_desc(side).len();
                        let better = match best {
                            None => true,
                            Some((l, p, s)) => {
                                levels > l || (levels == l && (pad < p || (pad == p && side > s)))
                            }
                        };
                        if better {
                            best = Some((levels, pad, side));
                        }
                    }
                    g *= 5;
                }
                p3 *= 3;
            }
            p2 *= 2;
        }
        match best {
            Some((levels, _, side)) if levels > exact.splits.len() => Plan {
                u: w.div_ceil(side),
                v: h.div_ceil(side),
                size: side,
                splits: prime_factors_desc(side),
                padded: !w.is_multiple_of(side) || !h.is_multiple_of(side),
            },
            _ => exact,
        }
    }
}
