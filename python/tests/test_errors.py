"""Bad input raises one clear exception naming what is wrong, and never crashes the
interpreter."""

import math

import numpy as np
import pytest

import tracer

BALL = tracer.Shape("1 - x^2 - y^2 - z^2")


@pytest.mark.parametrize("dtype", [np.float32, np.int64, np.complex128, object])
def test_wrong_dtypes(dtype):
    a = np.zeros((4, 3), dtype=dtype)
    with pytest.raises(TypeError, match="xyz: expected dtype float64"):
        BALL.eval(a)
    with pytest.raises(TypeError, match="lo: expected dtype float64"):
        BALL.eval_boxes(a, np.zeros((4, 3)))


@pytest.mark.parametrize("shape", [(4,), (4, 2), (3, 4), (2, 2, 3), ()])
def test_wrong_shapes(shape):
    with pytest.raises(ValueError, match=r"xyz: expected shape \(N, 3\)"):
        BALL.eval(np.zeros(shape))
    with pytest.raises(ValueError, match=r"hi: expected shape \(N, 3\)"):
        BALL.eval_boxes(np.zeros((4, 3)), np.zeros(shape))


def test_not_arrays():
    with pytest.raises(TypeError, match="numpy array"):
        BALL.eval([[0.0, 0.0, 0.0]])
    with pytest.raises(TypeError, match="numpy array"):
        BALL.eval(None)


def test_non_contiguous_arrays():
    a = np.zeros((10, 3))
    for view in (a[::2], np.asfortranarray(a), np.zeros((3, 10)).T):
        with pytest.raises(ValueError, match="not C-contiguous"):
            BALL.eval(view)
        with pytest.raises(ValueError, match="not C-contiguous"):
            BALL.eval_boxes(view, view)
    # A contiguous copy is fine.
    assert BALL.eval(np.ascontiguousarray(a[::2])).shape == (5,)


def test_bad_boxes():
    lo, hi = np.zeros((5, 3)), np.ones((5, 3))
    bad = lo.copy()
    bad[3, 1] = math.nan
    with pytest.raises(ValueError, match="box 3 axis 1"):
        BALL.eval_boxes(bad, hi)
    with pytest.raises(ValueError, match="box 2 axis 0"):
        hi2 = hi.copy()
        hi2[2, 0] = -1.0
        BALL.eval_boxes(lo, hi2)
    with pytest.raises(ValueError, match="box 0 axis 2"):
        inf = hi.copy()
        inf[0, 2] = math.inf
        BALL.eval_boxes(lo, inf)
    with pytest.raises(ValueError, match="lo, hi"):
        BALL.eval_boxes(lo, np.ones((4, 3)))
    with pytest.raises(ValueError, match="box: the box must be finite"):
        BALL.range((0, 0, 0, math.nan, 1, 1))
    with pytest.raises(ValueError, match="minimum must be at most"):
        BALL.range(((1, 0, 0), (0, 1, 1)))
    with pytest.raises(TypeError, match="six numbers"):
        BALL.range((1, 2, 3))


def test_unknown_arithmetic():
    for call in (
        lambda: BALL.eval_boxes(np.zeros((1, 3)), np.ones((1, 3)), arith="xyz"),
        lambda: BALL.range(arith="xyz"),
        lambda: tracer.render(BALL, size=(8, 8), arith="xyz"),
        lambda: tracer.mesh(BALL, depth=3, arith="xyz"),
    ):
        with pytest.raises(ValueError, match="unknown arithmetic 'xyz'.*revaa"):
            call()


def test_unknown_search():
    with pytest.raises(ValueError, match="search.*unknown search 'xyz'.*auto, slabs or paper"):
        tracer.render(BALL, size=(8, 8), search="xyz")


def test_bad_formula_names_line_and_column():
    with pytest.raises(tracer.ModelError) as e:
        tracer.Shape("1 - x^2 +* y")
    assert isinstance(e.value, ValueError)
    assert (e.value.line, e.value.column) == (1, 10)
    assert "column 10" in str(e.value)
    with pytest.raises(tracer.ModelError) as e:
        tracer.Shape("a = x^2;\nb = a +\n")
    assert e.value.line in (2, 3)
    with pytest.raises(tracer.ModelError, match="unknown"):
        tracer.Shape("1 - w^2")


def test_bad_files(tmp_path):
    hf = tmp_path / "bad.hf"
    hf.write_text("my_model(x[3], a[1])\n{\n  x1 = x[1];\n  my_model = 1 - x1 *;\n}\n")
    with pytest.raises(tracer.ModelError) as e:
        tracer.Shape.file(hf)
    assert e.value.line == 4 and e.value.column is not None
    assert str(hf) in str(e.value)
    vm = tmp_path / "bad.vm"
    vm.write_text("_0 var-x\n_1 frobnicate _0\n")
    with pytest.raises(tracer.ModelError) as e:
        tracer.Shape.file(vm)
    assert e.value.line == 2
    with pytest.raises(FileNotFoundError):
        tracer.Shape.file(tmp_path / "missing.expr")
    with pytest.raises(ValueError, match="cannot tell the format"):
        tracer.Shape.file(tmp_path / "model.txt")
    with pytest.raises(tracer.ModelError) as e:
        tracer.Shape.builtin("no-such-model")
    assert e.value.line is None and "mitchell" in str(e.value)


def test_bad_render_and_mesh_options():
    with pytest.raises(ValueError, match="size"):
        tracer.render(BALL, size=(0, 10))
    with pytest.raises(ValueError, match="camera"):
        tracer.render(BALL, size=(8, 8), eye=(0, 0, 0), look_at=(0, 0, 0))
    with pytest.raises(ValueError, match="eps"):
        tracer.render(BALL, size=(8, 8), eps=-1.0)
    with pytest.raises(ValueError, match="aa"):
        tracer.render(BALL, size=(8, 8), aa=0)
    with pytest.raises(ValueError, match="filter"):
        tracer.render(BALL, size=(8, 8), aa=2, filter="gauss")
    with pytest.raises(ValueError, match="device"):
        tracer.render(BALL, size=(8, 8), device="gpu")
    with pytest.raises(ValueError, match="threads"):
        tracer.render(BALL, size=(8, 8), threads=0)
    with pytest.raises(ValueError, match="domain"):
        tracer.render(BALL, size=(8, 8), domain=(1, 1, 1, 0, 0, 0))
    with pytest.raises(TypeError, match="progress"):
        tracer.render(BALL, size=(8, 8), progress="yes")
    with pytest.raises(ValueError, match="depth"):
        tracer.mesh(BALL, depth=1)
    with pytest.raises(ValueError, match="max_depth"):
        tracer.mesh(BALL, depth=5, max_depth=4)
    with pytest.raises(ValueError, match="merge"):
        tracer.mesh(BALL, depth=3, merge=-1.0)
    with pytest.raises(TypeError):
        tracer.render("1 - x^2", size=(8, 8))


def test_exceptions_from_progress_callbacks_stop_the_work():
    def stop(done, total):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        tracer.render(tracer.Shape("1 - x^2 - y^2 - z^2"), size=(1500, 1500), arith="aa", progress=stop)
