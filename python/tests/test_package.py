"""The package itself: docstring examples hold, help reads, objects pickle, the stubs
name what the module has."""

import doctest
import inspect
import pickle
from pathlib import Path

import pytest

import tracer
from tracer import _tracer


def docstring_owners():
    yield "tracer", tracer
    for name in dir(_tracer):
        obj = getattr(_tracer, name)
        if not name.startswith("_") and (inspect.isclass(obj) or callable(obj)):
            yield name, obj


@pytest.mark.parametrize("name,obj", list(docstring_owners()), ids=lambda v: v if isinstance(v, str) else "")
def test_docstring_examples(name, obj):
    finder = doctest.DocTestFinder(recurse=False)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in finder.find(obj, name, globs=dict(vars(tracer))):
        runner.run(test)
    assert runner.failures == 0


def test_every_public_function_and_class_has_a_docstring():
    for name in tracer.__all__:
        obj = getattr(tracer, name)
        if callable(obj):
            assert obj.__doc__ and len(obj.__doc__) > 20, name
    assert "Renders" in tracer.render.__doc__
    assert "shape" in inspect.signature(tracer.render).parameters


def test_stubs_cover_the_module():
    stubs = (Path(tracer.__file__).parent / "_tracer.pyi").read_text()
    for name in dir(_tracer):
        if not name.startswith("_"):
            assert f"def {name}(" in stubs or f"class {name}" in stubs or f"{name}:" in stubs, name
    assert (Path(tracer.__file__).parent / "py.typed").exists()


def test_shapes_and_cameras_pickle(tmp_path):
    f = tmp_path / "m.expr"
    f.write_text("# domain: -1,-1,-1,1,1,1\n1 - x^2 - y^2 - z^2\n")
    for s in (
        tracer.Shape("x^2 - y", domain=(0, 0, 0, 1, 1, 1)),
        tracer.Shape.builtin("mitchell"),
        tracer.Shape.file(f),
    ):
        t = pickle.loads(pickle.dumps(s))
        assert repr(t) == repr(s) and t.domain == s.domain and t.camera == s.camera
        assert t(0.3, 0.2, 0.1) == s(0.3, 0.2, 0.1)
    c = tracer.Camera((1, 2, 3), fov=20, ortho=2.0)
    assert pickle.loads(pickle.dumps(c)) == c


def test_models_and_arithmetics():
    assert "mitchell" in tracer.models()
    assert tracer.arithmetics() == ["ia", "aa", "raa", "revaa", "hull"]
    assert set(tracer.NUMBER_TYPES) == set(tracer.arithmetics())
    m = tracer.Shape.builtin("mitchell")
    assert m.name == "mitchell" and m.formula
