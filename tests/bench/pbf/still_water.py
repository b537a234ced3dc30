#!/usr/bin/env python3
"""Still water against walls (issue 25's first measure): a block of water at rest spacing is left
to settle for --seconds, then the last frame is measured: the free surface against the height
the water's volume gives, and the number density of the first particle layer at the floor, at a
side wall and in a vertical corner against the bulk's.

Two tanks: `box`, walled by the domain box alone, and `baked`, the tank of assets/float.json
(assets/tank.obj baked by the build: inner floor y = 0.03, inner walls x = +-0.37, z = +-0.22).

    python3 tests/bench/pbf/still_water.py --build build/dev [--seconds 3] [--tanks box,baked]

Measures, per tank (s = spacing, y0 = the floor, H = N s^3 / floor area):
- surface: the mean over interior columns (s x s, at least 2 s from a wall) of the highest
  particle centre + s / 2, as (surface - y0) / H - 1;
- floor, wall, corner: particles whose centre lies within s of the floor (interior x, z), of a
  side wall (mid-height, interior along the wall) or of two walls at once (mid-height), per
  slab volume, over the bulk's (interior, 3 s from every wall and from the surface).
Needs numpy. Prints one line per tank; --json FILE writes them.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from neighbour_stats import read_ply  # noqa: E402

TANKS = {
    # name: (inner min, inner max, colliders, domain)
    "box": ([0.0, 0.0, 0.0], [0.3, 0.4, 0.3], [], {"min": [0, 0, 0], "max": [0.3, 0.4, 0.3]}),
    "baked": ([-0.37, 0.03, -0.22], [0.37, 0.4, 0.22], [{"asset": "tank.slc"}],
              {"min": [-0.5, 0.0, -0.35], "max": [0.5, 0.7, 0.35]}),
}


def scene(name, spacing, depth, extra=None):
    lo, hi, colliders, domain = TANKS[name]
    top = lo[1] + depth
    sim = {"spacing": spacing}
    sim.update(extra or {})
    return {"version": 1, "name": f"still-{name}", "simulation": sim,
            "fluid": [{"box": {"min": lo, "max": [hi[0], top, hi[2]]}}],
            "colliders": colliders, "domain": domain}


def measure(x, lo, hi, s):
    lo, hi = np.array(lo), np.array(hi)
    n = len(x)
    area = (hi[0] - lo[0]) * (hi[2] - lo[2])
    height = n * s ** 3 / area
    y0 = lo[1]
    d_lo, d_hi = x - lo, hi - x  # distances to each wall (y: only the floor counts)
    inner = lambda m: (np.minimum(d_lo[:, 0], d_hi[:, 0]) >= m) & \
        (np.minimum(d_lo[:, 2], d_hi[:, 2]) >= m)
    # Free surface over interior columns.
    cols = inner(2 * s)
    key = np.floor((x[cols][:, [0, 2]] - lo[[0, 2]]) / s).astype(int)
    tops = {}
    for (i, k), y in zip(map(tuple, key), x[cols][:, 1]):
        tops[(i, k)] = max(tops.get((i, k), -1e9), y)
    surface = np.mean(list(tops.values())) + 0.5 * s
    mid = (d_lo[:, 1] >= 3 * s) & (x[:, 1] <= y0 + height - 3 * s)
    bulk_m = inner(3 * s) & mid
    bulk_v = (hi[0] - lo[0] - 6 * s) * (hi[2] - lo[2] - 6 * s) * (height - 6 * s)
    bulk = bulk_m.sum() / bulk_v
    floor_m = inner(3 * s) & (d_lo[:, 1] < s)
    floor = floor_m.sum() / ((hi[0] - lo[0] - 6 * s) * (hi[2] - lo[2] - 6 * s) * s)
    ylen = height - 6 * s
    walls, corners = [], []
    for a, b in ((0, 2), (2, 0)):
        along = hi[b] - lo[b] - 6 * s
        for d in (d_lo, d_hi):
            m = mid & (d[:, a] < s) & (np.minimum(d_lo[:, b], d_hi[:, b]) >= 3 * s)
            walls.append(m.sum() / (s * along * ylen))
    for da in (d_lo, d_hi):
        for db in (d_lo, d_hi):
            m = mid & (da[:, 0] < s) & (db[:, 2] < s)
            corners.append(m.sum() / (s * s * ylen))
    return {"particles": n, "height": height, "surface": surface - y0,
            "surfaceError": (surface - y0) / height - 1.0,
            "floor": floor / bulk, "wall": float(np.mean(walls)) / bulk,
            "corner": float(np.mean(corners)) / bulk, "bulkPerS3": bulk * s ** 3}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--build", default="build/dev")
    p.add_argument("--seconds", type=float, default=3.0)
    p.add_argument("--spacing", type=float, default=0.02)
    p.add_argument("--depth", type=float, default=0.16, help="[m] water depth at the start")
    p.add_argument("--tanks", default="box,baked")
    p.add_argument("--set", default="{}", help="JSON object merged into simulation")
    p.add_argument("--json")
    a = p.parse_args()
    play = os.path.join(a.build, "bin", "sluice-play")
    assets = os.path.join(a.build, "assets")
    steps = int(round(a.seconds * 60))  # the default time step is 1/60 s
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.tanks.split(","):
            path = os.path.join(assets if TANKS[name][2] else tmp, f"still-{name}.json")
            with open(path, "w") as f:
                json.dump(scene(name, a.spacing, a.depth, json.loads(a.set)), f)
            frames = os.path.join(tmp, name)
            try:
                subprocess.run([play, path, "--headless", "--deterministic", "--quiet",
                                "--steps", str(steps), "--dump-ply", frames,
                                "--dump-every", str(steps)], check=True)
            finally:
                if TANKS[name][2]:
                    os.remove(path)
            last = sorted(f for f in os.listdir(frames) if f.endswith(".ply"))[-1]
            r = measure(read_ply(os.path.join(frames, last)).astype(np.float64),
                        TANKS[name][0], TANKS[name][1], a.spacing)
            r.update(tank=name, seconds=a.seconds, spacing=a.spacing)
            out.append(r)
            print(f"{name:5s} {r['particles']} particles, {a.seconds:g} s: surface "
                  f"{100 * r['surfaceError']:+.1f} % of the volume's height "
                  f"{r['height']:.4f} m; first layer / bulk: floor {r['floor']:.3f}, wall "
                  f"{r['wall']:.3f}, corner {r['corner']:.3f} (bulk {r['bulkPerS3']:.3f} / s^3)")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=2)


if __name__ == "__main__":
    main()
