"""bake_many: the entries of a batch manifest on any concurrent.futures.Executor."""

from __future__ import annotations


def bake_many(manifest_or_entries, executor=None):  # pragma: no cover - filled in below
    raise NotImplementedError
