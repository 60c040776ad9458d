"""Shapes from every source the registry reads, their domains and cameras."""

import math

import numpy as np
import pytest

import tracer


def test_formula_domain_and_camera():
    s = tracer.Shape("1 - x^2 - y^2 - z^2")
    assert s.domain == ((-2.0, -2.0, -2.0), (2.0, 2.0, 2.0))
    assert s.name == "expr" and s.formula
    t = tracer.Shape("1 - x^2 - y^2 - z^2", domain=(-1, -1, -1, 1, 1, 1))
    assert t.domain == ((-1.0, -1.0, -1.0), (1.0, 1.0, 1.0))
    # The default camera frames the domain: the same as Camera.framing.
    assert t.camera == tracer.Camera.framing(t.domain)
    assert s.camera != t.camera


def test_model_files_of_every_format(tmp_path):
    ball = "1 - x^2 - y^2 - z^2"
    (tmp_path / "ball.expr").write_text(f"# domain: -1.5,-1.5,-1.5,1.5,1.5,1.5\n{ball}\n")
    (tmp_path / "ball.vm").write_text(
        "_x var-x\n_y var-y\n_z var-z\n_a square _x\n_b square _y\n_c square _z\n"
        "_s add _a _b\n_t add _s _c\n_one const 1\n_f sub _t _one\n"
    )
    (tmp_path / "ball.hf").write_text(
        "my_model(x[3], a[1])\n{\n  my_model = 1 - x[1]^2 - x[2]^2 - x[3]^2;\n}\n"
    )
    pts = np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.5], [1.0, 1.0, 0.0]])
    want = 1 - (pts**2).sum(axis=1)
    for ext in ("expr", "vm", "hf"):
        s = tracer.Shape.file(tmp_path / f"ball.{ext}")
        assert s.name == "ball"
        assert np.allclose(s.eval(pts), want), ext
        t = tracer.Shape.from_text((tmp_path / f"ball.{ext}").read_text(), format=ext)
        assert np.array_equal(t.eval(pts), s.eval(pts))
    assert tracer.Shape.file(tmp_path / "ball.expr").domain == ((-1.5,) * 3, (1.5,) * 3)
    assert tracer.Shape.file(tmp_path / "ball.vm", domain=(0, 0, 0, 1, 1, 1)).domain == (
        (0.0,) * 3,
        (1.0,) * 3,
    )


def test_builtin_models():
    for name in tracer.models():
        s = tracer.Shape.builtin(name)
        assert s.name == name and s.description
        (x0, y0, z0), (x1, y1, z1) = s.domain
        c = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
        assert math.isfinite(s(*c)) or math.isnan(s(*c))
    m = tracer.Shape.builtin("mitchell", domain=(-1, -1, -1, 1, 1, 1))
    assert m.domain == ((-1.0,) * 3, (1.0,) * 3)
    assert m.camera == tracer.Shape.builtin("mitchell").camera  # a built-in keeps its view


def test_cameras():
    c = tracer.Camera((0, 0, 5), look_at=(0, 0, 0), up=(0, 1, 0), fov=30)
    assert (c.eye, c.look_at, c.up, c.fov, c.ortho) == ((0.0, 0.0, 5.0), (0.0,) * 3, (0.0, 1.0, 0.0), 30.0, None)
    for k in range(1, 8):
        o = c.orbit(45 * k)
        assert math.isclose(np.linalg.norm(o.eye), 5.0)
        assert math.isclose(o.eye[1], 0.0, abs_tol=1e-12)
    assert np.allclose(c.orbit(0, 30).eye, (0, 5 * math.sin(math.radians(30)), 5 * math.cos(math.radians(30))))
    assert c.zoom(0.5).eye == (0.0, 0.0, 2.5)
    assert "Camera(eye=(0.0, 0.0, 5.0)" in repr(c)
    with pytest.raises(ValueError, match="eye"):
        tracer.Camera((0, 0, math.nan))
    with pytest.raises(TypeError, match="three numbers"):
        tracer.Camera("here")


def test_progress_line_on_stderr(capsys):
    tracer.render(tracer.Shape("1 - x^2 - y^2 - z^2"), size=(64, 64), progress=True)
    err = capsys.readouterr().err
    assert "render (tiles): 1/1" in err and err.endswith("\n")
