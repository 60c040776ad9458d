#!/usr/bin/env python3
"""Tests of scripts/peer_masks.py (python3 -m unittest scripts/test_peer_masks.py)."""
import json
import os
import struct
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peer_masks  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def npy(path, descr, code, rows, cols, values):
    header = f"{{'descr': '{descr}', 'fortran_order': False, 'shape': ({rows}, {cols}), }}"
    pad = (-(10 + len(header) + 1)) % 64
    header = header + " " * pad + "\n"
    with open(path, "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode())
        f.write(struct.pack(f"<{len(values)}{code}", *values))


class PeerMasks(unittest.TestCase):
    def test_counts_agreement_and_depth(self):
        inf = float("inf")
        with tempfile.TemporaryDirectory() as d:
            npy(f"{d}/m.npy", "|u1", "B", 2, 2, [1, 1, 0, 0])
            npy(f"{d}/o.npy", "<f4", "f", 2, 2, [2.5, inf, 3.0, inf])
            npy(f"{d}/pd.npy", "<f4", "f", 2, 2, [1.25, 0.5, inf, inf])
            out = subprocess.run(
                [sys.executable, f"{HERE}/peer_masks.py", f"{d}/m.npy", f"{d}/o.npy",
                 "--peer-depth", f"{d}/pd.npy", "--offset", "1", "--diff", f"{d}/x.png"],
                capture_output=True, text=True, check=True).stdout
            r = json.loads(out)
            self.assertEqual((r["peer_hits"], r["our_hits"], r["both_hit"]), (2, 2, 1))
            self.assertEqual((r["peer_only"], r["ours_only"]), (1, 1))
            self.assertEqual(r["agreement"], 0.5)
            self.assertAlmostEqual(r["depth_diff_median"], 0.25)
            with open(f"{d}/x.png", "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_shape_mismatch_is_one_error_line(self):
        with tempfile.TemporaryDirectory() as d:
            npy(f"{d}/m.npy", "|u1", "B", 1, 2, [1, 0])
            npy(f"{d}/o.npy", "<f4", "f", 2, 1, [1.0, 2.0])
            p = subprocess.run([sys.executable, f"{HERE}/peer_masks.py", f"{d}/m.npy",
                                f"{d}/o.npy"], capture_output=True, text=True)
            self.assertEqual(p.returncode, 1)
            self.assertEqual(p.stderr.count("\n"), 1)
            self.assertIn("shapes differ", p.stderr)

    def test_rejects_a_file_that_is_not_npy(self):
        with tempfile.TemporaryDirectory() as d:
            with open(f"{d}/x.npy", "wb") as f:
                f.write(b"not numpy")
            with self.assertRaises(ValueError):
                peer_masks.read_npy(f"{d}/x.npy")


if __name__ == "__main__":
    unittest.main()
