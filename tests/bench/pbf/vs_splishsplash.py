#!/usr/bin/env python3
"""Sluice's PBF against SPlisHSPlasH's PBF: same dam break, same particle count, same time step,
same 2 cores, one script, compared at matched average density error.

Both solvers run the dam break of assets/dam-break.json: the 0.3 x 0.3 x 0.43 m block released
in the 0.74 x 0.44 m tank, on the same particle lattice (the block is filled at the same spacing
s; kernel support h = 2 s, poly6 density and spiky gradient on both sides, which is
SPlisHSPlasH's own choice for PBF), with Sluice's substep dt as SPlisHSPlasH's fixed time step
(no CFL), min 2 / max 8 solver iterations on both sides, XSPH and vorticity confinement on both
sides. For each error target the script
runs sluice-play --bench and then SPlisHSPlasH (pip install pysplishsplash) in a subprocess,
back to back, each over the same simulated time window, and prints a table and the throughput
ratio at matched error.

Density error, the same formula on both sides: the mean over fluid particles of the clamped
compression max(rho_i / rho0 - 1, 0) after the step's last solver iteration.
  - Sluice: sluice-play --bench's avgDensityError (docs/pbf.md: E_k of the last iteration of the
    last substep of each measured step, averaged over the measured steps); early stop when
    E_k <= simulation.targetDensityError.
  - SPlisHSPlasH (TimeStepPBF): stops when mean(rho0 * max(rho/rho0 - 1, 0)) <= maxError% * rho0,
    checked before an iteration's position update, so maxError = 100 * targetDensityError is
    the same stopping rule. The script recomputes the achieved error the way its solver does
    (its kernel, fluid particles plus its boundary particles with their volumes, Akinci et al.
    2012) from the positions after the last step of every measured 1/60 s frame, as Sluice
    reports the last substep of each step.

Repeats: each target runs --repeat times, the two sides interleaved (Sluice, SPlisHSPlasH,
Sluice, ...), and every figure is reported as the median with the min-max range of the runs.
The ratio at a target is the ratio of the medians, with the range from the extremes (slowest
Sluice run over fastest SPlisHSPlasH run, and the reverse). The ratio is taken at measured
points, the same target on both sides, with each side's achieved error stated next to it (no
interpolation). Each run records the load average before and after it; the results file
records the CPU model and its SIMD flags (avx2, avx512*, fma).

Usage (repository root, after building sluice-play and the demo colliders):

    python3 -m venv /tmp/sph && /tmp/sph/bin/pip install pysplishsplash
    python3 tests/bench/pbf/vs_splishsplash.py --build build/h-perf --splishsplash-python /tmp/sph/bin/python
    python3 tests/bench/pbf/vs_splishsplash.py ... --particles 10000 --targets 0.005,0.0025 --repeat 3

The pysplishsplash 2.19 wheel bundles its own libGLdispatch, which crashes on import next to
Debian 12's libGLX (SIGSEGV in __glDispatchInit); the worker preloads the system
libGLdispatch.so.0, which avoids it (--no-preload turns that off).
"""

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, HERE)

import sweep  # noqa: E402  (spacing_for, block_count, machine_info)

SYSTEM_GLDISPATCH = "/lib/x86_64-linux-gnu/libGLdispatch.so.0"

# The tank of assets/make_meshes.py: interior x in [-0.37, 0.37], z in [-0.22, 0.22], floor at
# y = 0.03; sluice-play clamps into the domain box (top at y = 0.7), so SPlisHSPlasH gets a closed
# box up to 0.7.
TANK_MIN = (-0.37, 0.03, -0.22)
TANK_MAX = (0.37, 0.70, 0.22)


# The fluid's SPlisHSPlasH material: XSPH viscosity 0.01 and vorticity confinement 0.01, as
# Sluice's scenes have them.
FLUID_MATERIAL = {"id": "Fluid", "density0": 1000, "viscosityMethod": 2, "viscosity": 0.01,
                  "vorticityMethod": 2, "vorticity": 0.01}


# --------------------------------------------------------------------------------------------
# SPlisHSPlasH worker (runs in its own process: OMP_NUM_THREADS and the preload must be set
# before the module loads, and SPlisHSPlasH keeps global state).
# --------------------------------------------------------------------------------------------

def cubic_w(r, h):
    """SPlisHSPlasH's 3D cubic spline kernel (CubicKernel::W; its precomputed variant tabulates
    the same function)."""
    k = 8.0 / (np.pi * h ** 3)
    q = r / h
    return np.where(q <= 0.5, k * (6.0 * q ** 3 - 6.0 * q ** 2 + 1.0),
                    np.where(q <= 1.0, k * 2.0 * (1.0 - q) ** 3, 0.0))


def poly6_w(r, h):
    """Poly6 (Mueller et al. 2003), SPlisHSPlasH's Poly6Kernel::W."""
    return np.where(r < h, 315.0 / (64.0 * np.pi * h ** 9) * (h * h - r * r) ** 3, 0.0)


# SPlisHSPlasH's kernel enum (Simulation::KERNEL_METHOD) -> W(r, h).
SPH_KERNELS = {0: cubic_w, 2: poly6_w, 4: cubic_w}


def sph_density_ratio(xq, xs, vs, h, kernel=cubic_w):
    """sum_j V_j W(|xq_i - xs_j|) over source points within h (self included when xq is in xs),
    by a uniform grid of cell size h."""
    cells_s = np.floor(xs / h).astype(np.int64)
    key_s = (cells_s[:, 0] + 65536) * (1 << 42) + (cells_s[:, 1] + 65536) * (1 << 21) + \
        (cells_s[:, 2] + 65536)
    order = np.argsort(key_s, kind="stable")
    skey = key_s[order]
    xs_sorted, vs_sorted = xs[order], vs[order]
    cells_q = np.floor(xq / h).astype(np.int64)
    out = np.zeros(len(xq))
    for dz in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                c = cells_q + np.array([dx, dy, dz])
                k = (c[:, 0] + 65536) * (1 << 42) + (c[:, 1] + 65536) * (1 << 21) + (c[:, 2] + 65536)
                lo = np.searchsorted(skey, k, "left")
                cnt = np.searchsorted(skey, k, "right") - lo
                for w in range(int(cnt.max()) if len(cnt) else 0):
                    i = np.nonzero(cnt > w)[0]
                    j = lo[i] + w
                    r = np.linalg.norm(xq[i] - xs_sorted[j], axis=1)
                    out[i] += vs_sorted[j] * kernel(r, h)
    return out


def splishsplash_unit_box(python):
    """The unit cube OBJ the pysplishsplash wheel of `python` ships (the tank's mesh, scaled)."""
    probe = subprocess.run([python, "-c", "import sys, pysplishsplash; print(sys.prefix)"],
                           capture_output=True, text=True,
                           env=dict(os.environ, LD_PRELOAD=SYSTEM_GLDISPATCH))
    if probe.returncode != 0:
        raise SystemExit("pysplishsplash does not import with " + python + ":\n" +
                         probe.stderr[-2000:])
    unit_box = os.path.join(probe.stdout.strip(), "bin", "data", "models", "UnitBox.obj")
    if not os.path.isfile(unit_box):
        raise SystemExit(f"{unit_box} not found (it ships in the pysplishsplash wheel)")
    return unit_box


def start_splishsplash(sph, scene, work_dir, name):
    """Writes SPlisHSPlasH scene `scene` as work_dir/name.json and initialises a simulator on it
    without a GUI, cache or output files; returns the SimulatorBase."""
    os.makedirs(work_dir, exist_ok=True)
    scene_path = os.path.join(work_dir, name + ".json")
    with open(scene_path, "w") as f:
        json.dump(scene, f, indent=2)
    base = sph.Exec.SimulatorBase()
    base.init(sceneFile=scene_path, useGui=False, useCache=False, initialPause=False,
              outputDir=os.path.join(work_dir, name + "-out"), stopAt=-1.0)
    base.initSimulation()
    return base


def splishsplash_worker(cfg):
    import pysplishsplash as sph

    s = cfg["spacing"]
    r = 0.5 * s
    lo, counts = cfg["blockMin"], cfg["blockCounts"]
    # SPlisHSPlasH puts round(extent / 2r) - 1 particles per axis at min + 2r + j 2r: this box
    # gives exactly Sluice's lattice min + s (i + 0.5), i < n.
    start = [lo[a] - 0.5 * s for a in range(3)]
    end = [start[a] + (counts[a] + 1) * s for a in range(3)]
    # Sluice keeps particle centres r = s/2 inside the tank's SDF surface; an Akinci boundary
    # keeps them about one spacing from its boundary-particle layer. The SPlisHSPlasH box is the
    # tank interior grown by s/2 on every side, so the water has the same room on both sides and
    # the block's first layer (0.7 s from Sluice's wall at s = 2.5 cm) does not start inside the
    # boundary's support (which blows the block apart through the walls).
    grow = 0.5 * s
    lo_box = [TANK_MIN[a] - grow for a in range(3)]
    hi_box = [TANK_MAX[a] + grow for a in range(3)]
    centre = [0.5 * (lo_box[a] + hi_box[a]) for a in range(3)]
    size = [hi_box[a] - lo_box[a] for a in range(3)]
    scene = {
        "Configuration": {
            "particleRadius": r,
            "simulationMethod": 2,           # PBF
            "timeStepSize": cfg["dt"],
            "cflMethod": 0,                  # fixed time step
            "gravitation": [0, -9.81, 0],
            "boundaryHandlingMethod": 0,     # Akinci et al. 2012 boundary particles
            # No "kernel"/"gradKernel": SPlisHSPlasH's own choice for PBF, which is poly6 and
            # spiky (read back into the results), the same kernels as Sluice.
            "enableZSort": True,
            "pause": False,
            "enablePartioExport": False,
            "enableVTKExport": False,
            "PBF": {"minIterations": cfg["minIterations"], "maxIterations": cfg["maxIterations"],
                    "maxError": 100.0 * cfg["target"], "velocityUpdateMethod": 0},
        },
        "Materials": [FLUID_MATERIAL],
        "RigidBodies": [{"geometryFile": cfg["unitBox"], "translation": centre, "scale": size,
                         "isDynamic": False, "isWall": True, "mapInvert": True,
                         "mapThickness": 0.0, "mapResolution": [30, 30, 30], "samplingMode": 1}],
        "FluidBlocks": [{"denseMode": 0, "start": start, "end": end}],
    }
    base = start_splishsplash(sph, scene, cfg["workDir"], "splishsplash-dam-break")
    sim = sph.Simulation.getCurrent()
    ts = sim.getTimeStep()
    tm = sph.TimeManager.getCurrent()
    model = sim.getFluidModel(0)
    rho0 = model.getDensity0()
    warm, measured = cfg["warmupSteps"], cfg["measuredSteps"]
    state = {"k": 0, "wall": [], "cpu": [], "it": [], "err": [], "maxErr": [], "first": None}
    clock = [time.perf_counter(), time.process_time()]

    boundary = {}

    def boundary_particles():
        # Static boundary particles and their volumes; they exist only once runSimulation has
        # run SimulatorBase::deferredInit, so this is called from the first callback.
        if not boundary:
            bx, bv = [], []
            for b in range(sim.numberOfBoundaryModels()):
                bm = sim.getBoundaryModel(b)
                for i in range(bm.numberOfParticles()):
                    bx.append(bm.getPosition(i))
                    bv.append(bm.getVolume(i))
            boundary["x"] = np.array(bx, dtype=np.float64).reshape(-1, 3)
            boundary["v"] = np.array(bv, dtype=np.float64)
        return boundary["x"], boundary["v"]

    def on_step():
        # Time since the end of the previous callback: one SPlisHSPlasH step, nothing else.
        wall = time.perf_counter() - clock[0]
        cpu = time.process_time() - clock[1]
        k = state["k"]
        sample = k == 0 or (k >= warm and (k - warm) % cfg["errorEvery"] == cfg["errorEvery"] - 1)
        if sample:
            # The density TimeStepPBF's solver sees, recomputed from the positions after the
            # step: its kernel, fluid and boundary particles with their volumes. (The "density"
            # field is not it: TimeStep::computeDensities in this AVX build always uses the
            # cubic spline, whatever kernel the solver uses.)
            n = model.numActiveParticles()
            x = np.asarray(model.getFieldBuffer("position"))[:n].astype(np.float64)
            boundary_x, boundary_v = boundary_particles()
            rho = sph_density_ratio(x, np.concatenate([x, boundary_x]),
                                    np.concatenate([np.full(n, model.getVolume(0)), boundary_v]),
                                    sim.getSupportRadius(),
                                    SPH_KERNELS[sim.getValueInt(sph.Simulation.KERNEL_METHOD)])
            c = np.maximum(rho - 1.0, 0.0)
            if k == 0:
                state["first"] = {"meanDensityRatio": float(rho.mean()),
                                  "avgDensityError": float(c.mean())}
            else:
                state["err"].append(float(c.mean()))
                state["maxErr"].append(float(c.max()))
        if k >= warm:
            state["wall"].append(wall)
            state["cpu"].append(cpu)
            state["it"].append(ts.getNumIterations())
        state["k"] = k + 1
        clock[0], clock[1] = time.perf_counter(), time.process_time()

    base.setTimeStepCB(on_step)
    base.setValueFloat(base.STOP_AT, (warm + measured - 0.5) * cfg["dt"])
    clock[0], clock[1] = time.perf_counter(), time.process_time()
    base.runSimulation()  # runs SPlisHSPlasH's own no-GUI loop until stopAt
    n = model.numActiveParticles()
    steps = len(state["wall"])
    wall = sum(state["wall"])
    iters = sum(state["it"])
    return {
        "solver": "SPlisHSPlasH PBF (pysplishsplash %s)" % getattr(sph, "__version__", "2.19"),
        "particles": n,
        "boundaryParticles": len(boundary_particles()[1]),
        "volume": model.getVolume(0),
        "firstStep": state["first"],
        "dt": tm.getTimeStepSize(),
        "kernel": sim.getValueInt(sph.Simulation.KERNEL_METHOD),
        "gradKernel": sim.getValueInt(sph.Simulation.GRAD_KERNEL_METHOD),
        "minIterations": ts.getValueInt(sph.TimeStepPBF.MIN_ITERATIONS),
        "maxIterations": ts.getValueInt(sph.TimeStepPBF.MAX_ITERATIONS),
        "maxErrorPercent": ts.getValueFloat(sph.TimeStepPBF.MAX_ERROR),
        "measuredSteps": steps,
        "wallSeconds": wall,
        "cpuSeconds": sum(state["cpu"]),
        "meanIterations": iters / max(steps, 1),
        "avgDensityError": sum(state["err"]) / max(len(state["err"]), 1),
        "errorSamples": len(state["err"]),
        "maxDensityError": max(state["maxErr"]) if state["maxErr"] else None,
        "stepsPerSecond": steps / wall if wall > 0 else 0.0,
        "stepsPerCpuSecond": steps / sum(state["cpu"]) if state["cpu"] else 0.0,
        "particleIterationsPerCpuSecond": n * iters / sum(state["cpu"]) if state["cpu"] else 0.0,
        "particleIterationsPerSecond": n * iters / wall if wall > 0 else 0.0,
        "medianStepMs": 1e3 * sorted(state["wall"])[steps // 2] if steps else None,
    }


# --------------------------------------------------------------------------------------------
# Driver
# --------------------------------------------------------------------------------------------

def run_sluice(play, scene_path, warmup, steps, json_path):
    cmd = [play, scene_path, "--bench", "--warmup", str(warmup), "--steps", str(steps),
           "--bench-json", json_path]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    load = os.getloadavg()
    t0 = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr}")
    with open(json_path) as f:
        bench = json.load(f)
    substeps = bench["substeps"]
    measured_wall = steps / bench["stepsPerSecondWall"] if bench["stepsPerSecondWall"] else None
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    total_substeps = (warmup + steps) * substeps
    return {
        "loadAfter": os.getloadavg(),
        # Load-free figures: the process's CPU time over all its steps (warm-up and start-up
        # included, at the measured steps' iteration count, so slightly pessimistic).
        "stepsPerCpuSecond": total_substeps / cpu,
        "particleIterationsPerCpuSecond":
            bench["particles"] * bench["meanIterations"] * total_substeps / cpu,
        "solver": bench["tool"] + " (" + bench["renderer"] + ")",
        "command": " ".join(os.path.relpath(c, ROOT) if os.path.isabs(c) else c for c in cmd),
        "particles": bench["particles"],
        "substepsPerStep": substeps,
        "measuredSteps": steps,
        "meanIterations": bench["meanIterations"],
        "avgDensityError": bench["avgDensityError"],
        # One SPlisHSPlasH step = one Sluice substep (same dt): compare substeps per second.
        "stepsPerSecond": bench["stepsPerSecondWall"] * substeps,
        "stepsPerSecondGpuMedian": bench["stepsPerSecondGpu"] * substeps,
        "particleIterationsPerSecond": bench["particles"] * substeps * bench["meanIterations"] *
        bench["stepsPerSecondWall"],
        "particleIterationsPerSecondGpuMedian": bench["particleIterationsPerSecond"],
        "measuredWallSeconds": measured_wall,
        "processWallSeconds": wall,
        "processCpuSeconds": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime),
        "loadBefore": load,
        "bench": bench,
    }


def run_splishsplash(args, cfg):
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = str(args.threads)
    # Threads that wait at an OpenMP barrier sleep instead of spinning. On a machine shared
    # with other work, spinning lets a waiting thread burn the time slice the other thread
    # needs to finish its half: 10 steps of a 2k-particle run took 3.3 s spinning and 0.39 s
    # passive on the loaded development machine. llvmpipe's threads already sleep when idle.
    env["OMP_WAIT_POLICY"] = args.omp_wait_policy
    if not args.no_preload and os.path.exists(SYSTEM_GLDISPATCH):
        env["LD_PRELOAD"] = SYSTEM_GLDISPATCH
    load = os.getloadavg()
    t0 = time.monotonic()
    proc = subprocess.run([args.splishsplash_python, os.path.abspath(__file__),
                           "--worker", json.dumps(cfg)], capture_output=True, text=True, env=env)
    wall = time.monotonic() - t0
    if proc.returncode != 0:
        tail = (proc.stdout + proc.stderr)[-3000:]
        return {"error": f"exit {proc.returncode}", "log": tail}
    line = [l for l in proc.stdout.splitlines() if l.startswith("RESULT ")][-1]
    out = json.loads(line[len("RESULT "):])
    out["processWallSeconds"] = wall
    out["loadBefore"] = load
    out["loadAfter"] = os.getloadavg()
    return out


def interpolate(points, error):
    """Throughput at `error` from (error, throughput) points, linear in log(error)."""
    pts = sorted(p for p in points if p[0] > 0)
    if not pts:
        return None, "no point"
    if error <= pts[0][0]:
        return pts[0][1], "extrapolated: below the lowest measured error (held)"
    if error >= pts[-1][0]:
        return pts[-1][1], "extrapolated: above the highest measured error (held)"
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e0 <= error <= e1:
            f = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return t0 + f * (t1 - t0), "interpolated"
    return None, "?"


def sluice_cpu_figures(sl, warmup_frames):
    """Load-free figures of a Sluice row (for rows written before they were recorded)."""
    if "particleIterationsPerCpuSecond" not in sl:
        total = (warmup_frames + sl["measuredSteps"]) * sl["substepsPerStep"]
        sl["stepsPerCpuSecond"] = total / sl["processCpuSeconds"]
        sl["particleIterationsPerCpuSecond"] = (sl["particles"] * sl["meanIterations"] * total /
                                                sl["processCpuSeconds"])
    return sl


def report(rows):
    """Prints the table and the ratios at matched error; returns the matched comparison.
    Each Sluice point is compared with SPlisHSPlasH's throughput interpolated (linearly in
    log error) at the error Sluice achieved; wall figures and CPU-time figures separately."""
    ok = [r for r in rows if "error" not in r["splishsplash"]]
    matched = []
    for r in rows:
        sl = r["sluice"]
        m = {"target": r["target"], "sluiceAvgDensityError": sl["avgDensityError"]}
        for key in ("stepsPerSecond", "particleIterationsPerSecond", "stepsPerCpuSecond",
                    "particleIterationsPerCpuSecond"):
            pts = [(x["splishsplash"]["avgDensityError"], x["splishsplash"][key]) for x in ok
                   if key in x["splishsplash"]]
            other, how = interpolate(pts, sl["avgDensityError"])
            m["sluice_" + key] = sl.get(key)
            m["splishsplash_" + key + "_atSameError"] = other
            m["ratio_" + key] = sl[key] / other if other and sl.get(key) else None
            m["how"] = how
        matched.append(m)

    def fmt(v, f):
        return (f % v) if v is not None else "n/a"

    print("\n| solver | target | particles | mean it | avg density error | substeps/s (wall) | "
          "particle-it/s (wall) | particle-it per CPU-s |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        for name, x in (("Sluice", r["sluice"]), ("SPlisHSPlasH", r["splishsplash"])):
            if "error" in x:
                print(f"| {name} | {r['target']:g} | failed: {x['error']} | | | | | |")
                continue
            print(f"| {name} | {r['target']:g} | {x['particles']} | {x['meanIterations']:.2f} | "
                  f"{100 * x['avgDensityError']:.3f} % | {x['stepsPerSecond']:.3f} | "
                  f"{x['particleIterationsPerSecond']:.3g} | "
                  f"{fmt(x.get('particleIterationsPerCpuSecond'), '%.3g')} |")
    print("\n| Sluice target | Sluice error | ratio substeps/s (wall) | ratio particle-it/s (wall) "
          "| ratio substeps per CPU-s | ratio particle-it per CPU-s | SPlisHSPlasH side |")
    print("|---|---|---|---|---|---|---|")
    for m in matched:
        print(f"| {m['target']:g} | {100 * m['sluiceAvgDensityError']:.3f} % | "
              f"{fmt(m['ratio_stepsPerSecond'], '%.2f')} | "
              f"{fmt(m['ratio_particleIterationsPerSecond'], '%.2f')} | "
              f"{fmt(m['ratio_stepsPerCpuSecond'], '%.2f')} | "
              f"{fmt(m['ratio_particleIterationsPerCpuSecond'], '%.2f')} | {m['how']} |")
    return matched


def machine_simd():
    """CPU model and the SIMD flags that matter here, from /proc/cpuinfo."""
    info = sweep.machine_info()
    flags = set()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("flags"):
                    flags = set(line.split(":", 1)[1].split())
                    break
    except OSError:
        pass
    info["simdFlags"] = sorted(f for f in flags if f in ("sse4_2", "avx", "avx2", "fma") or
                               f.startswith("avx512"))
    info["avx2"] = "avx2" in flags
    info["avx512"] = any(f.startswith("avx512") for f in flags)
    return info


def spread(values):
    """Median and min-max of a list (None when empty)."""
    v = sorted(x for x in values if x is not None)
    if not v:
        return None
    mid = len(v) // 2
    median = v[mid] if len(v) % 2 else 0.5 * (v[mid - 1] + v[mid])
    return {"median": median, "min": v[0], "max": v[-1], "n": len(v)}


FIGURES = ("stepsPerCpuSecond", "particleIterationsPerCpuSecond", "stepsPerSecond",
           "avgDensityError", "meanIterations")


def summarize_target(target, sluice_runs, sph_runs):
    """Median and range per side, and the ratios of medians with their extreme ranges."""
    ok_sl = [r for r in sluice_runs if "error" not in r]
    ok_sp = [r for r in sph_runs if "error" not in r]
    out = {"target": target, "sluice": {}, "splishsplash": {}, "ratio": {}}
    for name, runs in (("sluice", ok_sl), ("splishsplash", ok_sp)):
        for key in FIGURES:
            out[name][key] = spread([r.get(key) for r in runs])
        out[name]["loads"] = [[r.get("loadBefore"), r.get("loadAfter")] for r in runs]
    for key in ("stepsPerCpuSecond", "stepsPerSecond", "particleIterationsPerCpuSecond"):
        a, b = out["sluice"][key], out["splishsplash"][key]
        if a and b and b["min"] > 0:
            out["ratio"][key] = {"median": a["median"] / b["median"],
                                 "min": a["min"] / b["max"], "max": a["max"] / b["min"]}
    return out


def print_summary(summaries):
    def rng(x, scale=1.0, f="%.3g"):
        if not x:
            return "n/a"
        return (f + " (" + f + "–" + f + ")") % (scale * x["median"], scale * x["min"],
                                                  scale * x["max"])

    print("\n| target | side | runs | avg density error % | mean it per substep | "
          "substeps per CPU-s | substeps/s (wall) |")
    print("|---|---|---|---|---|---|---|")
    for m in summaries:
        for name in ("sluice", "splishsplash"):
            x = m[name]
            n = x["stepsPerCpuSecond"]["n"] if x["stepsPerCpuSecond"] else 0
            print(f"| {m['target']:g} | {name} | {n} | {rng(x['avgDensityError'], 100, '%.3f')} | "
                  f"{rng(x['meanIterations'], 1, '%.2f')} | {rng(x['stepsPerCpuSecond'])} | "
                  f"{rng(x['stepsPerSecond'])} |")
    print("\n| target | ratio substeps per CPU-s | ratio substeps/s (wall) |")
    print("|---|---|---|")
    for m in summaries:
        r = m["ratio"]
        print(f"| {m['target']:g} | {rng(r.get('stepsPerCpuSecond'), 1, '%.2f')} | "
              f"{rng(r.get('stepsPerSecond'), 1, '%.2f')} |")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--worker", help=argparse.SUPPRESS)
    p.add_argument("--build", default="build/dev")
    p.add_argument("--splishsplash-python", default=sys.executable,
                   help="python with pysplishsplash installed")
    p.add_argument("--particles", type=int, default=30000)
    p.add_argument("--targets", default="0.01,0.005,0.0025,0.001",
                   help="error targets (fractions): Sluice targetDensityError, SPlisHSPlasH "
                        "maxError = 100 x target percent")
    p.add_argument("--min-iterations", type=int, default=2)
    p.add_argument("--max-iterations", type=int, default=8)
    p.add_argument("--warmup-frames", type=int, default=15,
                   help="1/60 s frames simulated before measuring (the column collapses)")
    p.add_argument("--measure-frames", type=int, default=6)
    p.add_argument("--threads", type=int, default=os.cpu_count() or 2)
    p.add_argument("--no-preload", action="store_true")
    p.add_argument("--omp-wait-policy", default="PASSIVE", choices=["PASSIVE", "ACTIVE"])
    p.add_argument("--machine", default="llvmpipe")
    p.add_argument("--out")
    p.add_argument("--report", metavar="RESULTS_JSON", help="print the tables of a results file")
    p.add_argument("--repeat", type=int, default=3,
                   help="runs per side and target, interleaved; median and min-max reported")
    args = p.parse_args()

    if args.report:
        with open(args.report) as f:
            doc = json.load(f)
        if "summary" in doc:  # a file with repeats: print it as written
            print_summary(doc["summary"])
            return 0
        for r in doc["rows"]:
            sluice_cpu_figures(r["sluice"], doc["settings"]["warmup_frames"])
            sp = r["splishsplash"]
            if "error" not in sp and "particleIterationsPerCpuSecond" not in sp:
                sp["stepsPerCpuSecond"] = sp["measuredSteps"] / sp["cpuSeconds"]
                sp["particleIterationsPerCpuSecond"] = (
                    sp["particles"] * sp["meanIterations"] * sp["measuredSteps"] /
                    sp["cpuSeconds"])
        doc["matched"] = report(doc["rows"])
        with open(args.report, "w") as f:
            json.dump(doc, f, indent=2)
            f.write("\n")
        return 0

    if args.worker:
        result = splishsplash_worker(json.loads(args.worker))
        print("RESULT " + json.dumps(result), flush=True)
        return 0

    args.out = args.out or os.path.join(ROOT, "docs", "results",
                                        f"pbf_vs_splishsplash_{args.machine}.json")
    build = os.path.abspath(args.build)
    play = os.path.join(build, "bin", "sluice-play")
    assets = os.path.join(build, "assets")
    work = os.path.join(assets, "pbf-vs-splishsplash")
    os.makedirs(work, exist_ok=True)
    unit_box = splishsplash_unit_box(args.splishsplash_python)

    rows, summaries = [], []
    for target in [float(t) for t in args.targets.split(",")]:
        path, spacing, count, scene = sweep.make_scene(os.path.join(assets, "dam-break.json"),
                                                       assets, work, args.particles)
        scene["simulation"].update({"targetDensityError": target,
                                    "minIterations": args.min_iterations,
                                    "maxIterations": args.max_iterations})
        scene["name"] = f"dam-break-{args.particles}-target-{target:g}"
        path = os.path.join(work, scene["name"] + ".json")
        with open(path, "w") as f:
            json.dump(scene, f, indent=4)
        sluice_runs, sph_runs = [], []
        for rep in range(args.repeat):
            print(f"target {target:g}, run {rep + 1}/{args.repeat}: Sluice ({count} particles) ...",
                  flush=True)
            sl = run_sluice(play, path, args.warmup_frames, args.measure_frames,
                            os.path.join(work, scene["name"] + ".bench.json"))
            substeps = int(sl["substepsPerStep"])
            box = scene["fluid"][0]["box"]
            counts = [math.floor((box["max"][a] - box["min"][a]) / spacing + 1e-4)
                      for a in range(3)]
            cfg = {"spacing": spacing, "blockMin": box["min"], "blockCounts": counts,
                   "dt": (1.0 / 60.0) / substeps, "target": target,
                   "minIterations": args.min_iterations, "maxIterations": args.max_iterations,
                   "warmupSteps": args.warmup_frames * substeps,
                   "measuredSteps": args.measure_frames * substeps, "unitBox": unit_box,
                   "errorEvery": substeps,
                   "workDir": work}
            print(f"target {target:g}, run {rep + 1}/{args.repeat}: SPlisHSPlasH "
                  f"(dt {cfg['dt']:.6g} s) ...", flush=True)
            sp = run_splishsplash(args, cfg)
            sluice_runs.append(sl)
            sph_runs.append(sp)
            for name, r in (("Sluice", sl), ("SPlisHSPlasH", sp)):
                if "error" in r:
                    print(f"  {name}: {r['error']}\n{r['log']}")
                else:
                    print(f"  {name}: {r['particles']} particles, {r['meanIterations']:.2f} it, "
                          f"avg error {100 * r['avgDensityError']:.3f} %, "
                          f"{r['stepsPerCpuSecond']:.3g} substeps per CPU-s, "
                          f"{r['stepsPerSecond']:.2f} substeps/s wall, "
                          f"load {r['loadBefore'][0]:.1f} -> {r['loadAfter'][0]:.1f}", flush=True)
        rows.append({"target": target, "sluiceRuns": sluice_runs, "splishsplashRuns": sph_runs})
        summaries.append(summarize_target(target, sluice_runs, sph_runs))
        write_results(args, rows, summaries)  # after every target: a cut run keeps what it did

    print_summary(summaries)
    write_results(args, rows, summaries)
    print(f"\nwrote {args.out}")
    return 0


def write_results(args, rows, summaries):
    doc = {
        "what": "Sluice PBF vs SPlisHSPlasH PBF, dam break (tests/bench/pbf/vs_splishsplash.py)",
        "date": sweep.utc_now(),
        "machineName": args.machine,
        "machine": machine_simd(),
        "settings": {k: v for k, v in vars(args).items() if k not in ("worker",)},
        "comparison": "at the same target on both sides, each side's achieved error stated; "
                      "median (min-max) of the runs; ratio of medians (extremes)",
        "summary": summaries,
        "rows": rows,
    }
    sweep.write_results(args.out, doc)


if __name__ == "__main__":
    sys.exit(main())
