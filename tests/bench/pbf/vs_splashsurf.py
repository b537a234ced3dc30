#!/usr/bin/env python3
"""Sluice's GPU surface meshes against splashsurf's, on the same particles in the same process.

Both reconstruct the fluid surface of the same (N, 3) float positions: Sluice with
``sluice.reconstruct_surface`` at its defaults (docs/surfaces.md: a density-normalised colour
field as wide as poly6 of support 4 r, as splashsurf's is, Gaussian by default, ``--kernel
poly6`` for poly6 itself, ``--no-normalised`` for the rest-volume field, on a sparse grid of
cell r, contoured by marching cubes at iso 0.6, or 0.5 without the normalisation, on the GPU:
llvmpipe here, in a headless context kept from the first call), splashsurf (pip install
pysplashsurf) with ``reconstruction_pipeline`` at its documented settings for SPH data of the
same particle radius r: smoothing length 2 r (support 4 r, the same as Sluice's), cube size r
(the same as Sluice's cell), its default iso threshold 0.6 of its density-normalised colour
field, multi-threaded over the same cores, no post-processing.

Figures, for each particle set:
  - time: the whole call on each side, --repeat runs interleaved (Sluice, splashsurf, ...),
    each timed call right after an untimed one of the same side, so that neither pays for the
    other's threads (splashsurf's rayon pool keeps its workers busy-waiting a while after a
    call: a Sluice call timed straight after one took up to 1.5x as long as after its own);
    median and min-max; the ratio is
    splashsurf's median over Sluice's (> 1: Sluice faster);
  - volume: each mesh's enclosed volume (divergence theorem), and their ratio;
  - distance: from every vertex of one mesh to the other mesh's surface (exact point-triangle
    distance to the 16 triangles whose centroids are nearest), both ways, as median, 95th
    percentile and maximum, in particle radii;
  - closed and manifold: every directed edge once and its reverse once (both meshes).

Usage (repository root, after building the dev preset with Python):

    python3 -m venv /tmp/ssurf && /tmp/ssurf/bin/pip install pysplashsurf numpy scipy
    PYTHONPATH=build/dev/python /tmp/ssurf/bin/python tests/bench/pbf/vs_splashsurf.py \
        --repeat 5 --json docs/results/surface_vs_splashsurf_llvmpipe.json
"""

import argparse
import json
import os
import platform
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))

SPACING = 0.02
RADIUS = 0.5 * SPACING


def lattice(n):
    """Lattice points ((i + 1/2) s) of an n[0] x n[1] x n[2] block."""
    axes = [(np.arange(k) + 0.5) * SPACING for k in n]
    return np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)


def particle_sets(build):
    import sluice
    rng = np.random.default_rng(7)
    block = lattice((32, 32, 16))
    ball = lattice((20, 20, 20)) - 10 * SPACING
    ball = ball[np.linalg.norm(ball, axis=1) < 0.19]
    jittered = lattice((64, 64, 32)) + rng.normal(0.0, 0.1 * SPACING, (64 * 64 * 32, 3))
    sim = sluice.Simulation(os.path.join(ROOT, build, "assets", "dam-break.json"),
                            deterministic=True)
    sim.step(60, progress=False)
    return [("block 32x32x16", block), ("ball r = 0.19 m", ball),
            ("dam-break step 60", sim.positions.astype(np.float64)),
            ("jittered block 64x64x32", jittered)]


OPTIONS = {"anisotropic": False, "kernel": "gaussian", "normalised": None}  # set by the flags


def sluice_mesh(points):
    import sluice
    m = sluice.reconstruct_surface(points.astype(np.float32), RADIUS, **OPTIONS)
    return m.vertices.astype(np.float64), m.triangles.astype(np.int64)


def splashsurf_mesh(points):
    import pysplashsurf
    mesh, _ = pysplashsurf.reconstruction_pipeline(
        points.astype(np.float64), particle_radius=RADIUS, smoothing_length=2.0, cube_size=1.0,
        iso_surface_threshold=0.6, multi_threading=True)
    return np.asarray(mesh.mesh.vertices, np.float64), np.asarray(mesh.mesh.triangles, np.int64)


def volume(v, t):
    return float(np.einsum("ij,ij->", v[t[:, 0]], np.cross(v[t[:, 1]], v[t[:, 2]])) / 6.0)


def closed_manifold(t):
    """Every directed edge once and its reverse once."""
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    key = e[:, 0] * (int(e.max()) + 1) + e[:, 1]
    rev = e[:, 1] * (int(e.max()) + 1) + e[:, 0]
    unique = np.unique(key)
    return bool(len(unique) == len(key) and np.isin(rev, unique).all())


def point_triangle_distance(p, a, b, c):
    """Distance from points p (N, 3) to triangles (a, b, c) (N, 3) each (Ericson 2005, 5.1.5)."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v, w = vb / denom, vc / denom
        q = a + ab * v[:, None] + ac * w[:, None]  # inside the face
        # Edges and corners where the face's barycentrics leave [0, 1].
        t_ab = np.clip(d1 / (d1 - d3), 0, 1)
        t_ac = np.clip(d2 / (d2 - d6), 0, 1)
        t_bc = np.clip((d4 - d3) / ((d4 - d3) + (d5 - d6)), 0, 1)
    cand = [q, a + ab * np.nan_to_num(t_ab)[:, None], a + ac * np.nan_to_num(t_ac)[:, None],
            b + (c - b) * np.nan_to_num(t_bc)[:, None], a, b, c]
    inside = (va >= 0) & (vb >= 0) & (vc >= 0) & (denom > 0)
    dist = np.full(len(p), np.inf)
    for k, x in enumerate(cand):
        d = np.linalg.norm(p - x, axis=1)
        if k == 0:
            d = np.where(inside, d, np.inf)
        dist = np.minimum(dist, d)
    return dist


def distances(points, v, t, k=16):
    """Distance from each of `points` to the mesh (v, t)."""
    from scipy.spatial import cKDTree
    centroids = (v[t[:, 0]] + v[t[:, 1]] + v[t[:, 2]]) / 3.0
    _, near = cKDTree(centroids).query(points, k=k)
    best = np.full(len(points), np.inf)
    for j in range(k):
        tri = t[near[:, j]]
        best = np.minimum(best, point_triangle_distance(points, v[tri[:, 0]], v[tri[:, 1]],
                                                        v[tri[:, 2]]))
    return best


def summary(values):
    return {"median": float(np.median(values)), "min": float(np.min(values)),
            "max": float(np.max(values))}


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


def compare(name, points, repeat):
    times = {"sluice": [], "splashsurf": []}
    meshes = {}
    for _ in range(repeat):
        for side, fn in (("sluice", sluice_mesh), ("splashsurf", splashsurf_mesh)):
            fn(points)  # untimed: the timed call below does not pay for the other side's threads
            start = time.perf_counter()
            meshes[side] = fn(points)
            times[side].append(time.perf_counter() - start)
    (sv, st), (pv, pt) = meshes["sluice"], meshes["splashsurf"]
    to_splash = distances(sv, pv, pt) / RADIUS
    to_sluice = distances(pv, sv, st) / RADIUS
    row = {
        "set": name, "particles": int(len(points)),
        "seconds": {side: summary(v) for side, v in times.items()},
        "speedup": float(np.median(times["splashsurf"]) / np.median(times["sluice"])),
        "speedupRange": [float(min(times["splashsurf"]) / max(times["sluice"])),
                         float(max(times["splashsurf"]) / min(times["sluice"]))],
        "triangles": {"sluice": int(len(st)), "splashsurf": int(len(pt))},
        "volume": {"sluice": volume(sv, st), "splashsurf": volume(pv, pt)},
        "closedManifold": {"sluice": closed_manifold(st), "splashsurf": closed_manifold(pt)},
        "distanceRadii": {
            "sluiceToSplashsurf": {"median": float(np.median(to_splash)),
                                   "p95": float(np.percentile(to_splash, 95)),
                                   "max": float(to_splash.max())},
            "splashsurfToSluice": {"median": float(np.median(to_sluice)),
                                   "p95": float(np.percentile(to_sluice, 95)),
                                   "max": float(to_sluice.max())}},
    }
    row["volumeRatio"] = row["volume"]["sluice"] / row["volume"]["splashsurf"]
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build/dev")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", default="")
    ap.add_argument("--anisotropic", action="store_true",
                    help="Sluice with anisotropic kernels (default centre smoothing)")
    ap.add_argument("--kernel", choices=("gaussian", "poly6"), default="gaussian",
                    help="Sluice's isotropic kernel (docs/surfaces.md, 'The field')")
    ap.add_argument("--normalised", action="store_true", default=None,
                    help="Sluice's density-normalised field, splashsurf's convention (iso 0.6; "
                    "the default but with --anisotropic)")
    ap.add_argument("--no-normalised", dest="normalised", action="store_false",
                    help="Sluice's rest-volume field (iso 0.5)")
    args = ap.parse_args()
    OPTIONS["normalised"] = args.normalised
    OPTIONS["anisotropic"] = args.anisotropic
    OPTIONS["kernel"] = args.kernel
    import sluice
    import pysplashsurf  # noqa: F401
    load = os.getloadavg()
    rows = [compare(name, pts, args.repeat) for name, pts in particle_sets(args.build)]
    print(f"{'set':26s} {'particles':>9s} {'Sluice s':>16s} {'splashsurf s':>16s} {'ratio':>6s}"
          f" {'V ratio':>8s} {'dist med/p95/max [r]':>22s} closed")
    for r in rows:
        s, p = r["seconds"]["sluice"], r["seconds"]["splashsurf"]
        d = r["distanceRadii"]["sluiceToSplashsurf"]
        print(f"{r['set']:26s} {r['particles']:9d} {s['median']:7.3f} ({s['min']:.3f}-{s['max']:.3f})"
              f" {p['median']:7.3f} ({p['min']:.3f}-{p['max']:.3f}) {r['speedup']:6.2f}"
              f" {r['volumeRatio']:8.4f} {d['median']:6.3f}/{d['p95']:.3f}/{d['max']:.3f}"
              f"   {r['closedManifold']['sluice']}/{r['closedManifold']['splashsurf']}")
    result = {
        "date": time.strftime("%Y-%m-%d %H:%M"), "cpu": cpu_model(), "cores": os.cpu_count(),
        "loadBefore": load, "loadAfter": os.getloadavg(), "repeat": args.repeat,
        "sluice": sluice.tool_version(), "renderer": "llvmpipe (no GPU) unless stated",
        "particleRadius": RADIUS, "sluiceOptions": dict(OPTIONS), "rows": rows,
    }
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()
