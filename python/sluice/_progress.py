"""Progress display for long calls: tqdm where installed, else the command line's bar."""

from __future__ import annotations

import time
from typing import Callable, Optional, Tuple


def progress_hooks(label: str, progress: bool
                   ) -> Tuple[bool, Optional[Callable[[int, int], None]], Callable[[], None]]:
    """(use the C++ bar, callback(done, total) or None, close()) for one long call.

    The callback shows a tqdm bar once the work has run for a second, as the command line's
    bar does; without tqdm the C++ bar (stderr) is used instead.
    """
    if not progress:
        return False, None, lambda: None
    try:
        from tqdm.auto import tqdm  # type: ignore
    except ImportError:
        return True, None, lambda: None
    start = time.monotonic()
    state = {"bar": None, "done": 0}

    def update(done: int, total: int) -> None:
        if state["bar"] is None:
            if time.monotonic() - start < 1.0:
                return
            unit = "step" if label == "stepping" else "voxel"
            state["bar"] = tqdm(total=total, desc=label, unit=unit, unit_scale=True)
        state["bar"].update(done - state["done"])
        state["done"] = done

    def close() -> None:
        if state["bar"] is not None:
            state["bar"].close()

    return False, update, close
