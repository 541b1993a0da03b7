"""Topological bands on embedded graphs: Chern and spin-Hall models, real-space markers that
quantise in hyperbolic space, Chern numbers of Abelian Bloch bands on closed surfaces.

Layer 3 (above graph/ and continuum/): :mod:`.models` (the models as hop lists),
:mod:`.markers` (flake invariants from dense diagonalisation), :mod:`.surfaces` (clusters:
Fukui–Hatsugai–Suzuki Chern numbers on the 2-subtori of the Abelian Brillouin zone),
:mod:`.kpm_marker` (the centre marker of big flakes by a Chebyshev expansion of the projector),
:mod:`.anderson` (the self-consistent Born approximation of disorder for the topological Anderson
insulator).
"""

from .markers import (EdgeChirality, FlakeTopology, OccupiedStates, edge_chirality, flake_topology, local_markers,
                      occupied_states)
from .models import (MODELS, ModelTerms, PlaneGraph, bloch_model_hamiltonian, honeycomb_flake, honeycomb_torus,
                     model_hamiltonian, model_terms, square_flake, square_torus)

__all__ = ["EdgeChirality", "edge_chirality", "FlakeTopology", "OccupiedStates", "flake_topology", "local_markers", "occupied_states", "MODELS",
           "ModelTerms", "PlaneGraph", "bloch_model_hamiltonian", "honeycomb_flake", "honeycomb_torus",
           "model_hamiltonian", "model_terms", "square_flake", "square_torus"]
