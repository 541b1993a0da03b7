"""A small on-disk cache for expensive, deterministic results (JSON values).

Entries are keyed on a name, the inputs and the package version, so a new version never
reads an old result. The directory is ``$HYPERLATTICE_CACHE`` or ``~/.cache/hyperlattice``;
it can be deleted at any time (``hyperlattice reproduce --clear-cache``).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path
from typing import Callable

from . import __version__

__all__ = ["Cache", "default_cache_dir"]


def default_cache_dir() -> Path:
    env = os.environ.get("HYPERLATTICE_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "hyperlattice"


class Cache:
    """JSON cache keyed on (name, inputs, package version). ``enabled=False`` computes always."""

    def __init__(self, directory: str | Path | None = None, *, enabled: bool = True):
        self.directory = Path(directory) if directory is not None else default_cache_dir()
        self.enabled = enabled
        self.hits = 0
        self.misses = 0

    def _path(self, name: str, inputs: dict) -> Path:
        blob = json.dumps({"name": name, "inputs": inputs, "version": __version__}, sort_keys=True)
        digest = hashlib.sha256(blob.encode()).hexdigest()[:24]
        return self.directory / __version__ / f"{name}-{digest}.json"

    def get(self, name: str, inputs: dict, compute: Callable[[], dict]) -> dict:
        """Return the cached value for ``(name, inputs)`` or compute, store and return it."""
        path = self._path(name, inputs)
        if self.enabled and path.exists():
            try:
                with open(path) as fh:
                    value = json.load(fh)
                self.hits += 1
                return value
            except (OSError, ValueError):
                pass  # unreadable entry: recompute and overwrite
        value = compute()
        self.misses += 1
        if self.enabled:
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(".tmp")
            with open(tmp, "w") as fh:
                json.dump(value, fh)
            os.replace(tmp, path)
        return value

    def clear(self) -> None:
        """Delete the whole cache directory."""
        if self.directory.exists():
            shutil.rmtree(self.directory)
