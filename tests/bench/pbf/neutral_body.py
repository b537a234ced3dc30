#!/usr/bin/env python3
"""A body as dense as the water (issue 25: "at 1.0 it neither rises nor sinks more than one
particle spacing in 3 s, anywhere in the water column"): a cube 8 spacings wide (assets/crate.obj
baked by the build, scaled) at 1000 kg/m3, released at rest low, in the middle and high in
water 16 spacings deep in a tank walled by the domain box, played --deterministic for --seconds
with each boundary model. Reads the centre of mass from --bodies-csv and prints, per run, where
it ends and how far it strayed from its start, in particle spacings.

    python3 tests/bench/pbf/neutral_body.py --build build/dev [--seconds 3] [--json FILE]
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
TANK = 0.4  # [m] square floor, walled by the domain box
DEPTH = 16 * SPACING
CRATE = 0.12  # [m] side of assets/crate.obj
RELEASES = {  # the cube's centre [m]: one spacing of water under it, mid-depth, one over it
    "low": SPACING + SIDE / 2,
    "middle": DEPTH / 2,
    "high": DEPTH - SPACING - SIDE / 2,
}


def scene(boundary, centre_y):
    return {"version": 1, "name": "neutral-body",
            "simulation": {"spacing": SPACING, "boundary": boundary},
            "fluid": [{"box": {"min": [0, 0, 0], "max": [TANK, DEPTH, TANK]}}],
            "colliders": [{"asset": "crate.slc", "scale": SIDE / CRATE,
                           "translation": [TANK / 2, centre_y, TANK / 2],
                           "dynamic": {"density": 1000}}],
            "domain": {"min": [0, 0, 0], "max": [TANK, 0.6, TANK]}}


def play(build, boundary, centre_y, seconds, work):
    path = os.path.join(build, "assets", f"neutral-{boundary}-{centre_y:.3f}.json")
    with open(path, "w") as f:
        json.dump(scene(boundary, centre_y), f, indent=4)
    table = os.path.join(work, "bodies.csv")
    steps = int(round(seconds * 60)) + 1  # the scenes' default step is 1/60 s
    subprocess.run([os.path.join(build, "bin", "sluice-play"), path, "--headless", "--steps",
                    str(steps), "--deterministic", "--stats-every", "3", "--bodies-csv", table],
                   check=True, capture_output=True, text=True)
    with open(table) as f:
        rows = [r for r in csv.DictReader(f) if float(r["time"]) <= seconds + 1e-6]
    return [(float(r["time"]), float(r["centre_of_mass_y"])) for r in rows]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--boundaries", default="bodies,solids")
    ap.add_argument("--json")
    a = ap.parse_args()
    results = []
    with tempfile.TemporaryDirectory() as work:
        for boundary in a.boundaries.split(","):
            for name, y in RELEASES.items():
                track = play(a.build, boundary, y, a.seconds, work)
                start = track[0][1]
                end = track[-1][1]
                worst = max(abs(c - start) for _, c in track)
                row = {"boundary": boundary, "release": name, "startY": start, "endY": end,
                       "seconds": track[-1][0], "endShiftSpacings": (end - start) / SPACING,
                       "worstShiftSpacings": worst / SPACING}
                results.append(row)
                print(f"{boundary:6s} {name:6s}: centre {start:.4f} -> {end:.4f} m after "
                      f"{track[-1][0]:.2f} s, {row['endShiftSpacings']:+.2f} spacings "
                      f"(farthest {row['worstShiftSpacings']:.2f})", flush=True)
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"what": "neutral body, tests/bench/pbf/neutral_body.py",
                       "seconds": a.seconds, "runs": results}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
