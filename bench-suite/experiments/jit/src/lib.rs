//! # tape-jit: an experiment in compiling tapes
//!
//! A [`model_ir::Tape`] compiled with Cranelift to one native function that evaluates it
//! over a batch of lanes, structure of arrays: [`PointJit`] over `f64` points,
//! [`IntervalJit`] over intervals (`lo` and `hi` arrays). Every lane's result is bit for
//! bit what the interpreter ([`Tape::eval`], [`Tape::eval_batch`]) gives in `f64` and in
//! [`arith_ia::Interval`] (for points: up to the payload of a NaN).
//!
//! How the intervals stay bit for bit: the JIT emits, per instruction, the *common path*
//! of arith-ia's operation as the same sequence of `f64` operations (the tight bounds of
//! `arith_core::round::tight`: the rounded result, its error by TwoSum or one FMA, one ulp
//! outward where the error says so; the same case analysis by signs as the scalar
//! product, as selects) together with a flag saying whether the scalar would also have
//! taken that path (finite bounds, products of at least `2^-960`, no point factor of 0,
//! ...). The flags of a lane are and-ed; a lane where any flag is false is evaluated again
//! by the interpreter ([`Tape::eval`] over `Interval`), so rare paths (overflow,
//! underflow, infinite bounds) cost time but never a bit. Instructions without an inline
//! form (`exp`, `ln`, `sin`, `cos`, `/` of two intervals, `powi` other than 2, the
//! R-functions, comparisons and selects) call the scalar operation itself through a
//! small `extern "C"` helper. [`Coverage`] counts both kinds.
//!
//! Code generation is lane-major: one loop over the lanes, the whole tape in SSA values
//! inside it (Cranelift's register allocator spills what does not fit), so no register
//! file in memory and no dispatch at all.

use arith_core::branch::Step;
use arith_core::{rfunc, Real};
use arith_ia::Interval;
use cranelift_codegen::ir::condcodes::FloatCC;
use cranelift_codegen::ir::{
    types, AbiParam, InstBuilder, MemFlags, Signature, StackSlot, StackSlotData, StackSlotKind,
    Value,
};
use cranelift_codegen::settings::{self, Configurable};
use cranelift_codegen::{isa, Context};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{default_libcall_names, Linkage, Module};
use model_ir::{Instr, Op, Tape};
use std::cell::Cell;
use std::time::{Duration, Instant};

/// `2^-960`: below this magnitude arith-ia's product and quotient bounds leave their
/// common path (`arith_core::round::tight::TINY`).
const TINY: f64 = f64::from_bits(63 << 52);

/// How many instructions of a tape the JIT compiled inline and how many call the scalar
/// operation through a helper.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Coverage {
    /// Emitted as native code.
    pub inline: usize,
    /// Calls to the scalar operation (`extern "C"` helper).
    pub helper: usize,
}

/// Why a tape could not be compiled (a Cranelift error, as text).
#[derive(Debug)]
pub struct JitError(pub String);

impl<E: std::fmt::Display> From<E> for JitError {
    fn from(e: E) -> Self {
        JitError(e.to_string())
    }
}

type PointFn = unsafe extern "C" fn(*const f64, *const f64, *const f64, *mut f64, u64);
type IntervalFn = unsafe extern "C" fn(*const IaArgs, u64);

/// The arguments of the compiled interval function.
#[repr(C)]
struct IaArgs {
    x: [*const f64; 2],
    y: [*const f64; 2],
    z: [*const f64; 2],
    out: [*mut f64; 2],
    /// The tape, for lanes that leave the common path.
    tape: *const Tape,
}

/// A tape compiled for `f64` points.
pub struct PointJit {
    _module: JITModule,
    f: PointFn,
    _tape: Box<Tape>,
    /// Inline and helper instructions.
    pub coverage: Coverage,
    /// Time Cranelift took (IR building, code generation and linking).
    pub compile_time: Duration,
}

/// A tape compiled for intervals ([`arith_ia::Interval`]).
pub struct IntervalJit {
    _module: JITModule,
    f: IntervalFn,
    tape: Box<Tape>,
    /// Inline and helper instructions.
    pub coverage: Coverage,
    /// Time Cranelift took (IR building, code generation and linking).
    pub compile_time: Duration,
}

// The compiled code reads only its arguments and the tape it owns (shared immutably).
unsafe impl Send for PointJit {}
unsafe impl Sync for PointJit {}
unsafe impl Send for IntervalJit {}
unsafe impl Sync for IntervalJit {}

impl PointJit {
    /// Compiles `tape` for points.
    pub fn new(tape: &Tape) -> Result<Self, JitError> {
        let t0 = Instant::now();
        let tape = Box::new(tape.clone());
        let (module, ptr, coverage) = compile(&tape, Kind::Point)?;
        // SAFETY: `compile` built a function of exactly this signature.
        let f = unsafe { std::mem::transmute::<*const u8, PointFn>(ptr) };
        Ok(PointJit {
            _module: module,
            f,
            _tape: tape,
            coverage,
            compile_time: t0.elapsed(),
        })
    }

    /// `out[l] = tape.eval(x[l], y[l], z[l])` for every lane (`out` resized to the
    /// inputs' common length).
    pub fn eval(&self, x: &[f64], y: &[f64], z: &[f64], out: &mut Vec<f64>) {
        let n = x.len();
        assert!(y.len() == n && z.len() == n, "inputs of unequal lengths");
        out.clear();
        out.resize(n, 0.0);
        // SAFETY: every pointer is valid for `n` lanes.
        unsafe {
            (self.f)(
                x.as_ptr(),
                y.as_ptr(),
                z.as_ptr(),
                out.as_mut_ptr(),
                n as u64,
            )
        }
    }
}

/// Intervals as structure of arrays: lower and upper bounds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lanes {
    /// Lower bounds.
    pub lo: Vec<f64>,
    /// Upper bounds.
    pub hi: Vec<f64>,
}

impl Lanes {
    /// The lanes of `v`.
    pub fn from_intervals(v: &[Interval]) -> Self {
        Lanes {
            lo: v.iter().map(|i| i.lo).collect(),
            hi: v.iter().map(|i| i.hi).collect(),
        }
    }

    /// Lane `k` as an interval.
    pub fn get(&self, k: usize) -> Interval {
        Interval {
            lo: self.lo[k],
            hi: self.hi[k],
        }
    }

    /// Number of lanes.
    pub fn len(&self) -> usize {
        self.lo.len()
    }

    /// No lanes.
    pub fn is_empty(&self) -> bool {
        self.lo.is_empty()
    }
}

impl IntervalJit {
    /// Compiles `tape` for intervals.
    pub fn new(tape: &Tape) -> Result<Self, JitError> {
        let t0 = Instant::now();
        let tape = Box::new(tape.clone());
        let (module, ptr, coverage) = compile(&tape, Kind::Interval)?;
        // SAFETY: `compile` built a function of exactly this signature.
        let f = unsafe { std::mem::transmute::<*const u8, IntervalFn>(ptr) };
        Ok(IntervalJit {
            _module: module,
            f,
            tape,
            coverage,
            compile_time: t0.elapsed(),
        })
    }

    /// `out` lane `l` = `tape.eval(x[l], y[l], z[l])` in interval arithmetic, bit for bit.
    pub fn eval(&self, x: &Lanes, y: &Lanes, z: &Lanes, out: &mut Lanes) {
        let n = x.len();
        for v in [x, y, z] {
            assert!(
                v.lo.len() == n && v.hi.len() == n,
                "inputs of unequal lengths"
            );
        }
        out.lo.clear();
        out.lo.resize(n, 0.0);
        out.hi.clear();
        out.hi.resize(n, 0.0);
        let args = IaArgs {
            x: [x.lo.as_ptr(), x.hi.as_ptr()],
            y: [y.lo.as_ptr(), y.hi.as_ptr()],
            z: [z.lo.as_ptr(), z.hi.as_ptr()],
            out: [out.lo.as_mut_ptr(), out.hi.as_mut_ptr()],
            tape: &*self.tape,
        };
        // SAFETY: every pointer is valid for `n` lanes, the tape outlives the call.
        unsafe { (self.f)(&args, n as u64) }
    }
}

// ---------------------------------------------------------------------------------------
// Helpers the compiled code calls: the scalar operations themselves.

/// One instruction over points, as the interpreter's `f64` path computes it.
fn point_op(i: &Instr, a: f64, b: f64, e: f64) -> f64 {
    match i.op {
        Op::Neg => -a,
        Op::Sqr => Real::sqr(&a),
        Op::Powi => Real::powi(&a, i.n),
        Op::Sqrt => Real::sqrt(&a),
        Op::Exp => Real::exp(&a),
        Op::Ln => Real::ln(&a),
        Op::Sin => Real::sin(&a),
        Op::Cos => Real::cos(&a),
        Op::Abs => Real::abs(&a),
        Op::Recip => Real::recip(&a),
        Op::AddC => a + i.c,
        Op::SubC => a - i.c,
        Op::RSubC => Real::rsub(a, i.c),
        Op::MulC => a * i.c,
        Op::DivC => a / i.c,
        Op::RDivC => Real::rdiv(a, i.c),
        Op::Add => a + b,
        Op::Sub => a - b,
        Op::Mul => a * b,
        Op::Div => a / b,
        Op::Hypot => Real::hypot(&a, &b),
        Op::Min => Real::min(&a, &b),
        Op::Max => Real::max(&a, &b),
        Op::Intersect => rfunc::intersect(a, b),
        Op::Union => rfunc::union(a, b),
        Op::Subtract => rfunc::subtract(a, b),
        Op::BlendUnion => rfunc::blend_union(a, b),
        Op::BlendIntersect => rfunc::blend_intersect(a, b),
        Op::Gt0 => Real::step(&a, Step::Pos),
        Op::Ge0 => Real::step(&a, Step::NonNeg),
        Op::Select => Real::select(&a, b, e),
        Op::X | Op::Y | Op::Z | Op::Const => unreachable!("inputs and constants are inline"),
    }
}

/// One instruction over intervals, as the interpreter computes it.
fn interval_op(i: &Instr, a: Interval, b: Interval, e: Interval) -> Interval {
    let c = i.c;
    match i.op {
        Op::Const => Interval::constant(c),
        Op::Neg => -a,
        Op::Sqr => a.sqr(),
        Op::Powi => a.powi(i.n),
        Op::Sqrt => a.sqrt(),
        Op::Exp => a.exp(),
        Op::Ln => a.ln(),
        Op::Sin => a.sin(),
        Op::Cos => a.cos(),
        Op::Abs => a.abs(),
        Op::Recip => a.recip(),
        Op::AddC => a + c,
        Op::SubC => a - c,
        Op::RSubC => a.rsub(c),
        Op::MulC => a * c,
        Op::DivC => a / c,
        Op::RDivC => a.rdiv(c),
        Op::Add => a + b,
        Op::Sub => a - b,
        Op::Mul => a * b,
        Op::Div => a / b,
        Op::Hypot => a.hypot(&b),
        Op::Min => a.min(&b),
        Op::Max => a.max(&b),
        Op::Intersect => rfunc::intersect(a, b),
        Op::Union => rfunc::union(a, b),
        Op::Subtract => rfunc::subtract(a, b),
        Op::BlendUnion => rfunc::blend_union(a, b),
        Op::BlendIntersect => rfunc::blend_intersect(a, b),
        Op::Gt0 => a.step(Step::Pos),
        Op::Ge0 => a.step(Step::NonNeg),
        Op::Select => a.select(b, e),
        Op::X | Op::Y | Op::Z => unreachable!("inputs are inline"),
    }
}

extern "C" fn point_helper(i: *const Instr, a: f64, b: f64, e: f64) -> f64 {
    // SAFETY: the compiled code passes an instruction of the tape it owns.
    let i = unsafe { &*i };
    point_op(i, a, b, e)
}

/// `io`: `[a.lo, a.hi, b.lo, b.hi, e.lo, e.hi, out.lo, out.hi]`.
extern "C" fn interval_helper(i: *const Instr, io: *mut f64) {
    // SAFETY: the compiled code passes an instruction of the tape it owns and a stack
    // slot of eight `f64`.
    let (i, io) = unsafe { (&*i, std::slice::from_raw_parts_mut(io, 8)) };
    let iv = |k: usize| Interval {
        lo: io[2 * k],
        hi: io[2 * k + 1],
    };
    let r = interval_op(i, iv(0), iv(1), iv(2));
    io[6] = r.lo;
    io[7] = r.hi;
}

thread_local! {
    /// Lanes the interpreter redid on this thread.
    static REDONE: Cell<u64> = const { Cell::new(0) };
}

/// How many interval lanes left the common path and were evaluated again by the
/// interpreter on this thread so far (every [`IntervalJit`] together).
pub fn lanes_redone() -> u64 {
    REDONE.with(Cell::get)
}

/// The interpreter on one lane that left the common path. `io`: `[x.lo, x.hi, y.lo,
/// y.hi, z.lo, z.hi, out.lo, out.hi]`.
extern "C" fn interval_lane(t: *const Tape, io: *mut f64) {
    REDONE.with(|r| r.set(r.get() + 1));
    // SAFETY: the compiled code passes the tape it owns and a slot of eight `f64`.
    let (t, io) = unsafe { (&*t, std::slice::from_raw_parts_mut(io, 8)) };
    let iv = |k: usize| Interval {
        lo: io[2 * k],
        hi: io[2 * k + 1],
    };
    let r = t.eval(iv(0), iv(1), iv(2));
    io[6] = r.lo;
    io[7] = r.hi;
}

// ---------------------------------------------------------------------------------------
// Code generation.

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Point,
    Interval,
}

fn isa() -> Result<isa::OwnedTargetIsa, JitError> {
    let mut flags = settings::builder();
    // `TAPE_JIT_OPT=none` trades code quality for compile time (default: speed).
    let opt = std::env::var("TAPE_JIT_OPT").unwrap_or_else(|_| "speed".into());
    flags.set("opt_level", &opt)?;
    flags.set("use_colocated_libcalls", "false")?;
    flags.set("is_pic", "false")?;
    // Host features (FMA, AVX): the same instructions the workspace targets (x86-64-v3).
    let builder = cranelift_native::builder().map_err(|e| JitError(e.to_string()))?;
    Ok(builder.finish(settings::Flags::new(flags))?)
}

fn compile(tape: &Tape, kind: Kind) -> Result<(JITModule, *const u8, Coverage), JitError> {
    let isa = isa()?;
    let ptr = isa.pointer_type();
    let mut module = JITModule::new(JITBuilder::with_isa(isa, default_libcall_names()));
    let mut ctx: Context = module.make_context();
    let sig = &mut ctx.func.signature;
    match kind {
        Kind::Point => {
            for _ in 0..4 {
                sig.params.push(AbiParam::new(ptr));
            }
        }
        Kind::Interval => sig.params.push(AbiParam::new(ptr)),
    }
    sig.params.push(AbiParam::new(types::I64));
    let id = module.declare_function("tape", Linkage::Local, &ctx.func.signature)?;
    let mut fctx = FunctionBuilderContext::new();
    let coverage = {
        let b = FunctionBuilder::new(&mut ctx.func, &mut fctx);
        let mut e = Emitter {
            b,
            ptr,
            ok: None,
            coverage: Coverage::default(),
            slot: None,
        };
        e.function(tape, kind);
        e.b.finalize();
        e.coverage
    };
    module.define_function(id, &mut ctx)?;
    module.clear_context(&mut ctx);
    module.finalize_definitions()?;
    let code = module.get_finalized_function(id);
    Ok((module, code, coverage))
}

struct Emitter<'a> {
    b: FunctionBuilder<'a>,
    ptr: types::Type,
    /// The lane's common-path flag so far (`None`: no condition yet).
    ok: Option<Value>,
    coverage: Coverage,
    /// The helpers' scratch slot.
    slot: Option<StackSlot>,
}

/// An interval in two SSA values.
#[derive(Clone, Copy)]
struct Iv {
    lo: Value,
    hi: Value,
}

impl Emitter<'_> {
    fn function(&mut self, tape: &Tape, kind: Kind) {
        let b = &mut self.b;
        let entry = b.create_block();
        let header = b.create_block();
        let body = b.create_block();
        let exit = b.create_block();
        b.append_block_params_for_function_params(entry);
        b.append_block_param(header, types::I64);
        b.switch_to_block(entry);
        let params = b.block_params(entry).to_vec();
        let n = *params.last().expect("n");
        let zero = b.ins().iconst(types::I64, 0);
        b.ins().jump(header, &[zero.into()]);

        b.switch_to_block(header);
        let i = b.block_params(header)[0];
        let more = b.ins().icmp(
            cranelift_codegen::ir::condcodes::IntCC::UnsignedLessThan,
            i,
            n,
        );
        b.ins().brif(more, body, &[], exit, &[]);

        b.switch_to_block(body);
        let off = b.ins().ishl_imm(i, 3);
        let next = b.ins().iadd_imm(i, 1);
        let mf = MemFlags::trusted();
        match kind {
            Kind::Point => {
                let load = |b: &mut FunctionBuilder, p: Value| {
                    let a = b.ins().iadd(p, off);
                    b.ins().load(types::F64, mf, a, 0)
                };
                let (x, y, z) = (
                    load(&mut self.b, params[0]),
                    load(&mut self.b, params[1]),
                    load(&mut self.b, params[2]),
                );
                let r = self.point_tape(tape, x, y, z);
                let a = self.b.ins().iadd(params[3], off);
                self.b.ins().store(mf, r, a, 0);
                self.b.ins().jump(header, &[next.into()]);
            }
            Kind::Interval => {
                let args = params[0];
                let ptr = self.ptr;
                let field = |b: &mut FunctionBuilder, k: i32| {
                    let p = b.ins().load(ptr, mf, args, 8 * k);
                    let a = b.ins().iadd(p, off);
                    b.ins().load(types::F64, mf, a, 0)
                };
                let mut inp = [Iv { lo: zero, hi: zero }; 3];
                for (k, v) in inp.iter_mut().enumerate() {
                    v.lo = field(&mut self.b, 2 * k as i32);
                    v.hi = field(&mut self.b, 2 * k as i32 + 1);
                }
                let r = self.interval_tape(tape, inp);
                let out_lo = self.b.ins().load(ptr, mf, args, 48);
                let out_hi = self.b.ins().load(ptr, mf, args, 56);
                let a = self.b.ins().iadd(out_lo, off);
                self.b.ins().store(mf, r.lo, a, 0);
                let a = self.b.ins().iadd(out_hi, off);
                self.b.ins().store(mf, r.hi, a, 0);
                match self.ok {
                    None => {
                        self.b.ins().jump(header, &[next.into()]);
                    }
                    Some(ok) => {
                        // A lane off the common path: the interpreter again.
                        let slow = self.b.create_block();
                        self.b.ins().brif(ok, header, &[next.into()], slow, &[]);
                        self.b.switch_to_block(slow);
                        self.b.set_cold_block(slow);
                        let io = self.slot();
                        for (k, v) in inp.iter().enumerate() {
                            self.b.ins().store(mf, v.lo, io, 16 * k as i32);
                            self.b.ins().store(mf, v.hi, io, 16 * k as i32 + 8);
                        }
                        let t = self.b.ins().load(ptr, mf, args, 64);
                        self.call(interval_lane as *const u8, &[t, io], &[], None);
                        let lo = self.b.ins().load(types::F64, mf, io, 48);
                        let hi = self.b.ins().load(types::F64, mf, io, 56);
                        let a = self.b.ins().iadd(out_lo, off);
                        self.b.ins().store(mf, lo, a, 0);
                        let a = self.b.ins().iadd(out_hi, off);
                        self.b.ins().store(mf, hi, a, 0);
                        self.b.ins().jump(header, &[next.into()]);
                    }
                }
            }
        }
        self.b.switch_to_block(exit);
        self.b.ins().return_(&[]);
        self.b.seal_all_blocks();
    }

    /// The address of the helpers' scratch slot of eight `f64` (one slot per function).
    fn slot(&mut self) -> Value {
        let ss = match self.slot {
            Some(ss) => ss,
            None => {
                let ss = self.b.create_sized_stack_slot(StackSlotData::new(
                    StackSlotKind::ExplicitSlot,
                    64,
                    3,
                ));
                self.slot = Some(ss);
                ss
            }
        };
        self.b.ins().stack_addr(self.ptr, ss, 0)
    }

    /// Calls the `extern "C"` function at `f` with `args` (pointers then `f64`s as typed
    /// by `types`); returns its `f64` result if `ret`.
    fn call(
        &mut self,
        f: *const u8,
        args: &[Value],
        f64_args: &[Value],
        ret: Option<types::Type>,
    ) -> Option<Value> {
        let mut sig = Signature::new(isa::CallConv::SystemV);
        for _ in args {
            sig.params.push(AbiParam::new(self.ptr));
        }
        for _ in f64_args {
            sig.params.push(AbiParam::new(types::F64));
        }
        if let Some(t) = ret {
            sig.returns.push(AbiParam::new(t));
        }
        let sref = self.b.import_signature(sig);
        let callee = self.b.ins().iconst(self.ptr, f as i64);
        let all: Vec<Value> = args.iter().chain(f64_args).copied().collect();
        let call = self.b.ins().call_indirect(sref, callee, &all);
        ret.map(|_| self.b.inst_results(call)[0])
    }

    // --- f64 building blocks -----------------------------------------------------------

    fn f(&mut self, c: f64) -> Value {
        self.b.ins().f64const(c)
    }

    fn cmp(&mut self, cc: FloatCC, a: Value, b: Value) -> Value {
        self.b.ins().fcmp(cc, a, b)
    }

    /// `c ? a : b` without a branch: Cranelift lowers a `select` of floats on x86-64
    /// to a jump around a move, and the conditions here (the sign of a rounding error)
    /// are noise to a branch predictor; a `select` of integers is a `cmov`.
    fn sel(&mut self, c: Value, a: Value, b: Value) -> Value {
        let ai = self.b.ins().bitcast(types::I64, MemFlags::new(), a);
        let bi = self.b.ins().bitcast(types::I64, MemFlags::new(), b);
        let r = self.b.ins().select(c, ai, bi);
        self.b.ins().bitcast(types::F64, MemFlags::new(), r)
    }

    fn and(&mut self, a: Value, b: Value) -> Value {
        self.b.ins().band(a, b)
    }

    fn or(&mut self, a: Value, b: Value) -> Value {
        self.b.ins().bor(a, b)
    }

    /// Adds `c` to the lane's common-path flag.
    fn require(&mut self, c: Value) {
        self.ok = Some(match self.ok {
            None => c,
            Some(ok) => self.b.ins().band(ok, c),
        });
    }

    /// `|x| < inf` (false for NaN).
    fn finite(&mut self, x: Value) -> Value {
        let a = self.b.ins().fabs(x);
        let inf = self.f(f64::INFINITY);
        self.cmp(FloatCC::LessThan, a, inf)
    }

    /// `x.next_down()` for finite nonzero `x` (other values: not used).
    fn next_down(&mut self, x: Value) -> Value {
        let bits = self.b.ins().bitcast(types::I64, MemFlags::new(), x);
        let s = self.b.ins().sshr_imm(bits, 63);
        let d = self.b.ins().bor_imm(s, 1);
        let r = self.b.ins().isub(bits, d);
        self.b.ins().bitcast(types::F64, MemFlags::new(), r)
    }

    /// `x.next_up()` for finite nonzero `x`.
    fn next_up(&mut self, x: Value) -> Value {
        let bits = self.b.ins().bitcast(types::I64, MemFlags::new(), x);
        let s = self.b.ins().sshr_imm(bits, 63);
        let d = self.b.ins().bor_imm(s, 1);
        let r = self.b.ins().iadd(bits, d);
        self.b.ins().bitcast(types::F64, MemFlags::new(), r)
    }

    /// `f64::min(a, b)` of two non-NaN values as rustc compiles it on x86-64 (`b < a ?
    /// b : a`; the zeros' signs are what can differ).
    fn fmin(&mut self, a: Value, b: Value) -> Value {
        let c = self.cmp(FloatCC::LessThan, b, a);
        self.sel(c, b, a)
    }

    /// `f64::max(a, b)` of two non-NaN values (`b > a ? b : a`).
    fn fmax(&mut self, a: Value, b: Value) -> Value {
        let c = self.cmp(FloatCC::GreaterThan, b, a);
        self.sel(c, b, a)
    }

    /// arith-core's `add_lo(a, b)` on its common path, and the flag of that path.
    fn add_lo(&mut self, a: Value, b: Value) -> (Value, Value) {
        let s = self.b.ins().fadd(a, b);
        // TwoSum.
        let bb = self.b.ins().fsub(s, a);
        let t = self.b.ins().fsub(s, bb);
        let ea = self.b.ins().fsub(a, t);
        let eb = self.b.ins().fsub(b, bb);
        let e = self.b.ins().fadd(ea, eb);
        // `e` finite implies `s` finite (an infinite or NaN `s` makes `e` NaN).
        let ok = self.finite(e);
        let dn = self.next_down(s);
        let zero = self.f(0.0);
        let neg = self.cmp(FloatCC::LessThan, e, zero);
        (self.sel(neg, dn, s), ok)
    }

    /// `add_hi(a, b) = -add_lo(-a, -b)`.
    fn add_hi(&mut self, a: Value, b: Value) -> (Value, Value) {
        let (na, nb) = (self.b.ins().fneg(a), self.b.ins().fneg(b));
        let (r, ok) = self.add_lo(na, nb);
        (self.b.ins().fneg(r), ok)
    }

    /// `mul_lo(a, b)` on its common path: a finite product of at least `TINY` (error by
    /// one FMA), or a zero factor (the exact signed zero).
    fn mul_lo(&mut self, a: Value, b: Value) -> (Value, Value) {
        let p = self.b.ins().fmul(a, b);
        let np = self.b.ins().fneg(p);
        let e = self.b.ins().fma(a, b, np);
        let fin = self.finite(p);
        let ap = self.b.ins().fabs(p);
        let tiny = self.f(TINY);
        let big = self.cmp(FloatCC::GreaterThanOrEqual, ap, tiny);
        let zero = self.f(0.0);
        let az = self.cmp(FloatCC::Equal, a, zero);
        let bz = self.cmp(FloatCC::Equal, b, zero);
        let z = self.or(az, bz);
        let bz = self.or(big, z);
        let ok = self.and(fin, bz);
        let dn = self.next_down(p);
        let neg = self.cmp(FloatCC::LessThan, e, zero);
        (self.sel(neg, dn, p), ok)
    }

    /// `mul_hi(a, b) = -mul_lo(-a, b)`.
    fn mul_hi(&mut self, a: Value, b: Value) -> (Value, Value) {
        let na = self.b.ins().fneg(a);
        let (r, ok) = self.mul_lo(na, b);
        (self.b.ins().fneg(r), ok)
    }

    /// `div_lo(a, b)` on its common path (finite quotient, `|q|, |a| >= TINY`, or `a`
    /// zero), remainder by one FMA.
    fn div_lo(&mut self, a: Value, b: Value) -> (Value, Value) {
        let q = self.b.ins().fdiv(a, b);
        let nq = self.b.ins().fneg(q);
        let r = self.b.ins().fma(nq, b, a);
        let fq = self.finite(q);
        let fb = self.finite(b);
        let tiny = self.f(TINY);
        let aq = self.b.ins().fabs(q);
        let aa = self.b.ins().fabs(a);
        let q_big = self.cmp(FloatCC::GreaterThanOrEqual, aq, tiny);
        let a_big = self.cmp(FloatCC::GreaterThanOrEqual, aa, tiny);
        let zero = self.f(0.0);
        let az = self.cmp(FloatCC::Equal, a, zero);
        let big = self.and(q_big, a_big);
        let path = self.or(big, az);
        let fin = self.and(fq, fb);
        let ok = self.and(fin, path);
        let rnz = self.cmp(FloatCC::NotEqual, r, zero);
        let rneg = self.cmp(FloatCC::LessThan, r, zero);
        let bneg = self.cmp(FloatCC::LessThan, b, zero);
        let differ = self.b.ins().bxor(rneg, bneg);
        let down = self.and(rnz, differ);
        let dn = self.next_down(q);
        (self.sel(down, dn, q), ok)
    }

    /// `div_hi(a, b) = -div_lo(-a, b)`.
    fn div_hi(&mut self, a: Value, b: Value) -> (Value, Value) {
        let na = self.b.ins().fneg(a);
        let (r, ok) = self.div_lo(na, b);
        (self.b.ins().fneg(r), ok)
    }

    /// arith-ia's `from_dir` on the common path: bounds in order.
    fn directed(&mut self, lo: (Value, Value), hi: (Value, Value)) -> Iv {
        let ordered = self.cmp(FloatCC::LessThanOrEqual, lo.0, hi.0);
        let ok = self.and(lo.1, hi.1);
        let ok = self.and(ok, ordered);
        self.require(ok);
        Iv { lo: lo.0, hi: hi.0 }
    }

    // --- interval operations -----------------------------------------------------------

    fn ia_add(&mut self, a: Iv, b: Iv) -> Iv {
        let lo = self.add_lo(a.lo, b.lo);
        let hi = self.add_hi(a.hi, b.hi);
        self.directed(lo, hi)
    }

    fn ia_neg(&mut self, a: Iv) -> Iv {
        Iv {
            lo: self.b.ins().fneg(a.hi),
            hi: self.b.ins().fneg(a.lo),
        }
    }

    fn ia_const(&mut self, c: f64) -> Iv {
        let p = Interval::point(c);
        Iv {
            lo: self.f(p.lo),
            hi: self.f(p.hi),
        }
    }

    /// `a * [c, c]` (`mul_point`) for a finite nonzero `c`.
    fn ia_mul_point(&mut self, a: Iv, c: f64) -> Iv {
        let cv = self.f(c);
        let (l, h) = if c >= 0.0 { (a.lo, a.hi) } else { (a.hi, a.lo) };
        let lo = self.mul_lo(l, cv);
        let hi = self.mul_hi(h, cv);
        self.directed(lo, hi)
    }

    /// `a / [c, c]` (`div_point`) for a finite nonzero `c`.
    fn ia_div_point(&mut self, a: Iv, c: f64) -> Iv {
        let cv = self.f(c);
        let (l, h) = if c > 0.0 { (a.lo, a.hi) } else { (a.hi, a.lo) };
        let lo = self.div_lo(l, cv);
        let hi = self.div_hi(h, cv);
        self.directed(lo, hi)
    }

    /// The product of two intervals: the scalar's corners chosen by the signs (as
    /// selects), both candidates where both factors straddle 0. Common path: finite
    /// bounds, no point factor `[0, 0]` (the scalar's `mul_point` gives `[+0, +0]` there),
    /// every product used on `mul_lo`'s common path. On it the scalar's point cases
    /// (`mul_point`) give the same bits as the corner table (see docs/jit.md).
    fn ia_mul(&mut self, a: Iv, b: Iv) -> Iv {
        let zero = self.f(0.0);
        for v in [a.lo, a.hi, b.lo, b.hi] {
            let f = self.finite(v);
            self.require(f);
        }
        for v in [a, b] {
            let point = self.cmp(FloatCC::Equal, v.lo, v.hi);
            let z = self.cmp(FloatCC::Equal, v.lo, zero);
            let pz = self.and(point, z);
            let not_pz = self.b.ins().bxor_imm(pz, 1);
            self.require(not_pz);
        }
        let ap = self.cmp(FloatCC::GreaterThanOrEqual, a.lo, zero);
        let an = self.cmp(FloatCC::LessThanOrEqual, a.hi, zero);
        let bp = self.cmp(FloatCC::GreaterThanOrEqual, b.lo, zero);
        let bn = self.cmp(FloatCC::LessThanOrEqual, b.hi, zero);
        // Case table (A+: a.lo >= 0, A-: a.hi <= 0, A0 otherwise; B likewise; B+ first):
        //        lo            hi
        // A+ B+  a.lo b.lo     a.hi b.hi
        // A+ B-  a.hi b.lo     a.lo b.hi
        // A+ B0  a.hi b.lo     a.hi b.hi
        // A- B+  a.lo b.hi     a.hi b.lo
        // A- B-  a.hi b.hi     a.lo b.lo
        // A- B0  a.lo b.hi     a.lo b.lo
        // A0 B+  a.lo b.hi     a.hi b.hi
        // A0 B-  a.hi b.lo     a.lo b.lo
        // A0 B0  min(a.lo b.hi, a.hi b.lo), max(a.lo b.lo, a.hi b.hi)
        // Within a row of A the choice depends on B; write each operand as a select.
        // sel3(A, x+, x-, x0) = A+ ? x+ : (A- ? x- : x0).
        let sel_b = |e: &mut Self, p: Value, n: Value, z: Value| {
            let t = e.sel(bn, n, z);
            e.sel(bp, p, t)
        };
        // lo corner, first factor.
        let l1_pos = sel_b(self, a.lo, a.hi, a.hi);
        let l1_neg = sel_b(self, a.lo, a.hi, a.lo);
        let l1_z = sel_b(self, a.lo, a.hi, a.lo);
        let t = self.sel(an, l1_neg, l1_z);
        let l1 = self.sel(ap, l1_pos, t);
        // lo corner, second factor.
        let l2_pos = sel_b(self, b.lo, b.lo, b.lo);
        let l2_neg = sel_b(self, b.hi, b.hi, b.hi);
        let l2_z = sel_b(self, b.hi, b.lo, b.hi);
        let t = self.sel(an, l2_neg, l2_z);
        let l2 = self.sel(ap, l2_pos, t);
        // hi corner, first factor.
        let h1_pos = sel_b(self, a.hi, a.lo, a.hi);
        let h1_neg = sel_b(self, a.hi, a.lo, a.lo);
        let h1_z = sel_b(self, a.hi, a.lo, a.lo);
        let t = self.sel(an, h1_neg, h1_z);
        let h1 = self.sel(ap, h1_pos, t);
        // hi corner, second factor.
        let h2_pos = sel_b(self, b.hi, b.hi, b.hi);
        let h2_neg = sel_b(self, b.lo, b.lo, b.lo);
        let h2_z = sel_b(self, b.hi, b.lo, b.lo);
        let t = self.sel(an, h2_neg, h2_z);
        let h2 = self.sel(ap, h2_pos, t);
        let (lo, ok_lo) = self.mul_lo(l1, l2);
        let (hi, ok_hi) = self.mul_hi(h1, h2);
        // Both straddle 0: the second candidates.
        let a_any = self.or(ap, an);
        let b_any = self.or(bp, bn);
        let some = self.or(a_any, b_any);
        let both0 = self.b.ins().bxor_imm(some, 1);
        let (lo2, ok_lo2) = self.mul_lo(a.hi, b.lo);
        let (hi2, ok_hi2) = self.mul_hi(a.hi, b.hi);
        let lo_m = self.fmin(lo, lo2);
        let hi_m = self.fmax(hi, hi2);
        let lo = self.sel(both0, lo_m, lo);
        let hi = self.sel(both0, hi_m, hi);
        let ok2 = self.and(ok_lo2, ok_hi2);
        let ok2 = self.or(ok2, some);
        let ok = self.and(ok_lo, ok2);
        self.directed((lo, ok), (hi, ok_hi))
    }

    /// `(mig, mag)` of arith-ia.
    fn mig_mag(&mut self, a: Iv) -> (Value, Value) {
        let zero = self.f(0.0);
        let ge = self.cmp(FloatCC::GreaterThanOrEqual, a.lo, zero);
        let le = self.cmp(FloatCC::LessThanOrEqual, a.hi, zero);
        let nlo = self.b.ins().fneg(a.lo);
        let nhi = self.b.ins().fneg(a.hi);
        let t = self.sel(le, nhi, zero);
        let mig = self.sel(ge, a.lo, t);
        let m = self.fmax(nlo, a.hi);
        let t = self.sel(le, nlo, m);
        let mag = self.sel(ge, a.hi, t);
        (mig, mag)
    }

    /// `a^2`: `[floor(mig^2), ceil(mag^2)]` (`powi_pos(2)`; `max(lo, 0)` is the floor
    /// itself on the common path).
    fn ia_sqr(&mut self, a: Iv) -> Iv {
        for v in [a.lo, a.hi] {
            let f = self.finite(v);
            self.require(f);
        }
        let (mig, mag) = self.mig_mag(a);
        let lo = self.mul_lo(mig, mig);
        let hi = self.mul_hi(mag, mag);
        self.directed(lo, hi)
    }

    /// `sqrt_enc(x)` on its common path `1e-250 <= x <= 1e300`: `(lo, hi, in range)`.
    fn sqrt_enc(&mut self, x: Value) -> (Value, Value, Value) {
        let s = self.b.ins().sqrt(x);
        let lo_lim = self.f(1.0e-250);
        let hi_lim = self.f(1.0e300);
        let c1 = self.cmp(FloatCC::GreaterThanOrEqual, x, lo_lim);
        let c2 = self.cmp(FloatCC::LessThanOrEqual, x, hi_lim);
        let ok = self.and(c1, c2);
        let p = self.b.ins().fmul(s, s);
        let d = self.b.ins().fsub(p, x);
        let np = self.b.ins().fneg(p);
        let e = self.b.ins().fma(s, s, np);
        let r = self.b.ins().fadd(d, e);
        let zero = self.f(0.0);
        let pos = self.cmp(FloatCC::GreaterThan, r, zero);
        let neg = self.cmp(FloatCC::LessThan, r, zero);
        let dn = self.next_down(s);
        let up = self.next_up(s);
        (self.sel(pos, dn, s), self.sel(neg, up, s), ok)
    }

    /// `range_sqrt(lo, hi)`: `[0, 0]` when `hi <= 0`, else `lo` from `sqrt_enc(lo)` (0
    /// when `lo <= 0`) and `hi` from `sqrt_enc(hi)`.
    fn ia_sqrt(&mut self, a: Iv) -> Iv {
        let zero = self.f(0.0);
        let (_, hi, ok_hi) = self.sqrt_enc(a.hi);
        let (lo, _, ok_lo) = self.sqrt_enc(a.lo);
        let lo_le0 = self.cmp(FloatCC::LessThanOrEqual, a.lo, zero);
        let hi_le0 = self.cmp(FloatCC::LessThanOrEqual, a.hi, zero);
        let lo = self.sel(lo_le0, zero, lo);
        let lo = self.sel(hi_le0, zero, lo);
        let hi = self.sel(hi_le0, zero, hi);
        let ok_lo = self.or(ok_lo, lo_le0);
        let ok = self.and(ok_lo, ok_hi);
        let ok = self.or(ok, hi_le0);
        self.directed((lo, ok), (hi, ok))
    }

    /// The scalar operation through [`interval_helper`].
    fn ia_helper(&mut self, i: &Instr, a: Iv, b: Iv, e: Iv) -> Iv {
        self.coverage.helper += 1;
        self.coverage.inline -= 1;
        let io = self.slot();
        let mf = MemFlags::trusted();
        for (k, v) in [a, b, e].iter().enumerate() {
            self.b.ins().store(mf, v.lo, io, 16 * k as i32);
            self.b.ins().store(mf, v.hi, io, 16 * k as i32 + 8);
        }
        let ip = self.b.ins().iconst(self.ptr, i as *const Instr as i64);
        self.call(interval_helper as *const u8, &[ip, io], &[], None);
        Iv {
            lo: self.b.ins().load(types::F64, mf, io, 48),
            hi: self.b.ins().load(types::F64, mf, io, 56),
        }
    }

    fn interval_tape(&mut self, tape: &Tape, [x, y, z]: [Iv; 3]) -> Iv {
        let ins = tape.instructions();
        let mut regs: Vec<Iv> = Vec::with_capacity(ins.len());
        for i in ins {
            self.coverage.inline += 1;
            let a = regs.get(i.a as usize).copied().unwrap_or(x);
            let b = regs.get(i.b as usize).copied().unwrap_or(x);
            let e = regs.get(i.e as usize).copied().unwrap_or(x);
            let c = i.c;
            let finite = c.is_finite();
            let v = match i.op {
                Op::X => x,
                Op::Y => y,
                Op::Z => z,
                Op::Const => self.ia_const(c),
                Op::Neg => self.ia_neg(a),
                Op::Add => self.ia_add(a, b),
                Op::Sub => {
                    let nb = self.ia_neg(b);
                    self.ia_add(a, nb)
                }
                Op::AddC | Op::SubC if finite => {
                    let k = if i.op == Op::AddC { c } else { -c };
                    let p = self.ia_const(k);
                    self.ia_add(a, p)
                }
                Op::RSubC if finite => {
                    let p = self.ia_const(c);
                    let na = self.ia_neg(a);
                    self.ia_add(p, na)
                }
                Op::MulC if c.is_nan() => self.ia_const(f64::NAN),
                Op::MulC if c == 0.0 => Iv {
                    lo: self.f(0.0),
                    hi: self.f(0.0),
                },
                Op::MulC if finite => self.ia_mul_point(a, c),
                Op::DivC if c.is_nan() || c == 0.0 => self.ia_const(f64::NAN),
                Op::DivC if finite => self.ia_div_point(a, c),
                Op::Mul => self.ia_mul(a, b),
                Op::Sqr => self.ia_sqr(a),
                Op::Powi if i.n == 2 => self.ia_sqr(a),
                Op::Sqrt => self.ia_sqrt(a),
                Op::Abs => {
                    let (mig, mag) = self.mig_mag(a);
                    Iv { lo: mig, hi: mag }
                }
                Op::Min => Iv {
                    lo: self.fmin(a.lo, b.lo),
                    hi: self.fmin(a.hi, b.hi),
                },
                Op::Max => Iv {
                    lo: self.fmax(a.lo, b.lo),
                    hi: self.fmax(a.hi, b.hi),
                },
                _ => self.ia_helper(i, a, b, e),
            };
            regs.push(v);
        }
        *regs.last().expect("a tape has an instruction")
    }

    // --- points ------------------------------------------------------------------------

    fn point_tape(&mut self, tape: &Tape, x: Value, y: Value, z: Value) -> Value {
        let ins = tape.instructions();
        let mut regs: Vec<Value> = Vec::with_capacity(ins.len());
        // What the interpreter's `sqrt(max(x, 0))` gives for `-0` (the sign of that zero
        // is the compiler's choice of `max`).
        let sqrt_neg0 = Real::sqrt(&std::hint::black_box(-0.0_f64));
        for i in ins {
            self.coverage.inline += 1;
            let a = regs.get(i.a as usize).copied().unwrap_or(x);
            let b = regs.get(i.b as usize).copied().unwrap_or(x);
            let e = regs.get(i.e as usize).copied().unwrap_or(x);
            let v = match i.op {
                Op::X => x,
                Op::Y => y,
                Op::Z => z,
                Op::Const => self.f(i.c),
                Op::Neg => self.b.ins().fneg(a),
                Op::Add => self.b.ins().fadd(a, b),
                Op::Sub => self.b.ins().fsub(a, b),
                Op::Mul => self.b.ins().fmul(a, b),
                Op::Div => self.b.ins().fdiv(a, b),
                Op::Sqr => self.b.ins().fmul(a, a),
                Op::Powi if i.n == 2 => self.b.ins().fmul(a, a),
                Op::AddC => {
                    let c = self.f(i.c);
                    self.b.ins().fadd(a, c)
                }
                Op::SubC => {
                    let c = self.f(i.c);
                    self.b.ins().fsub(a, c)
                }
                Op::RSubC => {
                    let c = self.f(i.c);
                    self.b.ins().fsub(c, a)
                }
                Op::MulC => {
                    let c = self.f(i.c);
                    self.b.ins().fmul(a, c)
                }
                Op::DivC => {
                    let c = self.f(i.c);
                    self.b.ins().fdiv(a, c)
                }
                Op::RDivC => {
                    let c = self.f(i.c);
                    self.b.ins().fdiv(c, a)
                }
                Op::Abs => self.b.ins().fabs(a),
                Op::Sqrt => {
                    // sqrt(max(x, 0)): NaN and negatives give +0.
                    let zero = self.f(0.0);
                    let s = self.b.ins().sqrt(a);
                    let cc = if sqrt_neg0.is_sign_negative() {
                        FloatCC::GreaterThanOrEqual
                    } else {
                        FloatCC::GreaterThan
                    };
                    let pos = self.cmp(cc, a, zero);
                    self.sel(pos, s, zero)
                }
                Op::Min | Op::Max => self.point_min_max(i.op == Op::Min, a, b),
                _ => {
                    self.coverage.inline -= 1;
                    self.coverage.helper += 1;
                    let ip = self.b.ins().iconst(self.ptr, i as *const Instr as i64);
                    self.call(
                        point_helper as *const u8,
                        &[ip],
                        &[a, b, e],
                        Some(types::F64),
                    )
                    .expect("a result")
                }
            };
            regs.push(v);
        }
        *regs.last().expect("a tape has an instruction")
    }

    /// `Real::min`/`max` on `f64`: equal operands give the or (and) of their bits (the
    /// zeros' signs), else `f64::min`/`max`, which returns the other operand for a NaN.
    fn point_min_max(&mut self, min: bool, a: Value, b: Value) -> Value {
        let eq = self.cmp(FloatCC::Equal, a, b);
        let ab = self.b.ins().bitcast(types::I64, MemFlags::new(), a);
        let bb = self.b.ins().bitcast(types::I64, MemFlags::new(), b);
        let bits = if min {
            self.b.ins().bor(ab, bb)
        } else {
            self.b.ins().band(ab, bb)
        };
        let same = self.b.ins().bitcast(types::F64, MemFlags::new(), bits);
        let m = if min {
            self.fmin(a, b)
        } else {
            self.fmax(a, b)
        };
        let a_nan = self.cmp(FloatCC::Unordered, a, a);
        let m = self.sel(a_nan, b, m);
        self.sel(eq, same, m)
    }
}
