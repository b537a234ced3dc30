#!/usr/bin/env python3
"""Bodies released in still water (issue 25's criteria): a cube 8 spacings wide (assets/crate.obj
baked by the build, scaled) in water 16 spacings deep (two cube sizes), in a tank walled by the
domain box 4 spacings wider than the cube on every side, played --deterministic with each
boundary model. The cases:

- neutral-low, -middle, -high: 1000 kg/m3 released at rest with one water layer under it, at
  mid-depth, and with one layer over it (it should stray under one spacing in 3 s);
- floor-0.3, -0.5, -0.7, -1.2: resting on the floor from the start (the lighter ones should rise
  and float at their draft, 1.2 stay down);
- dropped-0.5: 500 kg/m3 dropped from 0.3 m above the surface (it should come back up and float);
- heavy-1.1-top, -deep: 1100 kg/m3 released at rest with its top level with the surface, and
  four spacings under it (it should sink: water has to flow up past it, through the four
  spacings between it and the walls).

Reads the centre of mass and the submerged share from --bodies-csv and prints, per run, where
the centre starts and ends, how far it strayed (in spacings), and the share at the end.

    python3 tests/bench/pbf/body_releases.py --build build/dev [--seconds 3] [--cases ...]
        [--simulation '{"scorrK": 0}']
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

SPACING = 0.02
SIDE = 8 * SPACING
TANK = SIDE + 8 * SPACING  # [m] square floor
DEPTH = 16 * SPACING
CRATE = 0.12  # [m] side of assets/crate.obj
CASES = {  # name: (density ratio, the cube's centre at release [m])
    "neutral-low": (1.0, SPACING + SIDE / 2),
    "neutral-middle": (1.0, DEPTH / 2),
    "neutral-high": (1.0, DEPTH - SPACING - SIDE / 2),
    "floor-0.3": (0.3, SIDE / 2),
    "floor-0.5": (0.5, SIDE / 2),
    "floor-0.7": (0.7, SIDE / 2),
    "floor-1.2": (1.2, SIDE / 2),
    "dropped-0.5": (0.5, DEPTH + 0.3 + SIDE / 2),
    "heavy-1.1-top": (1.1, DEPTH - SIDE / 2),
    "heavy-1.1-deep": (1.1, DEPTH - 4 * SPACING - SIDE / 2),
}


def scene(boundary, ratio, centre_y, simulation=None):
    return {"version": 1, "name": "body-release",
            "simulation": {"spacing": SPACING, "boundary": boundary, **(simulation or {})},
            "fluid": [{"box": {"min": [0, 0, 0], "max": [TANK, DEPTH, TANK]}}],
            "colliders": [{"asset": "crate.slc", "scale": SIDE / CRATE,
                           "translation": [TANK / 2, centre_y, TANK / 2],
                           "dynamic": {"density": 1000 * ratio}}],
            "domain": {"min": [0, 0, 0], "max": [TANK, 1.0, TANK]}}


def play(build, boundary, name, seconds, work, simulation=None):
    ratio, centre_y = CASES[name]
    path = os.path.join(build, "assets", f"release-{boundary}-{name}.json")
    with open(path, "w") as f:
        json.dump(scene(boundary, ratio, centre_y, simulation), f, indent=4)
    table = os.path.join(work, "bodies.csv")
    steps = int(round(seconds * 60)) + 1  # the scenes' default step is 1/60 s
    subprocess.run([os.path.join(build, "bin", "sluice-play"), path, "--headless", "--steps",
                    str(steps), "--deterministic", "--stats-every", "3", "--bodies-csv", table],
                   check=True, capture_output=True, text=True)
    with open(table) as f:
        rows = [r for r in csv.DictReader(f) if float(r["time"]) <= seconds + 1e-6]
    return [(float(r["time"]), float(r["centre_of_mass_y"]), float(r["submerged_share"]))
            for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--boundaries", default="bodies,solids")
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--simulation", type=json.loads, default={},
                    help='JSON object of scene "simulation" settings to add, e.g. {"scorrK": 0}')
    ap.add_argument("--json")
    a = ap.parse_args()
    results = []
    with tempfile.TemporaryDirectory() as work:
        for boundary in a.boundaries.split(","):
            for name in a.cases.split(","):
                track = play(a.build, boundary, name, a.seconds, work, a.simulation)
                start, end = track[0][1], track[-1][1]
                worst = max(abs(c - start) for _, c, _ in track)
                row = {"boundary": boundary, "case": name, "ratio": CASES[name][0],
                       "startY": start, "endY": end, "seconds": track[-1][0],
                       "endShiftSpacings": (end - start) / SPACING,
                       "farthestSpacings": worst / SPACING, "endShare": track[-1][2]}
                results.append(row)
                print(f"{boundary:6s} {name:14s}: centre {start:.4f} -> {end:.4f} m after "
                      f"{track[-1][0]:.2f} s ({row['endShiftSpacings']:+.2f} spacings, farthest "
                      f"{row['farthestSpacings']:.2f}), submerged share {track[-1][2]:.3f}",
                      flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"what": "bodies released in still water, tests/bench/pbf/body_releases.py",
                       "seconds": a.seconds, "side": SIDE, "depth": DEPTH, "tank": TANK,
                       "simulation": a.simulation,
                       "runs": results}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
