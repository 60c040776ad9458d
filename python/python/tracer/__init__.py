"""Reliable range arithmetic, ray tracing and meshing of implicit surfaces.

A shape is an implicit function ``f(x, y, z)``, ``f >= 0`` inside, ``f = 0`` on the
surface: a formula, a model file (``.expr``, ``.vm``, ``.hf``) or a built-in model.
Ranges over boxes are sound (they enclose every value ``f`` takes there, after
rounding) in every arithmetic: ``ia`` (intervals), ``aa`` (affine), ``raa`` (reduced
affine AF1), ``revaa`` (revised affine), ``hull`` (revised affine with an interval
hull). The renderer never misses a root; the mesher never drops a part it could not
exclude.

>>> import numpy as np
>>> import tracer
>>> torus = tracer.Shape("0.16 - (1 - sqrt(x^2 + z^2))^2 - y^2")
>>> torus.range(((0.9, -0.1, -0.1), (1.1, 0.1, 0.1)), arith="revaa")[1] > 0
True
>>> torus.eval(np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]]))
array([ 0.16, -0.84])
>>> rgb, depth, stats = tracer.render(torus, size=(64, 48))
>>> vertices, triangles, mstats = tracer.mesh(torus, depth=5)
>>> mstats["euler"]
0

The number types (``Interval``, ``Affine``, ``ReducedAffine``, ``RevAffine``,
``Hull``) are the arithmetics themselves, for code of your own; the functions
``sqrt``, ``exp``, ``ln``, ... of this module take them and floats alike:

>>> x = tracer.Interval(1, 2)
>>> (x * x - x).bounds()
(-1.0, 3.0)
>>> y = tracer.RevAffine(1, 2, input=0)
>>> tracer.sqrt(y * y).bounds()[0] >= 0.0
True
"""

import math as _math

from ._tracer import (
    Affine,
    Camera,
    Hull,
    Interval,
    ModelError,
    ReducedAffine,
    RevAffine,
    Shape,
    __version__,
    arithmetics,
    mesh,
    models,
    render,
    save_depth,
    save_png,
)

#: The number type of each arithmetic, by its name.
NUMBER_TYPES = {
    "ia": Interval,
    "aa": Affine,
    "raa": ReducedAffine,
    "revaa": RevAffine,
    "hull": Hull,
}

__all__ = [
    "Affine",
    "Camera",
    "Hull",
    "Interval",
    "ModelError",
    "NUMBER_TYPES",
    "ReducedAffine",
    "RevAffine",
    "Shape",
    "__version__",
    "arithmetics",
    "cos",
    "exp",
    "hypot",
    "ln",
    "log",
    "mesh",
    "models",
    "recip",
    "render",
    "save_depth",
    "save_png",
    "sin",
    "sqr",
    "sqrt",
]


def _is_number(x):
    return isinstance(x, (int, float))


def sqrt(x):
    """Square root of ``max(x, 0)``, for floats and the number types alike."""
    return _math.sqrt(max(x, 0.0)) if _is_number(x) else x.sqrt()


def exp(x):
    """``e**x``, for floats and the number types alike."""
    return _math.exp(x) if _is_number(x) else x.exp()


def ln(x):
    """Natural logarithm, ``-inf`` at or below 0, for floats and the number types."""
    if _is_number(x):
        return _math.log(x) if x > 0 else -_math.inf
    return x.ln()


log = ln


def sin(x):
    """Sine, for floats and the number types alike."""
    return _math.sin(x) if _is_number(x) else x.sin()


def cos(x):
    """Cosine, for floats and the number types alike."""
    return _math.cos(x) if _is_number(x) else x.cos()


def sqr(x):
    """``x**2``, for floats and the number types alike."""
    return x * x if _is_number(x) else x.sqr()


def recip(x):
    """``1 / x`` (``inf`` with the sign of a zero ``x``), for floats and the number
    types alike."""
    if _is_number(x):
        return 1.0 / x if x != 0 else _math.copysign(_math.inf, x)
    return x.recip()


def hypot(x, y):
    """``sqrt(x**2 + y**2)``, for floats and the number types alike."""
    if _is_number(x) and _is_number(y):
        return _math.hypot(x, y)
    if _is_number(x):
        x, y = y, x
    return x.hypot(y)
