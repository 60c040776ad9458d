#!/usr/bin/env python3
"""Compares a peer renderer's hit mask with our tracer's depth map (python3 stdlib only).

    peer_masks.py PEER_MASK.npy OUR_DEPTH.npy [--peer-depth D.npy --offset O]
                  [--diff diff.png]

PEER_MASK: (H, W) u8/bool/float array, nonzero = hit. OUR_DEPTH: (H, W) float array,
finite = hit (+inf on a miss). Prints one JSON object: pixel count, hits of each,
agreement (fraction of pixels where both hit or both miss), and with --peer-depth the
median and 99th percentile of |our depth - O - peer depth| over pixels both hit (O: how
far our eye plane lies in front of the peer's depth origin). --diff writes a PNG: gray
both hit, black both miss, red peer only, green ours only.
"""
import argparse
import ast
import json
import struct
import sys
import zlib

DTYPES = {"|u1": "B", "u1": "B", "|b1": "?", "<f4": "f", "<f8": "d"}


def read_npy(path):
    """(shape, flat list of values) of a 2-D C-order .npy file."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:6] != b"\x93NUMPY":
        raise ValueError(f"{path}: not a .npy file")
    major = data[6]
    if major == 1:
        (hlen,), start = struct.unpack("<H", data[8:10]), 10
    elif major in (2, 3):
        (hlen,), start = struct.unpack("<I", data[8:12]), 12
    else:
        raise ValueError(f"{path}: .npy version {major} is not read")
    header = ast.literal_eval(data[start:start + hlen].decode("latin1"))
    code = DTYPES.get(header["descr"])
    if code is None:
        raise ValueError(f"{path}: dtype {header['descr']} is not read")
    if header["fortran_order"] or len(header["shape"]) != 2:
        raise ValueError(f"{path}: expected a 2-D C-order array, got {header}")
    rows, cols = header["shape"]
    body = data[start + hlen:]
    n = rows * cols
    if len(body) < n * struct.calcsize(code):
        raise ValueError(f"{path}: truncated data")
    return (rows, cols), struct.unpack(f"<{n}{code}", body[:n * struct.calcsize(code)])


def write_png(path, rows, cols, rgb):
    """Writes an 8-bit RGB PNG from a flat bytes-like of rows * cols * 3 values."""
    raw = b"".join(b"\x00" + bytes(rgb[r * cols * 3:(r + 1) * cols * 3]) for r in range(rows))

    def chunk(kind, payload):
        c = kind + payload
        return struct.pack(">I", len(payload)) + c + struct.pack(">I", zlib.crc32(c))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", cols, rows, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def percentile(sorted_values, q):
    if not sorted_values:
        return None
    return sorted_values[min(len(sorted_values) - 1, int(q * len(sorted_values)))]


def compare(peer_mask, our_depth, peer_depth=None, offset=0.0):
    """The JSON-ready comparison of two equally long flat arrays (and optional depths)."""
    inf = float("inf")
    peer = [v != 0 for v in peer_mask]
    ours = [abs(v) != inf and v == v for v in our_depth]
    n = len(peer)
    both = sum(1 for p, o in zip(peer, ours) if p and o)
    peer_hits, our_hits = sum(peer), sum(ours)
    out = {
        "pixels": n,
        "peer_hits": peer_hits,
        "our_hits": our_hits,
        "both_hit": both,
        "peer_only": peer_hits - both,
        "ours_only": our_hits - both,
        "agreement": (n - (peer_hits - both) - (our_hits - both)) / n,
    }
    if peer_depth is not None:
        diffs = sorted(abs(d - offset - pd) for p, o, d, pd in
                       zip(peer, ours, our_depth, peer_depth) if p and o)
        out["depth_diff_median"] = percentile(diffs, 0.5)
        out["depth_diff_p99"] = percentile(diffs, 0.99)
    return out, peer, ours


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("peer_mask")
    ap.add_argument("our_depth")
    ap.add_argument("--peer-depth")
    ap.add_argument("--offset", type=float, default=0.0)
    ap.add_argument("--diff")
    a = ap.parse_args(argv)
    try:
        shape_p, mask = read_npy(a.peer_mask)
        shape_o, depth = read_npy(a.our_depth)
        if shape_p != shape_o:
            raise ValueError(f"shapes differ: {shape_p} (peer) vs {shape_o} (ours)")
        pdepth = None
        if a.peer_depth:
            shape_d, pdepth = read_npy(a.peer_depth)
            if shape_d != shape_p:
                raise ValueError(f"shapes differ: {shape_d} (peer depth) vs {shape_p}")
    except (OSError, ValueError, SyntaxError, KeyError, struct.error) as e:
        print(f"peer_masks.py: error: {e}", file=sys.stderr)
        return 1
    out, peer, ours = compare(mask, depth, pdepth, a.offset)
    if a.diff:
        colors = {(True, True): (160, 160, 160), (False, False): (0, 0, 0),
                  (True, False): (255, 0, 0), (False, True): (0, 255, 0)}
        rgb = bytearray()
        for p, o in zip(peer, ours):
            rgb.extend(colors[(p, o)])
        write_png(a.diff, shape_p[0], shape_p[1], rgb)
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
