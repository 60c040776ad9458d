//! The prime-factor subdivision plan (Gamito and Maddock 2007, eq. 7): a
//! `w x h` image is tiled by `u x v` square samples of side `gcd(w, h)`, and each level
//! splits every sample `p x p`, `p` running over the prime factors of that side, largest
//! first, so any image size reaches single pixels without partial samples.

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
        }
    }
}
