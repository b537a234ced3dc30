"""Shared fixtures of the Python tests: the built programs, small meshes, a scratch folder.

Run by ctest (tests/python/CMakeLists.txt) with PYTHONPATH at the built package and
SLUICE_BIN_DIR at the built sluice-bake and sluice-play.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
ASSETS = REPO / "assets"
ASSIMP_MODELS = Path("/usr/share/assimp/models")


def bin_dir() -> Path:
    found = os.environ.get("SLUICE_BIN_DIR")
    if found:
        return Path(found)
    return REPO / "build" / "dev" / "bin"


def run_tool(name: str, *args: str, check: bool = True) -> subprocess.CompletedProcess:
    """Runs sluice-bake or sluice-play with `args`; returns the completed process."""
    exe = bin_dir() / name
    if not exe.exists():
        pytest.skip(f"{exe} is not built")
    done = subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True,
                          timeout=300)
    if check and done.returncode != 0:
        raise AssertionError(f"{name} {' '.join(map(str, args))} exited {done.returncode}:\n"
                             f"{done.stdout}\n{done.stderr}")
    return done


def write_tetrahedron(path: Path, scale: float = 1.0) -> Path:
    """A closed tetrahedron OBJ, 4 triangles (bakes in milliseconds)."""
    s = scale
    path.write_text(f"v 0 0 0\nv {s} 0 0\nv 0 {s} 0\nv 0 0 {s}\n"
                    "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    return path


@pytest.fixture
def tetra(tmp_path: Path) -> Path:
    return write_tetrahedron(tmp_path / "tetra.obj")


@pytest.fixture
def sphere_obj(tmp_path: Path) -> Path:
    """The demo sphere (assets/sphere.obj), copied so outputs land in tmp_path."""
    return Path(shutil.copy(ASSETS / "sphere.obj", tmp_path / "sphere.obj"))


@pytest.fixture
def ctx_ok() -> bool:
    """True when an OpenGL 4.5 context opens here (llvmpipe counts)."""
    done = run_tool("sluice-bake", "gl-info", check=False)
    return done.returncode == 0


def dump_json(path: Path, value) -> Path:
    path.write_text(json.dumps(value, indent=2))
    return path
