"""Render and mesh against ground truth: a sphere's depth map is analytic; a torus mesh
is closed with Euler characteristic 0; Ctrl-C stops long work with KeyboardInterrupt."""

import _thread
import signal
import threading
import time

import numpy as np
import pytest

import tracer

R = 0.8
EYE = np.array([0.3, 0.4, 3.0])


def sphere_depth(width, height, fov):
    """Distance from the eye to the sphere |p| = R along each pixel's ray (the pinhole
    formulas of the camera, pixel centres), inf where the ray misses, and the ray's
    closest approach to the sphere's surface (its margin)."""
    forward = -EYE / np.linalg.norm(EYE)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    t = np.tan(np.radians(fov) / 2)
    px = (np.arange(width) + 0.5)[None, :]
    py = (np.arange(height) + 0.5)[:, None]
    dx = (2 * px / width - 1) * t * width / height
    dy = (1 - 2 * py / height) * t
    d = forward + dx[..., None] * right + dy[..., None] * up
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    b = d @ EYE
    c = EYE @ EYE - R * R
    disc = b * b - c
    depth = np.where(disc >= 0, -b - np.sqrt(np.maximum(disc, 0)), np.inf)
    closest = np.sqrt(np.maximum(EYE @ EYE - b * b, 0)) - R
    return depth, closest


@pytest.mark.parametrize("search", ["slabs", "paper"])
@pytest.mark.parametrize("arith", ["auto"] + tracer.arithmetics())
def test_sphere_depth_is_analytic(arith, search):
    w, h, fov = 48, 36, 40.0
    shape = tracer.Shape(f"{R * R} - x^2 - y^2 - z^2", domain=((-1, -1, -1), (1, 1, 1)))
    cam = tracer.Camera(tuple(EYE), fov=fov)
    rgb, depth, stats = tracer.render(
        shape, size=(w, h), camera=cam, arith=arith, eps=1e-7, search=search
    )
    assert rgb.shape == (h, w, 3) and rgb.dtype == np.uint8
    assert depth.shape == (h, w) and depth.dtype == np.float32
    want, closest = sphere_depth(w, h, fov)
    hit = np.isfinite(want)
    # Never misses a root: every ray that meets the sphere is a hit.
    assert np.isfinite(depth[hit]).all()
    clear = closest < -0.01  # well inside the silhouette
    assert np.abs(depth[clear] - want[clear]).max() < 1e-5
    # Rays that pass the sphere by a margin hit nothing.
    assert np.isinf(depth[closest > 0.01]).all()
    assert stats["hits"] == int(np.isfinite(depth).sum())
    assert stats["arith"] == arith and stats["search"] == search
    assert (rgb[~np.isfinite(depth)] == rgb[0, 0]).all()  # background


def test_default_search_follows_specialisation():
    # Eight balls in a row under max: a tape long enough to specialise.
    balls = "0.04 - (x + 0.7)^2 - y^2 - z^2"
    for k in range(1, 8):
        balls = f"max({balls}, 0.04 - (x - {0.2 * k - 0.7:.1f})^2 - y^2 - z^2)"
    _, _, stats = tracer.render(tracer.Shape(balls), size=(16, 12))
    assert stats["search"] == "slabs"
    _, _, stats = tracer.render(tracer.Shape(balls), size=(16, 12), specialise=False)
    assert stats["search"] == "paper"


def test_render_options():
    shape = tracer.Shape("1 - x^2 - y^2 - z^2")
    calls = []
    rgb, depth, stats = tracer.render(
        shape, size=(20, 10), aa=3, filter="cubic", shadows=True, threads=1,
        progress=lambda done, total: calls.append((done, total)), arith="hull",
    )
    assert rgb.shape == (10, 20, 3) and depth.shape == (10, 20)
    assert stats["arith"] == "hull" and stats["shadow_rays"] > 0
    assert calls and calls[-1][0] == calls[-1][1] > 0
    ortho, _, _ = tracer.render(shape, size=(16, 16), ortho=3.0, eye=(0, 0, 5), look_at=(0, 0, 0))
    assert ortho.shape == (16, 16, 3)


def test_save_png_and_depth(tmp_path):
    shape = tracer.Shape("1 - x^2 - y^2 - z^2")
    rgb, depth, _ = tracer.render(shape, size=(24, 16))
    tracer.save_png(tmp_path / "a.png", rgb)
    tracer.save_depth(tmp_path / "a.npy", depth)
    assert (tmp_path / "a.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert np.array_equal(np.load(tmp_path / "a.npy"), depth)


def edges_of(triangles):
    e = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    return np.sort(e, axis=1)


@pytest.mark.parametrize("arith", tracer.arithmetics())
def test_torus_mesh_is_closed_with_euler_characteristic_0(arith):
    torus = tracer.Shape("0.16 - (1 - sqrt(x^2 + z^2))^2 - y^2", domain=((-1.5,) * 3, (1.5,) * 3))
    v, t, stats = tracer.mesh(torus, depth=5, arith=arith)
    assert v.dtype == np.float64 and v.shape[1] == 3
    assert t.dtype == np.uint32 and t.shape[1] == 3
    assert t.max() < len(v)
    edges, counts = np.unique(edges_of(t), axis=0, return_counts=True)
    assert (counts == 2).all(), "every edge is shared by exactly two triangles"
    assert len(v) - len(edges) + len(t) == 0
    assert stats["euler"] == 0 and stats["watertight"] and stats["manifold"]
    assert stats["vertices"] == len(v) and stats["triangles"] == len(t)
    # The vertices lie near the surface: |f| small next to f's range over the domain.
    assert np.abs(torus.eval(v)).max() < 0.05
    # Wound outward: the signed volume is the torus's, 2 pi^2 R r^2.
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    assert abs(volume - 2 * np.pi**2 * 1.0 * 0.16) < 0.05 * 2 * np.pi**2 * 0.16


def test_mesh_options():
    ball = tracer.Shape("1 - x^2 - y^2 - z^2")
    v, t, stats = tracer.mesh(ball, depth=4, merge=False, check=False, certify=False, threads=1)
    assert stats["euler"] == 2 and stats["self_intersections"] is None
    assert stats["certified_cells"] is None and stats["merged_vertices"] == 0


def interrupt_after(seconds):
    # A process started in the background by a shell without job control ignores
    # SIGINT, and then interrupt_main does nothing: give SIGINT Python's own handler.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(seconds, _thread.interrupt_main)
    timer.start()
    return timer


SLOW = "s = sin(9*x)*sin(9*y)*sin(9*z); 0.2 - s*s - 0.01*(x^2 + y^2 + z^2) + 0.001*cos(40*x*y*z)"


def test_ctrl_c_stops_a_render():
    shape = tracer.Shape(SLOW)
    timer = interrupt_after(0.5)
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        tracer.render(shape, size=(2000, 2000), arith="aa", threads=1)
    timer.join()
    assert time.monotonic() - start < 10


def test_ctrl_c_stops_a_meshing():
    shape = tracer.Shape(SLOW)
    timer = interrupt_after(0.5)
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        tracer.mesh(shape, depth=8, arith="aa", threads=1)
    timer.join()
    assert time.monotonic() - start < 10


def test_work_releases_the_gil():
    # A Python thread keeps ticking while a render runs in the main thread.
    shape = tracer.Shape("1 - x^2 - y^2 - z^2")
    ticks = []
    stop = threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.005)

    th = threading.Thread(target=ticker)
    th.start()
    time.sleep(0.05)
    t0 = time.monotonic()
    tracer.render(shape, size=(800, 800), arith="aa", threads=1)
    t1 = time.monotonic()
    stop.set()
    th.join()
    inside = [t for t in ticks if t0 <= t <= t1]
    # At most one tick per 5 ms; a held GIL would leave none for the whole render.
    assert t1 - t0 > 0.05 and len(inside) >= (t1 - t0) / 0.005 / 4
