//! The arithmetics as Python number types: one class per arithmetic, wrapping the Rust
//! form of a 3-D cell (three input symbols), with `+ - * /` (floats on either side),
//! `**` by an integer, the non-affine functions and `.bounds()`. Every operation is the
//! Rust type's own, so values share noise symbols exactly as the Rust forms do: `x - x`
//! is `0` for an affine form made once and used twice.

use crate::toolkit::forms::{Aa, Hull, Interval, Raa, RevAa};
use crate::toolkit::{Range, Real, Shape};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// `Range::input(i, lo, hi)` or `Range::from_interval(lo, hi)` (a constant where
/// `hi` is not given), after checking the bounds.
fn make<R: Range>(lo: f64, hi: Option<f64>, input: Option<usize>) -> PyResult<R> {
    let hi_ = hi.unwrap_or(lo);
    if lo.is_nan() || hi_.is_nan() {
        return Err(PyValueError::new_err("bounds must not be NaN"));
    }
    if lo > hi_ {
        return Err(PyValueError::new_err(format!(
            "lower bound {lo} is above upper bound {hi_}"
        )));
    }
    match input {
        Some(i) => {
            if !(lo.is_finite() && hi_.is_finite()) {
                return Err(PyValueError::new_err(format!(
                    "input {i}: bounds must be finite, got [{lo}, {hi_}]"
                )));
            }
            Ok(R::input(i, lo, hi_))
        }
        None if hi.is_none() => Ok(R::constant(lo)),
        None => Ok(R::from_interval(lo, hi_)),
    }
}

/// Defines one Python number type over the Rust form `$t` (see the module doc).
macro_rules! number_type {
    ($py:ident, $operand:ident, $name:literal, $t:ty, $inputs:literal, $doc:literal) => {
        #[doc = $doc]
        #[doc = ""]
        #[doc = concat!(
            "``", $name, "(lo, hi=None, *, input=None)``: with ``input=i`` (0, 1, 2, ...) the ",
            "``i``-th input variable ranging over ``[lo, hi]`` (values made with the same ",
            "input index are the same variable; ", $inputs, "); without it a value only ",
            "known to lie in ``[lo, hi]``; without ``hi`` the exact constant ``lo``.\n\n",
            "Operators ``+ - * /`` take another ``", $name, "`` or a float on either side, ",
            "``x ** n`` an integer ``n``; methods ``sqr``, ``sqrt``, ``exp``, ``ln``, ``sin``, ",
            "``cos``, ``abs``, ``recip``, ``powi``, ``min``, ``max``, ``hypot``. The bounds ",
            "enclose every real value, after rounding: ``sqrt`` clips below 0, ``ln`` is ",
            "``-inf`` at or below 0, division by a range holding 0 is the whole line."
        )]
        #[pyclass(module = "tracer", name = $name, frozen)]
        #[derive(Clone)]
        pub struct $py {
            pub v: $t,
        }

        /// An operand: a value of the same type, or a float taken as an exact constant.
        #[derive(FromPyObject)]
        enum $operand<'py> {
            Form(PyRef<'py, $py>),
            Num(f64),
        }

        impl $operand<'_> {
            fn value(&self) -> $t {
                match self {
                    $operand::Form(f) => f.v.clone(),
                    $operand::Num(c) => <$t as Real>::constant(*c),
                }
            }
        }

        impl $py {
            fn of(v: $t) -> Self {
                $py { v }
            }
        }

        #[pymethods]
        impl $py {
            #[new]
            #[pyo3(signature = (lo, hi=None, *, input=None))]
            fn new(lo: f64, hi: Option<f64>, input: Option<usize>) -> PyResult<Self> {
                make::<$t>(lo, hi, input).map($py::of)
            }

            /// The exact constant ``c``.
            #[staticmethod]
            fn constant(c: f64) -> Self {
                $py::of(<$t as Real>::constant(c))
            }

            /// The ``i``-th input variable over ``[lo, hi]`` (finite bounds).
            #[staticmethod]
            fn input(i: usize, lo: f64, hi: f64) -> PyResult<Self> {
                make::<$t>(lo, Some(hi), Some(i)).map($py::of)
            }

            /// ``(lo, hi)``: the enclosure, never NaN, ``-inf``/``inf`` where unbounded.
            fn bounds(&self) -> (f64, f64) {
                self.v.bounds()
            }

            /// The lower bound.
            #[getter]
            fn lo(&self) -> f64 {
                self.v.bounds().0
            }

            /// The upper bound.
            #[getter]
            fn hi(&self) -> f64 {
                self.v.bounds().1
            }

            /// Whether 0 lies in the bounds.
            fn contains_zero(&self) -> bool {
                self.v.contains_zero()
            }

            fn __contains__(&self, x: f64) -> bool {
                let (lo, hi) = self.v.bounds();
                lo <= x && x <= hi
            }

            fn __repr__(&self) -> String {
                let (lo, hi) = self.v.bounds();
                format!("{}([{lo:?}, {hi:?}])", $name)
            }

            fn __add__(&self, o: $operand<'_>) -> Self {
                $py::of(match o {
                    $operand::Num(c) => self.v.clone() + c,
                    o => self.v.clone() + o.value(),
                })
            }

            fn __radd__(&self, o: $operand<'_>) -> Self {
                self.__add__(o)
            }

            fn __sub__(&self, o: $operand<'_>) -> Self {
                $py::of(match o {
                    $operand::Num(c) => self.v.clone() - c,
                    o => self.v.clone() - o.value(),
                })
            }

            fn __rsub__(&self, o: $operand<'_>) -> Self {
                $py::of(match o {
                    $operand::Num(c) => self.v.clone().rsub(c),
                    o => o.value() - self.v.clone(),
                })
            }

            fn __mul__(&self, o: $operand<'_>) -> Self {
                $py::of(match o {
                    $operand::Num(c) => self.v.clone() * c,
                    o => self.v.clone() * o.value(),
                })
            }

            fn __rmul__(&self, o: $operand<'_>) -> Self {
                self.__mul__(o)
            }

            fn __truediv__(&self, o: $operand<'_>) -> Self {
                $py::of(match o {
                    $operand::Num(c) => self.v.clone() / c,
                    o => self.v.clone() / o.value(),
                })
            }

            fn __rtruediv__(&self, o: $operand<'_>) -> Self {
                $py::of(match o {
                    $operand::Num(c) => self.v.clone().rdiv(c),
                    o => o.value() / self.v.clone(),
                })
            }

            fn __pow__(&self, n: i32, _modulo: Option<i32>) -> Self {
                $py::of(self.v.powi(n))
            }

            fn __neg__(&self) -> Self {
                $py::of(-self.v.clone())
            }

            fn __pos__(&self) -> Self {
                self.clone()
            }

            fn __abs__(&self) -> Self {
                $py::of(self.v.abs())
            }

            /// ``x**2``, never wider than ``x * x``.
            fn sqr(&self) -> Self {
                $py::of(self.v.sqr())
            }

            /// ``x**n`` for an integer ``n`` (negative: ``1 / x**-n``).
            fn powi(&self, n: i32) -> Self {
                $py::of(self.v.powi(n))
            }

            /// Square root of ``max(x, 0)``.
            fn sqrt(&self) -> Self {
                $py::of(self.v.sqrt())
            }

            /// ``e**x``.
            fn exp(&self) -> Self {
                $py::of(self.v.exp())
            }

            /// Natural logarithm (``-inf`` at or below 0).
            fn ln(&self) -> Self {
                $py::of(self.v.ln())
            }

            /// Natural logarithm, as :meth:`ln`.
            fn log(&self) -> Self {
                self.ln()
            }

            /// Sine.
            fn sin(&self) -> Self {
                $py::of(self.v.sin())
            }

            /// Cosine.
            fn cos(&self) -> Self {
                $py::of(self.v.cos())
            }

            /// ``|x|``.
            fn abs(&self) -> Self {
                $py::of(self.v.abs())
            }

            /// ``1 / x``.
            fn recip(&self) -> Self {
                $py::of(self.v.recip())
            }

            /// ``min(x, y)``.
            fn min(&self, o: $operand<'_>) -> Self {
                $py::of(self.v.min(&o.value()))
            }

            /// ``max(x, y)``.
            fn max(&self, o: $operand<'_>) -> Self {
                $py::of(self.v.max(&o.value()))
            }

            /// ``sqrt(x**2 + y**2)``.
            fn hypot(&self, o: $operand<'_>) -> Self {
                $py::of(self.v.hypot(&o.value()))
            }
        }
    };
}

number_type!(
    PyInterval,
    IntervalOperand,
    "Interval",
    Interval,
    "intervals keep no correlation, so ``x - x`` over ``[0, 1]`` is ``[-1, 1]``",
    "Interval arithmetic with outward rounding (the ``ia`` arithmetic).\n\n\
     >>> x = Interval(1, 2)\n>>> (x * x - x).bounds()\n(-1.0, 3.0)"
);
number_type!(
    PyAffine,
    AffineOperand,
    "Affine",
    Aa,
    "inputs 0 to 63 have symbols of their own, and every value made without an input \
     index, and every operation's error, gets a fresh symbol",
    "Standard affine arithmetic (the ``aa`` arithmetic): forms over noise symbols.\n\n\
     >>> x = Affine(1, 2)\n>>> (x - x).bounds() == (0.0, 0.0)\nTrue"
);
number_type!(
    PyReducedAffine,
    ReducedAffineOperand,
    "ReducedAffine",
    Raa<3>,
    "inputs 0, 1 and 2 have symbols of their own; other values go to the error term",
    "Reduced affine arithmetic AF1, RAA* (the ``raa`` arithmetic): three input symbols \
     and one accumulated error term.\n\n\
     >>> x = ReducedAffine(1, 2, input=0)\n>>> (x - x).bounds()\n(0.0, 0.0)"
);
number_type!(
    PyRevAffine,
    RevAffineOperand,
    "RevAffine",
    RevAa<3>,
    "inputs 0, 1 and 2 have symbols of their own; other values go to the error term",
    "Revised affine arithmetic (the ``revaa`` arithmetic): three input symbols and a \
     symmetric error term.\n\n\
     >>> x = RevAffine(1, 2, input=0)\n>>> [round(b, 9) for b in (x * x - x).bounds()]\n[-0.25, 2.0]"
);
number_type!(
    PyHull,
    HullOperand,
    "Hull",
    Hull<3>,
    "inputs 0, 1 and 2 have symbols of their own; other values go to the error term",
    "Revised affine forms carrying an interval hull (the ``hull`` arithmetic): bounds \
     are the intersection of both.\n\n\
     >>> x = Hull(1, 2, input=0)\n>>> [round(b, 9) for b in (x * x - x).bounds()]\n[-0.25, 2.0]"
);

/// Adds the number types to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyInterval>()?;
    m.add_class::<PyAffine>()?;
    m.add_class::<PyReducedAffine>()?;
    m.add_class::<PyRevAffine>()?;
    m.add_class::<PyHull>()?;
    Ok(())
}

/// `shape(x, y, z)` at floats or at values of one number type (floats mixed in are
/// constants of that type); `None` when the arguments are of no one such type.
pub fn eval_at<S: Shape>(
    py: Python<'_>,
    shape: &S,
    args: [&Bound<'_, PyAny>; 3],
) -> PyResult<Option<Py<PyAny>>> {
    if let (Ok(x), Ok(y), Ok(z)) = (
        args[0].extract::<f64>(),
        args[1].extract::<f64>(),
        args[2].extract::<f64>(),
    ) {
        return Ok(Some(
            shape.eval(x, y, z).into_pyobject(py)?.into_any().unbind(),
        ));
    }
    macro_rules! try_type {
        ($py:ident, $operand:ident) => {
            if args.iter().any(|a| a.is_instance_of::<$py>()) {
                let v: PyResult<Vec<$operand<'_>>> = args.iter().map(|a| a.extract()).collect();
                if let Ok(v) = v {
                    let r = shape.eval(v[0].value(), v[1].value(), v[2].value());
                    return Ok(Some(Py::new(py, $py::of(r))?.into_any()));
                }
            }
        };
    }
    try_type!(PyInterval, IntervalOperand);
    try_type!(PyAffine, AffineOperand);
    try_type!(PyReducedAffine, ReducedAffineOperand);
    try_type!(PyRevAffine, RevAffineOperand);
    try_type!(PyHull, HullOperand);
    Ok(None)
}
