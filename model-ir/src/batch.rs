//! Batched evaluation: one tape over many inputs per call, instruction by instruction
//! over all of them (structure of arrays: each register holds one value per lane). The
//! dispatch on the instruction, the operand lookups and the register traffic are paid
//! once per instruction and batch, not once per evaluation, and each instruction's loop
//! over the lanes is a tight loop of one operation.
//!
//! Points (`f64`), intervals ([`Interval`], and its four-lane packs [`IntervalX4`])
//! and forward-mode gradients ([`Dual<f64>`], [`Tape::eval_gradient_batch`]) run the
//! kernels of this module: eight lanes per instruction of the processor's
//! fastest path of [`arith_core::lanes`] (AVX-512 with per-instruction rounding, AVX2,
//! or emulated), over one flat register file per thread ([`regfile`]) that a batch
//! reuses without allocating. Points are bit for bit what [`Tape::eval`] gives; interval
//! bounds are the same numbers on the AVX-512 and emulated paths (a zero bound may
//! differ in sign) and enclose them within an ulp per rounding on the AVX2 path;
//! gradients are bit for bit what [`Tape::eval`] gives over `Dual<f64>`. Revised affine
//! forms ([`RevAa<N>`] for one and three symbols, and their four-form packs) run a
//! kernel of their affine operations, product, square, `min` and `max` in lanes, every
//! other instruction lane by lane through the scalar form: bit for bit the scalar forms
//! on the AVX-512 path, as sound on the AVX2 path (whose square may take a radius bound
//! an ulp higher); the emulated path runs them in the generic loop, which is faster
//! there and gives the same bits. Every
//! other type runs the generic loop below, whose every lane is, bit for bit, what
//! [`Tape::eval`] gives on that lane's inputs.
//!
//! Lanes may themselves be SIMD packs ([`arith_core::pack::Pack`]: four ray forms in
//! one value), so a batch of `n` packs evaluates `4 n` ray segments.

mod gradients;
mod intervals;
mod parts;
mod points;
mod regfile;
mod revaa;
mod revaa_approx;

pub(crate) use regfile::Slots;

use crate::instr::{Instr, Op};
use crate::tape::Tape;
use arith_core::branch::Step;
use arith_core::dual::Dual;
use arith_core::lanes::{dispatch, F64x8, Path, LANES};
use arith_core::pack::{Pack, LANES as PACK};
use arith_core::simd::f64x4;
use arith_core::{rfunc, Real};
use arith_ia::{Interval, IntervalX4};
use arith_revaa::{RevAa, RevAaX4};
use std::any::{Any, TypeId};
use std::cell::RefCell;
use std::marker::PhantomData;

thread_local! {
    /// Spare register vectors per value type and thread, reused across batches.
    static SPARE: RefCell<Vec<Box<dyn Any>>> = const { RefCell::new(Vec::new()) };
}

/// The register file of one batch: one vector of lanes per register, taken at an
/// operand's last read (so its allocation becomes the result's) and otherwise copied.
struct Regs<R> {
    regs: Vec<Vec<R>>,
    spare: Vec<Vec<R>>,
}

impl<R: Clone> Regs<R> {
    /// Operand `k` of `i`, owned: moved out at its last read, else copied.
    fn owned(&mut self, i: &Instr, k: usize) -> Vec<R> {
        let r = i.reg(k) as usize;
        if i.last & (1 << k) != 0 {
            std::mem::take(&mut self.regs[r])
        } else {
            let mut v = self.spare.pop().unwrap_or_default();
            v.clone_from(&self.regs[r]);
            v
        }
    }

    /// Operand `k` of `i`, borrowed.
    fn get(&self, i: &Instr, k: usize) -> &[R] {
        &self.regs[i.reg(k) as usize]
    }

    /// Gives back the storage of operand `k` of `i` if this was its last read.
    fn release(&mut self, i: &Instr, k: usize) {
        if i.last & (1 << k) != 0 {
            let mut v = std::mem::take(&mut self.regs[i.reg(k) as usize]);
            v.clear();
            self.spare.push(v);
        }
    }

    fn fresh(&mut self) -> Vec<R> {
        self.spare.pop().unwrap_or_default()
    }
}

/// `f(a[l])` for every lane, into a fresh vector (`a`'s storage goes back to the
/// spares).
#[inline(always)]
fn map<R: Real>(regs: &mut Regs<R>, mut a: Vec<R>, f: impl Fn(R) -> R) -> Vec<R> {
    let mut o = regs.fresh();
    o.extend(a.drain(..).map(f));
    regs.spare.push(a);
    o
}

/// `f(a[l], b[l])` for every lane, into a fresh vector.
#[inline(always)]
fn zip<R: Real>(
    regs: &mut Regs<R>,
    mut a: Vec<R>,
    k: usize,
    i: &Instr,
    f: impl Fn(R, R) -> R,
) -> Vec<R> {
    let mut o = regs.fresh();
    o.extend(
        a.drain(..)
            .zip(regs.get(i, k))
            .map(|(x, y)| f(x, y.clone())),
    );
    regs.spare.push(a);
    o
}

impl Tape {
    /// Evaluates the tape on every lane `l` of the inputs, `(x[l], y[l], z[l])`, into
    /// `out` (cleared first), on this process's lane path ([`Path::current`]): `out[l]`
    /// encloses `self.eval(x[l], y[l], z[l])` (see the [module](crate::batch) for how
    /// exactly on each path). The three slices have the same length.
    ///
    /// ```
    /// use arith_core::{Range, Real};
    /// use arith_ia::Interval;
    /// use model_ir::Tape;
    /// let t = Tape::record(|x, y, z| (x.sqr() + y.sqr() + z.sqr()).rsub(1.0));
    /// let xs: Vec<Interval> = (0..8).map(|k| Interval::from_interval(k as f64 / 8.0, 1.0)).collect();
    /// let zero = vec![Interval::constant(0.0); 8];
    /// let mut out = Vec::new();
    /// t.eval_batch(&xs, &zero, &zero, &mut out);
    /// for (o, x) in out.iter().zip(&xs) {
    ///     let (lo, hi) = t.eval(*x, zero[0], zero[0]).bounds();
    ///     assert!(o.lo <= lo && hi <= o.hi);
    /// }
    /// ```
    pub fn eval_batch<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        self.eval_batch_on(Path::current(), x, y, z, out)
    }

    /// [`Tape::eval_batch`] on the lane path `path` (a path this processor lacks runs
    /// emulated; types without a kernel ignore the path).
    pub fn eval_batch_on<R: Real>(&self, path: Path, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        let n = x.len();
        assert!(
            y.len() == n && z.len() == n,
            "eval_batch: inputs of unequal lengths"
        );
        out.clear();
        if n == 0 {
            return;
        }
        let id = TypeId::of::<R>();
        let src = [x, y, z];
        if id == TypeId::of::<f64>() {
            self.batch_parts::<points::Points>(
                path,
                n,
                |q, l, p| p[0] = *cast_ref::<R, f64>(&src[q][l]),
                |_, p| out.push(cast(p[0])),
            );
        } else if id == TypeId::of::<Interval>() {
            self.batch_parts::<intervals::Intervals>(
                path,
                n,
                |q, l, p| {
                    let i: &Interval = cast_ref(&src[q][l]);
                    p.copy_from_slice(&[i.lo, i.hi]);
                },
                |_, p| out.push(cast(Interval { lo: p[0], hi: p[1] })),
            );
        } else if id == TypeId::of::<IntervalX4>() {
            let mut lanes = ([0.0; PACK], [0.0; PACK]);
            self.batch_parts::<intervals::Intervals>(
                path,
                PACK * n,
                |q, l, p| {
                    let v: &IntervalX4 = cast_ref(&src[q][l / PACK]);
                    p.copy_from_slice(&[v.lo.to_array()[l % PACK], v.hi.to_array()[l % PACK]]);
                },
                |l, p| {
                    (lanes.0[l % PACK], lanes.1[l % PACK]) = (p[0], p[1]);
                    if l % PACK == PACK - 1 {
                        let p = IntervalX4 {
                            lo: f64x4::new(lanes.0),
                            hi: f64x4::new(lanes.1),
                        };
                        out.push(cast(p));
                    }
                },
            );
        } else if is_revaa::<R>() && !revaa_lanes(path) {
            // Without SIMD lanes the directed sums of `min` and `max` cost more than the
            // generic loop over four-form packs, which gives the same bits.
            self.batch_generic(x, y, z, out);
        } else if id == TypeId::of::<RevAa<1>>() {
            self.batch_revaa::<1, R>(path, src, out);
        } else if id == TypeId::of::<RevAa<3>>() {
            self.batch_revaa::<3, R>(path, src, out);
        } else if id == TypeId::of::<RevAaX4<1>>() {
            self.batch_revaa_packs::<1, R>(path, src, out);
        } else if id == TypeId::of::<RevAaX4<3>>() {
            self.batch_revaa_packs::<3, R>(path, src, out);
        } else if id == TypeId::of::<Dual<f64>>() {
            self.batch_gradients(
                path,
                n,
                |q, l| {
                    let d: &Dual<f64> = cast_ref(&src[q][l]);
                    (d.v, d.g)
                },
                |d| out.push(cast(d)),
            );
        } else {
            self.batch_generic(x, y, z, out);
        }
    }

    /// The value and gradient of the tape at every point `(x[l], y[l], z[l])`, into
    /// `out` (cleared first), by forward-mode differentiation over eight lanes on this
    /// process's lane path ([`Path::current`]): `out[l]` is, bit for bit, what
    /// [`Tape::eval`] gives over [`Dual<f64>`] at that point (each input's partial 1 by
    /// itself, 0 by the others). One evaluation per point gives a normal's direction.
    /// The three slices have the same length.
    ///
    /// ```
    /// use arith_core::dual::Dual;
    /// use arith_core::Real;
    /// use model_ir::Tape;
    /// // The unit ball: f = 1 - x^2 - y^2 - z^2, gradient (-2x, -2y, -2z).
    /// let t = Tape::record(|x, y, z| (x.sqr() + y.sqr() + z.sqr()).rsub(1.0));
    /// let xs: Vec<f64> = (0..10).map(|k| k as f64 / 10.0).collect();
    /// let (ys, zs) = (vec![0.5; 10], vec![-0.25; 10]);
    /// let mut out = Vec::new();
    /// t.eval_gradient_batch(&xs, &ys, &zs, &mut out);
    /// for (d, &x) in out.iter().zip(&xs) {
    ///     assert_eq!(d.g, [-2.0 * x, -1.0, 0.5]);
    ///     assert_eq!(*d, t.eval(Dual::var(x, 0), Dual::var(0.5, 1), Dual::var(-0.25, 2)));
    /// }
    /// ```
    pub fn eval_gradient_batch(&self, x: &[f64], y: &[f64], z: &[f64], out: &mut Vec<Dual<f64>>) {
        self.eval_gradient_batch_on(Path::current(), x, y, z, out)
    }

    /// [`Tape::eval_gradient_batch`] on the lane path `path` (a path this processor
    /// lacks runs emulated; every path gives the same bits).
    pub fn eval_gradient_batch_on(
        &self,
        path: Path,
        x: &[f64],
        y: &[f64],
        z: &[f64],
        out: &mut Vec<Dual<f64>>,
    ) {
        let n = x.len();
        assert!(
            y.len() == n && z.len() == n,
            "eval_gradient_batch: inputs of unequal lengths"
        );
        out.clear();
        if n == 0 {
            return;
        }
        let seed = |q: usize| core::array::from_fn(|k| if k == q { 1.0 } else { 0.0 });
        let seeds: [[f64; 3]; 3] = [seed(0), seed(1), seed(2)];
        self.batch_gradients(path, n, |q, l| ([x, y, z][q][l], seeds[q]), |d| out.push(d));
    }

    /// The register slots of the batch kernels.
    fn slots(&self) -> &Slots {
        self.shared()
            .slots
            .get_or_init(|| Slots::allocate(self.instructions()))
    }

    /// The gradient kernel over `n` lanes, lane `l` of input `q` (its value and
    /// partials) from `lane(q, l)`; each result handed to `put` in order.
    fn batch_gradients(
        &self,
        path: Path,
        n: usize,
        lane: impl Fn(usize, usize) -> (f64, [f64; 3]),
        mut put: impl FnMut(Dual<f64>),
    ) {
        let stage = |q: usize, l: usize, p: &mut [f64]| {
            let (v, g) = lane(q, l);
            p.copy_from_slice(&[v, g[0], g[1], g[2]]);
        };
        self.batch_parts::<gradients::Duals>(path, n, stage, |_, p| {
            put(Dual {
                v: p[0],
                g: [p[1], p[2], p[3]],
            })
        });
    }

    /// The RevAA kernel over lanes of type `RevAa<N>` (`R` is that type).
    fn batch_revaa<const N: usize, R: Real>(&self, path: Path, src: [&[R]; 3], out: &mut Vec<R>) {
        let lane = |q: usize, l: usize| *cast_ref::<R, RevAa<N>>(&src[q][l]);
        self.revaa_kernel::<N>(path, src[0].len(), lane, |_, f| out.push(cast(f)));
    }

    /// The RevAA kernel over four-form packs `RevAaX4<N>` (`R` is that type).
    fn batch_revaa_packs<const N: usize, R: Real>(
        &self,
        path: Path,
        src: [&[R]; 3],
        out: &mut Vec<R>,
    ) {
        let lane =
            |q: usize, l: usize| cast_ref::<R, RevAaX4<N>>(&src[q][l / PACK]).unpack()[l % PACK];
        let mut lanes = [RevAa::<N>::constant(0.0); PACK];
        self.revaa_kernel::<N>(path, PACK * src[0].len(), lane, |l, f| {
            lanes[l % PACK] = f;
            if l % PACK == PACK - 1 {
                out.push(cast(RevAaX4::<N>::pack(lanes)));
            }
        });
    }

    /// The RevAA kernel over `n` lanes, lane `l` of input `q` from `lane(q, l)`; each
    /// result lane `l` handed to `put(l, form)` in order.
    fn revaa_kernel<const N: usize>(
        &self,
        path: Path,
        n: usize,
        lane: impl Fn(usize, usize) -> RevAa<N>,
        mut put: impl FnMut(usize, RevAa<N>),
    ) {
        let stage = |q: usize, l: usize, p: &mut [f64]| {
            let f = lane(q, l);
            p[0] = f.x0;
            p[1..=N].copy_from_slice(&f.xs);
            p[N + 1] = f.e;
        };
        self.batch_parts::<revaa::Forms<N>>(path, n, stage, |l, p| {
            let xs = core::array::from_fn(|k| p[1 + k]);
            put(l, RevAa::<N>::from_parts(p[0], xs, p[N + 1]))
        });
    }

    /// A kernel over values of `P::PARTS` parts ([`parts`]) over `n` lanes: lane `l` of
    /// input `q` written into its parts by `stage(q, l, parts)`, each result lane `l`
    /// handed to `put(l, parts)` in order.
    fn batch_parts<P: parts::PartOps>(
        &self,
        path: Path,
        n: usize,
        stage: impl Fn(usize, usize, &mut [f64]),
        put: impl FnMut(usize, &[f64]),
    ) {
        self.watched_parts::<P>(path, n, stage, put, (&[], &mut []));
    }

    /// [`Tape::batch_parts`], the registers `watch` maps to a place `w` (`u32::MAX`:
    /// not watched) also copied to `seen`, laid out as the staged input `w` would be
    /// ([`parts::Parts`]).
    fn watched_parts<P: parts::PartOps>(
        &self,
        path: Path,
        n: usize,
        stage: impl Fn(usize, usize, &mut [f64]),
        mut put: impl FnMut(usize, &[f64]),
        (watch, seen): (&[u32], &mut [F64x8]),
    ) {
        let np = P::PARTS;
        let chunks = n.div_ceil(LANES);
        let slots = self.slots();
        let mut buf = [0.0; parts::MAX_PARTS];
        let pass = chunks.min(parts::pass_blocks(np));
        regfile::with_file(
            np * (slots.count + parts::SCRATCH) * pass,
            4 * np * chunks,
            |file, staged| {
                let (inputs, output) = staged.split_at_mut(3 * np * chunks);
                for q in 0..3 {
                    for j in 0..chunks {
                        let at = np * (q * chunks + j);
                        for l in 0..LANES {
                            stage(q, (j * LANES + l).min(n - 1), &mut buf[..np]);
                            for (k, &v) in buf[..np].iter().enumerate() {
                                inputs[at + k].0[l] = v;
                            }
                        }
                    }
                }
                let kernel = parts::Parts::<P> {
                    ins: self.instructions(),
                    slots,
                    file,
                    inputs,
                    output: &mut *output,
                    chunks,
                    watch,
                    seen,
                    kind: PhantomData,
                };
                dispatch(path, kernel);
                for l in 0..n {
                    let b = np * (l / LANES);
                    for (k, v) in buf[..np].iter_mut().enumerate() {
                        *v = output[b + k].0[l % LANES];
                    }
                    put(l, &buf[..np]);
                }
            },
        );
    }

    /// [`Tape::eval_batch`] over boxes on the current lane path (the same bits), the
    /// registers that `watch` maps to a place also copied to `seen` as
    /// [`Tape::watched_intervals`] lays them out (`2 * (w * chunks + l / LANES)` holds
    /// lane `l`'s lower bounds of place `w`, the next its upper bounds; `seen` has room
    /// for every place and chunk).
    pub(crate) fn eval_boxes_watched(
        &self,
        [x, y, z]: [&[Interval]; 3],
        out: &mut Vec<Interval>,
        (watch, seen): (&[u32], &mut [F64x8]),
    ) {
        out.clear();
        if x.is_empty() {
            return;
        }
        let src = [x, y, z];
        self.watched_parts::<intervals::Intervals>(
            Path::current(),
            x.len(),
            |q, l, p| p.copy_from_slice(&[src[q][l].lo, src[q][l].hi]),
            |_, p| out.push(Interval { lo: p[0], hi: p[1] }),
            (watch, seen),
        );
    }

    /// The interval bounds over `n` boxes (box `l`'s side `q` is `lane(q, l)`) of the
    /// registers that `watch` maps to a place `w < count` (`u32::MAX`: not watched):
    /// `seen(l, w, (lo, hi))` for every box and watched register, on the lane kernel
    /// of the current path, each bound what the scalar [`Interval`] gives.
    pub(crate) fn watched_intervals(
        &self,
        watch: &[u32],
        count: usize,
        n: usize,
        lane: impl Fn(usize, usize) -> (f64, f64),
        mut seen: impl FnMut(usize, usize, (f64, f64)),
    ) {
        if n == 0 {
            return;
        }
        let chunks = n.div_ceil(LANES);
        regfile::with_seen(2 * count * chunks, |seen_file| {
            let stage = |q: usize, l: usize, p: &mut [f64]| {
                let (lo, hi) = lane(q, l);
                p.copy_from_slice(&[lo, hi]);
            };
            let path = Path::current();
            let watched = (watch, &mut *seen_file);
            self.watched_parts::<intervals::Intervals>(path, n, stage, |_, _| {}, watched);
            for w in 0..count {
                for l in 0..n {
                    let at = 2 * (w * chunks + l / LANES);
                    let b = (seen_file[at].0[l % LANES], seen_file[at + 1].0[l % LANES]);
                    seen(l, w, b);
                }
            }
        });
    }

    /// The generic loop: one vector of values per register.
    fn batch_generic<R: Real>(&self, x: &[R], y: &[R], z: &[R], out: &mut Vec<R>) {
        let ins = self.instructions();
        let spare = take_spare::<R>();
        let mut regs = Regs {
            regs: Vec::with_capacity(ins.len()),
            spare,
        };
        for i in ins {
            let v = step(&mut regs, i, [x, y, z]);
            regs.regs.push(v);
        }
        let last = regs.regs.pop().unwrap_or_default();
        out.extend(last);
        let Regs { regs, mut spare } = regs;
        for mut v in regs {
            if v.capacity() > 0 {
                v.clear();
                spare.push(v);
            }
        }
        give_spare(spare);
    }
}

/// Whether [`Tape::eval_batch`] over lanes of type `R` runs a lane kernel (points,
/// intervals, dual numbers, and RevAA forms on a hardware lane path), rather than the
/// generic loop, for which packs of four forms ([`arith_core::pack`]) are the faster
/// input.
pub fn lane_kernel<R: 'static>() -> bool {
    let id = TypeId::of::<R>();
    let plain = [
        TypeId::of::<f64>(),
        TypeId::of::<Interval>(),
        TypeId::of::<Dual<f64>>(),
    ];
    let revaa = [TypeId::of::<RevAa<1>>(), TypeId::of::<RevAa<3>>()];
    plain.contains(&id) || (revaa.contains(&id) && revaa_lanes(Path::current()))
}

/// Whether RevAA forms run the lane kernel on `path`: on the hardware paths this
/// processor has (emulated, the directed sums of `min` and `max` cost more than the
/// generic loop over four-form packs).
fn revaa_lanes(path: Path) -> bool {
    path != Path::Emulated && path.available()
}

/// Whether `R` is a revised affine form of the RevAA kernel.
fn is_revaa<R: 'static>() -> bool {
    let id = TypeId::of::<R>();
    [
        TypeId::of::<RevAa<1>>(),
        TypeId::of::<RevAa<3>>(),
        TypeId::of::<RevAaX4<1>>(),
        TypeId::of::<RevAaX4<3>>(),
    ]
    .contains(&id)
}

/// `v` as the type `R` that it is (checked by the caller's `TypeId` test).
fn cast<T: 'static, R: 'static>(v: T) -> R {
    let mut o = Some(v);
    (&mut o as &mut dyn Any)
        .downcast_mut::<Option<R>>()
        .and_then(Option::take)
        .expect("kernel type checked by TypeId")
}

/// `v` as the type `T` that it is (checked by the caller's `TypeId` test).
fn cast_ref<R: 'static, T: 'static>(v: &R) -> &T {
    (v as &dyn Any)
        .downcast_ref::<T>()
        .expect("kernel type checked by TypeId")
}

/// The lanes of instruction `i`.
fn step<R: Real>(regs: &mut Regs<R>, i: &Instr, [x, y, z]: [&[R]; 3]) -> Vec<R> {
    let input = |regs: &mut Regs<R>, v: &[R]| {
        let mut o = regs.fresh();
        o.extend_from_slice(v);
        o
    };
    let c = i.c;
    macro_rules! un {
        ($f:expr) => {{
            let a = regs.owned(i, 0);
            map(regs, a, $f)
        }};
    }
    macro_rules! bin {
        ($f:expr) => {{
            let a = regs.owned(i, 0);
            let out = zip(regs, a, 1, i, $f);
            regs.release(i, 1);
            out
        }};
    }
    match i.op {
        Op::X => input(regs, x),
        Op::Y => input(regs, y),
        Op::Z => input(regs, z),
        Op::Const => {
            let mut o = regs.fresh();
            o.resize(x.len(), R::constant(c));
            o
        }
        Op::Neg => un!(|a: R| -a),
        Op::Sqr => un!(|a: R| a.sqr()),
        Op::Powi => un!(|a: R| a.powi(i.n)),
        Op::Sqrt => un!(|a: R| a.sqrt()),
        Op::Recip => un!(|a: R| a.recip()),
        Op::Exp => un!(|a: R| a.exp()),
        Op::Ln => un!(|a: R| a.ln()),
        Op::Sin => un!(|a: R| a.sin()),
        Op::Cos => un!(|a: R| a.cos()),
        Op::Abs => un!(|a: R| a.abs()),
        Op::AddC => un!(|a: R| a + c),
        Op::SubC => un!(|a: R| a - c),
        Op::RSubC => un!(|a: R| a.rsub(c)),
        Op::MulC => un!(|a: R| a * c),
        Op::DivC => un!(|a: R| a / c),
        Op::RDivC => un!(|a: R| a.rdiv(c)),
        Op::Gt0 => un!(|a: R| a.step(Step::Pos)),
        Op::Ge0 => un!(|a: R| a.step(Step::NonNeg)),
        Op::Add => bin!(|a: R, b: R| a + b),
        Op::Sub => bin!(|a: R, b: R| a - b),
        Op::Mul => bin!(|a: R, b: R| a * b),
        Op::Div => bin!(|a: R, b: R| a / b),
        Op::Hypot => bin!(|a: R, b: R| a.hypot(&b)),
        Op::Min => bin!(|a: R, b: R| a.min(&b)),
        Op::Max => bin!(|a: R, b: R| a.max(&b)),
        Op::Intersect => bin!(rfunc::intersect),
        Op::Union => bin!(rfunc::union),
        Op::Subtract => bin!(rfunc::subtract),
        Op::BlendUnion => bin!(rfunc::blend_union),
        Op::BlendIntersect => bin!(rfunc::blend_intersect),
        Op::Select => {
            let cnd = regs.owned(i, 0);
            let (t, e) = (regs.get(i, 1), regs.get(i, 2));
            let mut o = cnd;
            for ((c, t), e) in o.iter_mut().zip(t).zip(e) {
                *c = c.select(t.clone(), e.clone());
            }
            regs.release(i, 1);
            regs.release(i, 2);
            o
        }
    }
}

fn take_spare<R: 'static>() -> Vec<Vec<R>> {
    SPARE
        .try_with(|pool| {
            let mut pool = pool.try_borrow_mut().ok()?;
            let k = pool.iter().position(|b| b.is::<Vec<Vec<R>>>())?;
            let b = pool.swap_remove(k);
            b.downcast::<Vec<Vec<R>>>().ok().map(|b| *b)
        })
        .ok()
        .flatten()
        .unwrap_or_default()
}

fn give_spare<R: 'static>(spare: Vec<Vec<R>>) {
    let _ = SPARE.try_with(|pool| {
        if let Ok(mut pool) = pool.try_borrow_mut() {
            pool.push(Box::new(spare));
        }
    });
}
