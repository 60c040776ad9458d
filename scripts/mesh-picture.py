#!/usr/bin/env python3
"""Draws a mesh that `tracer mesh` wrote (.obj) to a PNG: flat-shaded triangles, edges
faintly outlined, seen from one fixed direction. Needs matplotlib (PyPI).

    tracer mesh decocube --depth 5 --out decocube.obj
    python3 scripts/mesh-picture.py decocube.obj docs/mesh-decocube.png
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_obj(path):
    vs, fs = [], []
    for line in open(path, encoding="utf-8"):
        p = line.split()
        if not p:
            continue
        if p[0] == "v":
            vs.append([float(x) for x in p[1:4]])
        elif p[0] == "f":
            fs.append([int(x.split("/")[0]) - 1 for x in p[1:4]])
    return np.array(vs), np.array(fs)


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: mesh-picture.py MESH.obj OUT.png")
    v, f = read_obj(sys.argv[1])
    tri = v[f]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    light = np.array([0.4, 0.5, 0.77])
    light /= np.linalg.norm(light)
    shade = 0.25 + 0.75 * np.clip(n @ light, 0, 1)
    colours = np.stack([shade * 0.85, shade * 0.6, shade * 0.35, np.ones_like(shade)], 1)
    fig = plt.figure(figsize=(6, 6), dpi=100)
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(
        Poly3DCollection(tri, facecolors=colours, edgecolors=(0, 0, 0, 0.08), linewidths=0.2)
    )
    lo, hi = v.min(0), v.max(0)
    c, r = (lo + hi) / 2, (hi - lo).max() / 2
    for s, k in ((ax.set_xlim, 0), (ax.set_ylim, 1), (ax.set_zlim, 2)):
        s(c[k] - r, c[k] + r)
    ax.view_init(elev=25, azim=35, vertical_axis="y")
    ax.set_axis_off()
    fig.savefig(sys.argv[2], bbox_inches="tight", pad_inches=0)


if __name__ == "__main__":
    main()
