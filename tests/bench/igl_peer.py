#!/usr/bin/env python3
# Times libigl's signed_distance on the grid points of a bake_bench run (sign by the fast winding
# number unless --sign says otherwise). With the fast winding number libigl's distances are not
# the exact ones (up to ~0.1 voxel off on armadillo.off): the script prints how far off.
#
#   bake_bench MESH 64 128 --dump DIR      (writes DIR/grid_RES.txt and DIR/cgal_RES.f32)
#   python3 tests/bench/igl_peer.py MESH DIR 64 128
#
# Needs `pip install libigl`. Prints per resolution: seconds (best of --repeat runs, wall clock;
# libigl runs its queries on every core), max |phi_igl - phi_cgal| in voxels and the sign
# mismatches against CGAL (points where both are non-zero and disagree). Not a ctest test.
import argparse
import time

import igl
import numpy as np


SIGN_TYPES = {
    "fast_winding_number": igl.SIGNED_DISTANCE_TYPE_FAST_WINDING_NUMBER,
    "pseudonormal": igl.SIGNED_DISTANCE_TYPE_PSEUDONORMAL,
    "winding_number": igl.SIGNED_DISTANCE_TYPE_WINDING_NUMBER,
}


def grid_points(spec_path):
    with open(spec_path) as f:
        values = f.read().split()
    origin = np.array([float(v) for v in values[0:3]])
    voxel = float(values[3])
    dims = [int(v) for v in values[4:7]]
    # x fastest, as the asset stores points.
    k, j, i = np.meshgrid(np.arange(dims[2]), np.arange(dims[1]), np.arange(dims[0]),
                          indexing="ij")
    ijk = np.stack([i.ravel(), j.ravel(), k.ravel()], axis=1).astype(np.float64)
    return origin + ijk * voxel, voxel


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("mesh")
    parser.add_argument("dump_dir")
    parser.add_argument("resolutions", nargs="+", type=int)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--sign", choices=sorted(SIGN_TYPES), default="fast_winding_number")
    args = parser.parse_args()
    sign_type = SIGN_TYPES[args.sign]

    v, f = igl.read_triangle_mesh(args.mesh)
    v = np.ascontiguousarray(v, dtype=np.float64)
    f = np.ascontiguousarray(f, dtype=np.int64)
    print(f"mesh {args.mesh}: {len(f)} triangles; libigl signed_distance, sign: {args.sign}")
    print("| resolution | points | igl s | max err vs cgal [voxel] | sign mismatches |")
    print("|---|---|---|---|---|")
    for res in args.resolutions:
        points, voxel = grid_points(f"{args.dump_dir}/grid_{res}.txt")
        cgal = np.fromfile(f"{args.dump_dir}/cgal_{res}.f32", dtype="<f4").astype(np.float64)
        best = float("inf")
        for _ in range(max(1, args.repeat)):
            start = time.perf_counter()
            s, _, _, _ = igl.signed_distance(points, v, f, sign_type=sign_type)
            best = min(best, time.perf_counter() - start)
        error = np.max(np.abs(s - cgal)) / voxel
        mismatches = int(np.count_nonzero((s != 0) & (cgal != 0) & ((s < 0) != (cgal < 0))))
        print(f"| {res} | {len(points)} | {best:.3f} | {error:.2g} | {mismatches} |", flush=True)


if __name__ == "__main__":
    main()
