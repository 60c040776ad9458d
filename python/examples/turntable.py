"""A turntable: N frames of a shape rendered in parallel with Dask, written as numbered
PNGs.

    python turntable.py --frames 36 --size 320x240 --out turntable/

runs a `dask.distributed.LocalCluster` on this machine (--workers processes, one
render thread each); `--scheduler tcp://HOST:8786` sends the same frames to a running
cluster instead. Shapes and cameras pickle, so they travel to the workers as they are.
"""

import argparse
import os
import sys

import tracer

DEFAULT_FORMULA = "0.16 - (1 - sqrt(x^2 + z^2))^2 - y^2 + 0.04*sin(6*x)*sin(6*z)"
# A box that holds the default formula's surface tightly (the camera frames the domain).
DEFAULT_DOMAIN = ((-1.5, -0.7, -1.5), (1.5, 0.7, 1.5))


def render_frame(shape, k, frames, size, out_dir):
    """Renders frame `k` of `frames` (the shape's camera turned by 360 k / frames
    degrees about its up direction) into `out_dir/frame_KKKK.png`; returns the path
    and the render's wall time."""
    camera = shape.camera.orbit(360.0 * k / frames)
    rgb, _, stats = tracer.render(shape, size=size, camera=camera, threads=1)
    path = os.path.join(out_dir, f"frame_{k:04d}.png")
    tracer.save_png(path, rgb)
    return path, stats["wall_s"]


def turntable(client, shape, frames, size, out_dir):
    """The frames rendered by the workers of `client`, their paths in order."""
    os.makedirs(out_dir, exist_ok=True)
    futures = client.map(
        render_frame,
        [shape] * frames,
        range(frames),
        [frames] * frames,
        [size] * frames,
        [out_dir] * frames,
        pure=False,
    )
    return client.gather(futures)


def parse_size(s):
    w, h = s.lower().split("x")
    return int(w), int(h)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--formula", default=None, help="a formula (default: a wavy torus)")
    p.add_argument("--model", default=None, help="a built-in model or a model file")
    p.add_argument("--frames", type=int, default=36)
    p.add_argument("--size", type=parse_size, default=(320, 240), help="WxH")
    p.add_argument("--out", default="turntable")
    p.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    p.add_argument("--scheduler", default=None, help="address of a running Dask scheduler")
    a = p.parse_args(argv)

    from dask.distributed import Client, LocalCluster

    if a.model is None:
        shape = tracer.Shape(DEFAULT_FORMULA, domain=DEFAULT_DOMAIN) if a.formula is None else tracer.Shape(a.formula)
    elif a.model in tracer.models():
        shape = tracer.Shape.builtin(a.model)
    else:
        shape = tracer.Shape.file(a.model)
    if a.scheduler:
        cluster = None
        client = Client(a.scheduler)
    else:
        cluster = LocalCluster(
            n_workers=a.workers, threads_per_worker=1, processes=True, dashboard_address=None
        )
        client = Client(cluster)
    try:
        results = turntable(client, shape, a.frames, a.size, a.out)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    for path, wall in results:
        print(f"{path} ({wall:.2f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
