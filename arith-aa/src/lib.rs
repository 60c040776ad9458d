//! # arith-aa: standard affine arithmetic (de Figueiredo & Stolfi)
//!
//! An [`Aa`] is an affine form `x0 + Σ coef_k·ε_k` over noise symbols `ε_k ∈ [-1, 1]`,
//! stored as a sparse list of `(symbol, coef)` sorted by symbol id. Input `i` of an
//! evaluation uses the reserved symbol `i` (ids below [`INPUTS`]); every non-affine
//! operation, every rounding error and [`Range::from_interval`] get a *fresh* symbol,
//! so forms keep growing: that is what makes standard AA precise on correlated
//! expressions and slow on long ones (the baseline of the papers' comparisons).
//!
//! Soundness: every operation rounds to nearest and bounds its own error (TwoSum for
//! sums, `err` bounds for products unless a bit count proves them exact), sums those
//! bounds with a rigorous upward bound and puts them on one fresh symbol per operation;
//! exact operations add no symbol. Non-affine functions all go through the shared
//! [`arith_core::approx`] approximations `f(x) ∈ alpha·x + zeta ± delta` (built on the
//! form's bounds), except `sqr`, which uses the form's structure: `(Σ xi·εi)² ∈ [0, R²]`
//! is centred, so `sqr` spends `R²/2` where the general product `x * x` spends `R²`.
//! The product is the standard one (new symbol `Σ|xi|·Σ|yi|`). An overflow or a domain
//! edge (`recip`/`ln` of a range reaching 0) gives the unbounded form, never NaN.
//!
//! Inputs follow the [`Range::bounds_at_inputs`] convention exactly: `input(i, lo, hi)`
//! with `ε_i = eps` is the point `(lo+hi)/2 + (hi-lo)/2·eps` of exact real arithmetic;
//! when those are not floats, the rounding goes on a fresh symbol.
//!
//! ```
//! use arith_aa::Aa;
//! use arith_core::{Range, Real};
//!
//! let x = Aa::input(0, 1.0, 2.0);
//! // Correlation: x - x is exactly 0, where intervals would give [-1, 1].
//! assert_eq!((x.clone() - x.clone()).bounds(), (0.0, 0.0));
//! // Affine expressions are tight: 3x - 2x + 1 ranges over [2, 3].
//! let y = 3.0 * x.clone() - 2.0 * x + 1.0;
//! assert_eq!(y.bounds(), (2.0, 3.0));
//! ```

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use arith_core::approx::{self, Approx};
use arith_core::round::{err, two_sum};
use arith_core::{AffinePart, Arithmetic, Linear, Range, Real};
use core::cell::Cell;
use core::ops::{Add, Div, Mul, Neg, Sub};
use std::sync::atomic::{AtomicU64, Ordering};

/// Number of reserved input symbols: input `i < INPUTS` uses symbol id `i`.
pub const INPUTS: usize = 64;

/// How many fresh ids a thread takes from the global counter at once, so that creating a
/// symbol is a thread-local increment, not a contended atomic operation.
const BLOCK: u64 = 1 << 16;

/// Next free block of fresh ids. Block 0 would overlap the reserved input ids, so the
/// counter starts at block 1.
static NEXT_BLOCK: AtomicU64 = AtomicU64::new(1);

thread_local! {
    /// `(next, end)`: this thread's unused ids `next..end`.
    static CURSOR: Cell<(u64, u64)> = const { Cell::new((0, 0)) };
}

/// A symbol id never handed out before, by any thread (ids are at least `BLOCK`, so
/// never a reserved input id). Ids increase within one thread.
pub fn fresh_symbol() -> u64 {
    CURSOR.with(|c| {
        let (mut next, mut end) = c.get();
        if next == end {
            let block = NEXT_BLOCK.fetch_add(1, Ordering::Relaxed);
            next = block * BLOCK;
            end = next + BLOCK;
        }
        c.set((next + 1, end));
        next
    })
}

/// An affine form `x0 + Σ coef·ε_sym`, or the unbounded form (the whole line).
///
/// Invariants: `terms` is sorted by strictly increasing symbol id and holds only
/// non-zero finite coefficients; `x0` is finite, except for the unbounded form, which has
/// `x0 = +inf` and no terms (so a non-finite centre is the one "unbounded" test).
#[derive(Clone, Debug, PartialEq)]
pub struct Aa {
    x0: f64,
    terms: Vec<(u64, f64)>,
}

/// Standard affine arithmetic as an [`Arithmetic`]: rays and cells both use [`Aa`]
/// (sparse forms pay only for the symbols they use).
#[derive(Clone, Copy, Debug, Default)]
pub struct AaArith;

impl Arithmetic for AaArith {
    const NAME: &'static str = "aa";
    const LABEL: &'static str = "AA";
    type Ray = Aa;
    type Cell = Aa;
    type RayPack = arith_core::pack::Lanes<Aa>;
    type CellPack = arith_core::pack::Lanes<Aa>;
}

/// The smallest float `>= a + b`: `fl(a + b)` when TwoSum shows it exact or rounded up,
/// its successor when rounded down, so exact sums stay exact. Overflow, NaN and a
/// non-finite TwoSum residual (intermediate overflow) give `+inf`.
#[inline]
fn sum_up(a: f64, b: f64) -> f64 {
    let (s, t) = two_sum(a, b);
    if t <= 0.0 && t > f64::NEG_INFINITY && !s.is_nan() {
        s
    } else if t > 0.0 && t < f64::INFINITY {
        s.next_up()
    } else {
        f64::INFINITY
    }
}

/// A lower bound of `a + b`, exact when the sum is (see [`sum_up`]).
#[inline]
fn sum_down(a: f64, b: f64) -> f64 {
    -sum_up(-a, -b)
}

/// Adds `|e|` (NaN meaning "unbounded") to the error accumulator `acc`, rounding up;
/// exact zeros leave it untouched so exact operations add no symbol.
#[inline]
fn acc_err(acc: &mut f64, e: f64) {
    if e != 0.0 {
        *acc = sum_up(*acc, e.abs());
    }
}

/// Accumulates rounding-error bounds `|e_i|` with plain additions, bounding the
/// summation's own rounding at the end: for `n` non-negative terms recursive summation
/// gives `S <= ŝ/(1 - γ_{n-1}) <= ŝ·(1 + 2(n-1)u)` (Higham, Thm 4.1 with
/// `γ_k = ku/(1-ku)`, `ku <= 1/4`; float addition never underflows inexactly).
#[derive(Default)]
struct ErrAcc {
    s: f64,
    n: u32,
}

impl ErrAcc {
    /// Adds `|e|` (NaN meaning "unbounded"); exact zeros are skipped, so exact operations
    /// add no symbol.
    #[inline]
    fn add(&mut self, e: f64) {
        if e != 0.0 {
            self.s += e.abs();
            self.n += 1;
        }
    }

    /// An upper bound of the exact sum (`+inf` for overflow or NaN).
    #[inline]
    fn bound(&self) -> f64 {
        match self.n {
            0 => 0.0,
            1 if !self.s.is_nan() => self.s,
            _ if self.s.is_nan() => f64::INFINITY,
            // (n - 1)·2^-52 and 1 + that are exact for n < 2^52.
            n => (self.s * (1.0 + (n - 1) as f64 * f64::EPSILON)).next_up(),
        }
    }
}

/// Number of significant bits of a normal float (53 minus trailing zero bits of the
/// significand with its implicit bit); 54 (never "short") for other values.
#[inline]
fn sig_bits(x: f64) -> u32 {
    if x.is_normal() {
        let m = (x.to_bits() & ((1u64 << 52) - 1)) | (1u64 << 52);
        53 - m.trailing_zeros()
    } else {
        54
    }
}

/// `fl(a * b)` and a bound on its rounding error: zero when the product is provably
/// exact (the significands have at most 53 significant bits together and the result is
/// normal, as when scaling short coefficients by small integers), else [`err`] (also
/// `+inf` on overflow). A bit-count test instead of an FMA residual: `mul_add` is a
/// slow library call on targets compiled without FMA.
#[inline]
fn prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let exact = if p == 0.0 {
        a == 0.0 || b == 0.0
    } else {
        // Strictly above: a rounded `p > MIN_POSITIVE` implies an exact product above it.
        p.abs() > f64::MIN_POSITIVE && p.is_finite() && sig_bits(a) + sig_bits(b) <= 53
    };
    (p, if exact { 0.0 } else { err(p) })
}

/// `sqr` centres the quadratic term only when `R >= SQR_SHIFT_MIN·(|x0| + R)`, i.e. when
/// the gain `R²` exceeds `2^-40·(|x0| + R)²`, far above the few ulps by which the
/// differently rounded bounds of `sqr` and `x * x` can disagree.
const SQR_SHIFT_MIN: f64 = 1.0 / (1u64 << 20) as f64;

/// An upper bound of `a * b` for `a, b >= 0`, exact when the product is.
#[inline]
fn mul_up_exact(a: f64, b: f64) -> f64 {
    let (p, pe) = prod(a, b);
    if pe == 0.0 {
        p
    } else {
        sum_up(p, pe)
    }
}

/// Whether multiplying by `c` only shifts the exponent (`c = ±2^k` or `0`), so the
/// product is exact unless it leaves the normal range.
#[inline]
fn is_exact_scale(c: f64) -> bool {
    c == 0.0 || (c.is_normal() && c.to_bits() & ((1u64 << 52) - 1) == 0)
}

impl Aa {
    /// The unbounded form: bounds `(-inf, +inf)`.
    pub fn entire() -> Aa {
        Aa {
            x0: f64::INFINITY,
            terms: Vec::new(),
        }
    }

    /// Whether this is the unbounded form.
    #[inline]
    pub fn is_entire(&self) -> bool {
        !self.x0.is_finite()
    }

    /// The centre `x0` (`+inf` for the unbounded form).
    pub fn centre(&self) -> f64 {
        self.x0
    }

    /// The `(symbol id, coefficient)` terms, sorted by id.
    pub fn terms(&self) -> &[(u64, f64)] {
        &self.terms
    }

    /// Sum of `|coef|` over all terms, rounded up (the radius).
    pub fn radius(&self) -> f64 {
        let mut r = 0.0;
        for &(_, c) in &self.terms {
            acc_err(&mut r, c);
        }
        r
    }

    /// The form `mid + rad·ε_sym` for `[lo, hi]`, with `mid = (lo + hi)/2` and
    /// `rad = (hi - lo)/2` as exact reals, so that `ε_sym = eps` is exactly the point
    /// `mid + rad·eps` (the convention of [`Range::bounds_at_inputs`]). When `mid` or
    /// `rad` is not a float, the stored rounded values are off by at most `e`, which
    /// goes on a fresh symbol: `mid + rad·eps` then still lies within the form for
    /// `ε_sym = eps`. Unbounded for NaN, infinite or reversed bounds.
    fn with_symbol(sym: u64, lo: f64, hi: f64) -> Aa {
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Aa::entire();
        }
        // Halving first cannot overflow like `lo + hi`; it is exact except for
        // subnormals, where its error (< ETA) shifts both mid and rad.
        let (a, b) = (0.5 * lo, 0.5 * hi);
        let mut e = ErrAcc::default();
        for (half, full) in [(a, lo), (b, hi)] {
            if 2.0 * half != full {
                e.add(2.0 * arith_core::round::ETA);
            }
        }
        let (mid, tm) = two_sum(a, b);
        let (rad, tr) = two_sum(b, -a);
        e.add(tm);
        e.add(tr);
        let mut terms = Vec::with_capacity(2);
        if rad != 0.0 {
            terms.push((sym, rad));
        }
        Aa { x0: mid, terms }.finish(e.bound())
    }

    /// Puts the accumulated error bound `e` on a fresh symbol (if non-zero) and turns
    /// any overflow into the unbounded form.
    #[inline]
    fn finish(mut self, e: f64) -> Aa {
        if !(self.x0.is_finite() && e.is_finite()) {
            return Aa::entire();
        }
        if e != 0.0 {
            push_symbol(&mut self.terms, fresh_symbol(), e);
        }
        self
    }

    /// `self + s·other` for `s = ±1`, merging in place into `self`'s buffer.
    fn add_signed(mut self, other: &Aa, s: f64) -> Aa {
        if self.is_entire() || other.is_entire() {
            return Aa::entire();
        }
        let (c0, e0) = two_sum(self.x0, s * other.x0);
        self.x0 = c0;
        let mut e = ErrAcc::default();
        e.add(e0);
        let b = &other.terms;
        if !b.is_empty() {
            let a = &mut self.terms;
            let (n, m) = (a.len(), b.len());
            a.resize(n + m, (0, 0.0));
            // Merge from the back: slot k-1 is always at or after the unread a[..i]
            // (k - i >= j >= 1 while b has unread terms), so nothing is overwritten early.
            let (mut i, mut j, mut k) = (n, m, n + m);
            while j > 0 {
                let (bs, bc) = b[j - 1];
                if i > 0 && a[i - 1].0 > bs {
                    k -= 1;
                    a[k] = a[i - 1];
                    i -= 1;
                } else if i > 0 && a[i - 1].0 == bs {
                    let (c, ce) = two_sum(a[i - 1].1, s * bc);
                    e.add(ce);
                    i -= 1;
                    j -= 1;
                    if c != 0.0 {
                        k -= 1;
                        a[k] = (bs, c);
                    }
                } else {
                    k -= 1;
                    a[k] = (bs, s * bc);
                    j -= 1;
                }
            }
            // a[..i] is in place; close the gap between it and the merged tail.
            if i < k {
                a.copy_within(k..n + m, i);
                a.truncate(i + (n + m - k));
            }
        }
        self.finish(e.bound())
    }

    /// `c·self` in place.
    fn scale(mut self, c: f64) -> Aa {
        if self.is_entire() || !c.is_finite() {
            return Aa::entire();
        }
        if c == 0.0 {
            self.x0 = 0.0;
            self.terms.clear();
            return self;
        }
        if c == 1.0 {
            return self;
        }
        let mut e = ErrAcc::default();
        let (p, pe) = prod(self.x0, c);
        self.x0 = p;
        e.add(pe);
        for t in &mut self.terms {
            let (p, pe) = prod(t.1, c);
            t.1 = p;
            e.add(pe);
        }
        // Underflow to zero leaves a zero coefficient; its error is already counted.
        self.terms.retain(|t| t.1 != 0.0);
        self.finish(e.bound())
    }

    /// `self / c` in place.
    fn div_scalar(mut self, c: f64) -> Aa {
        if self.is_entire() || c == 0.0 || !c.is_finite() {
            return Aa::entire();
        }
        let r = 1.0 / c;
        if is_exact_scale(c) && is_exact_scale(r) && r.is_normal() {
            return self.scale(r);
        }
        let mut e = ErrAcc::default();
        self.x0 /= c;
        e.add(err(self.x0));
        for t in &mut self.terms {
            t.1 /= c;
            e.add(err(t.1));
        }
        self.terms.retain(|t| t.1 != 0.0);
        self.finish(e.bound())
    }

    /// `alpha·self + zeta ± delta`, the one place every non-affine function goes through.
    fn apply(mut self, a: Approx) -> Aa {
        if self.is_entire() || a.is_entire() || a.delta < 0.0 {
            return Aa::entire();
        }
        let mut e = ErrAcc::default();
        e.add(a.delta);
        if a.alpha == 0.0 {
            self.terms.clear();
            self.x0 = a.zeta;
        } else {
            let (p, pe) = prod(self.x0, a.alpha);
            e.add(pe);
            let (c, ce) = two_sum(p, a.zeta);
            e.add(ce);
            self.x0 = c;
            if a.alpha != 1.0 {
                for t in &mut self.terms {
                    let (p, pe) = prod(t.1, a.alpha);
                    t.1 = p;
                    e.add(pe);
                }
                self.terms.retain(|t| t.1 != 0.0);
            }
        }
        self.finish(e.bound())
    }

    /// Applies the approximation `f` built on this form's range; unbounded forms and
    /// ranges that overflowed give the unbounded form.
    fn nonaffine(self, f: impl FnOnce(f64, f64) -> Approx) -> Aa {
        if self.is_entire() {
            return self;
        }
        let (lo, hi) = self.bounds();
        if !(lo.is_finite() && hi.is_finite()) {
            return Aa::entire();
        }
        let a = f(lo, hi);
        self.apply(a)
    }

    /// Standard AA product: `x0·y0 + Σ (x0·yi + y0·xi)·εi + (Σ|xi|·Σ|yi|)·ε_new`.
    fn mul_aa(self, other: &Aa) -> Aa {
        if self.is_entire() || other.is_entire() {
            return Aa::entire();
        }
        if other.terms.is_empty() {
            return self.scale(other.x0);
        }
        if self.terms.is_empty() {
            return other.clone().scale(self.x0);
        }
        let (x0, y0) = (self.x0, other.x0);
        let (rx, ry) = (self.radius(), other.radius());
        let mut e = ErrAcc::default();
        e.add(mul_up_exact(rx, ry));
        let (p0, pe) = prod(x0, y0);
        e.add(pe);
        let (a, b) = (&self.terms, &other.terms);
        let mut t = Vec::with_capacity(a.len() + b.len() + 1);
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let c;
            let sym;
            if j == b.len() || (i < a.len() && a[i].0 < b[j].0) {
                sym = a[i].0;
                let (p, pe) = prod(y0, a[i].1);
                e.add(pe);
                c = p;
                i += 1;
            } else if i == a.len() || b[j].0 < a[i].0 {
                sym = b[j].0;
                let (p, pe) = prod(x0, b[j].1);
                e.add(pe);
                c = p;
                j += 1;
            } else {
                sym = a[i].0;
                let (p, pe) = prod(y0, a[i].1);
                let (q, qe) = prod(x0, b[j].1);
                e.add(pe);
                e.add(qe);
                let (s, se) = two_sum(p, q);
                e.add(se);
                c = s;
                i += 1;
                j += 1;
            }
            if c != 0.0 {
                t.push((sym, c));
            }
        }
        Aa { x0: p0, terms: t }.finish(e.bound())
    }

    /// `x^2` as `x0² + s + Σ 2·x0·xi·εi ± r`: the quadratic part `(Σ xi·εi)²` lies in
    /// `[0, R²]` (`R = Σ|xi|`), so it is centred at `s ≈ R²/2` with radius
    /// `max(s, R² - s)`, half the `R²` that the general product `x * x` spends.
    fn sqr_aa(&self) -> Aa {
        if self.is_entire() {
            return Aa::entire();
        }
        let x0 = self.x0;
        let mut e = ErrAcc::default();
        let (p, pe) = prod(x0, x0);
        e.add(pe);
        if self.terms.is_empty() {
            return Aa {
                x0: p,
                terms: Vec::new(),
            }
            .finish(e.bound());
        }
        let r = self.radius();
        // When R² is below a few ulps of the result, the shift below gains less than
        // rounding noise; the plain product keeps `sqr` never wider than `x * x`.
        if r < (x0.abs() + r) * SQR_SHIFT_MIN {
            return self.clone().mul_aa(self);
        }
        let r2 = mul_up_exact(r, r);
        // The centre moves by exactly h - t = c - p (TwoSum: c + t = p + h), so the
        // quadratic part minus the shift lies in [-(h - t), r2 - (h - t)]: no rounding
        // error of its own.
        let h = 0.5 * r2;
        let (c, t) = two_sum(p, h);
        e.add(f64::max(sum_up(h, -t), sum_up(sum_up(r2, -h), t)));
        let t = 2.0 * x0;
        let mut terms = Vec::with_capacity(self.terms.len() + 1);
        if t != 0.0 {
            for &(sym, xi) in &self.terms {
                let (ci, cie) = prod(t, xi);
                e.add(cie);
                if ci != 0.0 {
                    terms.push((sym, ci));
                }
            }
        }
        Aa { x0: c, terms }.finish(e.bound())
    }
}

/// Appends `(sym, c)` keeping the list sorted: fresh ids increase within a thread, so
/// this is a push, except for forms that moved between threads.
#[inline]
fn push_symbol(terms: &mut Vec<(u64, f64)>, sym: u64, c: f64) {
    match terms.last() {
        Some(&(last, _)) if last >= sym => {
            let at = terms.partition_point(|t| t.0 < sym);
            terms.insert(at, (sym, c));
        }
        _ => terms.push((sym, c)),
    }
}

impl Add for Aa {
    type Output = Aa;
    fn add(self, rhs: Aa) -> Aa {
        // Merge into the longer buffer.
        if rhs.terms.len() > self.terms.len() {
            rhs.add_signed(&self, 1.0)
        } else {
            self.add_signed(&rhs, 1.0)
        }
    }
}

impl Sub for Aa {
    type Output = Aa;
    fn sub(self, rhs: Aa) -> Aa {
        if rhs.terms.len() > self.terms.len() {
            (-rhs).add_signed(&self, 1.0)
        } else {
            self.add_signed(&rhs, -1.0)
        }
    }
}

impl Mul for Aa {
    type Output = Aa;
    fn mul(self, rhs: Aa) -> Aa {
        self.mul_aa(&rhs)
    }
}

impl Div for Aa {
    type Output = Aa;
    fn div(self, rhs: Aa) -> Aa {
        if rhs.terms.is_empty() && !rhs.is_entire() {
            return self.div_scalar(rhs.x0);
        }
        self.mul_aa(&rhs.recip())
    }
}

impl Neg for Aa {
    type Output = Aa;
    fn neg(mut self) -> Aa {
        if self.is_entire() {
            return self;
        }
        self.x0 = -self.x0;
        for t in &mut self.terms {
            t.1 = -t.1;
        }
        self
    }
}

impl Add<f64> for Aa {
    type Output = Aa;
    fn add(mut self, rhs: f64) -> Aa {
        if self.is_entire() || !rhs.is_finite() {
            return Aa::entire();
        }
        let (c, ce) = two_sum(self.x0, rhs);
        self.x0 = c;
        let mut e = ErrAcc::default();
        e.add(ce);
        self.finish(e.bound())
    }
}

impl Sub<f64> for Aa {
    type Output = Aa;
    fn sub(self, rhs: f64) -> Aa {
        self + (-rhs)
    }
}

impl Mul<f64> for Aa {
    type Output = Aa;
    fn mul(self, rhs: f64) -> Aa {
        self.scale(rhs)
    }
}

impl Div<f64> for Aa {
    type Output = Aa;
    fn div(self, rhs: f64) -> Aa {
        self.div_scalar(rhs)
    }
}

arith_core::impl_f64_lhs_ops!(Aa);

impl Real for Aa {
    fn known(&self) -> arith_core::Known {
        let (lo, hi) = self.bounds();
        arith_core::Known::Range(lo, hi)
    }
    fn from_bounds(lo: f64, hi: f64) -> Option<Self> {
        Some(<Self as Range>::from_interval(lo, hi))
    }
    fn constant(c: f64) -> Aa {
        if c.is_finite() {
            Aa {
                x0: c,
                terms: Vec::new(),
            }
        } else {
            Aa::entire()
        }
    }
    fn sqr(&self) -> Aa {
        self.sqr_aa()
    }
    fn powi(&self, n: i32) -> Aa {
        match n {
            0 => Aa::constant(1.0),
            1 => self.clone(),
            2 => self.sqr(),
            i32::MIN => self.powi(n / 2).sqr(),
            n if n < 0 => self.powi(-n).recip(),
            n => self.clone().nonaffine(|a, b| approx::powi(a, b, n)),
        }
    }
    fn sqrt(&self) -> Aa {
        self.clone().nonaffine(approx::sqrt)
    }
    fn hypot(&self, other: &Aa) -> Aa {
        let floor = approx::sum_sq_floor(self.bounds(), other.bounds());
        (self.sqr() + other.sqr()).nonaffine(|a, b| approx::sqrt_at_least(a, b, floor))
    }
    fn recip(&self) -> Aa {
        self.clone().nonaffine(approx::recip)
    }
    fn exp(&self) -> Aa {
        self.clone().nonaffine(approx::exp)
    }
    fn ln(&self) -> Aa {
        self.clone().nonaffine(approx::ln)
    }
    fn sin(&self) -> Aa {
        self.clone().nonaffine(approx::sin)
    }
    fn cos(&self) -> Aa {
        self.clone().nonaffine(approx::cos)
    }
    fn abs(&self) -> Aa {
        let (lo, hi) = self.bounds();
        if lo >= 0.0 {
            self.clone()
        } else if hi <= 0.0 {
            -self.clone()
        } else {
            self.clone().nonaffine(approx::abs)
        }
    }
    fn min(&self, other: &Aa) -> Aa {
        let ((alo, ahi), (blo, bhi)) = (self.bounds(), other.bounds());
        if ahi <= blo {
            self.clone()
        } else if bhi <= alo {
            other.clone()
        } else {
            // min(x, y) = (x + y - |x - y|) / 2.
            let d = (self.clone() - other.clone()).abs();
            (self.clone() + other.clone() - d) * 0.5
        }
    }
    fn max(&self, other: &Aa) -> Aa {
        let ((alo, ahi), (blo, bhi)) = (self.bounds(), other.bounds());
        if ahi <= blo {
            other.clone()
        } else if bhi <= alo {
            self.clone()
        } else {
            // max(x, y) = (x + y + |x - y|) / 2.
            let d = (self.clone() - other.clone()).abs();
            (self.clone() + other.clone() + d) * 0.5
        }
    }
    fn rsub(self, c: f64) -> Aa {
        -self + c
    }
    fn rdiv(self, c: f64) -> Aa {
        self.recip() * c
    }
}

impl Range for Aa {
    const NAME: &'static str = "aa";
    const INPUTS: usize = INPUTS;

    fn input(i: usize, lo: f64, hi: f64) -> Aa {
        let sym = if i < INPUTS { i as u64 } else { fresh_symbol() };
        Aa::with_symbol(sym, lo, hi)
    }
    fn from_interval(lo: f64, hi: f64) -> Aa {
        Aa::with_symbol(fresh_symbol(), lo, hi)
    }
    fn bounds(&self) -> (f64, f64) {
        if self.is_entire() {
            return (f64::NEG_INFINITY, f64::INFINITY);
        }
        // x0 ∓ r can overflow to ±inf, never NaN (r is finite or +inf, x0 finite).
        let r = self.radius();
        (sum_down(self.x0, -r), sum_up(self.x0, r))
    }
    fn linear_part(&self) -> Option<Linear> {
        if self.is_entire() {
            return None;
        }
        let (f1, rest) = match self.terms.first() {
            Some(&(0, c)) => (c, &self.terms[1..]),
            _ => (0.0, &self.terms[..]),
        };
        let mut e = 0.0;
        for &(_, c) in rest {
            acc_err(&mut e, c);
        }
        Some(Linear { f0: self.x0, f1, e })
    }
    /// The input symbols `0..K` as they are, every other term's magnitude in `e`.
    fn affine_part<const K: usize>(&self) -> Option<AffinePart<K>> {
        if self.is_entire() {
            return None;
        }
        let mut xs = [0.0; K];
        let mut e = 0.0;
        for &(sym, c) in &self.terms {
            match xs.get_mut(sym as usize) {
                Some(x) if (sym as usize) < INPUTS => *x = c,
                _ => acc_err(&mut e, c),
            }
        }
        (e.is_finite() && xs.iter().all(|c| c.is_finite())).then_some(AffinePart {
            x0: self.x0,
            xs,
            e,
        })
    }
    fn bounds_at_inputs(&self, eps: &[f64]) -> (f64, f64) {
        if self.is_entire() {
            return (f64::NEG_INFINITY, f64::INFINITY);
        }
        let (mut lo, mut hi) = (self.x0, self.x0);
        let fixed = eps.len().min(INPUTS) as u64;
        for &(sym, c) in &self.terms {
            if sym < fixed {
                let (p, pe) = prod(c, eps[sym as usize]);
                lo = sum_down(lo, p);
                hi = sum_up(hi, p);
                if pe != 0.0 {
                    lo = sum_down(lo, -pe);
                    hi = sum_up(hi, pe);
                }
            } else {
                lo = sum_down(lo, -c.abs());
                hi = sum_up(hi, c.abs());
            }
        }
        // Both are sound enclosures, so their intersection is too.
        let (blo, bhi) = self.bounds();
        (lo.max(blo), hi.min(bhi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use arith_core::round::{two_prod, ETA};
    use astro_float::{BigFloat, RoundingMode};
    use proptest::prelude::*;

    /// Floats of every magnitude, short significands included (exact products).
    fn any_f64() -> impl Strategy<Value = f64> {
        prop_oneof![
            proptest::num::f64::NORMAL | proptest::num::f64::SUBNORMAL | proptest::num::f64::ZERO,
            (-1000i64..1000, -60i32..60).prop_map(|(m, e)| m as f64 * 2f64.powi(e)),
            (-1000i64..1000, -1080i32..-1000).prop_map(|(m, e)| m as f64 * 2f64.powi(e)),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(4096))]

        /// `prod`'s bound covers the exact FMA residual, and "exact" (bound 0) is never
        /// claimed for an inexact product.
        #[test]
        fn prod_error_bound_is_sound(a in any_f64(), b in any_f64()) {
            let (p, e) = prod(a, b);
            prop_assert_eq!(p.to_bits(), (a * b).to_bits());
            if !p.is_finite() {
                prop_assert_eq!(e, f64::INFINITY);
            } else if e == 0.0 && a != 0.0 && b != 0.0 {
                // Scaling the smaller factor by 2^600 (exact) moves a tiny product far
                // from underflow, where the FMA residual is exact: it must be 0.
                let s = if p.abs() > 1e-290 { 1.0 } else { 2f64.powi(600) };
                let (a, b) = if a.abs() < b.abs() { (a * s, b) } else { (a, b * s) };
                let (q, r) = two_prod(a, b);
                prop_assert!(r == 0.0 && q == p * s, "{a} * {b} claimed exact");
            } else if e == 0.0 {
                prop_assert_eq!(p, 0.0);
            } else if p.abs() > 1e-290 {
                let (_, r) = two_prod(a, b);
                prop_assert!(r.abs() <= e, "{a} * {b}: residual {r} > bound {e}");
            } else {
                prop_assert!(e >= ETA);
            }
        }

        /// `sum_up`/`sum_down` bracket the exact sum, exactly when it is a float.
        #[test]
        fn directed_sums_bracket(a in any_f64(), b in any_f64()) {
            let (s, t) = two_sum(a, b);
            let (u, d) = (sum_up(a, b), sum_down(a, b));
            if s.is_finite() {
                if t == 0.0 {
                    prop_assert!(u == s && d == s);
                } else if t > 0.0 {
                    prop_assert!(u == s.next_up() && d == s);
                } else {
                    prop_assert!(u == s && d == s.next_down());
                }
            } else {
                prop_assert!(u == f64::INFINITY && d == f64::NEG_INFINITY);
            }
        }

        /// The error accumulator's bound is at least the exact sum of `|terms|`.
        #[test]
        fn err_acc_bounds_exact_sum(v in proptest::collection::vec(any_f64(), 0..40)) {
            const P: usize = 4096;
            let mut acc = ErrAcc::default();
            let mut exact = BigFloat::from_f64(0.0, P);
            for &x in &v {
                acc.add(x);
                exact = exact.add(&BigFloat::from_f64(x.abs(), P), P, RoundingMode::None);
            }
            let b = acc.bound();
            prop_assert!(b >= 0.0);
            prop_assert!(
                exact.cmp(&BigFloat::from_f64(b, P)).is_some_and(|c| c <= 0),
                "bound {b} below the exact sum {exact}"
            );
        }
    }
}
