"""Magnetism on the package's graphs: quantum spin-1/2 XXZ by SSE (:mod:`hyperlattice.spins.quantum`)."""
