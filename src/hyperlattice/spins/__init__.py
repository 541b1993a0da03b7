"""Magnetism on the package's graphs: classical spins (Ising, XY, Heisenberg) by cluster and
heat-bath Monte Carlo (:mod:`hyperlattice.spins.classical`), and quantum spins where a module for
them is installed alongside.

The names are imported on first use (numba kernels are never compiled at import).
"""

from __future__ import annotations

import importlib
import importlib.util

__all__ = ["classical_mc", "classical_mc_memory", "merge_classical", "ClassicalResult", "SpinWarning"]

_CLASSICAL = {"classical_mc", "classical_mc_memory", "merge_classical", "ClassicalResult", "SpinWarning", "MODELS"}


def __getattr__(name: str):
    if name in _CLASSICAL:
        return getattr(importlib.import_module(f"{__name__}.classical"), name)
    # the quantum spins' names, when their module is installed alongside
    if not name.startswith("_") and importlib.util.find_spec(f"{__name__}.quantum") is not None:
        quantum = importlib.import_module(f"{__name__}.quantum")
        if name in getattr(quantum, "__all__", ()):
            return getattr(quantum, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
