"""Fluid surfaces from Python: ``reconstruct_surface`` on any points and
``Simulation.surface_mesh()``; closed, manifold meshes of the right volume, the same mesh as
``sluice-play --surface-mesh`` for the same particles, and bad input refused."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import numpy as np
import pytest

import sluice
from conftest import run_tool

SPACING = 0.02
RADIUS = 0.5 * SPACING


def lattice(n: int) -> np.ndarray:
    axis = (np.arange(n) + 0.5) * SPACING
    return np.stack(np.meshgrid(axis, axis, axis, indexing="ij"), -1).reshape(-1, 3)


def edge_use(triangles: np.ndarray) -> dict:
    """How many times each directed edge appears."""
    counts: dict = {}
    for a, b, c in triangles.tolist():
        for e in ((a, b), (b, c), (c, a)):
            counts[e] = counts.get(e, 0) + 1
    return counts


def assert_closed_manifold_edges(mesh: sluice.SurfaceMesh) -> None:
    counts = edge_use(mesh.triangles)
    assert max(counts.values()) == 1, "a directed edge used twice"
    assert all((b, a) in counts for (a, b) in counts), "an open edge"
    assert len(np.unique(mesh.triangles)) == len(mesh.vertices), "an unused vertex"


def test_a_ball_of_particles_is_a_closed_sphere_of_its_volume() -> None:
    # 12.5 spacings across, where the lattice points inside hold the sphere's volume (0.5 %).
    r = 0.25
    points = lattice(26) - 13 * SPACING
    points = points[np.linalg.norm(points, axis=1) < r]
    mesh = sluice.reconstruct_surface(points, RADIUS)
    assert mesh.vertices.dtype == np.float32 and mesh.vertices.shape[1] == 3
    assert mesh.normals.dtype == np.float32 and mesh.normals.shape == mesh.vertices.shape
    assert mesh.triangles.dtype == np.uint32 and mesh.triangles.shape[1] == 3
    assert_closed_manifold_edges(mesh)
    assert mesh.volume == pytest.approx(4.0 / 3.0 * np.pi * r ** 3, rel=0.02)
    assert mesh.volume == pytest.approx(len(points) * SPACING ** 3, rel=0.01)
    outward = np.einsum("ij,ij->i", mesh.normals, mesh.vertices / np.linalg.norm(
        mesh.vertices, axis=1, keepdims=True))
    assert outward.min() > 0.8


def test_a_box_of_particles_has_its_volume_and_any_order_gives_the_same_mesh() -> None:
    points = lattice(16)
    mesh = sluice.reconstruct_surface(points, RADIUS)
    assert mesh.volume == pytest.approx((16 * SPACING) ** 3, rel=0.02)
    again = sluice.reconstruct_surface(points[::-1].copy(), RADIUS)
    assert np.array_equal(mesh.vertices, again.vertices)
    assert np.array_equal(mesh.triangles, again.triangles)


def test_the_isotropic_kernels_are_density_normalised_by_default() -> None:
    """Each kernel scaled by the rest density over its particle's own, as splashsurf's: a
    small ball keeps the particles' own volume (the rest-volume field loses 4 %) and a lone
    particle is a drop. The anisotropic kernels are not, unless asked."""
    points = lattice(10) - 5 * SPACING
    points = points[np.linalg.norm(points, axis=1) < 0.1]
    own = len(points) * SPACING ** 3
    mesh = sluice.reconstruct_surface(points, RADIUS)
    normalised = sluice.reconstruct_surface(points, RADIUS, normalised=True)
    plain = sluice.reconstruct_surface(points, RADIUS, normalised=False)
    assert np.array_equal(mesh.vertices, normalised.vertices)
    assert np.array_equal(mesh.triangles, normalised.triangles)
    assert mesh.volume == pytest.approx(own, rel=0.015)
    assert plain.volume < 0.97 * own
    assert len(sluice.reconstruct_surface(points[:1], RADIUS).triangles) > 0
    assert len(sluice.reconstruct_surface(points[:1], RADIUS, normalised=False).triangles) == 0
    flat = sluice.reconstruct_surface(points, RADIUS, anisotropic=True)
    flat_plain = sluice.reconstruct_surface(points, RADIUS, anisotropic=True, normalised=False)
    assert np.array_equal(flat.vertices, flat_plain.vertices)


def read_ply(path: Path):
    """The vertex (and face) arrays of a binary little-endian PLY with float and uint
    properties, as sluice-play writes them."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    elements, current = [], None
    for line in header:
        words = line.split()
        if words[0] == "element":
            current = [words[1], int(words[2]), []]
            elements.append(current)
        elif words[0] == "property":
            current[2].append(words[-1] if words[1] != "list" else "list")
    at, out = end, {}
    for name, count, props in elements:
        if props == ["list"]:
            faces = np.frombuffer(data, dtype=[("n", "u1"), ("i", "<u4", (3,))], count=count,
                                  offset=at)
            out[name] = faces["i"]
            at += 13 * count
        else:
            dtype = [(p, "<u4" if p == "id" else "<f4") for p in props]
            out[name] = np.frombuffer(data, dtype=dtype, count=count, offset=at)
            at += 4 * len(props) * count
    return out


@pytest.mark.parametrize("kernel, anisotropic, normalised",
                         [("gaussian", False, None), ("poly6", False, None),
                          ("gaussian", True, None), ("gaussian", False, False),
                          ("gaussian", True, True)])
def test_the_command_line_and_python_give_the_same_mesh(tmp_path: Path, kernel: str,
                                                        anisotropic: bool,
                                                        normalised: Optional[bool]) -> None:
    scene = Path(__file__).resolve().parents[2] / "assets" / "martin-moyce.json"
    run_tool("sluice-play", scene, "--headless", "--steps", 2, "--deterministic", "--quiet",
             "--dump-ply", tmp_path / "ply", "--dump-every", 2, "--surface-mesh",
             tmp_path / "mesh", "--surface-every", 2,
             "--surface-kernel", kernel, *(["--surface-anisotropic"] if anisotropic else []),
             *({None: [], True: ["--surface-normalised"],
                False: ["--no-surface-normalised"]}[normalised]))
    particles = read_ply(tmp_path / "ply" / "frame_000002.ply")["vertex"]
    points = np.stack([particles["x"], particles["y"], particles["z"]], -1)
    cli = read_ply(tmp_path / "mesh" / "surface_000002.ply")
    mesh = sluice.reconstruct_surface(points, RADIUS, anisotropic=anisotropic, kernel=kernel,
                                      normalised=normalised)
    assert set(mesh.timings) == {"bounds", "kernels", "blocks", "field", "contour", "download"}
    assert (mesh.timings["kernels"] > 0.0) == anisotropic
    # The isotropic kernels differ from each other and from the anisotropic ones.
    if not anisotropic:
        shape = sluice.reconstruct_surface(points, RADIUS, kernel="poly6" if kernel == "gaussian"
                                           else "gaussian", normalised=normalised)
        assert shape.vertices.shape != mesh.vertices.shape or not np.array_equal(
            shape.vertices, mesh.vertices)
        assert shape.volume == pytest.approx(mesh.volume, rel=0.05)
    # The two kernels give two different meshes.
    other = sluice.reconstruct_surface(points, RADIUS, anisotropic=not anisotropic,
                                       kernel=kernel, normalised=normalised)
    assert other.vertices.shape != mesh.vertices.shape or not np.array_equal(other.vertices,
                                                                             mesh.vertices)
    cli_vertices = np.stack([cli["vertex"][k] for k in ("x", "y", "z")], -1)
    cli_normals = np.stack([cli["vertex"][k] for k in ("nx", "ny", "nz")], -1)
    assert np.array_equal(mesh.vertices, cli_vertices)
    assert np.array_equal(mesh.normals, cli_normals)
    assert np.array_equal(mesh.triangles, cli["face"])
    # And the live simulation's own surface, after the same steps.
    sim = sluice.Simulation(scene, deterministic=True)
    sim.step(2, progress=False)
    live = sim.surface_mesh(anisotropic=anisotropic, kernel=kernel, normalised=normalised)
    assert np.array_equal(live.triangles, mesh.triangles)
    assert np.array_equal(live.vertices, mesh.vertices)
    # save_ply writes what sluice-play writes, header comment aside.
    live.save_ply(tmp_path / "live.ply")
    saved = read_ply(tmp_path / "live.ply")
    assert np.array_equal(saved["face"], cli["face"])
    assert np.array_equal(saved["vertex"], cli["vertex"])


@pytest.mark.parametrize("points, radius, kw, text", [
    (np.zeros((4, 2)), RADIUS, {}, r"shape \(N, 3\)"),
    (np.zeros((4, 3)), 0.0, {}, "particle radius"),
    (np.array([[0.0, 0.0, 0.0], [np.nan, 0.0, 0.0]]), RADIUS, {}, "particle 1 is not finite"),
    (np.zeros((4, 3)), RADIUS, {"cell_size": -1.0}, "cell size"),
    (np.zeros((4, 3)), RADIUS, {"anisotropic": True, "centre_smoothing": 1.5}, "centre smoothing"),
    (np.zeros((4, 3)), RADIUS, {"anisotropic": True, "centre_smoothing": -0.1}, "centre smoothing"),
    (np.zeros((4, 3)), RADIUS, {"kernel": "cubic"}, "kernel must be 'gaussian' or 'poly6'"),
])
def test_bad_input_raises_invalid_argument(points, radius, kw, text) -> None:
    with pytest.raises(sluice.InvalidArgument, match=text):
        sluice.reconstruct_surface(points, radius, **kw)


def test_no_points_give_an_empty_mesh() -> None:
    mesh = sluice.reconstruct_surface(np.zeros((0, 3), np.float32), RADIUS)
    assert mesh.vertices.shape == (0, 3) and mesh.triangles.shape == (0, 3)
    assert mesh.volume == 0.0


def test_a_simulation_deleted_while_the_mesher_is_current_leaves_the_mesher_whole() -> None:
    # Found when the bounds moved to the GPU: deleting a Simulation ran its GL deletes in
    # whichever context was current, the mesher's, and took the mesher's buffers with them.
    points = lattice(8)
    before = sluice.reconstruct_surface(points, RADIUS)
    scene = Path(__file__).resolve().parents[2] / "assets" / "martin-moyce.json"
    sim = sluice.Simulation(scene)
    sim.step(1, progress=False)
    sluice.reconstruct_surface(points, RADIUS)  # the mesher's context is current now
    del sim
    after = sluice.reconstruct_surface(points, RADIUS)
    assert len(before.triangles) > 0
    assert np.array_equal(after.vertices, before.vertices)
    assert np.array_equal(after.triangles, before.triangles)
