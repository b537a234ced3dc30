#!/usr/bin/env python3
"""The Martin & Moyce (1952) dam-break front: Sluice against SPlisHSPlasH
and the experiment, in one run.

The setup is SimulationPhysics.DamBreakFrontFollowsMartinAndMoyceWithinFifteenPercent's
(tests/runtime/sim/SimulationPhysicsTest.cpp): a column a = 0.2 m wide and 2a high in the
corner of a tank 5a long and 3a high, particle spacing s = 1 cm, kernel support h = 2 s, time
step 1/60 s in 4 substeps, 2 to 8 solver iterations with the early stop at 0.5 %, XSPH 0.01 and
vorticity confinement on both sides. The tank is `--depth` particles deep between walls (4 in
the test). The front is what the test measures: the largest x of the particles below a / 4,
as Z = x / a, at T = t sqrt(2 g / a) after every 1/60 s step; the deviation from the
experiment is |Z - Z_MM| / Z_MM over the steps with T >= 0.5 (the test's 16 points).

Runs, each one process:
  - Sluice (the Python package of --build), its walls adding boundary volume,
  - the same with the tank one particle deep (the nearest Sluice, which is 3D, comes to 2D),
  - SPlisHSPlasH's PBF (pip install pysplishsplash) in 2D ("sim2D") on the same lattice, time
    step and parameters, with Bender et al. 2019 volume maps (the model Sluice implements;
    in 3D its volume map integrates 27,000 points per map node, hours on two cores) and with
    Akinci et al. 2012 boundary particles (its box grown by s / 2, as
    tests/bench/pbf/vs_splishsplash.py does, so the water has the same room).

Usage (repository root, after the dev build):

    python3 -m venv /tmp/sph && /tmp/sph/bin/pip install pysplishsplash
    python3 tests/bench/pbf/martin_moyce.py --build build/dev \\
        --splishsplash-python /tmp/sph/bin/python --out docs/results/martin_moyce.json
"""

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, HERE)

import sweep  # noqa: E402  (machine_info)
from vs_splishsplash import (FLUID_MATERIAL, SYSTEM_GLDISPATCH, splishsplash_unit_box,  # noqa: E402
                             start_splishsplash)

A = 0.2            # column width [m]
SPACING = 0.01     # particle spacing s [m]
G = 9.81
SUBSTEPS = 4
FRAME = 1.0 / 60.0
T_STOP = 3.0       # the test steps while T < 3, so its last point is just past it



def read_martin_moyce():
    """The measured (T, Z) points, read from the test's table (tests/runtime/sim/MartinMoyce.h),
    so the script and the test compare with the same data."""
    with open(os.path.join(ROOT, "tests", "runtime", "sim", "MartinMoyce.h")) as f:
        text = f.read()
    table = text[text.index("kMartinMoyceFront"):]
    table = table[:table.index("}};")]
    return [(float(t), float(z)) for t, z in re.findall(r"\{([0-9.]+), ([0-9.]+)\}", table)]


MARTIN_MOYCE = read_martin_moyce()


def martin_moyce(t):
    for (t0, z0), (t1, z1) in zip(MARTIN_MOYCE, MARTIN_MOYCE[1:]):
        if t <= t1:
            return z0 + (t - t0) / (t1 - t0) * (z1 - z0)
    return MARTIN_MOYCE[-1][1]


def time_scale():
    return math.sqrt(2.0 * G / A)


def front_of(positions):
    """Z: the largest x of the particles below a / 4, over a."""
    xs = [p[0] for p in positions if p[1] < 0.25 * A]
    return max(xs) / A if xs else 0.0


def deviation(curve):
    """Mean and largest |Z - Z_MM| / Z_MM and the mean signed one over T >= 0.5."""
    d = [(z - martin_moyce(t)) / martin_moyce(t) for t, z in curve if t >= 0.5]
    if not d:
        return {"points": 0}
    return {"points": len(d), "meanAbs": sum(abs(x) for x in d) / len(d),
            "meanSigned": sum(d) / len(d), "maxAbs": max(abs(x) for x in d)}


# --------------------------------------------------------------------------------------------
# Sluice
# --------------------------------------------------------------------------------------------

def sluice_scene(depth):
    h = 2.0 * SPACING
    return {
        "version": 1, "name": "martin-moyce-%d" % depth,
        "simulation": {
            "spacing": SPACING, "kernelRadius": h, "restDensity": 1000.0, "timeStep": FRAME,
            "substeps": SUBSTEPS, "minIterations": 2, "maxIterations": 8,
            "targetDensityError": 0.005, "relaxation": 0.01, "scorrK": 0.1, "scorrN": 4.0,
            "scorrDeltaQ": 0.2 * h, "xsph": 0.01, "vorticity": 0.01 * math.sqrt(G * h),
            "gravity": [0.0, -G, 0.0],
        },
        "fluid": [{"box": {"min": [0.0, 0.0, 0.0], "max": [A, 2 * A, depth * SPACING]}}],
        "domain": {"min": [0.0, 0.0, 0.0], "max": [5 * A, 3 * A, depth * SPACING]},
    }


def run_sluice(build, depth):
    sys.path.insert(0, os.path.join(build, "python"))
    import sluice

    sim = sluice.Simulation(sluice_scene(depth))
    curve = []
    while sim.time * time_scale() < T_STOP:
        sim.step(1, progress=False)
        curve.append((sim.time * time_scale(), front_of(sim.positions.tolist())))
    return {"solver": "Sluice PBF, %d deep" % depth,
            "particles": sim.particle_count, "curve": curve}


# --------------------------------------------------------------------------------------------
# SPlisHSPlasH (its own process: the preload and its global state)
# --------------------------------------------------------------------------------------------

def splishsplash_worker(cfg):
    import numpy as np
    import pysplishsplash as sph

    s, depth, two_d = SPACING, cfg["depth"], cfg["sim2D"]
    counts = [round(A / s), round(2 * A / s), 1 if two_d else depth]
    # SPlisHSPlasH fills [start, end] with round(extent / s) - 1 particles per axis from start
    # + s: this gives Sluice's lattice s (i + 1/2).
    start = [-0.5 * s, -0.5 * s, -0.5 * s]
    end = [start[i] + (counts[i] + 1) * s for i in range(3)]
    tank = [5 * A, 3 * A, depth * s]
    akinci = cfg["boundaryHandlingMethod"] == 0
    grow = 0.5 * s if akinci else 0.0
    lo = [-grow, -grow, -grow]
    hi = [tank[i] + grow for i in range(3)]
    if two_d:
        start[2], end[2] = -2 * s, 2 * s  # SPlisHSPlasH's 2D blocks want a z extent
        lo[2], hi[2] = -0.5, 0.5
    centre = [0.5 * (lo[i] + hi[i]) for i in range(3)]
    size = [hi[i] - lo[i] for i in range(3)]
    box = {"geometryFile": cfg["unitBox"], "translation": centre, "scale": size,
           "isDynamic": False, "isWall": True, "mapInvert": True, "mapThickness": 0.0,
           "samplingMode": 1}
    if not akinci:
        box["mapResolution"] = [60, 40, 1] if two_d else [60, 40, 10]
    scene = {
        "Configuration": {
            "particleRadius": 0.5 * s, "sim2D": two_d, "simulationMethod": 2,  # PBF
            "timeStepSize": FRAME / SUBSTEPS, "cflMethod": 0, "gravitation": [0, -G, 0],
            "boundaryHandlingMethod": cfg["boundaryHandlingMethod"], "enableZSort": True,
            "pause": False, "enablePartioExport": False, "enableVTKExport": False,
            "PBF": {"minIterations": 2, "maxIterations": 8, "maxError": 0.5,
                    "velocityUpdateMethod": 0},
        },
        "Materials": [FLUID_MATERIAL],
        "RigidBodies": [box],
        "FluidBlocks": [{"denseMode": 0, "start": start, "end": end}],
    }
    base = start_splishsplash(sph, scene, cfg["workDir"], "martin-moyce")
    sim = sph.Simulation.getCurrent()
    model = sim.getFluidModel(0)
    curve, k = [], [0]

    def on_step():
        k[0] += 1
        if k[0] % SUBSTEPS == 0:
            n = model.numActiveParticles()
            x = np.asarray(model.getFieldBuffer("position"))[:n].tolist()
            curve.append((k[0] * FRAME / SUBSTEPS * time_scale(), front_of(x)))

    base.setTimeStepCB(on_step)
    frames = math.ceil(T_STOP / time_scale() / FRAME)  # the frames Sluice's loop steps
    base.setValueFloat(base.STOP_AT, (frames + 0.5) * FRAME)
    base.runSimulation()
    method = "Akinci et al. 2012 boundary particles" if akinci else \
        "Bender et al. 2019 volume maps"
    return {"solver": "SPlisHSPlasH PBF (pysplishsplash %s), %s%s"
            % (getattr(sph, "__version__", "2.19"), method, ", 2D" if two_d else ""),
            "particles": model.numActiveParticles(), "curve": curve}


def run_splishsplash(python, cfg, preload):
    env = dict(os.environ, OMP_NUM_THREADS=str(os.cpu_count() or 1))
    if preload and os.path.exists(SYSTEM_GLDISPATCH):
        env["LD_PRELOAD"] = SYSTEM_GLDISPATCH
    out = subprocess.run([python, os.path.abspath(__file__), "--worker", json.dumps(cfg)],
                         env=env, capture_output=True, text=True, timeout=3600)
    if out.returncode != 0:
        raise RuntimeError("SPlisHSPlasH worker failed (%d): %s" % (out.returncode,
                                                                  out.stderr[-2000:]))
    return json.loads(out.stdout.strip().splitlines()[-1])


# --------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------

def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--worker":
        print(json.dumps(splishsplash_worker(json.loads(sys.argv[2]))))
        return 0
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build", "dev"))
    ap.add_argument("--splishsplash-python", help="a Python with pysplishsplash (else skipped)")
    ap.add_argument("--depth", type=int, default=4, help="particles between the z walls")
    ap.add_argument("--no-preload", action="store_true")
    ap.add_argument("--out", help="results JSON")
    args = ap.parse_args()

    runs = [run_sluice(args.build, d) for d in (args.depth, 1)]
    if args.splishsplash_python:
        work = tempfile.mkdtemp(prefix="sluice-mm-")
        unit_box = splishsplash_unit_box(args.splishsplash_python)
        # In 3D SPlisHSPlasH's Akinci walls blow a slab a few particles deep apart at the start
        # (its front 34 % ahead of the experiment at 4 deep), so both of its runs are 2D.
        for method, two_d in ((2, True), (0, True)):
            cfg = {"depth": args.depth, "sim2D": two_d, "boundaryHandlingMethod": method,
                   "unitBox": unit_box,
                   "workDir": os.path.join(work, "sph-%d-%d" % (method, two_d))}
            runs.append(run_splishsplash(args.splishsplash_python, cfg, not args.no_preload))
    print("%-72s %6s %9s %9s %9s" % ("solver", "points", "mean |d|", "signed", "max |d|"))
    for r in runs:
        r["deviation"] = dev = deviation(r["curve"])
        print("%-72s %6d %8.1f%% %8.1f%% %8.1f%%" % (r["solver"], dev["points"],
              100 * dev["meanAbs"], 100 * dev["meanSigned"], 100 * dev["maxAbs"]))
    ts = [t for t, _ in runs[0]["curve"]]
    print("\n%6s %7s" % ("T", "M&M") + "".join(" %7s" % ("run%d" % i) for i in range(len(runs))))
    for j, t in enumerate(ts):
        row = "%6.3f %7.3f" % (t, martin_moyce(t))
        for r in runs:
            row += " %7.3f" % r["curve"][j][1] if j < len(r["curve"]) else " %7s" % "-"
        print(row)
    if args.out:
        with open(args.out, "w") as f:
            json.dump({"machine": sweep.machine_info(), "loadAverage": os.getloadavg(),
                       "depth": args.depth, "runs": runs}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
