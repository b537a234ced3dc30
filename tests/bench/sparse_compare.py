#!/usr/bin/env python3
"""Sparse bakes against their peers, whole processes, in one interleaved run.

    python3 tests/bench/sparse_compare.py MESH [--bin build/dev/bin] [--sizes 256 512 1024]
                                               [--repeat 3] [--band 3] [--skip-cgal-above N]

For each size, each repeat runs, one after the other (interleaved, so drifting load hits all of
them alike): `sluice-bake bake --sparse` on the GPU and with CGAL, OpenVDB's `meshToLevelSet`
at the same voxel size and band (`sparse_bench`), and where the grid fits a dense GPU bake, the
dense GPU bake of the same grid. Every run is a whole process under `/usr/bin/time`: wall seconds
and maximum resident set. Prints the machine (CPU model, load before and after), then one row per
run kind with the median and range, and the ratios of the medians. Not a ctest test.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile


def timed(cmd):
    """Wall seconds, peak resident MiB and stdout of one process."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as t:
        run = subprocess.run(["/usr/bin/time", "-f", "%e %M", "-o", t.name] + cmd,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if run.returncode != 0:
            sys.exit(f"failed ({run.returncode}): {' '.join(cmd)}\n{run.stderr[-2000:]}")
        wall, kib = t.read().split()[-2:]
    return float(wall), int(kib) / 1024.0, run.stdout


def cpu_model():
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return "unknown"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh")
    ap.add_argument("--bin", default="build/dev/bin")
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--band", type=float, default=3.0)
    ap.add_argument("--skip-cgal-above", type=int, default=0,
                    help="leave out the CGAL sparse bake above this size (it is the slow one)")
    args = ap.parse_args()
    bake = os.path.join(args.bin, "sluice-bake")
    vdb = os.path.join(args.bin, "sparse_bench")
    out = tempfile.mkdtemp(prefix="sparse-compare-")
    band = f"{args.band:g}"

    print(f"machine: {cpu_model()}, {os.cpu_count()} logical CPUs; "
          f"load before {os.getloadavg()[0]:.2f}")
    results = {}  # (size, kind) -> list of (wall, MiB)
    info = {}
    for size in args.sizes:
        kinds = {
            "sparse gpu": [bake, "bake", args.mesh, "-o", f"{out}/g{size}.slc", "--sparse",
                           "--band", band, "--resolution", str(size), "--backend", "gpu",
                           "--quiet", "--json"],
            "openvdb meshToLevelSet": [vdb, args.mesh, "--resolution", str(size), "--band", band],
        }
        if not args.skip_cgal_above or size <= args.skip_cgal_above:
            kinds["sparse cgal"] = [bake, "bake", args.mesh, "-o", f"{out}/c{size}.slc",
                                    "--sparse", "--band", band, "--resolution", str(size),
                                    "--backend", "cgal", "--quiet", "--json"]
        # The dense GPU bake of the same grid (the sparse padding), where llvmpipe's largest
        # storage block holds it: tried once, left out if refused.
        dense = [bake, "bake", args.mesh, "-o", f"{out}/d{size}.slc", "--resolution", str(size),
                 "--padding", f"{max(4.0, float(int(args.band + 0.999999)) + 1):g}", "--backend",
                 "gpu", "--quiet", "--json"]
        if subprocess.run(dense, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode == 0:
            kinds["dense gpu"] = dense
        for r in range(args.repeat):
            for kind, cmd in kinds.items():
                wall, mib, stdout = timed(cmd)
                results.setdefault((size, kind), []).append((wall, mib))
                if r == 0 and kind.startswith("sparse"):
                    j = json.loads(stdout)
                    info[(size, kind)] = j.get("sparse", {})
        print(f"  size {size} done, load {os.getloadavg()[0]:.2f}", flush=True)
    print(f"load after {os.getloadavg()[0]:.2f}\n")

    print("| run | wall s, median (range) | peak memory, MiB, median | bricks |")
    print("|---|---|---|---|")
    med = {}
    for (size, kind), runs in results.items():
        walls = [w for w, _ in runs]
        mibs = [m for _, m in runs]
        med[(size, kind)] = (statistics.median(walls), statistics.median(mibs))
        bricks = info.get((size, kind), {}).get("bricks", "")
        print(f"| {kind}, {size} | {statistics.median(walls):.2f} ({min(walls):.2f}-"
              f"{max(walls):.2f}) | {statistics.median(mibs):.0f} | {bricks} |")
    print()
    for size in args.sizes:
        g = med.get((size, "sparse gpu"))
        for peer in ("sparse cgal", "openvdb meshToLevelSet", "dense gpu"):
            p = med.get((size, peer))
            if g and p:
                print(f"size {size}: {peer} / sparse gpu = {p[0] / g[0]:.2f}x the time, "
                      f"{p[1] / g[1]:.2f}x the memory")


if __name__ == "__main__":
    main()
