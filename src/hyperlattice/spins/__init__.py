"""Magnetism on the package's graphs: classical spins (Ising, XY, Heisenberg) by cluster and
heat-bath Monte Carlo (:mod:`hyperlattice.spins.classical`; parallel tempering over a set of
temperatures in :mod:`hyperlattice.spins.tempering`) and the quantum spin-1/2 XXZ model by
SSE on the bosons' directed-loop kernels (:mod:`hyperlattice.spins.quantum`).

The names are imported on first use (numba kernels are never compiled at import).
"""

from __future__ import annotations

import importlib

_CLASSICAL = ("classical_mc", "classical_mc_memory", "merge_classical", "ClassicalResult", "SpinWarning")
_TEMPERING = ("tempering_mc", "TemperingResult")
_QUANTUM = ("XXZResult", "XXZExact", "xxz_qmc", "xxz_exact", "merge_xxz")

__all__ = [*_CLASSICAL, *_TEMPERING, *_QUANTUM]


def __getattr__(name: str):
    if name in _CLASSICAL or name == "MODELS":
        return getattr(importlib.import_module(f"{__name__}.classical"), name)
    if name in _TEMPERING:
        return getattr(importlib.import_module(f"{__name__}.tempering"), name)
    if name in _QUANTUM:
        return getattr(importlib.import_module(f"{__name__}.quantum"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
