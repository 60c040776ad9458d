"""Batched evaluation from numpy: eval_boxes encloses eval at points inside each box, in
every arithmetic, for formulas and built-in models; the batches agree with the scalar
paths bit for bit, except intervals through exp, ln, sin and cos, which the batch
computes in SIMD lanes with their own proven error bounds: there both are enclosures,
so they overlap, and the batch's is at most twice as wide as the scalar one."""

import numpy as np
import pytest

import tracer

FORMULAS = [
    "1 - x^2 - y^2 - z^2",
    "0.16 - (1 - sqrt(x^2 + z^2))^2 - y^2",
    "min(1 - abs(x), 1 - abs(y)) * exp(-z^2) - 0.1 + 0.05*sin(7*x)*cos(5*y)",
    "b = 0.36 - x^2; s = 0.7 - x^2 - y^2; max(b, s) - ln(1 + z^2) + x/(2 + y^2)",
]


def shapes():
    out = [(f, tracer.Shape(f)) for f in FORMULAS]
    out += [(n, tracer.Shape.builtin(n)) for n in tracer.models()]
    return out


SHAPES = shapes()


def random_boxes(rng, shape, n):
    (x0, y0, z0), (x1, y1, z1) = shape.domain
    lo_d, hi_d = np.array([x0, y0, z0]), np.array([x1, y1, z1])
    centre = lo_d + (hi_d - lo_d) * rng.random((n, 3))
    half = (hi_d - lo_d) * 10 ** rng.uniform(-4, -0.5, (n, 1))
    return centre - half, centre + half


@pytest.mark.parametrize("arith", tracer.arithmetics())
@pytest.mark.parametrize("name,shape", SHAPES, ids=[n[:24] for n, _ in SHAPES])
def test_boxes_enclose_the_points_inside(name, shape, arith):
    rng = np.random.default_rng(7)
    n, per_box = 150, 9
    lo, hi = random_boxes(rng, shape, n)
    bounds = shape.eval_boxes(lo, hi, arith=arith)
    assert bounds.shape == (n, 2) and bounds.dtype == np.float64
    assert not np.isnan(bounds).any()
    assert (bounds[:, 0] <= bounds[:, 1]).all()
    # Random points and the two extreme corners of every box.
    t = rng.random((n, per_box, 3))
    t[:, 0, :], t[:, 1, :] = 0.0, 1.0
    pts = lo[:, None, :] + (hi - lo)[:, None, :] * t
    pts = np.minimum(np.maximum(pts, lo[:, None, :]), hi[:, None, :])
    values = shape.eval(np.ascontiguousarray(pts.reshape(-1, 3))).reshape(n, per_box)
    finite = np.isfinite(values)
    inside = (bounds[:, :1] <= values) & (values <= bounds[:, 1:])
    bad = np.argwhere(finite & ~inside)
    assert bad.size == 0, [
        (lo[k], hi[k], bounds[k], values[k, j]) for k, j in bad[:5]
    ]


@pytest.mark.parametrize("name,shape", SHAPES[:4], ids=[n[:24] for n, _ in SHAPES[:4]])
def test_batches_are_the_scalar_paths(name, shape):
    rng = np.random.default_rng(3)
    lo, hi = random_boxes(rng, shape, 40)
    lanes = any(f in name for f in ("exp", "ln", "sin", "cos"))
    for arith in tracer.arithmetics():
        b = shape.eval_boxes(lo, hi, arith=arith)
        for k in range(0, 40, 7):
            box = (tuple(lo[k]), tuple(hi[k]))
            (blo, bhi), (slo, shi) = tuple(b[k]), shape.range(box, arith=arith)
            # Intervals' and RevAA's lanes compute exp and ln with the lanes' proven
            # functions, not libm's: overlapping ranges, at most about twice as wide.
            if arith in ("ia", "revaa") and lanes:
                assert blo <= shi and slo <= bhi, (box, (blo, bhi), (slo, shi))
                slack = 4 * np.spacing(max(abs(slo), abs(shi)))
                assert bhi - blo <= 2 * (shi - slo) + slack, (box, (blo, bhi), (slo, shi))
            else:
                assert (blo, bhi) == (slo, shi)
    pts = lo + (hi - lo) * rng.random((40, 3))
    v = shape.eval(pts)
    for k in range(40):
        assert v[k] == shape(*pts[k]) or (np.isnan(v[k]) and np.isnan(shape(*pts[k])))


def test_large_batches_cross_chunk_boundaries():
    shape = tracer.Shape("x + 2*y + 4*z")
    n = 100_003
    xyz = np.arange(3 * n, dtype=np.float64).reshape(n, 3) / n
    assert np.array_equal(shape.eval(xyz), xyz[:, 0] + 2 * xyz[:, 1] + 4 * xyz[:, 2])
    b = shape.eval_boxes(xyz, xyz + 1.0, arith="revaa")
    assert b.shape == (n, 2)
    exact = xyz[:, 0] + 2 * xyz[:, 1] + 4 * xyz[:, 2]
    assert (b[:, 0] <= exact).all() and (exact + 7.0 <= b[:, 1] + 1e-9).all()


def test_empty_batches():
    shape = tracer.Shape("x")
    assert shape.eval(np.zeros((0, 3))).shape == (0,)
    assert shape.eval_boxes(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0, 2)


def test_range_in_every_arithmetic():
    shape = tracer.Shape("x*x - x", domain=((0, 0, 0), (1, 1, 1)))
    all_ = shape.range(arith="all")
    assert set(all_) == set(tracer.arithmetics())
    for lo, hi in all_.values():
        assert lo <= -0.25 and hi >= 0.0
    assert all_["ia"] == shape.range()
    # Affine forms see that x - x cancels; intervals do not.
    assert all_["revaa"][1] - all_["revaa"][0] < all_["ia"][1] - all_["ia"][0]
