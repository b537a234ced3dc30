#!/usr/bin/env python3
"""What the solids' boundary volume costs (docs/pbf.md, "Boundary volume"): sluice-play --bench
on still water in float.json's baked tank (assets/tank.slc, a static collider) and in a tank that
is only the domain box, with "boundary": "bodies" (the default) and "solids", interleaved and
repeated. The cost is the median GPU step with "solids" over the one with "bodies" of the same
tank. Results: docs/results/pbf_boundary_cost_<machine>.json.

    python3 tests/bench/pbf/boundary_cost.py --build build/dev --repeat 5
"""

import json
import os
import statistics
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import sweep  # noqa: E402

TANKS = {
    # name: (water box, colliders, domain), as tests/bench/pbf/still_water.py's tanks
    "baked": ({"min": [-0.37, 0.03, -0.22], "max": [0.37, 0.19, 0.22]}, [{"asset": "tank.slc"}],
              {"min": [-0.5, 0.0, -0.35], "max": [0.5, 0.7, 0.35]}),
    "box": ({"min": [0.0, 0.0, 0.0], "max": [0.3, 0.16, 0.3]}, [],
            {"min": [0, 0, 0], "max": [0.3, 0.4, 0.3]}),
}
MODELS = ("bodies", "solids")


def make_scene(tank, model, spacing, solids_target=None):
    water, colliders, domain = TANKS[tank]
    sim = {"spacing": spacing, "boundary": model}
    if model == "solids" and solids_target is not None:
        sim["targetDensityError"] = solids_target
    return {"version": 1, "name": f"boundary-{tank}-{model}",
            "simulation": sim,
            "fluid": [{"box": water}], "colliders": colliders, "domain": domain}


def main():
    a, play, assets = sweep.parse_bench_args(
        __doc__, [("--tanks", dict(default="baked,box")),
                  ("--spacing", dict(type=float, default=0.02)),
                  ("--solids-target", dict(type=float, help="targetDensityError of the solids "
                                           "runs (default: the scene default, 0.005)"))],
        warmup=60, steps=30, repeat=5, repeat_help="runs per tank and model, interleaved",
        results_name="pbf_boundary_cost")
    tanks = a.tanks.split(",")
    runs = []
    for rep in range(a.repeat):
        for tank in tanks:
            for model in MODELS:
                path = os.path.join(assets, f"bench-boundary-{tank}-{model}.json")
                with open(path, "w") as f:
                    json.dump(make_scene(tank, model, a.spacing, a.solids_target), f, indent=4)
                try:
                    cmd, bench, wall, extra, error = sweep.run_bench(
                        play, path, a.warmup, a.steps, path.replace(".json", ".bench.json"),
                        1800)
                finally:
                    os.remove(path)
                if error:
                    raise SystemExit(f"{tank} {model}: {error}")
                rec = {"tank": tank, "boundary": model, "repeat": rep,
                       "iterations": bench["meanIterations"],
                       "stepMs": bench["medianStepMs"], "solveMs": bench["medianPassMs"]["solve"],
                       "particles": bench["particles"], "wallSeconds": wall,
                       "loadBefore": extra["loadBefore"]}
                runs.append(rec)
                print(f"{tank:5s} {model:6s} rep {rep}: step {rec['stepMs']:8.2f} ms, solve "
                      f"{rec['solveMs']:8.2f} ms, {rec['iterations']:.2f} iterations, {rec['particles']} particles, load "
                      f"{extra['loadBefore'][0]:.1f}", flush=True)
    summary = []
    for tank in tanks:
        med = {}
        for model in MODELS:
            steps = [r["stepMs"] for r in runs if r["tank"] == tank and r["boundary"] == model]
            med[model] = statistics.median(steps)
            summary.append({"tank": tank, "boundary": model, "medianStepMs": med[model],
                            "rangeStepMs": [min(steps), max(steps)]})
        summary[-1]["solidsOverBodies"] = med["solids"] / med["bodies"]
        print(json.dumps(summary[-2]))
        print(json.dumps(summary[-1]))
    doc = {"what": "sluice-play --bench, still water, boundary bodies vs solids "
                   "(tests/bench/pbf/boundary_cost.py)",
           "date": sweep.utc_now(), "machineName": a.machine, "machine": sweep.machine_info(),
           "solidsTarget": a.solids_target,
           "warmup": a.warmup, "steps": a.steps, "runs": runs, "summary": summary}
    sweep.write_results(a.out, doc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
