"""Sluice from Python: bake meshes into signed-distance colliders and run PBF fluids against them.

A thin layer over the C++ libraries (``sluice_bake``, ``sluice_format``, ``sluice_runtime``)
through the nanobind module ``sluice._sluice``: the same code, files and errors as the
``sluice-bake`` and ``sluice-play`` command lines. See docs/python.md.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _sluice
from ._errors import (AssetError, BakeError, Error, FileError, GpuError, InvalidArgument,
                      MeshError, SceneError)
from ._progress import progress_hooks

__all__ = [
    "Error", "FileError", "MeshError", "AssetError", "SceneError", "GpuError", "BakeError",
    "InvalidArgument", "Mesh", "Collider", "Simulation", "load_mesh", "bake", "read_asset",
    "validate", "bake_many", "tool_version", "reconstruct_surface", "SurfaceMesh",
]
__version__ = _sluice.__version__

PathLike = Union[str, "os.PathLike[str]"]

_SCENE_DICT_LABEL = "<scene dict>"
"""What error messages call a scene given as a dict (a file's path otherwise)."""


class Mesh:
    """A triangle mesh ready to bake: ``vertices`` (N, 3) float64, ``triangles`` (M, 3) uint32,
    and ``diagnostics``, what the baker reports about it (as ``sluice-bake bake --json``)."""

    def __init__(self, vertices: Any, triangles: Any, name: str = "arrays") -> None:
        v = np.ascontiguousarray(vertices, dtype=np.float64)
        t = np.asarray(triangles)
        if t.dtype.kind not in "iu":
            raise InvalidArgument("triangles: expected integer vertex indices [InvalidArgument]",
                                  "InvalidArgument")
        if t.size and (t.min() < 0 or t.max() > 0xFFFFFFFF):
            raise InvalidArgument("triangles: an index is out of range [InvalidArgument]",
                                  "InvalidArgument")
        t = np.ascontiguousarray(t, dtype=np.uint32)
        self.scale = 1.0
        if v.ndim != 2 or v.shape[1] != 3 or t.ndim != 2 or t.shape[1] != 3:
            raise InvalidArgument("vertices and triangles must have shape (N, 3) and (M, 3) "
                                  "[InvalidArgument]", "InvalidArgument")
        self._m = _sluice.mesh_from_arrays(v, t, name)

    @classmethod
    def _wrap(cls, core: "_sluice.Mesh") -> "Mesh":
        mesh = cls.__new__(cls)
        mesh._m = core
        mesh.scale = 1.0
        return mesh

    scale: float
    """The uniform scale the vertices were read at (recorded in a bake's provenance)."""

    @property
    def vertices(self) -> np.ndarray:
        """(N, 3) float64 welded vertex positions [world units], read-only, no copy."""
        return self._m.vertices

    @property
    def triangles(self) -> np.ndarray:
        """(M, 3) uint32 indices into ``vertices``, read-only, no copy."""
        return self._m.triangles

    @property
    def diagnostics(self) -> Dict[str, Any]:
        """Counts of triangles, vertices, degenerate triangles, boundary and non-manifold
        edges, ``closed`` and ``selfIntersecting``."""
        return self._m.diagnostics

    @property
    def source_file(self) -> str:
        return self._m.source_file

    @property
    def source_hash(self) -> str:
        """XXH3-64 of the file's bytes (16 hex digits), as assets record it."""
        return self._m.source_hash

    @property
    def path(self) -> str:
        return self._m.path

    def __repr__(self) -> str:
        d = self.diagnostics
        return f"<sluice.Mesh {self.source_file!r}: {d['triangles']} triangles, {d['vertices']} vertices>"


class Collider:
    """A baked collider: phi on a dense grid, negative inside [world units].

    ``values[i, j, k]`` is phi at ``origin + (i, j, k) * voxel_size``; it is a float32 view of
    the collider's own memory (no copy; x fastest in memory, as in the file).
    """

    def __init__(self, core: "_sluice.Collider") -> None:
        self._c = core

    @property
    def values(self) -> np.ndarray:
        return self._c.values

    @property
    def origin(self) -> Tuple[float, float, float]:
        """[world units] position of grid point (0, 0, 0)."""
        return self._c.origin

    @property
    def voxel_size(self) -> float:
        """[world units] spacing between grid points."""
        return self._c.voxel_size

    @property
    def dims(self) -> Tuple[int, int, int]:
        """[grid points] along x, y, z."""
        return self._c.dims

    @property
    def metadata(self) -> Dict[str, Any]:
        """The provenance, exactly the ``asset`` object of ``sluice-bake bake --json``."""
        return json.loads(self._c.metadata_json)

    @property
    def path(self) -> str:
        """The file read or last saved; empty for a collider only in memory."""
        return self._c.path

    @property
    def volume_map_supports(self) -> List[float]:
        """[asset units] the supports of the volume maps baked with it (``bake(volume_maps=)``,
        ``sluice-bake bake --volume-map``); a scene whose kernel radius over the collider's scale
        is one of them loads its map instead of building it."""
        return list(self._c.volume_map_supports)

    def save(self, path: PathLike) -> None:
        """Writes the asset atomically, as ``sluice-bake bake -o`` does."""
        self._c.save(os.fspath(path))

    def export_vdb(self, path: PathLike) -> None:
        """Writes an OpenVDB float level set, as ``sluice-bake export`` does."""
        self._c.export_vdb(os.fspath(path))

    def sample(self, points: Any) -> Tuple[np.ndarray, np.ndarray]:
        """The CPU trilinear sampler: ``(phi (N,) float32, gradient (N, 3) float64)`` at
        (N, 3) world positions (or one point of shape (3,))."""
        p = np.ascontiguousarray(points, dtype=np.float64)
        single = p.ndim == 1
        phi, grad = self._c.sample(p.reshape(-1, 3))
        return (phi[0], grad[0]) if single else (phi, grad)

    def __repr__(self) -> str:
        return f"<sluice.Collider dims={self.dims} voxel_size={self.voxel_size:g}>"


def tool_version() -> str:
    """"sluice-bake <version>", as assets record it."""
    return _sluice.tool_version()


def load_mesh(path: PathLike, scale: float = 1.0) -> Mesh:
    """Reads a mesh (any format assimp reads, or a level-set .vdb) at ``scale``, welded, with
    its diagnostics, exactly as ``sluice-bake bake`` reads it."""
    mesh = Mesh._wrap(_sluice.load_mesh(os.fspath(path), float(scale)))
    mesh.scale = float(scale)
    return mesh


def read_asset(path: PathLike) -> Collider:
    """Reads a collider asset (.slc), or the first float grid of a .vdb densely."""
    return Collider(_sluice.read_asset(os.fspath(path)))


def _as_mesh(mesh: Union[Mesh, PathLike, Tuple[Any, Any]], scale: Optional[float]) -> Mesh:
    if isinstance(mesh, Mesh):
        if scale is not None and float(scale) != mesh.scale:
            raise InvalidArgument(f"scale={scale}: the mesh was read at scale {mesh.scale}; "
                                  "read it again with load_mesh(path, scale) [InvalidArgument]",
                                  "InvalidArgument")
        return mesh
    s = 1.0 if scale is None else float(scale)
    if isinstance(mesh, tuple) and len(mesh) == 2:
        m = Mesh(np.asarray(mesh[0], dtype=np.float64) * s, mesh[1])
        m.scale = s
        return m
    return load_mesh(mesh, s)


def bake(mesh: Union[Mesh, PathLike, Tuple[Any, Any]], resolution: Optional[int] = None,
         voxel_size: Optional[float] = None, padding: float = 3.0, backend: str = "auto",
         sign: str = "auto", storage: str = "f32", scale: Optional[float] = None,
         sparse: bool = False, band: float = 3.0, for_spacing: Optional[float] = None,
         for_kernel_radius: Optional[float] = None, volume_maps: Sequence[float] = (),
         progress: bool = True) -> Collider:
    """Bakes a mesh into a collider, as ``sluice-bake bake`` does (same grid, field, provenance
    and, once saved, bytes).

    ``mesh`` is a Mesh (baked at the scale it was read at), a path (read at ``scale``, default
    1) or a ``(vertices, triangles)`` pair (scaled by ``scale``); the asset records the scale. Give ``resolution`` [voxels along the longest side, default 64] or
    ``voxel_size`` [world units]. ``sparse=True`` bakes a narrow band of ``band`` voxels into a
    NanoVDB grid (``sluice-bake bake --sparse --band``), on either backend; ``for_spacing``
    [world units] picks the band a scene of that particle spacing needs instead (``--for-spacing``,
    with ``for_kernel_radius`` for a scene's own kernel radius). ``volume_maps`` bakes the
    boundary model's volume map for each support (a scene's kernel radius over the collider's
    placement scale, ``--volume-map``; computed with OpenGL 4.5). The GIL is released
    while it runs; a progress bar shows for
    bakes over a second (tqdm where installed); Ctrl-C stops it (KeyboardInterrupt).
    """
    if resolution is not None and voxel_size is not None:
        raise InvalidArgument("give resolution or voxel_size, not both [InvalidArgument]",
                              "InvalidArgument")
    m = _as_mesh(mesh, scale)
    request = _sluice.BakeRequest()
    request.backend = backend
    request.resolution = 64 if resolution is None else int(resolution)
    request.voxel_size = 0.0 if voxel_size is None else float(voxel_size)
    request.padding = float(padding)
    request.sign = sign
    request.storage = storage
    request.scale = m.scale
    request.sparse = bool(sparse)
    request.band = float(band)
    if for_spacing is not None:
        if not sparse:
            raise InvalidArgument("for_spacing picks a sparse band: add sparse=True "
                                  "[InvalidArgument]", "InvalidArgument")
        request.for_spacing = float(for_spacing)
    if for_kernel_radius is not None:
        if for_spacing is None:
            raise InvalidArgument("for_kernel_radius goes with for_spacing [InvalidArgument]",
                                  "InvalidArgument")
        request.for_kernel_radius = float(for_kernel_radius)
    request.volume_maps = [float(h) for h in volume_maps]
    bar, callback, close = progress_hooks("baking " + m.source_file, progress)
    try:
        return Collider(_sluice.bake_mesh(m._m, request, bar, callback))
    finally:
        close()


def validate(collider: Union[Collider, PathLike], mesh: Union[Mesh, PathLike, Tuple[Any, Any]],
             samples: Optional[int] = None, sign: Optional[str] = None, seed: int = 1,
             max_error: Optional[float] = None, max_sign_errors: float = 0.0,
             progress: bool = True) -> Dict[str, Any]:
    """Checks a collider against the exact CGAL reference of its mesh; returns the report of
    ``sluice-bake validate --json`` as a dict (figures, limits, ``withinLimits``). ``mesh`` is
    taken as ``bake`` takes it: a Mesh as it is, while a path, read as the command line does, and
    a ``(vertices, triangles)`` pair are both scaled by the scale the collider records."""
    c = collider if isinstance(collider, Collider) else read_asset(collider)
    m = _as_mesh(mesh, None if isinstance(mesh, Mesh) else c.metadata["bake"]["scale"])
    request = _sluice.ValidateRequest()
    if samples is not None:
        request.samples = int(samples)
    if sign is not None:
        request.sign = sign
    request.seed = int(seed)
    request.max_error = max_error
    request.max_sign_errors_percent = float(max_sign_errors)
    bar, callback, close = progress_hooks("validating", progress)
    try:
        return json.loads(_sluice.validate_json(c._c, m._m, request, bar, callback))
    finally:
        close()


class Simulation:
    """Position Based Fluids on the GPU, in a headless OpenGL context of its own.

    ``scene`` is a scene file path or a dict in the scene format (docs/scene-format.md);
    collider assets in a dict are relative to ``base_dir`` (default: the current folder).
    ``deterministic=True`` gives identical bytes run to run, as ``sluice-play --deterministic``.
    """

    def __init__(self, scene: Union[PathLike, Dict[str, Any]], deterministic: bool = False,
                 base_dir: Optional[PathLike] = None) -> None:
        if isinstance(scene, dict):
            folder = os.fspath(base_dir) if base_dir is not None else os.getcwd()
            # The file name only anchors relative asset paths; messages say "<scene dict>".
            self._s = _sluice.SimulationCore.from_json(json.dumps(scene),
                                                       os.path.join(folder, "scene.json"),
                                                       deterministic, label=_SCENE_DICT_LABEL)
        else:
            self._s = _sluice.SimulationCore.from_file(os.fspath(scene), deterministic)

    def step(self, n: int = 1, progress: bool = True) -> None:
        """Advances ``n`` steps of the scene's timeStep. The GIL is released while the GPU
        works; Ctrl-C stops between steps (KeyboardInterrupt). Runs over a second show a tqdm
        bar where tqdm is installed."""
        if n < 0:
            raise InvalidArgument(f"step: n = {n} must be >= 0 [InvalidArgument]",
                                  "InvalidArgument")
        n = int(n)
        _, update, close = progress_hooks("stepping", progress)
        if update is None:
            self._s.step(n)
            return
        # In chunks of about 0.2 s, so the bar moves without a GPU sync per step.
        import time
        done, chunk = 0, 1
        try:
            while done < n:
                k = min(chunk, n - done)
                start = time.monotonic()
                self._s.step(k)
                done += k
                update(done, n)
                elapsed = time.monotonic() - start
                chunk = max(1, min(4 * chunk, int(k * 0.2 / elapsed) if elapsed > 0 else 4 * chunk))
        finally:
            close()

    @property
    def positions(self) -> np.ndarray:
        """(N, 3) float32 particle positions [m], in memory order (see ``particles``)."""
        return self._s.positions()

    @property
    def velocities(self) -> np.ndarray:
        """(N, 3) float32 particle velocities [m/s]."""
        return self._s.velocities()

    @property
    def particles(self) -> Dict[str, np.ndarray]:
        """A snapshot: ``{"positions", "velocities", "ids"}``; give it back to set_particles."""
        p, v, ids = self._s.particles()
        return {"positions": p, "velocities": v, "ids": ids}

    def set_particles(self, snapshot: Optional[Dict[str, Any]] = None, *,
                      positions: Any = None, velocities: Any = None, ids: Any = None) -> None:
        """Replaces every particle: a ``particles`` snapshot, or arrays (velocities default
        to zero, ids to 0..N-1)."""
        if snapshot is not None:
            positions, velocities, ids = (snapshot["positions"], snapshot["velocities"],
                                          snapshot["ids"])
        p = np.ascontiguousarray(positions, dtype=np.float32).reshape(-1, 3)
        v = (np.zeros_like(p) if velocities is None
             else np.ascontiguousarray(velocities, dtype=np.float32).reshape(-1, 3))
        i = (np.arange(len(p), dtype=np.uint32) if ids is None
             else np.ascontiguousarray(ids, dtype=np.uint32))
        self._s.set_particles(p, v, i)

    def add_particles(self, positions: Any, velocities: Any = None) -> np.ndarray:
        """Adds particles at (N, 3) ``positions`` [m] with ``velocities`` [m/s] (default at
        rest), uploading only them; returns their ids (every other particle keeps its own).
        They join at the next step."""
        p = np.ascontiguousarray(positions, dtype=np.float32).reshape(-1, 3)
        v = (None if velocities is None
             else np.ascontiguousarray(velocities, dtype=np.float32).reshape(-1, 3))
        first = self._s.add_particles(p, v)
        return np.arange(first, first + len(p), dtype=np.uint32)

    def set_collider_pose(self, index: int, translation: Sequence[float],
                          rotation: Sequence[float] = (0.0, 0.0, 0.0, 1.0)) -> None:
        """Places static or kinematic collider ``index`` (or a body held with
        ``set_body_kinematic``) at ``translation`` [m] and the
        quaternion ``rotation`` (x, y, z, w) by the end of the next step, moving there across
        its substeps (docs/embedding.md)."""
        self._s.set_collider_pose(int(index), [float(t) for t in translation],
                                  [float(r) for r in rotation])

    def set_body_kinematic(self, index: int, kinematic: bool = True) -> None:
        """Hands dynamic body ``index`` to the program (``kinematic``: from the next step it
        goes only where ``set_collider_pose`` puts it, the water still feeling it and reporting
        its force in ``bodies``) or back to the water (it keeps its last step's velocity)."""
        self._s.set_body_kinematic(int(index), bool(kinematic))

    def measure_force(self, index: int, on: bool = True) -> None:
        """Starts (or stops) measuring the water's force and torque on static or kinematic
        collider ``index`` from the next step (the scene's ``measureForce``)."""
        self._s.measure_force(int(index), bool(on))

    def latest_forces(self) -> Optional[Dict[str, Any]]:
        """The measured colliders' forces as the newest step the GPU has finished left them,
        without waiting: ``None`` until there is one, else ``{"step", "time", "colliders":
        {index: ((fx, fy, fz) [N], (tx, ty, tz) [N m] about its origin)}}``."""
        return self._s.latest_forces()

    @property
    def stats(self) -> Dict[str, Any]:
        """The latest step's statistics, as each entry of ``sluice-play --stats-json``'s
        ``steps``."""
        return json.loads(self._s.stats_json())

    @property
    def bodies(self) -> List[Dict[str, Any]]:
        """Every dynamic body after the latest step (docs/bodies.md), as ``--stats-json``'s
        ``bodies``: collider, mass, position (centre of mass), orientation [x, y, z, w],
        linearVelocity, angularVelocity, the fluid's force and torque, contacts. Empty
        without bodies."""
        return json.loads(self._s.bodies_json())

    @property
    def parameters(self) -> Dict[str, Any]:
        """The resolved parameters and derived constants (``--stats-json``'s ``parameters``)."""
        return json.loads(self._s.parameters_json())

    def set_parameters(self, **kw: Any) -> None:
        """Changes parameters from the next step on; keys as in the scene file's
        ``simulation`` object (``xsph=0.02``, ``maxIterations=4``; snake_case works too)."""
        def camel(key: str) -> str:
            head, *rest = key.split("_")
            return head + "".join(w[:1].upper() + w[1:] for w in rest)
        self._s.set_parameters({camel(k): v for k, v in kw.items()})

    @property
    def particle_count(self) -> int:
        return self._s.particle_count

    @property
    def capacity(self) -> int:
        return self._s.capacity

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._s.time

    @property
    def steps(self) -> int:
        return self._s.steps

    @property
    def renderer(self) -> str:
        """GL_RENDERER of the context ("llvmpipe (...)" without a GPU)."""
        return self._s.renderer

    def solid_boundary_at(self, points: Any) -> Tuple[np.ndarray, np.ndarray]:
        """The boundary volume the domain's walls and the static and kinematic colliders add to
        a particle's density at each of the (N, 3) points [m], as the solver adds it, volume
        maps included (docs/pbf.md,
        "Volume maps"): ``(shares (N,) float32 of rho / rho0, gradients (N, 3) float32 [1/m])``.
        """
        pts = np.ascontiguousarray(np.asarray(points, dtype=np.float32).reshape(-1, 3))
        return self._s.solid_boundary_at(pts)

    def surface_mesh(self, cell_size: Optional[float] = None, iso: Optional[float] = None,
                     smoothing_radius: Optional[float] = None, anisotropic: bool = False,
                     centre_smoothing: Optional[float] = None,
                     kernel: str = "gaussian",
                     normalised: Optional[bool] = None) -> "SurfaceMesh":
        """The fluid's surface now, as ``sluice-play --surface-mesh`` writes it
        (:func:`reconstruct_surface` of :attr:`positions` at the scene's particle radius)."""
        radius = self.parameters["derived"]["particleRadius"]
        return reconstruct_surface(self.positions, radius, cell_size=cell_size, iso=iso,
                                   smoothing_radius=smoothing_radius, anisotropic=anisotropic,
                                   centre_smoothing=centre_smoothing, kernel=kernel,
                                   normalised=normalised)


from ._batch import bake_entry, bake_many  # noqa: E402
from ._surface import SurfaceMesh, reconstruct_surface  # noqa: E402
