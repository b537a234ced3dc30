"""Fluid surfaces from particles: the GPU reconstruction of ``sluice-play --surface-mesh``
(docs/surfaces.md) for any (N, 3) points."""

from __future__ import annotations

import os
import threading
from typing import Any, Optional, Union

import numpy as np

from . import _sluice
from ._errors import InvalidArgument


class SurfaceMesh:
    """A closed, manifold triangle mesh: ``vertices`` (V, 3) float32 [m], unit ``normals``
    (V, 3) float32 pointing out of the fluid, ``triangles`` (T, 3) uint32, counter-clockwise
    seen from outside. ``timings``: where the reconstruction's time went, {stage: ms} (bounds,
    kernels, blocks, field, contour, download; docs/surfaces.md)."""

    def __init__(self, vertices: np.ndarray, normals: np.ndarray, triangles: np.ndarray,
                 timings: Optional[dict] = None) -> None:
        self.vertices = vertices
        self.normals = normals
        self.triangles = triangles
        self.timings = dict(timings or {})

    @property
    def volume(self) -> float:
        """The enclosed volume [m^3] (divergence theorem, in double precision)."""
        v = self.vertices.astype(np.float64)
        a, b, c = (v[self.triangles[:, k]] for k in range(3))
        return float(np.einsum("ij,ij->", a, np.cross(b, c)) / 6.0)

    def save_ply(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes a binary little-endian PLY, as ``--surface-mesh`` does."""
        header = ("ply\nformat binary_little_endian 1.0\ncomment fluid surface written by sluice\n"
                  f"element vertex {len(self.vertices)}\n"
                  "property float x\nproperty float y\nproperty float z\n"
                  "property float nx\nproperty float ny\nproperty float nz\n"
                  f"element face {len(self.triangles)}\n"
                  "property list uchar uint vertex_indices\nend_header\n").encode("ascii")
        vertex = np.hstack([self.vertices, self.normals]).astype("<f4")
        face = np.zeros(len(self.triangles), dtype=[("n", "u1"), ("i", "<u4", (3,))])
        face["n"] = 3
        face["i"] = self.triangles
        tmp = os.fspath(path) + ".tmp"
        with open(tmp, "wb") as f:
            f.write(header)
            f.write(vertex.tobytes())
            f.write(face.tobytes())
        os.replace(tmp, path)

    def __repr__(self) -> str:
        return f"SurfaceMesh({len(self.vertices)} vertices, {len(self.triangles)} triangles)"


_local = threading.local()


def _mesher() -> "_sluice.SurfaceMesher":
    """This thread's context with the surface passes compiled, made at its first call (a GL
    context is current on one thread at a time) and again in a child process, which must not
    use its parent's."""
    if getattr(_local, "pid", None) != os.getpid():
        _local.mesher = None
        _local.mesher = _sluice.SurfaceMesher()
        _local.pid = os.getpid()
    return _local.mesher


def reconstruct_surface(points: Any, particle_radius: float, *, cell_size: Optional[float] = None,
                        iso: Optional[float] = None, smoothing_radius: Optional[float] = None,
                        anisotropic: bool = False,
                        centre_smoothing: Optional[float] = None,
                        kernel: str = "gaussian",
                        normalised: Optional[bool] = None) -> SurfaceMesh:
    """The fluid surface of (N, 3) particle positions, reconstructed on the GPU in a headless
    context of this thread's own, kept for the next call (docs/surfaces.md): an SPH colour
    field of the particles (as wide as poly6 over ``smoothing_radius``, default 4 particle
    radii), each particle's kernel scaled by the rest density over its own as splashsurf's is,
    sampled on a sparse grid of ``cell_size`` (default: the particle radius) where the particles
    reach, contoured at ``iso`` (a share of the field inside the fluid; default 0.6, which puts
    a flat surface about half a spacing beyond the outer particles' centres). The same points
    give the same mesh as ``sluice-play --surface-mesh``, bit for bit. ``anisotropic=True``
    gives each particle a kernel shaped by its neighbours (after Yu & Turk 2013: flat across
    surfaces and thin sheets, which then stay whole), as ``--surface-anisotropic``; its centre
    moves ``centre_smoothing`` (in [0, 1], default 0.25) of the way to its neighbours' mean.
    ``kernel`` is the isotropic kernel's shape, as ``--surface-kernel``: ``"gaussian"``
    (default: a Gaussian as wide as poly6, deposited and blurred) or ``"poly6"`` (splatted
    particle by particle, slower on a software renderer). ``normalised=False`` scales each
    kernel by the rest volume alone instead (``--no-surface-normalised``; one field pass, iso
    default 0.5): thin sheets and droplets then lose volume, and curved surfaces move in or
    out by up to a fifth of a radius. The default (None) normalises the isotropic kernels and
    not the anisotropic ones, which keep thin sheets by their shape."""
    p = np.asarray(points)
    if p.ndim != 2 or p.shape[1] != 3:
        raise InvalidArgument(f"reconstruct_surface: points must have shape (N, 3), not "
                              f"{p.shape} [InvalidArgument]", "InvalidArgument")
    if kernel not in ("gaussian", "poly6"):
        raise InvalidArgument(f"reconstruct_surface: kernel must be 'gaussian' or 'poly6', not "
                              f"{kernel!r} [InvalidArgument]", "InvalidArgument")
    p = np.ascontiguousarray(p, dtype=np.float32)
    v, n, t, timings = _mesher().reconstruct(p, float(particle_radius), float(cell_size or 0.0),
                                    float(smoothing_radius or 0.0), float(iso or 0.0),
                                    bool(anisotropic),
                                    None if centre_smoothing is None else float(centre_smoothing),
                                    kernel == "poly6",
                                    None if normalised is None else bool(normalised))
    return SurfaceMesh(v, n, t, timings)
