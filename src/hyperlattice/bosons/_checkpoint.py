"""The QMC chain's checkpoint file, lock and stop signals: :mod:`hyperlattice._mc_chain` (shared with
the spin chains), under the name the bosons' engine imports."""

from .._mc_chain import FORMAT, StopSignals, Stopped, digest, locked, read, write

__all__ = ["FORMAT", "StopSignals", "Stopped", "digest", "locked", "read", "write"]
