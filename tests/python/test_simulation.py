"""A short simulation through Python: the particle count the scene states, finite positions
outside the collider, the statistics of `sluice-play --stats-json` for the same deterministic
run, live parameters and snapshots."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import sluice
from conftest import ASSETS, dump_json, run_tool

STEPS = 4


def scene_dict(collider: str) -> dict:
    return {
        "simulation": {"spacing": 0.02, "maxIterations": 4},
        "fluid": [{"box": {"min": [-0.1, 0.14, -0.1], "max": [0.1, 0.24, 0.1]}}],
        "colliders": [{"asset": collider, "friction": 0.1}],
        "domain": {"min": [-0.2, -0.2, -0.2], "max": [0.2, 0.4, 0.2]},
    }


@pytest.fixture
def scene(sphere_obj: Path, tmp_path: Path) -> Path:
    """A block of water above a 10 cm sphere collider (baked through Python)."""
    sluice.bake(sphere_obj, resolution=16, backend="cgal", scale=0.1).save(tmp_path / "ball.slc")
    return dump_json(tmp_path / "scene.json", scene_dict("ball.slc"))


def test_a_short_run_matches_sluice_play_stats_json(scene: Path, tmp_path: Path) -> None:
    stats_file = tmp_path / "stats.json"
    run_tool("sluice-play", scene, "--headless", "--steps", STEPS, "--stats-every", 1,
             "--deterministic", "--quiet", "--stats-json", stats_file)
    cli = json.loads(stats_file.read_text())

    sim = sluice.Simulation(scene, deterministic=True)
    assert sim.particle_count == cli["steps"][0]["particles"]
    assert sim.parameters == cli["parameters"]
    rows = []
    for _ in range(STEPS):
        sim.step()
        rows.append(sim.stats)
    assert rows == cli["steps"]
    assert sim.steps == STEPS and sim.time == pytest.approx(rows[-1]["time"])


def test_positions_are_finite_outside_the_collider_and_as_many_as_the_scene_says(
        scene: Path) -> None:
    sim = sluice.Simulation(scene)
    # 10 x 5 x 10 lattice points at 2 cm in the 20 x 10 x 20 cm block (docs/pbf.md).
    n = sim.particle_count
    assert n == 10 * 5 * 10
    before = sim.positions
    assert before.shape == (n, 3) and before.dtype == np.float32
    sim.step(5)
    pos, vel = sim.positions, sim.velocities
    assert pos.shape == (n, 3) and vel.shape == (n, 3)
    assert np.isfinite(pos).all() and np.isfinite(vel).all()
    assert pos[:, 1].mean() < before[:, 1].mean()  # falling
    assert (np.linalg.norm(pos, axis=1) > 0.1 - 0.02).all()  # none deep inside the ball
    assert sim.stats["insideColliders"] == 0 and sim.stats["nonFinite"] == 0


def test_a_scene_dict_with_relative_assets_uses_base_dir(scene: Path) -> None:
    sim = sluice.Simulation(scene_dict("ball.slc"), base_dir=scene.parent)
    assert sim.particle_count == 500
    with pytest.raises(sluice.FileError):
        sluice.Simulation(scene_dict("ball.slc"), base_dir=scene.parent / "elsewhere")


def test_snapshots_restore_the_state(scene: Path) -> None:
    sim = sluice.Simulation(scene, deterministic=True)
    sim.step(2)
    snap = sim.particles
    assert set(snap) == {"positions", "velocities", "ids"}
    assert sorted(snap["ids"]) == list(range(sim.particle_count))
    sim.step(2)
    after = sim.positions
    sim.set_particles(snap)
    assert np.array_equal(sim.positions, snap["positions"])
    sim.step(2)
    assert np.allclose(sim.positions, after, atol=1e-4)
    # Hand-made particles: fewer of them, at rest.
    sim.set_particles(positions=[[0.0, 0.3, 0.0], [0.05, 0.3, 0.0]])
    assert sim.particle_count == 2
    sim.step()
    assert sim.velocities[:, 1].max() < 0.0


def test_live_parameters_change_the_run(scene: Path) -> None:
    sim = sluice.Simulation(scene)
    sim.set_parameters(gravity=[0.0, 0.0, 0.0], xsph=0.02, max_iterations=3)
    params = sim.parameters
    assert params["gravity"] == [0.0, 0.0, 0.0] and params["maxIterations"] == 3
    assert params["xsph"] == pytest.approx(0.02)
    # One boundary model: nothing to choose while running.
    assert "boundary" not in params
    with pytest.raises(sluice.InvalidArgument, match="simulation.boundary: not a parameter"):
        sim.set_parameters(boundary="bodies")
    falling = sluice.Simulation(scene)
    sim.step(3)
    falling.step(3)
    # Without gravity the block does not fall: its mean vertical velocity stays near 0, where
    # the same block under gravity falls at g t (3 steps of 1/60 s: 0.49 m/s).
    assert abs(sim.velocities[:, 1].mean()) < 0.02
    assert falling.velocities[:, 1].mean() == pytest.approx(-9.81 * 3 / 60, rel=0.05)


def test_steps_in_chunks_with_a_progress_bar_give_the_same_run(scene: Path, monkeypatch) -> None:
    import sys
    import types
    updates = []

    class FakeTqdm:
        def __init__(self, total, desc, **kw):
            updates.append(("open", total))

        def update(self, k):
            updates.append(k)

        def close(self):
            pass

    monkeypatch.setitem(sys.modules, "tqdm", types.ModuleType("tqdm"))
    monkeypatch.setitem(sys.modules, "tqdm.auto", types.SimpleNamespace(tqdm=FakeTqdm))
    a = sluice.Simulation(scene, deterministic=True)
    b = sluice.Simulation(scene, deterministic=True)
    a.step(6)                   # chunked, through the (fake) bar
    b.step(6, progress=False)   # one call
    assert a.steps == b.steps == 6
    assert np.array_equal(a.positions, b.positions)


def test_a_floating_box_reports_its_state_as_sluice_play_does(tmp_path: Path) -> None:
    """A dynamic box (analytic-free: baked from the shipped crate mesh at half the water's
    density) reports the same body state through Python as sluice-play's --stats-json."""
    sluice.bake(ASSETS / "crate.obj", resolution=16, backend="cgal").save(tmp_path / "box.slc")
    scene = dump_json(tmp_path / "float.json", {
        "simulation": {"spacing": 0.02, "maxIterations": 4},
        "fluid": [{"box": {"min": [-0.15, 0.0, -0.15], "max": [0.15, 0.08, 0.15]}}],
        "colliders": [{"asset": "box.slc", "translation": [0.0, 0.12, 0.0],
                       "dynamic": {"density": 500}}],
        "domain": {"min": [-0.15, 0.0, -0.15], "max": [0.15, 0.4, 0.15]},
    })
    stats_file = tmp_path / "stats.json"
    run_tool("sluice-play", scene, "--headless", "--steps", STEPS, "--stats-every", 1,
             "--deterministic", "--quiet", "--stats-json", stats_file)
    cli = json.loads(stats_file.read_text())

    sim = sluice.Simulation(scene, deterministic=True)
    sim.step(STEPS)
    bodies = sim.bodies
    assert bodies == cli["steps"][-1]["bodies"]
    assert sim.stats == cli["steps"][-1]
    (box,) = bodies
    assert box["collider"] == 0
    assert box["mass"] == pytest.approx(500 * 0.12 ** 3, rel=1e-6)  # the mesh's exact volume
    assert box["centreOfMass"][1] < 0.12  # it fell towards the water
    assert box["linearVelocity"][1] < 0


def test_the_solids_boundary_share_is_probed_where_walls_and_colliders_meet(scene: Path) -> None:
    # The domain's walls and the ball (2.5 cm radius) add boundary volume: a particle radius
    # from the floor it is the flat share, in the domain's corner three walls' (the walls'
    # product, docs/pbf.md), on the ball's top some (past its grid box, padded by 3 voxels, its
    # volume map does not reach: the flat closed form), far from everything none.
    r = 0.01
    points = [[0.0, -0.2 + r, 0.0], [-0.2 + r, -0.2 + r, -0.2 + r], [0.0, 0.025 + r, 0.0],
              [0.0, 0.3, 0.0]]
    solids = scene_dict("ball.slc")
    solids["simulation"]["boundary"] = "solids"  # the one model, named as older scenes may
    sim = sluice.Simulation(solids, base_dir=scene.parent)
    share, slope = sim.solid_boundary_at(points)
    assert share.shape == (4,) and slope.shape == (4, 3)
    floor, corner, ball, far = share
    assert 0.15 < floor < 0.3  # the calibrated flat share at a particle radius
    assert corner > 2.0 * floor
    assert 0.1 < ball < 0.3
    assert far == 0.0 and not slope[3].any()
    assert slope[0, 1] < 0.0  # the floor's share falls going up
    default = sluice.Simulation(scene_dict("ball.slc"), base_dir=scene.parent)
    assert np.array_equal(default.solid_boundary_at(points)[0], share), "the default is solids"
    # A scene naming the removed model plays with the one model, with a warning.
    removed = scene_dict("ball.slc")
    removed["simulation"]["boundary"] = "bodies"
    with pytest.warns(UserWarning, match='"bodies" was removed'):
        bodies = sluice.Simulation(removed, base_dir=scene.parent)
    assert np.array_equal(bodies.solid_boundary_at(points)[0], share)


def test_added_particles_get_new_ids_and_a_set_pose_moves_the_collider(scene: Path) -> None:
    room = scene_dict("ball.slc")
    room["simulation"]["capacity"] = 600
    sim = sluice.Simulation(room, base_dir=scene.parent)
    before = sim.particles["ids"]
    ids = sim.add_particles([[0.0, 0.3, 0.0], [0.02, 0.3, 0.0]], [[0.0, -1.0, 0.0]] * 2)
    assert list(ids) == [before.max() + 1, before.max() + 2]
    sim.set_collider_pose(0, (0.05, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
    sim.step(2)
    after = sim.particles
    assert set(after["ids"]) == set(before) | set(ids)
    assert np.isfinite(after["positions"]).all()
    with pytest.raises(sluice.InvalidArgument, match="collider 1 of 1"):
        sim.set_collider_pose(1, (0.0, 0.0, 0.0))
    with pytest.raises(sluice.Error, match="not finite"):
        sim.add_particles([[float("nan"), 0.0, 0.0]])
    assert sim.particle_count == len(after["ids"])


def test_a_capsule_shape_and_a_measured_floor_from_python(scene: Path) -> None:
    room = scene_dict("ball.slc")
    room["fluid"] = [{"box": {"min": [-0.1, 0.0, -0.1], "max": [0.1, 0.06, 0.1]}}]
    room["colliders"] = [
        {"shape": {"box": {"size": [1.0, 0.1, 1.0]}}, "translation": [0.0, -0.05, 0.0],
         "measureForce": True},
        {"shape": {"capsule": {"radius": 0.03, "height": 0.2}}, "translation": [0.1, 0.2, 0.0]},
    ]
    sim = sluice.Simulation(room, base_dir=scene.parent)
    assert sim.latest_forces() is None  # no step finished yet
    sim.step(3)
    sim.particles  # a readback: the GPU has finished every step
    reading = sim.latest_forces()
    assert reading is not None and reading["step"] == 3
    force, torque = reading["colliders"][0]
    assert force[1] < 0.0 and len(torque) == 3
    sim.measure_force(0, False)
    sim.step()
    assert sim.latest_forces() is None
    with pytest.raises(sluice.InvalidArgument, match="collider 2 of 2"):
        sim.measure_force(2)


def test_a_body_the_program_holds_stays_where_it_is_put(scene: Path) -> None:
    room = scene_dict("ball.slc")
    room["fluid"] = [{"box": {"min": [-0.1, -0.2, -0.1], "max": [0.1, -0.16, 0.1]}}]
    room["colliders"] = [{"shape": {"box": {"size": [0.06, 0.06, 0.06]}},
                          "translation": [0.0, 0.2, 0.0], "dynamic": {"density": 500}}]
    sim = sluice.Simulation(room, base_dir=scene.parent)
    with pytest.raises(sluice.InvalidArgument, match="setBodyKinematic"):
        sim.set_collider_pose(0, (0.0, 0.15, 0.0))
    sim.set_body_kinematic(0)
    sim.set_collider_pose(0, (0.0, 0.15, 0.0))
    sim.step(3)
    held = sim.bodies[0]
    assert held["kinematic"] and held["centreOfMass"][1] == pytest.approx(0.15, abs=1e-5)
    sim.set_body_kinematic(0, False)
    sim.step(3)  # falling from rest: about 1.3 cm in 3 steps
    free = sim.bodies[0]
    assert not free["kinematic"] and free["centreOfMass"][1] < 0.15 - 0.01
    with pytest.raises(sluice.InvalidArgument, match="collider 1 of 1"):
        sim.set_body_kinematic(1)
