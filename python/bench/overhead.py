"""The binding's overhead: `Shape.eval` on 10^6 points and `Shape.eval_boxes` on 10^5
boxes from Python against the same batch code called from Rust (the benchmark
`batch_overhead` of this crate), measured in turns in one run.

    python bench/overhead.py [--model mitchell] [--rounds 5] [--reps 5]

Each round runs the Python calls (REPS each, in this process) and then the Rust
benchmark (REPS each, in its own process); a round's figure per side is its median
call, and the ratio Python / Rust is taken round by round. Prints one row per
measurement: the median of the rounds' ratios, with their min and max.
"""

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import tracer

CRATE = Path(__file__).resolve().parent.parent
# The Weyl sequences of the Rust benchmark (the same IEEE operations, the same points).
G = np.array([0.6180339887498949, 0.7548776662466927, 0.5698402909980532])
HALF_SIDE = 0.01


def points(n, lo, hi):
    k = np.arange(n, dtype=np.float64)[:, None]
    return np.ascontiguousarray(lo + (hi - lo) * ((k * G) % 1.0))


def time_calls(f, reps):
    out = []
    for _ in range(reps):
        t = time.perf_counter()
        f()
        out.append(time.perf_counter() - t)
    return out


def rust_side(model, n_points, n_boxes, reps, ariths):
    cmd = ["cargo", "bench", "-q", "-p", "tracer-python", "--bench", "batch_overhead", "--",
           model, str(n_points), str(n_boxes), str(reps), ",".join(ariths)]
    out = subprocess.run(cmd, cwd=CRATE, check=True, capture_output=True, text=True).stdout
    times = {}
    for line in out.splitlines():
        *key, secs = line.split()
        times.setdefault(" ".join(key), []).append(float(secs))
    return times


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--model", default="mitchell", help="a built-in model or a formula")
    p.add_argument("--points", type=int, default=10**6)
    p.add_argument("--boxes", type=int, default=10**5)
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--reps", type=int, default=5)
    p.add_argument("--arith", default="ia,revaa")
    a = p.parse_args()
    ariths = a.arith.split(",")
    shape = tracer.Shape.builtin(a.model) if a.model in tracer.models() else tracer.Shape(a.model)
    (lo, _, _), (hi, _, _) = shape.domain
    xyz = points(a.points, lo, hi)
    centres = points(a.boxes, lo, hi)
    blo, bhi = centres - HALF_SIDE, centres + HALF_SIDE

    def python_side():
        times = {"points": time_calls(lambda: shape.eval(xyz), a.reps)}
        for ar in ariths:
            times[f"boxes {ar}"] = time_calls(lambda: shape.eval_boxes(blo, bhi, arith=ar), a.reps)
        return times

    # Build the Rust side first (not timed), and warm both up.
    rust_side(a.model, 1000, 100, 1, ariths)
    python_side()
    ratios, py_med, rs_med = {}, {}, {}
    for _ in range(a.rounds):
        py = python_side()
        rs = rust_side(a.model, a.points, a.boxes, a.reps, ariths)
        for key in py:
            mp, mr = statistics.median(py[key]), statistics.median(rs[key])
            ratios.setdefault(key, []).append(mp / mr)
            py_med.setdefault(key, []).append(mp)
            rs_med.setdefault(key, []).append(mr)
    print(f"model {a.model}: {a.points} points, {a.boxes} boxes; {a.rounds} rounds of {a.reps} calls")
    print(f"{'batch':14} {'python ms':>10} {'rust ms':>10} {'ratio (median [min, max])':>28}")
    for key, r in ratios.items():
        n = a.points if key == "points" else a.boxes
        label = f"eval {n}" if key == "points" else f"eval_boxes {key.split()[1]}"
        print(
            f"{label:14} {1e3 * statistics.median(py_med[key]):10.2f} "
            f"{1e3 * statistics.median(rs_med[key]):10.2f} "
            f"{statistics.median(r):12.3f} [{min(r):.3f}, {max(r):.3f}]"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
