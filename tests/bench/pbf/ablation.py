#!/usr/bin/env python3
"""Scene-knob ablations of sluice-play --bench: what the idle solver iterations, each extra
iteration and the vorticity pass cost, measured with the shipped solver (no code change).

Runs the dam break at one particle count (default 10k) with:
  base       the defaults (min 2, max 8 iterations, targetDensityError 0.005)
  max2       maxIterations 2: the same 2 iterations, without the 6 idle ones that the solve
             loop still dispatches after the early stop (empty lambda + copying delta)
  fixed8     targetDensityError 0: all 8 iterations do work
  novort     vorticity 0: the vorticity pass is skipped (confine/XSPH still runs)
and prints per-pass medians, wall and CPU seconds. Results: docs/results/pbf_ablation_<machine>.json.

    python3 tests/bench/pbf/ablation.py --build build/h-perf
"""

import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import sweep  # noqa: E402

VARIANTS = {
    "base": {},
    "max2": {"maxIterations": 2},
    "fixed8": {"targetDensityError": 0.0},
    "novort": {"vorticity": 0.0},
}


def main():
    a, play, assets = sweep.parse_bench_args(
        __doc__, [("--particles", dict(type=int, default=10000))], warmup=10, steps=10, repeat=2,
        repeat_help="runs per variant, interleaved", results_name="pbf_ablation")
    work = os.path.join(assets, "pbf-ablation")
    runs = []
    for rep in range(a.repeat):
        for name, knobs in VARIANTS.items():
            path, spacing, count, scene = sweep.make_scene(os.path.join(assets, "dam-break.json"),
                                                           assets, work, a.particles)
            scene["simulation"].update(knobs)
            scene["name"] = f"dam-break-{a.particles}-{name}"
            path = os.path.join(work, scene["name"] + ".json")
            with open(path, "w") as f:
                json.dump(scene, f, indent=4)
            cmd, bench, wall, extra, error = sweep.run_bench(
                play, path, a.warmup, a.steps, os.path.join(work, scene["name"] + ".bench.json"),
                timeout=1800)
            if error:
                raise SystemExit(f"{name}: {error}")
            rec = {"variant": name, "repeat": rep, "knobs": knobs, "warmup": a.warmup,
                   "steps": a.steps, "bench": bench,
                   **{k: v for k, v in extra.items() if k != "stdout"}}
            rec.update(sweep.cpu_normalised(rec))
            runs.append(rec)
            passes = bench["medianPassMs"]
            print(f"{name:7s} rep {rep}: step {bench['medianStepMs']:8.1f} ms  solve "
                  f"{passes['solve']:8.1f}  vort+xsph {passes['vorticity+xsph']:7.1f}  "
                  f"it {bench['meanIterations']:.2f}  cpu/step {rec['cpuSecondsPerStep']:.3f} s  "
                  f"load {extra['loadBefore'][0]:.1f}", flush=True)
    doc = {"what": "sluice-play --bench knob ablations (tests/bench/pbf/ablation.py)",
           "date": sweep.utc_now(),
           "machineName": a.machine, "machine": sweep.machine_info(),
           "particles": a.particles, "runs": runs}
    doc["machine"]["renderer"] = runs[0]["bench"]["renderer"] if runs else None
    sweep.write_results(a.out, doc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
