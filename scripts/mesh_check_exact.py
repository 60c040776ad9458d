#!/usr/bin/env python3
"""Confirms mesh_check.py's self-intersection verdicts in exact rational arithmetic, on a
random sample of the candidate pairs that share no vertex, and of those that share one
(needs numpy).

    mesh_check_exact.py MESH.{obj,ply,stl} [--sample N] [--seed S]

A different formulation than the checker's orientation signs: the point where an edge
crosses the other triangle's plane, in fractions, then its three edge-side signs in
that triangle (strictly inside); for pairs sharing one vertex, the edge opposite it.
Prints one line per kind of pair: the pairs the checker reports crossing, and on how
many of the sampled crossing / non-crossing pairs the exact test agrees. Exit code 1 if any sampled pair disagrees, 2 on bad input.
"""
import argparse
import os
import random
import sys
from fractions import Fraction as Q

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mesh_check as mc  # noqa: E402


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def crosses(p, q, tri):
    u, w, x = tri
    n = cross(sub(w, u), sub(x, u))
    dp, dq = dot(n, sub(p, u)), dot(n, sub(q, u))
    if not ((dp > 0 > dq) or (dp < 0 < dq)):
        return False
    s = dp / (dp - dq)
    r = [p[i] + s * (q[i] - p[i]) for i in range(3)]

    def side(a, b):
        return dot(n, cross(sub(b, a), sub(r, a)))

    return side(u, w) > 0 and side(w, x) > 0 and side(x, u) > 0


def exact(v, t, i, j):
    X = [[Q(float(c)) for c in v[k]] for k in t[i]]
    Y = [[Q(float(c)) for c in v[k]] for k in t[j]]
    return any(crosses(S[k], S[(k + 1) % 3], T) for S, T in ((X, Y), (Y, X)) for k in range(3))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("--sample", type=int, default=40)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    if a.sample < 1:
        print("mesh_check_exact.py: error: --sample must be at least 1", file=sys.stderr)
        sys.exit(2)
    try:
        v, t = mc.read_mesh(a.mesh)
    except mc.Bad as e:
        print(f"mesh_check_exact.py: error: {e}", file=sys.stderr)
        sys.exit(2)
    tv = v[t]
    pairs = mc.candidate_pairs(tv.min(axis=1), tv.max(axis=1)) if len(t) > 1 else np.zeros((0, 2), int)
    A, B = t[pairs[:, 0]], t[pairs[:, 1]]
    eq = A[:, :, None] == B[:, None, :]
    shared = eq.sum(axis=(1, 2))
    rng = random.Random(a.seed)
    good = True
    for kind in (0, 1):
        m = shared == kind
        P, E = pairs[m], eq[m]
        h = np.zeros(len(P), bool)
        if kind == 0:
            PA, PB = v[t[P[:, 0]]], v[t[P[:, 1]]]
            for X, Y in ((PA, PB), (PB, PA)):
                for k in range(3):
                    h |= mc.segment_crosses(X[:, k], X[:, (k + 1) % 3], Y[:, 0], Y[:, 1], Y[:, 2])
        else:
            h = mc.self_intersection_flags(v, t, P) if len(P) else h

        def exact_pair(k):
            i, j = P[k]
            if kind == 0:
                return exact(v, t, i, j)
            X = [[Q(float(c)) for c in v[q]] for q in t[i]]
            Y = [[Q(float(c)) for c in v[q]] for q in t[j]]
            ka = int(np.argmax(E[k].any(axis=1)))
            kb = int(np.argmax(E[k].any(axis=0)))
            return (crosses(X[(ka + 1) % 3], X[(ka + 2) % 3], Y)
                    or crosses(Y[(kb + 1) % 3], Y[(kb + 2) % 3], X))

        pos = [int(k) for k in np.nonzero(h)[0]]
        neg = [int(k) for k in np.nonzero(~h)[0]]
        sp = rng.sample(pos, min(a.sample, len(pos)))
        sn = rng.sample(neg, min(5 * a.sample, len(neg)))
        ok_p = sum(exact_pair(k) for k in sp)
        ok_n = sum(not exact_pair(k) for k in sn)
        good &= ok_p == len(sp) and ok_n == len(sn)
        print(f"{a.mesh}: {len(pos)} crossing pairs sharing {('no', 'one')[kind]} vertex; exact "
              f"test agrees on {ok_p}/{len(sp)} sampled crossing and {ok_n}/{len(sn)} sampled "
              "non-crossing pairs")
    sys.exit(0 if good else 1)


if __name__ == "__main__":
    main()
