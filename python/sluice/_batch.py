"""bake_many: the entries of a batch manifest, baked on any concurrent.futures.Executor.

Each entry is one task: the worker reads the mesh and bakes it through the same library calls
as ``sluice-bake batch`` (the same freshness rule, the same bytes). A failing entry reports its
error and the others still bake. A local process pool is the default; a Dask cluster's
``Client.get_executor()`` (or any Executor whose workers can import sluice) spreads a content
library over a farm.
"""

from __future__ import annotations

import os
from concurrent.futures import Executor, ProcessPoolExecutor
from typing import Any, Dict, Iterable, List, Optional, Union

_OPTION_KEYS = ("resolution", "voxelSize", "padding", "sign", "storage", "scale", "backend",
                "sparse", "band", "forSpacing", "forKernelRadius")


def _entries(manifest_or_entries: Union[str, "os.PathLike[str]", Iterable[Dict[str, Any]]]
             ) -> List[Dict[str, Any]]:
    from . import _sluice
    if isinstance(manifest_or_entries, (str, os.PathLike)):
        return list(_sluice.read_batch_manifest(os.fspath(manifest_or_entries)))
    entries = []
    for n, e in enumerate(manifest_or_entries):
        if "mesh" not in e or "output" not in e:
            from ._errors import InvalidArgument
            raise InvalidArgument(f"entries[{n}] needs \"mesh\" and \"output\" [InvalidArgument]",
                                  "InvalidArgument")
        entry = {k: e[k] for k in _OPTION_KEYS if k in e}
        entry.update(mesh=os.fspath(e["mesh"]), output=os.fspath(e["output"]),
                     label=str(e.get("label", os.fspath(e["output"]))))
        entries.append(entry)
    return entries


def bake_entry(entry: Dict[str, Any], force: bool = False) -> Dict[str, Any]:
    """Bakes one manifest entry (in a worker): a result dict, never an exception for a sluice
    error: ``{"status": "baked" | "fresh" | "failed", "output", "label", "seconds", "points",
    "maxError", "error"}`` where ``error`` is ``{"type", "code", "message"}`` for a failure."""
    from . import _sluice
    from ._errors import Error
    if entry.get("backend", "auto") != "cgal" and _sluice.forked_from_gl_process():
        return _bake_entry_in_fresh_process(entry, force)
    request = _sluice.BakeRequest()
    request.resolution = int(entry.get("resolution", 64))
    request.voxel_size = float(entry.get("voxelSize", 0.0))
    request.padding = float(entry.get("padding", 3.0))
    request.sign = str(entry.get("sign", "auto"))
    request.storage = str(entry.get("storage", "f32"))
    request.scale = float(entry.get("scale", 1.0))
    request.backend = str(entry.get("backend", "auto"))
    request.sparse = bool(entry.get("sparse", False))
    request.band = float(entry.get("band", 3.0))
    request.for_spacing = float(entry.get("forSpacing", 0.0))
    request.for_kernel_radius = float(entry.get("forKernelRadius", 0.0))
    try:
        result = _sluice.bake_batch_entry(entry["mesh"], entry["output"], entry["label"], request,
                                          force, False, None)
        result["error"] = None
        return result
    except Error as e:
        return {"output": entry["output"], "label": entry["label"], "status": "failed",
                "seconds": 0.0, "points": 0, "maxError": None,
                "error": {"type": type(e).__name__, "code": e.code, "message": str(e)}}


# The child of _bake_entry_in_fresh_process: this interpreter's sys.path, then (entry, force) on
# stdin; the result pickled on the original stdout, which nothing else may write to.
_FRESH_PROCESS = """
import os, pickle, sys
out = os.fdopen(os.dup(1), "wb")
os.dup2(2, 1)
sys.path[:] = pickle.load(sys.stdin.buffer)
from sluice._batch import bake_entry
pickle.dump(bake_entry(*pickle.load(sys.stdin.buffer)), out)
"""


def _bake_entry_in_fresh_process(entry: Dict[str, Any], force: bool) -> Dict[str, Any]:
    """bake_entry in a new interpreter, for a worker forked from a process that had an OpenGL
    context open (a fork-started pool after a Simulation): GL drivers keep threads that fork()
    does not copy, so this process can open no context of its own (docs/python.md)."""
    import pickle
    import subprocess
    import sys
    payload = pickle.dumps(sys.path) + pickle.dumps((entry, force))
    done = subprocess.run([sys.executable, "-c", _FRESH_PROCESS], input=payload,
                          stdout=subprocess.PIPE, check=False)
    if done.returncode == 0:
        return pickle.loads(done.stdout)
    return {"output": entry["output"], "label": entry["label"], "status": "failed",
            "seconds": 0.0, "points": 0, "maxError": None,
            "error": {"type": "BakeError", "code": "Unknown",
                      "message": f"{entry['mesh']}: the process baking it (fresh, since this one "
                                 f"was forked from one with an OpenGL context) exited with "
                                 f"status {done.returncode}"}}


def bake_many(manifest_or_entries: Union[str, "os.PathLike[str]", Iterable[Dict[str, Any]]],
              executor: Optional[Executor] = None, force: bool = False) -> List[Dict[str, Any]]:
    """Bakes every entry of a batch manifest (a path, read as ``sluice-bake batch`` reads it) or
    of a list of entry dicts (``mesh``, ``output`` and the manifest's optional fields), one task
    per entry on ``executor``: by default a local process pool, or e.g. a Dask cluster's
    ``dask.distributed.Client(...).get_executor()``. Outputs are fresh (skipped) or baked to the
    same bytes as the command line; returns one result dict per entry, in order (see
    ``bake_entry``). A mesh that fails reports its error there; the others still bake. A
    fork-started pool works too: its workers bake in a fresh interpreter when they were forked
    from a process with an OpenGL context open (a Simulation), which cannot open one itself."""
    entries = _entries(manifest_or_entries)
    own = executor is None
    if own:
        import multiprocessing
        # spawn: no fork of a process that holds GL contexts and thread pools.
        executor = ProcessPoolExecutor(max_workers=max(1, min(len(entries), os.cpu_count() or 1)),
                                       mp_context=multiprocessing.get_context("spawn"))
    try:
        futures = [executor.submit(bake_entry, entry, force) for entry in entries]
        return [f.result() for f in futures]
    finally:
        if own:
            executor.shutdown()
