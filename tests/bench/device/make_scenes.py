#!/usr/bin/env python3
"""Writes the scenes the GPU floors of the performance issue are measured on, with their
colliders beside them, into one folder that travels to the GPU machine (.devpack/scenes).

    python3 tests/bench/device/make_scenes.py --assets BUILD/assets --out .devpack/scenes

Scenes (same geometry as assets/wave-sphere.json and assets/dam-break.json; sweep.py picks the
spacing that fills the block with the wanted count):

  wave-sphere-15k.json       the paper's scene size, shipped defaults (adaptive iterations):
                             the ">= 3,000 steps/s at 15,000 particles" floor
  wave-sphere-15k-max3.json  the same with maxIterations 3: the early stop at 2 issues no
                             idle dispatches, so the difference is what the 10 idle ones cost
  dam-break-1m-4it.json      1,000,000 particles, exactly 4 iterations a substep
                             (minIterations = maxIterations = 4, targetDensityError = 0): the
                             "1M particles, 4 iterations, <= 4 ms per full step" floor, read per
                             substep (one solver step), and the 1M impostor render
  dam-break-1m.json          1,000,000 particles, shipped defaults
  bodies-N-sS.json           tests/bench/pbf/bodies.py's pool with N = 0, 1, 16, 64 floating
                             crates, at its llvmpipe spacing (2 cm, ~4,900 particles) and at
                             5 mm (~300,000 particles): the coupling's share of the step
  <every shipped scene>      assets/*.json as built, for running every shader on the driver

Colliders are named by file name, so the folder can live anywhere.
"""

import argparse
import glob
import json
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, os.path.join(HERE, "..", "pbf"))
from sweep import spacing_for  # noqa: E402  (the spacing rule of the sweep, shared)
from bodies import make_scene as make_bodies_scene  # noqa: E402  (the body bench's pool)


def write_scene(template, assets, out, name, target, simulation_extra, description):
    with open(os.path.join(ROOT, "assets", template)) as f:
        scene = json.load(f)
    box = scene["fluid"][0]["box"]
    spacing, count = spacing_for(box["min"], box["max"], target)
    scene["name"] = name
    scene["description"] = (f"{description} {count} particles at spacing {spacing} m; "
                            "written by tests/bench/device/make_scenes.py.")
    scene["simulation"]["spacing"] = spacing
    scene["simulation"].update(simulation_extra)
    for collider in scene.get("colliders", []):
        source = os.path.join(assets, collider["asset"])
        if not os.path.isfile(source):
            raise SystemExit(f"{source} is missing: build the sluice_assets target")
        shutil.copy2(source, os.path.join(out, os.path.basename(source)))
        collider["asset"] = os.path.basename(source)
    path = os.path.join(out, name + ".json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=4)
        f.write("\n")
    print(f"{path}: {count} particles, spacing {spacing}")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--assets", required=True, help="BUILD/assets: the built scenes and colliders")
    p.add_argument("--out", required=True, help="folder to write")
    args = p.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for scene in sorted(glob.glob(os.path.join(args.assets, "*.json"))):
        shutil.copy2(scene, args.out)
    for collider in sorted(glob.glob(os.path.join(args.assets, "*.slc"))):
        shutil.copy2(collider, args.out)
    write_scene("wave-sphere.json", args.assets, args.out, "wave-sphere-15k", 15_000, {},
                "The wave-with-sphere scene at the paper's size:")
    write_scene("wave-sphere.json", args.assets, args.out, "wave-sphere-15k-max3", 15_000,
                {"maxIterations": 3},
                "The wave-with-sphere scene at the paper's size, at most 3 iterations:")
    write_scene("dam-break.json", args.assets, args.out, "dam-break-1m-4it", 1_000_000,
                {"minIterations": 4, "maxIterations": 4, "targetDensityError": 0},
                "Dam break, exactly 4 solver iterations a substep:")
    write_scene("dam-break.json", args.assets, args.out, "dam-break-1m", 1_000_000, {},
                "Dam break, shipped solver defaults:")
    for spacing, tag in ((0.02, "s20mm"), (0.005, "s5mm")):
        for bodies in (0, 1, 16, 64):
            path = os.path.join(args.out, f"bodies-{bodies}-{tag}.json")
            with open(path, "w") as f:
                json.dump(make_bodies_scene(bodies, spacing), f, indent=4)
                f.write("\n")
            print(f"{path}: {bodies} crates, spacing {spacing}")


if __name__ == "__main__":
    main()
