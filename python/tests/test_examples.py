"""The examples run: the Dask turntable at a tiny size on two workers, and the
notebook-style script at a reduced scale."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def test_dask_turntable_writes_numbered_frames(tmp_path):
    pytest.importorskip("dask.distributed")
    mpimg = pytest.importorskip("matplotlib.image")
    out = tmp_path / "frames"
    r = subprocess.run(
        [sys.executable, str(EXAMPLES / "turntable.py"), "--frames", "4", "--size", "32x32",
         "--workers", "2", "--out", str(out)],
        capture_output=True, text=True, timeout=240,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    frames = sorted(out.glob("frame_*.png"))
    assert [f.name for f in frames] == [f"frame_{k:04d}.png" for k in range(4)]
    images = [mpimg.imread(f) for f in frames]
    assert all(im.shape[:2] == (32, 32) for im in images)
    # The camera turns: the frames differ, and each shows the shape.
    assert not np.array_equal(images[0], images[1])
    assert all(len(np.unique(im.reshape(-1, im.shape[-1]), axis=0)) > 2 for im in images)


def test_notebook_example_plots(tmp_path):
    pytest.importorskip("matplotlib")
    env = dict(os.environ, TRACER_EXAMPLE_SCALE="0.125", TRACER_EXAMPLE_OUT=str(tmp_path / "nb.png"), MPLBACKEND="Agg")
    r = subprocess.run(
        [sys.executable, str(EXAMPLES / "notebook.py")],
        capture_output=True, text=True, timeout=240, env=env, cwd=tmp_path,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    assert (tmp_path / "nb.png").stat().st_size > 1000
    assert "Euler characteristic" in r.stdout
