# %% [markdown]
# # Rendering and meshing a formula
#
# A notebook-style script (run it with `python notebook.py`, or cell by cell in an
# editor that knows `# %%` cells): a shape from a formula, its sound ranges, a slice of
# its values, a reliable render with its depth map, and a mesh, all plotted with
# matplotlib into `notebook.png`.

# %%
import os
import sys

import matplotlib

if "ipykernel" not in sys.modules:
    matplotlib.use("Agg")  # no window outside a notebook
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

import tracer

# Sizes can be made smaller for a quick run: TRACER_EXAMPLE_SCALE=0.25.
SCALE = float(os.environ.get("TRACER_EXAMPLE_SCALE", "1"))
OUT = os.environ.get("TRACER_EXAMPLE_OUT", "notebook.png")

# %% [markdown]
# The union of a torus and a ball (`f >= 0` inside), in a domain that holds it tightly
# (the default camera frames the domain).

# %%
shape = tracer.Shape(
    "t = 0.16 - (1 - sqrt(x^2 + z^2))^2 - y^2; b = 0.36 - x^2 - (y - 0.5)^2 - z^2; max(t, b)",
    domain=((-1.5, -0.6, -1.5), (1.5, 1.2, 1.5)),
)
print(shape.domain)

# %% [markdown]
# Sound ranges over a box in every arithmetic: each encloses every value of `f` there.

# %%
for arith, (lo, hi) in shape.range(((0.5, -0.2, -0.2), (1.2, 0.3, 0.4)), arith="all").items():
    print(f"{arith:6} [{lo:.4f}, {hi:.4f}]")

# %% [markdown]
# Values on the slice `z = 0`, a million points in one call.

# %%
n = max(int(1000 * SCALE), 16)
xs = np.linspace(-2, 2, n)
X, Y = np.meshgrid(xs, xs)
xyz = np.stack([X.ravel(), Y.ravel(), np.zeros(X.size)], axis=1)
values = shape.eval(xyz).reshape(n, n)

# %% [markdown]
# A reliable render (every pixel whose ray meets the surface is a hit) and a mesh.

# %%
size = (max(int(480 * SCALE), 8), max(int(360 * SCALE), 6))
rgb, depth, stats = tracer.render(shape, size=size, aa=2)
print(f"render: {stats['hits']} hits in {stats['wall_s']:.2f} s ({stats['arith']})")
vertices, triangles, mstats = tracer.mesh(shape, depth=max(int(6 + np.log2(SCALE)), 3))
print(
    f"mesh: {len(vertices)} vertices, {len(triangles)} triangles, "
    f"Euler characteristic {mstats['euler']}, watertight {mstats['watertight']}"
)

# %%
fig = plt.figure(figsize=(16, 4))
ax = fig.add_subplot(1, 4, 1)
ax.set_title("f on z = 0")
ax.imshow(values, extent=(-2, 2, -2, 2), origin="lower", cmap="RdBu", vmin=-1, vmax=1)
ax.contour(X, Y, values, levels=[0], colors="k")
ax = fig.add_subplot(1, 4, 2)
ax.set_title("render")
ax.imshow(rgb)
ax.axis("off")
ax = fig.add_subplot(1, 4, 3)
ax.set_title("depth (inf: white)")
ax.imshow(np.where(np.isfinite(depth), depth, np.nan), cmap="viridis")
ax.axis("off")
ax = fig.add_subplot(1, 4, 4, projection="3d")
ax.set_title("mesh")
# The model's y is up: matplotlib's z.
ax.add_collection3d(
    Poly3DCollection(vertices[:, [0, 2, 1]][triangles], facecolor="tan", edgecolor="k", linewidth=0.05)
)
ax.set_xlim(-1.5, 1.5)
ax.set_ylim(-1.5, 1.5)
ax.set_zlim(-1.5, 1.5)
fig.tight_layout()
fig.savefig(OUT, dpi=100)
print(f"wrote {OUT}")
