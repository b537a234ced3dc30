"""bake_many on a process pool and on a Dask LocalCluster with 2 workers: the bytes of
`sluice-bake batch`, the same freshness rule, and a broken mesh that fails alone."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import sluice
from conftest import ASSETS, dump_json, run_tool, write_tetrahedron

MANIFEST = {"colliders": [
    {"mesh": "meshes/sphere.obj", "output": "sphere.slc", "resolution": 16, "backend": "cgal",
     "scale": 0.5},
    {"mesh": "meshes/broken.obj", "output": "broken.slc", "resolution": 8, "backend": "cgal"},
    {"mesh": "meshes/tetra.obj", "output": "tetra.slc", "voxelSize": 0.1, "storage": "f16",
     "sign": "winding", "backend": "cgal"},
    {"mesh": "meshes/tetra.obj", "output": "tetra-auto.slc", "resolution": 8},
]}
BAKED = ["sphere.slc", "tetra.slc", "tetra-auto.slc"]


def make_library(folder: Path) -> Path:
    """A content library: three meshes (one broken) and the manifest."""
    (folder / "meshes").mkdir(parents=True)
    shutil.copy(ASSETS / "sphere.obj", folder / "meshes" / "sphere.obj")
    write_tetrahedron(folder / "meshes" / "tetra.obj")
    (folder / "meshes" / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nl 1 2\n")
    return dump_json(folder / "manifest.json", MANIFEST)


@pytest.fixture
def cli_library(tmp_path: Path) -> Path:
    manifest = make_library(tmp_path / "cli")
    done = run_tool("sluice-bake", "batch", manifest, check=False)
    assert done.returncode == 2, done.stdout + done.stderr  # the broken mesh
    return manifest.parent


def check_results(results, folder: Path, cli: Path, first_status: str) -> None:
    assert [r["label"] for r in results] == [e["output"] for e in MANIFEST["colliders"]]
    by_label = {r["label"]: r for r in results}
    broken = by_label["broken.slc"]
    assert broken["status"] == "failed"
    assert broken["error"]["type"] == "MeshError" and broken["error"]["code"] == "EmptyMesh"
    assert "broken.obj" in broken["error"]["message"]
    assert not (folder / "broken.slc").exists()
    for name in BAKED:
        assert by_label[name]["status"] == first_status, by_label[name]
        assert by_label[name]["error"] is None
        assert (folder / name).read_bytes() == (cli / name).read_bytes(), name


def test_bake_many_on_a_process_pool_matches_sluice_bake_batch(tmp_path: Path,
                                                               cli_library: Path) -> None:
    manifest = make_library(tmp_path / "py")
    with ProcessPoolExecutor(max_workers=2) as pool:
        results = sluice.bake_many(manifest, executor=pool)
    check_results(results, manifest.parent, cli_library, "baked")
    # A failed entry leaves its previous output as it was.
    (manifest.parent / "broken.slc").write_bytes(b"previous")
    assert sluice.bake_many(manifest, force=True)[1]["status"] == "failed"
    assert (manifest.parent / "broken.slc").read_bytes() == b"previous"
    (manifest.parent / "broken.slc").unlink()
    assert results[0]["points"] == sluice.read_asset(cli_library / "sphere.slc").values.size
    # A second run finds everything fresh; a changed mesh rebakes only its entries.
    again = sluice.bake_many(manifest)  # the default local process pool
    check_results(again, manifest.parent, cli_library, "fresh")
    write_tetrahedron(manifest.parent / "meshes" / "tetra.obj", scale=2.0)
    third = {r["label"]: r["status"] for r in sluice.bake_many(manifest)}
    assert third == {"sphere.slc": "fresh", "broken.slc": "failed", "tetra.slc": "baked",
                     "tetra-auto.slc": "baked"}
    # The command line agrees that what Python baked is fresh.
    done = run_tool("sluice-bake", "batch", manifest, check=False)
    assert "0 baked, 3 fresh, 1 failed" in done.stdout, done.stdout


def test_bake_many_on_a_dask_local_cluster(tmp_path: Path, cli_library: Path) -> None:
    distributed = pytest.importorskip("distributed")
    manifest = make_library(tmp_path / "dask")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        results = sluice.bake_many(manifest, executor=client.get_executor())
    check_results(results, manifest.parent, cli_library, "baked")


def test_entries_can_be_given_as_dicts(tmp_path: Path) -> None:
    mesh = write_tetrahedron(tmp_path / "t.obj")
    results = sluice.bake_many(
        [{"mesh": mesh, "output": tmp_path / "t.slc", "resolution": 6, "backend": "cgal"},
         {"mesh": tmp_path / "missing.obj", "output": tmp_path / "m.slc"}],
        executor=ProcessPoolExecutor(max_workers=1))
    assert [r["status"] for r in results] == ["baked", "failed"]
    assert results[1]["error"]["type"] == "FileError"
    assert sluice.read_asset(tmp_path / "t.slc").metadata["bake"]["resolution"] == 6
    # A sparse entry stays sparse, with its band.
    sparse = sluice.bake_many(
        [{"mesh": mesh, "output": tmp_path / "s.slc", "resolution": 8, "backend": "cgal",
          "sparse": True, "band": 2}], executor=ProcessPoolExecutor(max_workers=1))
    assert sparse[0]["status"] == "baked", sparse[0]
    meta = sluice.read_asset(tmp_path / "s.slc").metadata
    assert (meta["layout"], meta["bandWidth"]) == ("sparse", 2.0)
    # A band for a particle spacing: 1 m over 8 voxels, 2.05 x 0.1 m / 0.125 m + sqrt(3) = 3.37.
    spaced = sluice.bake_many(
        [{"mesh": mesh, "output": tmp_path / "f.slc", "resolution": 8, "backend": "cgal",
          "sparse": True, "forSpacing": 0.1}], executor=ProcessPoolExecutor(max_workers=1))
    assert spaced[0]["status"] == "baked", spaced[0]
    assert sluice.read_asset(tmp_path / "f.slc").metadata["bandWidth"] == 4.0
    with pytest.raises(sluice.InvalidArgument):
        sluice.bake_many([{"mesh": "x.obj"}])
    with pytest.raises(sluice.FileError):
        sluice.bake_many(tmp_path / "no-manifest.json")


# The user's report: a GPU bake, a Simulation stepped, then bake_many on a fork-started process
# pool (ProcessPoolExecutor's default before Python 3.14). Then a child forked by hand, which can
# open no GL context, fails at once instead of waiting for the parent's driver threads.
FORK_AFTER_SIMULATION = """
import json, multiprocessing, os, sys
from concurrent.futures import ProcessPoolExecutor
import sluice
folder = sys.argv[1]
sluice.bake(folder + "/t.obj", resolution=8, progress=False).save(folder + "/t.slc")
sim = sluice.Simulation({"simulation": {"spacing": 0.05},
                         "fluid": [{"box": {"min": [-0.1, 0.3, -0.1], "max": [0.1, 0.4, 0.1]}}],
                         "colliders": [{"asset": "t.slc"}],
                         "domain": {"min": [-0.2, -0.2, -0.2], "max": [1.2, 1.2, 1.2]}},
                        base_dir=folder)
sim.step(2, progress=False)
entries = [{"mesh": folder + "/t.obj", "output": folder + f"/{i}.slc", "resolution": 8}
           for i in range(2)]
fork = None if sys.version_info < (3, 14) else multiprocessing.get_context("fork")
with ProcessPoolExecutor(2, mp_context=fork) as pool:
    results = sluice.bake_many(entries, executor=pool)
print(json.dumps([r["status"] for r in results]), flush=True)
pid = os.fork()
if pid == 0:
    try:
        sluice.bake(folder + "/t.obj", resolution=8, backend="gpu", progress=False)
    except sluice.GpuError as e:
        print("bake", e.code, "spawn" in str(e), flush=True)
    try:
        sim.step(1, progress=False)
    except sluice.GpuError as e:
        print("step", e.code, flush=True)
    del sim  # dropped without a GL call: the context is the parent's
    os._exit(0)
print("child", os.waitpid(pid, 0)[1], flush=True)
"""


def test_bake_many_on_a_fork_pool_after_a_simulation_bakes_on_the_gpu(tmp_path: Path) -> None:
    write_tetrahedron(tmp_path / "t.obj")
    package_root = str(Path(sluice.__file__).resolve().parents[1])
    env = dict(os.environ, PYTHONPATH=package_root)
    # A session of its own: a hang kills the pool's workers too, not only the script.
    run = subprocess.Popen([sys.executable, "-c", FORK_AFTER_SIMULATION, str(tmp_path)],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                           start_new_session=True)
    try:
        out, err = run.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        os.killpg(run.pid, signal.SIGKILL)
        out, err = run.communicate()
        pytest.fail(f"bake_many hung after a Simulation:\n{out}\n{err}")
    assert run.returncode == 0, out + err
    assert out.splitlines() == ['["baked", "baked"]', "bake NoGlContext True",
                                "step NoGlContext", "child 0"], out + err
    # Baked on the GPU, as in a fresh process: the same field as the parent's own bake.
    parent = sluice.read_asset(tmp_path / "t.slc")
    for name in ("0.slc", "1.slc"):
        baked = sluice.read_asset(tmp_path / name)
        assert baked.metadata["bake"]["backend"] == "gpu"
        assert np.array_equal(baked.values, parent.values)
