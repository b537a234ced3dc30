#!/usr/bin/env python3
"""Counts what the 27-cell neighbour loop of shaders/glsl/PbfGlsl.h visits, per particle, on a
particle state written by `sluice-play --dump-ply`: bucket entries visited (candidates, hash
collisions included), candidates in the 27 true cells, and true neighbours (|x_i - x_j| < h).

    python3 tests/bench/pbf/neighbour_stats.py FRAME.ply --spacing 0.02 [--kernel-radius H]

Needs numpy. Uses the cell size h and the hash of docs/pbf.md step 3, with the table size of
Simulation.cpp (max(1024, bit_ceil(2 * particles))).
"""

import argparse
import sys

import numpy as np


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    n = int([l for l in header.splitlines() if l.startswith("element vertex")][0].split()[-1])
    rec = np.dtype([("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("vx", "<f4"), ("vy", "<f4"),
                    ("vz", "<f4"), ("id", "<u4")])
    arr = np.frombuffer(data, dtype=rec, count=n, offset=end)
    return np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float32)


def cell_hash(c, mask):
    c = c.astype(np.int64).astype(np.uint32)
    return ((c[:, 0] * np.uint32(73856093)) ^ (c[:, 1] * np.uint32(19349663)) ^
            (c[:, 2] * np.uint32(83492791))) & np.uint32(mask)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("ply")
    p.add_argument("--spacing", type=float, required=True)
    p.add_argument("--kernel-radius", type=float)
    a = p.parse_args()
    h = a.kernel_radius or 2.0 * a.spacing
    x = read_ply(a.ply)
    n = len(x)
    table = max(1024, 1 << (2 * n - 1).bit_length())
    cells = np.floor(x * np.float32(1.0 / h)).astype(np.int64)
    buckets = cell_hash(cells, table - 1)
    bucket_count = np.bincount(buckets, minlength=table)
    # Particles per exact cell.
    key = (cells[:, 0] + 4096) * (1 << 40) + (cells[:, 1] + 4096) * (1 << 20) + (cells[:, 2] + 4096)
    order = np.argsort(key, kind="stable")
    skey = key[order]
    visited = np.zeros(n, np.int64)
    in_cells = np.zeros(n, np.int64)
    neighbours = np.zeros(n, np.int64)
    h2 = np.float32(h * h)
    for dz in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                cc = cells + np.array([dx, dy, dz])
                visited += bucket_count[cell_hash(cc, table - 1)]
                k = (cc[:, 0] + 4096) * (1 << 40) + (cc[:, 1] + 4096) * (1 << 20) + (cc[:, 2] + 4096)
                lo = np.searchsorted(skey, k, "left")
                hi = np.searchsorted(skey, k, "right")
                cnt = hi - lo
                in_cells += cnt
                width = int(cnt.max()) if n else 0
                for w in range(width):
                    has = cnt > w
                    i = np.nonzero(has)[0]
                    j = order[lo[has] + w]
                    d = x[i] - x[j]
                    close = (np.einsum("ij,ij->i", d, d) < h2) & (i != j)
                    np.add.at(neighbours, i[close], 1)
    in_cells -= 1  # the particle itself
    visited -= 1
    interior = neighbours >= np.percentile(neighbours, 50)
    print(f"{a.ply}: {n} particles, h = {h:g} m, table {table} buckets")
    print("| per particle | mean | median | p95 | interior half (mean) |")
    print("|---|---|---|---|---|")
    for name, v in (("bucket entries visited (27 buckets)", visited),
                    ("candidates in the 27 cells", in_cells),
                    ("true neighbours (< h)", neighbours)):
        print(f"| {name} | {v.mean():.1f} | {np.median(v):.0f} | {np.percentile(v, 95):.0f} | "
              f"{v[interior].mean():.1f} |")
    print(f"| neighbours / visited | {neighbours.sum() / max(visited.sum(), 1):.3f} | | | "
          f"{neighbours[interior].sum() / max(visited[interior].sum(), 1):.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
