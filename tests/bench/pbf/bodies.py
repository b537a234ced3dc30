#!/usr/bin/env python3
"""What dynamic bodies cost: sluice-play --bench on a pool with 0, 1, 16 and 64 floating crates,
the same water in every run, interleaved and repeated.

The crates (assets/crate.obj baked by the build, scaled so N of them fit side by side) start
just above the water at half its density and land during the warm-up. Each run reports the
median GPU step time and its passes; the coupling's cost is the step time over the fluid-only
run's (the boundary volume in the lambda and delta passes and the reaction sums) plus the body
pass itself, both from the same run. Each round runs every count once, so the ratio of a
count's step to the fluid-only step of the same round is an interleaved pair; the summary gives
the median of those pairs and their range, as well as the ratio of the medians. Results:
docs/results/pbf_bodies_<machine>.json.

    python3 tests/bench/pbf/bodies.py --build build/dev --repeat 5 --bodies 0,12,16,64

With --resting the crates start on the floor under the water (--density 1200: they stay there),
so the film model works every substep.
"""

import json
import math
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import sweep  # noqa: E402

# A pool the size of assets/float.json's tank, walled by the domain box alone (a scene holds at
# most 64 colliders, so the 64-body run has no room for the tank).
POOL = {"min": [-0.37, 0.0, -0.22], "max": [0.37, 0.12, 0.22]}
DOMAIN = {"min": [-0.37, 0.0, -0.22], "max": [0.37, 0.6, 0.22]}
CRATE = 0.12  # [m] side of assets/crate.obj


def make_scene(bodies, spacing, resting=False, density=500):
    colliders = []
    if bodies:
        k = math.ceil(math.sqrt(bodies))
        cell_x, cell_z = 0.7 / k, 0.42 / k
        size = min(CRATE, 0.7 * min(cell_x, cell_z))
        for i in range(bodies):
            x = -0.35 + (i % k + 0.5) * cell_x
            z = -0.21 + (i // k + 0.5) * cell_z
            # Just above the water, or resting on the floor under it (their bottoms held by the
            # film model: docs/bodies.md, "The film under a body").
            y = 0.5 * size if resting else POOL["max"][1] + 0.6 * size + 0.01
            colliders.append({"asset": "crate.slc", "scale": size / CRATE,
                              "translation": [x, y, z], "dynamic": {"density": density}})
    return {"version": 1, "name": f"bodies-{bodies}",
            "simulation": {"spacing": spacing},
            "fluid": [{"box": POOL}],
            "colliders": colliders,
            "domain": DOMAIN}


def main():
    a, play, assets = sweep.parse_bench_args(
        __doc__, [("--bodies", dict(default="0,1,16,64")),
                  ("--spacing", dict(type=float, default=0.02)),
                  ("--resting", dict(action="store_true",
                                     help="crates start on the pool's floor, under the water")),
                  ("--density", dict(type=float, default=500.0, help="the crates' [kg/m^3]"))],
        warmup=30, steps=10, repeat=3, repeat_help="runs per body count, interleaved",
        results_name="pbf_bodies")
    counts = [int(c) for c in a.bodies.split(",")]
    runs = []
    for rep in range(a.repeat):
        for n in counts:
            scene = make_scene(n, a.spacing, a.resting, a.density)
            path = os.path.join(assets, f"bench-bodies-{n}.json")
            with open(path, "w") as f:
                json.dump(scene, f, indent=4)
            cmd, bench, wall, extra, error = sweep.run_bench(
                play, path, a.warmup, a.steps, path.replace(".json", ".bench.json"), 1800)
            if error:
                raise SystemExit(f"{n} bodies: {error}")
            passes = bench["medianPassMs"]
            rec = {"bodies": n, "repeat": rep, "stepMs": bench["medianStepMs"],
                   "bodiesPassMs": passes.get("bodies", 0.0), "solveMs": passes["solve"],
                   "particles": bench["particles"], "wallSeconds": wall,
                   "cpuSeconds": extra["cpuSeconds"], "loadBefore": extra["loadBefore"]}
            runs.append(rec)
            print(f"{n:3d} bodies rep {rep}: step {rec['stepMs']:8.2f} ms, solve "
                  f"{rec['solveMs']:8.2f}, body pass {rec['bodiesPassMs']:6.3f} ms, "
                  f"{rec['particles']} particles, load {extra['loadBefore'][0]:.1f}", flush=True)
    summary = []
    base = [r["stepMs"] for r in runs if r["bodies"] == 0]
    for n in counts:
        steps = [r["stepMs"] for r in runs if r["bodies"] == n]
        passes = [r["bodiesPassMs"] for r in runs if r["bodies"] == n]
        med = statistics.median(steps)
        row = {"bodies": n, "medianStepMs": med, "rangeStepMs": [min(steps), max(steps)],
               "medianBodiesPassMs": statistics.median(passes)}
        if base and n:
            row["stepOverFluidOnly"] = med / statistics.median(base)
            pairs = [r["stepMs"] / b["stepMs"] for r in runs if r["bodies"] == n
                     for b in runs if b["bodies"] == 0 and b["repeat"] == r["repeat"]]
            row["pairRatios"] = pairs
            row["medianPairRatio"] = statistics.median(pairs)
            row["rangePairRatio"] = [min(pairs), max(pairs)]
            row["couplingShareOfStep"] = 1.0 - statistics.median(base) / med
            row["bodyPassShareOfStep"] = row["medianBodiesPassMs"] / med
        summary.append(row)
        print(json.dumps(row))
    doc = {"what": "sluice-play --bench with dynamic bodies (tests/bench/pbf/bodies.py)",
           "date": sweep.utc_now(),
           "machineName": a.machine, "machine": sweep.machine_info(),
           "resting": a.resting, "density": a.density,
           "warmup": a.warmup, "steps": a.steps, "runs": runs, "summary": summary}
    sweep.write_results(a.out, doc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
