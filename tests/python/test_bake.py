"""Baking through Python against the sluice-bake command line: same bytes, same metadata, views
that share memory, the sampler, validation figures, VDB round trip, and the GIL released."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import sluice
from conftest import ASSETS, run_tool


@pytest.mark.parametrize("backend,storage", [("cgal", "f32"), ("cgal", "f16"), ("gpu", "f32")])
def test_python_and_cli_bakes_are_byte_identical(sphere_obj: Path, tmp_path: Path, backend: str,
                                                 storage: str, ctx_ok: bool) -> None:
    if backend == "gpu" and not ctx_ok:
        pytest.skip("no OpenGL 4.5 context")
    cli_out = tmp_path / "cli.slc"
    done = run_tool("sluice-bake", "bake", sphere_obj, "-o", cli_out, "--resolution", "20",
                    "--backend", backend, "--storage", storage, "--scale", "0.5", "--json")
    collider = sluice.bake(sphere_obj, resolution=20, backend=backend, storage=storage,
                           scale=0.5)
    py_out = tmp_path / "py.slc"
    collider.save(py_out)
    assert py_out.read_bytes() == cli_out.read_bytes()
    # The metadata is the command line's "asset" object, the measured quantization included.
    assert collider.metadata == json.loads(done.stdout)["asset"]
    assert collider.metadata["toolVersion"] == sluice.tool_version()


@pytest.mark.parametrize("backend", ["cgal", "gpu"])
def test_sparse_bakes_match_the_cli(sphere_obj: Path, tmp_path: Path, backend: str,
                                    ctx_ok: bool) -> None:
    if backend == "gpu" and not ctx_ok:
        pytest.skip("no OpenGL 4.5 context")
    cli_out = tmp_path / "cli.slc"
    run_tool("sluice-bake", "bake", sphere_obj, "-o", cli_out, "--resolution", "24", "--sparse",
             "--band", "4", "--backend", backend, "--quiet")
    collider = sluice.bake(sphere_obj, resolution=24, backend=backend, sparse=True, band=4)
    py_out = tmp_path / "py.slc"
    collider.save(py_out)
    assert py_out.read_bytes() == cli_out.read_bytes()
    assert collider.metadata["layout"] == "sparse"
    assert collider.metadata["bandWidth"] == 4.0
    assert collider.metadata["bake"]["backend"] == backend
    # Deep inside: -band voxels; the band is exact near the surface.
    assert collider.sample([0.0, 0.0, 0.0])[0] < 0.0
    with pytest.raises(sluice.InvalidArgument):
        sluice.bake(sphere_obj, resolution=24, sparse=True, band=0.5)


def test_a_band_for_a_spacing_matches_the_cli(sphere_obj: Path, tmp_path: Path) -> None:
    cli_out = tmp_path / "cli.slc"
    run_tool("sluice-bake", "bake", sphere_obj, "-o", cli_out, "--resolution", "24", "--sparse",
             "--for-spacing", "0.02", "--backend", "cgal", "--quiet")
    collider = sluice.bake(sphere_obj, resolution=24, backend="cgal", sparse=True,
                           for_spacing=0.02)
    collider.save(tmp_path / "py.slc")
    assert (tmp_path / "py.slc").read_bytes() == cli_out.read_bytes()
    # 0.5 m over 24 voxels: (2 + 0.15) x 2 cm / 20.8 mm + sqrt(3) = 3.80, so 4 voxels.
    assert collider.metadata["bandWidth"] == 4.0
    with pytest.raises(sluice.InvalidArgument):
        sluice.bake(sphere_obj, resolution=24, for_spacing=0.02)  # not sparse
    with pytest.raises(sluice.InvalidArgument):
        sluice.bake(sphere_obj, resolution=24, sparse=True, for_spacing=0.02,
                    for_kernel_radius=0.2)  # 10 spacings
    with pytest.raises(sluice.InvalidArgument):
        sluice.bake(sphere_obj, resolution=24, sparse=True, for_kernel_radius=0.04)


def test_voxel_size_and_padding_match_the_cli(tetra: Path, tmp_path: Path) -> None:
    run_tool("sluice-bake", "bake", tetra, "-o", tmp_path / "cli.slc", "--voxel-size", "0.05",
             "--padding", "2", "--sign", "winding", "--backend", "cgal", "--quiet")
    sluice.bake(tetra, voxel_size=0.05, padding=2, sign="winding", backend="cgal").save(
        tmp_path / "py.slc")
    assert (tmp_path / "py.slc").read_bytes() == (tmp_path / "cli.slc").read_bytes()


def test_load_mesh_returns_arrays_and_the_diagnostics_the_baker_reports(sphere_obj: Path,
                                                                        tmp_path: Path) -> None:
    mesh = sluice.load_mesh(sphere_obj, scale=2.0)
    assert mesh.vertices.dtype == np.float64 and mesh.vertices.shape == (642, 3)
    assert mesh.triangles.dtype == np.uint32 and mesh.triangles.shape == (1280, 3)
    radii = np.linalg.norm(mesh.vertices, axis=1)
    assert np.allclose(radii.max(), 2 * np.linalg.norm(sluice.load_mesh(sphere_obj).vertices,
                                                       axis=1).max())
    done = run_tool("sluice-bake", "bake", sphere_obj, "-o", tmp_path / "s.slc", "--scale", "2",
                    "--resolution", "8", "--backend", "cgal", "--json")
    assert mesh.diagnostics == json.loads(done.stdout)["asset"]["mesh"]
    assert mesh.diagnostics["closed"] and not mesh.diagnostics["selfIntersecting"]
    assert not mesh.vertices.flags.writeable
    # A Mesh bakes at the scale it was read at, and records it, as a path with that scale does.
    assert mesh.scale == 2.0
    from_mesh = sluice.bake(mesh, resolution=8, backend="cgal")
    from_path = sluice.bake(sphere_obj, resolution=8, backend="cgal", scale=2.0)
    assert from_mesh.metadata == from_path.metadata
    with pytest.raises(sluice.InvalidArgument):
        sluice.bake(mesh, scale=1.0)


def test_bake_accepts_arrays(sphere_obj: Path) -> None:
    mesh = sluice.load_mesh(sphere_obj)
    from_file = sluice.bake(mesh, resolution=16, backend="cgal")
    from_arrays = sluice.bake((mesh.vertices.copy(), mesh.triangles.astype(np.int64)),
                              resolution=16, backend="cgal")
    assert from_arrays.dims == from_file.dims
    assert np.array_equal(from_arrays.values, from_file.values)
    assert from_arrays.metadata["mesh"] == from_file.metadata["mesh"]
    assert from_arrays.metadata["sourceFile"] == "arrays"


def test_metadata_holds_the_mass_properties_of_closed_meshes_only(sphere_obj: Path) -> None:
    mass = sluice.bake(sphere_obj, resolution=8, backend="cgal").metadata["massProperties"]
    ball = 4.0 / 3.0 * np.pi * 0.25**3  # the demo sphere is a little inside this ball
    assert 0.97 * ball < mass["volume"] < ball
    assert np.allclose(mass["centerOfMass"], 0.0, atol=1e-12)
    inertia = np.array(mass["inertia"])
    assert inertia.shape == (3, 3) and np.array_equal(inertia, inertia.T)
    # A tetrahedron without its base is open: no mass properties.
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    sides = np.array([[0, 1, 3], [1, 2, 3], [2, 0, 3]], dtype=np.uint32)
    opened = sluice.bake((corners, sides), resolution=8, backend="cgal")
    assert opened.metadata["mesh"]["closed"] is False
    assert opened.metadata["massProperties"] is None


def test_values_is_a_view_of_the_collider_not_a_copy(tetra: Path) -> None:
    collider = sluice.bake(tetra, resolution=12, backend="cgal")
    a, b = collider.values, collider.values
    assert a.shape == collider.dims and a.dtype == np.float32
    assert np.shares_memory(a, b)
    # x fastest in memory, as in the file: values[i, j, k] at origin + (i, j, k) * voxel.
    assert a.strides == (4, 4 * a.shape[0], 4 * a.shape[0] * a.shape[1])
    # Writing through the view changes what the collider samples and saves.
    corner = np.array(collider.origin)
    before = collider.sample(corner)[0]
    a[0, 0, 0] = 123.0
    assert collider.sample(corner)[0] == pytest.approx(123.0)
    assert b[0, 0, 0] == 123.0 and before != 123.0
    # The view keeps the collider alive.
    view = sluice.bake(tetra, resolution=12, backend="cgal").values
    assert np.isfinite(view).all()


def trilinear(values: np.ndarray, origin, voxel: float, p: np.ndarray) -> np.ndarray:
    """A NumPy trilinear interpolation inside the grid box, for the sampler's check."""
    g = (p - np.asarray(origin)) / voxel
    i0 = np.clip(np.floor(g).astype(int), 0, np.array(values.shape) - 2)
    f = g - i0
    out = np.zeros(len(p))
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                w = ((f[:, 0] if dx else 1 - f[:, 0]) * (f[:, 1] if dy else 1 - f[:, 1]) *
                     (f[:, 2] if dz else 1 - f[:, 2]))
                out += w * values[i0[:, 0] + dx, i0[:, 1] + dy, i0[:, 2] + dz]
    return out


def test_sample_is_the_cpp_trilinear_sampler(sphere_obj: Path) -> None:
    collider = sluice.bake(sphere_obj, resolution=20, backend="cgal")
    v = collider.values
    # At grid points: the stored values exactly.
    idx = np.array([[0, 0, 0], [3, 5, 7], [10, 10, 10], [v.shape[0] - 1, 2, v.shape[2] - 1]])
    pts = np.asarray(collider.origin) + idx * collider.voxel_size
    phi, grad = collider.sample(pts)
    assert phi.dtype == np.float32 and grad.shape == (4, 3)
    assert np.array_equal(phi, v[idx[:, 0], idx[:, 1], idx[:, 2]])
    # Between them: trilinear, and the gradient of the sphere's field points outward.
    rng = np.random.default_rng(3)
    lo = np.asarray(collider.origin)
    hi = lo + (np.array(v.shape) - 1) * collider.voxel_size
    pts = rng.uniform(lo, hi, size=(2000, 3))
    phi, grad = collider.sample(pts)
    assert np.allclose(phi, trilinear(v, collider.origin, collider.voxel_size, pts), atol=1e-5)
    far = np.linalg.norm(pts, axis=1) > 0.3
    radial = pts[far] / np.linalg.norm(pts[far], axis=1, keepdims=True)
    assert np.median(np.sum(grad[far] * radial, axis=1)) > 0.95
    # Outside the box: phi(c) + |p - c|, an upper bound that grows with distance.
    out = collider.sample(np.array([[10.0, 0.0, 0.0], [20.0, 0.0, 0.0]]))[0]
    assert out[1] - out[0] == pytest.approx(10.0, rel=1e-5)
    nan = collider.sample(np.array([np.nan, 0.0, 0.0]))[0]
    assert np.isnan(nan)


def test_read_asset_and_vdb_round_trip(sphere_obj: Path, tmp_path: Path) -> None:
    collider = sluice.bake(sphere_obj, resolution=16, backend="cgal")
    collider.save(tmp_path / "s.slc")
    back = sluice.read_asset(tmp_path / "s.slc")
    assert back.metadata == collider.metadata and np.array_equal(back.values, collider.values)
    assert back.path == str(tmp_path / "s.slc")
    collider.export_vdb(tmp_path / "s.vdb")
    run_tool("sluice-bake", "export", tmp_path / "s.slc", tmp_path / "cli.vdb")
    vdb = sluice.read_asset(tmp_path / "s.vdb")
    assert vdb.dims == collider.dims and np.array_equal(vdb.values, collider.values)
    assert vdb.metadata["sourceHash"] == collider.metadata["sourceHash"]
    # A level set bakes like a mesh (its zero isosurface), as `sluice-bake bake x.vdb` does.
    mesh = sluice.load_mesh(tmp_path / "cli.vdb")
    assert mesh.diagnostics["closed"] and mesh.diagnostics["triangles"] > 100


def test_validate_gives_the_figures_of_validate_json(sphere_obj: Path, tmp_path: Path) -> None:
    asset = tmp_path / "s.slc"
    sluice.bake(sphere_obj, resolution=16, backend="cgal", scale=0.5).save(asset)
    done = run_tool("sluice-bake", "validate", asset, sphere_obj, "--json")
    report = sluice.validate(asset, sphere_obj)
    assert report == json.loads(done.stdout)
    assert report["withinLimits"] and report["figures"]["maxError"] < 1e-3
    assert report["sourceHashMatches"] is True
    # Sampled: the same seed gives the same figures as the command line.
    done = run_tool("sluice-bake", "validate", asset, sphere_obj, "--json", "--samples", "500",
                    "--sign", "winding")
    mesh = sluice.load_mesh(sphere_obj, 0.5)
    report = sluice.validate(sluice.read_asset(asset), mesh, samples=500, sign="winding")
    cli = json.loads(done.stdout)
    assert report["figures"] == cli["figures"] and report["referenceSign"] == "winding"


TETRA_VERTICES = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
TETRA_TRIANGLES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])  # tetra.obj's faces


def test_validate_takes_arrays_as_bake_does(tetra: Path) -> None:
    # Arrays are the mesh file's numbers: scaled by the collider's scale, as the file is.
    collider = sluice.bake(tetra, resolution=8, backend="cgal", scale=2.0, progress=False)
    from_file = sluice.validate(collider, tetra, progress=False)
    from_arrays = sluice.validate(collider, (TETRA_VERTICES, TETRA_TRIANGLES), progress=False)
    assert from_file["figures"]["pointsChecked"] == 15 ** 3  # 8 voxels and 3 of padding a side
    assert from_file["withinLimits"] and from_file["figures"]["maxError"] < 1e-5
    # Only what names the mesh differs: its file and whether the asset's source hash matches it.
    assert (from_file["mesh"], from_file["sourceHashMatches"]) == (str(tetra), True)
    assert from_arrays["sourceHashMatches"] is False
    same = {k: v for k, v in from_file.items() if k not in ("mesh", "sourceHashMatches")}
    assert {k: v for k, v in from_arrays.items() if k in same} == same
    sampled = sluice.validate(collider, (TETRA_VERTICES, TETRA_TRIANGLES), samples=200, seed=3,
                              progress=False)
    assert sampled["figures"] == sluice.validate(collider, tetra, samples=200, seed=3,
                                                 progress=False)["figures"]


@pytest.mark.parametrize("vertices,triangles", [
    (TETRA_VERTICES[:, :2], TETRA_TRIANGLES),                          # (N, 2)
    (TETRA_VERTICES, TETRA_TRIANGLES.ravel()),                         # flat indices
    (TETRA_VERTICES, TETRA_TRIANGLES.astype(float)),                   # not integers
    (TETRA_VERTICES, np.where(TETRA_TRIANGLES == 3, -1, TETRA_TRIANGLES)),  # negative
    (TETRA_VERTICES, np.where(TETRA_TRIANGLES == 3, 4, TETRA_TRIANGLES)),   # past the end
    (np.where(TETRA_VERTICES == 1, np.inf, TETRA_VERTICES), TETRA_TRIANGLES),  # not finite
])
def test_validate_rejects_bad_arrays_with_the_errors_of_bake(tetra: Path, vertices,
                                                             triangles) -> None:
    collider = sluice.bake(tetra, resolution=4, backend="cgal", progress=False)
    with pytest.raises(sluice.Error) as baked:
        sluice.bake((vertices, triangles), resolution=4, backend="cgal", progress=False)
    with pytest.raises(sluice.Error) as validated:
        sluice.validate(collider, (vertices, triangles), progress=False)
    assert isinstance(baked.value, (sluice.InvalidArgument, sluice.MeshError))
    assert type(validated.value) is type(baked.value)
    assert (validated.value.code, str(validated.value)) == (baked.value.code, str(baked.value))


def test_the_gil_is_released_while_baking(sphere_obj: Path) -> None:
    mesh = sluice.load_mesh(sphere_obj)
    ticks = []
    stop = threading.Event()

    def count() -> None:
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.005)

    start = time.monotonic()
    sluice.bake(mesh, resolution=8, backend="cgal")  # warm up
    thread = threading.Thread(target=count)
    thread.start()
    try:
        t0 = time.monotonic()
        sluice.bake(mesh, resolution=56, backend="cgal", progress=False)
        t1 = time.monotonic()
    finally:
        stop.set()
        thread.join()
    during = [t for t in ticks if t0 < t < t1]
    assert t1 - t0 > 0.2, "the bake is too short to tell"
    # The thread kept ticking all through the bake, not only before and after it.
    assert len(during) >= 10, (len(during), t1 - t0, start)
    assert max(np.diff([t0, *during, t1])) < 0.5 * (t1 - t0)


def test_ctrl_c_stops_a_bake_with_keyboard_interrupt(tmp_path: Path) -> None:
    import os
    import signal
    import subprocess
    import sys
    script = tmp_path / "long.py"
    script.write_text(
        "import sys, time, sluice\n"
        f"mesh = sluice.load_mesh({str(ASSETS / 'sphere.obj')!r})\n"
        "print('start', flush=True)\n"
        "t = time.monotonic()\n"
        "try:\n"
        "    sluice.bake(mesh, resolution=400, backend='cgal', progress=False)\n"
        "    print('finished')\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted after %.2f s' % (time.monotonic() - t), flush=True)\n"
        "    sys.exit(7)\n")
    proc = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True,
                            env=os.environ.copy())
    assert proc.stdout.readline().strip() == "start"
    time.sleep(1.0)
    proc.send_signal(signal.SIGINT)
    out, _ = proc.communicate(timeout=60)
    assert proc.returncode == 7, out
    assert "interrupted" in out


def test_stubs_are_generated_for_editors() -> None:
    package = Path(sluice.__file__).parent
    stub = (package / "_sluice.pyi").read_text()
    for name in ("class Collider", "class Mesh", "def bake_mesh", "class SimulationCore",
                 "def read_asset"):
        assert name in stub, name
    assert (package / "py.typed").exists()


def test_progress_reaches_python_and_an_exception_there_stops_the_bake(sphere_obj: Path) -> None:
    from sluice import _sluice
    mesh = sluice.load_mesh(sphere_obj)
    request = _sluice.BakeRequest()
    request.backend, request.resolution = "cgal", 56
    calls = []
    _sluice.bake_mesh(mesh._m, request, False, lambda done, total: calls.append((done, total)))
    assert calls, "the bake ran under 50 ms: no progress call to check"
    dims = sluice.bake(mesh, resolution=56, backend="cgal", progress=False).dims
    assert {total for _, total in calls} == {dims[0] * dims[1] * dims[2]}
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)

    class Stop(Exception):
        pass

    def stop(done: int, total: int) -> None:
        raise Stop(f"{done} of {total}")

    with pytest.raises(Stop):
        _sluice.bake_mesh(mesh._m, request, False, stop)


def test_a_tqdm_bar_shows_for_work_over_a_second(monkeypatch) -> None:
    import sys
    import types
    shown = []

    class FakeTqdm:
        def __init__(self, total, desc, **kw):
            shown.append(("open", total, desc))

        def update(self, n):
            shown.append(("update", n))

        def close(self):
            shown.append(("close",))

    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", types.SimpleNamespace(tqdm=FakeTqdm))
    from sluice._progress import progress_hooks
    bar, update, close = progress_hooks("baking x", True)
    assert bar is False and update is not None
    update(10, 100)  # within the first second: nothing shown
    assert shown == []
    monkeypatch.setattr(time, "monotonic", lambda: 1e9)
    update(40, 100)
    update(100, 100)
    close()
    assert shown == [("open", 100, "baking x"), ("update", 40), ("update", 60), ("close",)]
    assert progress_hooks("x", False)[:2] == (False, None)


def test_volume_maps_bake_as_the_cli_bakes_them(sphere_obj: Path, tmp_path: Path) -> None:
    cli_out = tmp_path / "cli.slc"
    run_tool("sluice-bake", "bake", sphere_obj, "-o", cli_out, "--resolution", "20",
             "--backend", "cgal", "--volume-map", "0.2", "--quiet")
    collider = sluice.bake(sphere_obj, resolution=20, backend="cgal", volume_maps=[0.2],
                           progress=False)
    assert collider.volume_map_supports == [0.2]
    collider.save(tmp_path / "py.slc")
    assert (tmp_path / "py.slc").read_bytes() == cli_out.read_bytes()
    assert sluice.read_asset(tmp_path / "py.slc").volume_map_supports == [0.2]
    with pytest.raises(sluice.InvalidArgument, match="given twice"):
        sluice.bake(sphere_obj, resolution=20, backend="cgal", volume_maps=[0.2, 0.2],
                    progress=False)
