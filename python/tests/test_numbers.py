"""The number types: soundness against mpmath at 50 digits on random expressions, shared
noise symbols as in the Rust types, operators with floats, and refusals."""

import math
import random

import mpmath
import pytest

import tracer
from tracer import NUMBER_TYPES, Affine, Hull, Interval, ReducedAffine, RevAffine

mpmath.mp.dps = 50

TYPES = list(NUMBER_TYPES.values())

UNARY = ["neg", "sqr", "sqrt", "exp", "ln", "sin", "cos", "abs", "recip", "powi"]
BINARY = ["add", "sub", "mul", "div", "min", "max", "hypot", "addc", "mulc", "rsubc", "rdivc"]
# Constants: exact binary fractions and decimals that are not floats.
CONSTANTS = [0.5, 2.0, -1.25, 0.1, 3.7, -0.3, 1e-3]


def random_expr(rng, depth):
    """A random expression tree over the variables 0, 1, 2."""
    if depth == 0 or rng.random() < 0.2:
        return ("var", rng.randrange(3))
    if rng.random() < 0.45:
        op = rng.choice(UNARY)
        arg = random_expr(rng, depth - 1)
        if op == "powi":
            return (op, arg, rng.randint(-3, 4))
        return (op, arg)
    op = rng.choice(BINARY)
    if op.endswith("c"):
        return (op, random_expr(rng, depth - 1), rng.choice(CONSTANTS))
    return (op, random_expr(rng, depth - 1), random_expr(rng, depth - 1))


def eval_forms(e, xs):
    """The expression over number-type values (the operators and methods of the type)."""
    op = e[0]
    if op == "var":
        return xs[e[1]]
    a = eval_forms(e[1], xs)
    if op in ("neg",):
        return -a
    if op == "powi":
        return a ** e[2]
    if op in UNARY:
        return getattr(a, op)()
    if op == "addc":
        return e[2] + a
    if op == "mulc":
        return a * e[2]
    if op == "rsubc":
        return e[2] - a
    if op == "rdivc":
        return e[2] / a
    b = eval_forms(e[2], xs)
    return {
        "add": lambda: a + b,
        "sub": lambda: a - b,
        "mul": lambda: a * b,
        "div": lambda: a / b,
        "min": lambda: a.min(b),
        "max": lambda: a.max(b),
        "hypot": lambda: a.hypot(b),
    }[op]()


def eval_mp(e, xs):
    """The real value at a point, at 50 digits, with the toolkit's extended sqrt and ln
    (sqrt(max(x, 0)), ln(x) = -inf for x <= 0). Raises ZeroDivisionError at a pole."""
    op = e[0]
    if op == "var":
        return xs[e[1]]
    a = eval_mp(e[1], xs)
    if op == "neg":
        return -a
    if op == "sqr":
        return a * a
    if op == "sqrt":
        return mpmath.sqrt(max(a, 0))
    if op == "exp":
        return mpmath.exp(a)
    if op == "ln":
        return mpmath.log(a) if a > 0 else mpmath.mpf("-inf")
    if op == "sin":
        return mpmath.sin(a)
    if op == "cos":
        return mpmath.cos(a)
    if op == "abs":
        return abs(a)
    if op == "recip":
        return 1 / a
    if op == "powi":
        return a ** e[2] if e[2] >= 0 else 1 / a ** (-e[2])
    c = mpmath.mpf(e[2]) if op.endswith("c") else None
    if op == "addc":
        return c + a
    if op == "mulc":
        return a * c
    if op == "rsubc":
        return c - a
    if op == "rdivc":
        return c / a
    b = eval_mp(e[2], xs)
    return {
        "add": lambda: a + b,
        "sub": lambda: a - b,
        "mul": lambda: a * b,
        "div": lambda: a / b,
        "min": lambda: min(a, b),
        "max": lambda: max(a, b),
        "hypot": lambda: mpmath.sqrt(a * a + b * b),
    }[op]()


@pytest.mark.parametrize("kind", list(NUMBER_TYPES))
def test_random_expressions_enclose_the_real_values(kind):
    T = NUMBER_TYPES[kind]
    rng = random.Random(1234 + list(NUMBER_TYPES).index(kind))
    checked = 0
    for _ in range(300):
        e = random_expr(rng, 4)
        box = []
        for _ in range(3):
            c = rng.uniform(-3, 3)
            r = 10 ** rng.uniform(-4, 0.3)
            box.append((c - r, c + r))
        xs = [T.input(i, lo, hi) for i, (lo, hi) in enumerate(box)]
        lo, hi = eval_forms(e, xs).bounds()
        assert not (math.isnan(lo) or math.isnan(hi)), e
        assert lo <= hi, e
        # The corners and random points inside.
        points = [[lo_ if (k >> i) & 1 else hi_ for i, (lo_, hi_) in enumerate(box)] for k in (0, 7)]
        points += [[rng.uniform(a, b) for a, b in box] for _ in range(12)]
        for p in points:
            try:
                v = eval_mp(e, [mpmath.mpf(c) for c in p])
            except ZeroDivisionError:
                continue
            if not mpmath.isfinite(v):
                continue
            checked += 1
            assert mpmath.mpf(lo) <= v <= mpmath.mpf(hi), (kind, e, box, p, (lo, hi), v)
    assert checked > 1000


def encloses_tightly(bounds, lo, hi, slack=1e-12):
    """`bounds` hold [lo, hi] and exceed it by at most `slack` (rounding) each side."""
    b_lo, b_hi = bounds
    return lo - slack <= b_lo <= lo and hi <= b_hi <= hi + slack


@pytest.mark.parametrize("T", [Affine, ReducedAffine, RevAffine, Hull])
def test_the_same_value_twice_is_one_variable(T):
    x = T(1, 2, input=0)
    assert (x - x).bounds() == (0.0, 0.0)
    # Another variable over the same range is independent.
    y = T(1, 2, input=1)
    assert encloses_tightly((x - y).bounds(), -1.0, 1.0)


def test_affine_values_without_an_input_get_fresh_symbols():
    a = Affine(1, 2)
    assert (a - a).bounds() == (0.0, 0.0)
    assert (a - Affine(1, 2)).bounds() == (-1.0, 1.0)


def test_intervals_keep_no_correlation():
    x = Interval(0, 1)
    assert (x - x).bounds() == (-1.0, 1.0)
    assert (x * x - x).bounds() == (-1.0, 1.0)


@pytest.mark.parametrize("T", [RevAffine, ReducedAffine, Hull, Affine])
def test_affine_forms_are_tighter_than_intervals_on_correlated_expressions(T):
    x = T(1, 2, input=0)
    lo, hi = (x * x - x).bounds()
    ilo, ihi = (Interval(1, 2) * Interval(1, 2) - Interval(1, 2)).bounds()
    assert hi - lo < ihi - ilo
    assert lo <= 0.0 and hi >= 2.0  # x^2 - x takes 0 and 2 on [1, 2]


@pytest.mark.parametrize("T", TYPES)
def test_operators_with_floats_on_either_side(T):
    x = T(1, 2, input=0)
    assert encloses_tightly((x + 1).bounds(), 2.0, 3.0)
    assert encloses_tightly((1 + x).bounds(), 2.0, 3.0)
    assert encloses_tightly((3 - x).bounds(), 1.0, 2.0)
    assert encloses_tightly((x * 2).bounds(), 2.0, 4.0)
    assert encloses_tightly((2 * x).bounds(), 2.0, 4.0)
    lo, hi = (1 / x).bounds()
    assert lo <= 0.5 and hi >= 1.0 and hi < 1.2
    assert encloses_tightly((-x).bounds(), -2.0, -1.0)
    assert encloses_tightly(abs(-x).bounds(), 1.0, 2.0)
    lo, hi = (x ** 2).bounds()
    assert lo <= 1.0 and hi >= 4.0
    assert 1.5 in x and 2.5 not in x
    assert T.constant(0.1).bounds() == (0.1, 0.1)
    assert T(0.25).bounds() == (0.25, 0.25)


@pytest.mark.parametrize("T", TYPES)
def test_module_functions_take_number_types_and_floats(T):
    x = T(0.5, 1, input=0)
    for f in (tracer.sqrt, tracer.exp, tracer.ln, tracer.sin, tracer.cos, tracer.sqr, tracer.recip):
        lo, hi = f(x).bounds()
        for p in (0.5, 0.75, 1.0):
            assert lo <= f(p) <= hi, f
    assert tracer.sqrt(-4.0) == 0.0
    assert tracer.ln(0.0) == -math.inf


def test_mixing_number_types_is_refused():
    with pytest.raises(TypeError):
        Interval(1, 2) + RevAffine(1, 2)
    with pytest.raises(TypeError):
        RevAffine(1, 2) * Hull(1, 2)
    with pytest.raises(TypeError):
        Interval(1, 2) ** 0.5
    with pytest.raises(TypeError):
        Interval(1, 2) + "1"


@pytest.mark.parametrize("T", TYPES)
def test_bad_bounds_are_refused(T):
    with pytest.raises(ValueError, match="above"):
        T(2, 1)
    with pytest.raises(ValueError, match="NaN"):
        T(math.nan, 1)
    with pytest.raises(ValueError, match="finite"):
        T.input(0, -math.inf, 1)


def test_shapes_evaluate_number_types_as_their_range():
    s = tracer.Shape("x*y - z^2 + sin(x)")
    box = ((0.1, -0.2, 0.3), (0.4, 0.5, 0.6))
    for name, T in NUMBER_TYPES.items():
        xs = [T.input(i, box[0][i], box[1][i]) for i in range(3)]
        assert s(*xs).bounds() == s.range(box, arith=name)
    assert s(0.5, 1, 2) == 0.5 - 4 + math.sin(0.5)
    mixed = s(Interval(0, 1), 0.5, 0.25)
    assert isinstance(mixed, Interval)
    with pytest.raises(TypeError, match="one number type"):
        s(Interval(0, 1), RevAffine(0, 1), 0.0)
