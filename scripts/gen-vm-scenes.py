#!/usr/bin/env python3
"""Generates fidget `.vm` tapes (fidget's SSA text format, f < 0 inside) for the peer
comparison (scripts/peer-fidget.sh) and the tape-length scaling (scripts/tape-scaling.sh).
Deterministic: the same arguments give the same bytes.

    scripts/gen-vm-scenes.py DIR                      # the three peer scenes into DIR
    scripts/gen-vm-scenes.py DIR --kinds spheres --n 2000
    scripts/gen-vm-scenes.py DIR --kinds balls --n 10,100,1000,10000

Kinds (every scene inside fidget's default view box [-1, 1]^3, render3d --scale 1):
  spheres   a union (min) of N spheres (default 2000), centres uniform in [-0.8, 0.8]^3,
            radii uniform in [0.02, 0.08]; written as spheres-N.vm.
  csg       a CSG tree of about N primitives (default 300), spheres and boxes, built
            down a k-d split of the box: unions of the halves, and at random nodes a
            difference (max(a, -b)) or an intersection with a primitive of that region;
            written as csg-N.vm.
  lattice   a transcendental lattice: a gyroid sheet (sin/cos, 3.5 periods across)
            and a Schwarz P sheet joined, inside a box with a ball cut out of a corner;
            written as lattice.vm.
  balls     N balls with radii shrinking as N^(-1/3) (0.3 (10/N)^(1/3) times U(0.6, 1)),
            centres uniform in [-0.85, 0.85]^3, each |p - c|^2 - r^2 (polynomial, as
            bench-suite scenes builds them; other random numbers): the tape-length
            scaling; written as balls-N.vm.
Unions are balanced trees of `min`. Each file states `# domain: -1,-1,-1,1,1,1` in its
header (our tracer's reading; fidget ignores comments).
"""
import argparse
import math
import os
import random
import sys

DEFAULT_N = {"spheres": 2000, "csg": 300, "lattice": 1, "balls": 1000}


class Tape:
    """Writes SSA lines `_ID OPCODE ARGS`, sharing the variables and constants."""

    def __init__(self, header):
        self.lines = [f"# {h}" for h in header]
        self.n = 0
        self.consts = {}
        self.x, self.y, self.z = self.op("var-x"), self.op("var-y"), self.op("var-z")

    def op(self, opcode, *args):
        name = f"_{self.n:x}"
        self.n += 1
        self.lines.append(" ".join([name, opcode, *args]))
        return name

    def const(self, c):
        text = repr(float(round(c, 6)))
        if text not in self.consts:
            self.consts[text] = self.op("const", text)
        return self.consts[text]

    def sub_c(self, a, c):
        return self.op("sub", a, self.const(c)) if c != 0 else a

    def union(self, items):
        """Balanced tree of `min`."""
        while len(items) > 1:
            items = [self.op("min", items[i], items[i + 1]) if i + 1 < len(items) else items[i]
                     for i in range(0, len(items), 2)]
        return items[0]

    def sphere(self, c, r):
        d = [self.op("square", self.sub_c(v, cv)) for v, cv in zip((self.x, self.y, self.z), c)]
        s = self.op("add", self.op("add", d[0], d[1]), d[2])
        return self.op("sub", self.op("sqrt", s), self.const(r))

    def ball(self, c, r):
        """|p - c|^2 - r^2: bench-suite scenes' polynomial ball (no square root)."""
        d = [self.op("square", self.sub_c(v, cv)) for v, cv in zip((self.x, self.y, self.z), c)]
        s = self.op("add", self.op("add", d[0], d[1]), d[2])
        return self.op("sub", s, self.const(r * r))

    def box(self, c, h):
        """max over axes of |p - c| - h (inside < 0; exact inside, a bound outside)."""
        t = [self.op("sub", self.op("abs", self.sub_c(v, cv)), self.const(hv))
             for v, cv, hv in zip((self.x, self.y, self.z), c, h)]
        return self.op("max", self.op("max", t[0], t[1]), t[2])

    def text(self):
        return "\n".join(self.lines) + "\n"


def spheres(n, seed):
    rng = random.Random(seed)
    t = Tape([f"union of {n} spheres, seed {seed} (scripts/gen-vm-scenes.py)",
              "domain: -1,-1,-1,1,1,1"])
    items = []
    for _ in range(n):
        c = [rng.uniform(-0.8, 0.8) for _ in range(3)]
        items.append(t.sphere(c, rng.uniform(0.02, 0.08)))
    t.union(items)
    return t.text()


def balls(n, seed):
    rng = random.Random(seed)
    r0 = 0.3 * (10.0 / n) ** (1.0 / 3.0)
    t = Tape([f"{n} balls, radii 0.3 (10/N)^(1/3) U(0.6, 1), seed {seed} "
              "(scripts/gen-vm-scenes.py)", "domain: -1,-1,-1,1,1,1"])
    items = []
    for _ in range(n):
        c = [rng.uniform(-0.85, 0.85) for _ in range(3)]
        items.append(t.ball(c, r0 * rng.uniform(0.6, 1.0)))
    t.union(items)
    return t.text()


def csg(n, seed):
    rng = random.Random(seed)
    t = Tape([f"CSG tree of {n} spheres and boxes with differences, seed {seed} "
              "(scripts/gen-vm-scenes.py)", "domain: -1,-1,-1,1,1,1"])
    counts = {"sphere": 0, "box": 0, "difference": 0, "intersection": 0}

    def prim(lo, hi, frac):
        c = [rng.uniform(a + 0.3 * (b - a), b - 0.3 * (b - a)) for a, b in zip(lo, hi)]
        ext = min(b - a for a, b in zip(lo, hi))
        if rng.random() < 0.5:
            counts["sphere"] += 1
            return t.sphere(c, frac * ext * rng.uniform(0.6, 1.0))
        counts["box"] += 1
        return t.box(c, [frac * ext * rng.uniform(0.4, 0.9) for _ in range(3)])

    def build(lo, hi, k):
        if k == 1:
            return prim(lo, hi, 0.6)
        r = rng.random()
        if k >= 3 and r < 0.3:
            counts["difference"] += 1
            rest = build(lo, hi, k - 1)
            return t.op("max", rest, t.op("neg", prim(lo, hi, 0.45)))
        if k >= 3 and r < 0.38:
            counts["intersection"] += 1
            rest = build(lo, hi, k - 1)
            return t.op("max", rest, prim(lo, hi, 0.9))
        axis = max(range(3), key=lambda a: (hi[a] - lo[a], -a))
        mid = 0.5 * (lo[axis] + hi[axis])
        hi_a, lo_b = list(hi), list(lo)
        hi_a[axis], lo_b[axis] = mid, mid
        k_a = k // 2
        return t.op("min", build(lo, hi_a, k_a), build(lo_b, hi, k - k_a))

    build([-0.9] * 3, [0.9] * 3, n)
    t.lines[0] += (f"; {counts['sphere']} spheres, {counts['box']} boxes, "
                   f"{counts['difference']} differences, {counts['intersection']} intersections")
    return t.text()


def lattice(_n, _seed):
    t = Tape(["transcendental lattice: gyroid sheet | Schwarz P sheet, in a box minus a "
              "ball (scripts/gen-vm-scenes.py)", "domain: -1,-1,-1,1,1,1"])
    k = 3.5 * 2 * math.pi / 1.6  # 3.5 periods across the box's 1.6
    p = [t.op("mul", v, t.const(k)) for v in (t.x, t.y, t.z)]
    s = [t.op("sin", v) for v in p]
    c = [t.op("cos", v) for v in p]
    g = t.op("add", t.op("add", t.op("mul", s[0], c[1]), t.op("mul", s[1], c[2])),
             t.op("mul", s[2], c[0]))
    # |g| / k - thickness: a sheet about 0.03 thick, in model units.
    gyroid = t.op("sub", t.op("div", t.op("abs", g), t.const(k)), t.const(0.012))
    q = [t.op("cos", t.op("mul", v, t.const(0.5 * k))) for v in (t.x, t.y, t.z)]
    sp = t.op("add", t.op("add", q[0], q[1]), q[2])
    schwarz = t.op("sub", t.op("div", t.op("abs", sp), t.const(0.5 * k)), t.const(0.008))
    sheets = t.op("min", gyroid, schwarz)
    box = t.box([0, 0, 0], [0.8, 0.8, 0.8])
    ball = t.sphere([0.8, 0.8, 0.8], 0.75)
    solid = t.op("max", box, t.op("neg", ball))
    t.op("max", sheets, solid)
    return t.text()


KINDS = {"spheres": spheres, "csg": csg, "lattice": lattice, "balls": balls}


class Parser(argparse.ArgumentParser):
    def error(self, message):
        print(f"error: gen-vm-scenes.py: {message}", file=sys.stderr)
        sys.exit(2)


def main():
    ap = Parser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dir", help="output folder (created)")
    ap.add_argument("--kinds", default="spheres,csg,lattice",
                    help="comma-separated kinds: spheres, csg, lattice, balls")
    ap.add_argument("--n", default=None,
                    help="comma-separated sizes (primitives; default per kind)")
    ap.add_argument("--seed", type=int, default=41)
    a = ap.parse_args()
    kinds = [k.strip() for k in a.kinds.split(",") if k.strip()]
    for k in kinds:
        if k not in KINDS:
            ap.error(f"--kinds: '{k}' is not one of {', '.join(KINDS)}")
    sizes = None
    if a.n is not None:
        try:
            sizes = [int(s) for s in a.n.split(",")]
        except ValueError:
            sizes = [0]
        if not sizes or min(sizes) < 1:
            ap.error(f"--n '{a.n}' is not a comma-separated list of whole numbers above 0")
    os.makedirs(a.dir, exist_ok=True)
    for k in kinds:
        for n in sizes or [DEFAULT_N[k]]:
            name = "lattice.vm" if k == "lattice" else f"{k}-{n}.vm"
            path = os.path.join(a.dir, name)
            text = KINDS[k](n, a.seed)
            # Rewrite only on change, so timestamps (and caches) stay put.
            old = None
            if os.path.exists(path):
                with open(path) as f:
                    old = f.read()
            if old != text:
                with open(path, "w") as f:
                    f.write(text)
            print(path)


if __name__ == "__main__":
    main()
