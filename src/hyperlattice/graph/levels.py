r"""The graph's level result: :class:`Spectrum`, the lowest levels of a lattice Hamiltonian.

It lives below every route that produces it (:mod:`hyperlattice.graph.spectrum` chooses the
route, :mod:`hyperlattice.graph.sectors` solves the sector-only flakes), so that both import it
and neither imports the other's module for it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..results import Levels

__all__ = ["Spectrum"]


# ----------------------------------------------------------------------------
# the result
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class Spectrum(Levels):
    r"""Lowest levels of a lattice Hamiltonian with their labels (a :class:`~hyperlattice.results.Levels`).

    Attributes
    ----------
    energies : ndarray, shape (K,)
        Ascending eigenvalues of :math:`H = -tA` (plus the on-site term and flux phases), in the
        unit in which ``t`` was given (units of t for the default t = 1); a degenerate
        :math:`\pm m` pair appears twice (once per state).
    n : ndarray of int, shape (K,)
        Index 1, 2, ... of the level within its rotation sector m.
    m : ndarray of int, shape (K,), or None
        The signed rotation sector in :math:`(-p/2, p/2]`; the pair +m, -m is listed +m first.
        ``None`` if the on-site term breaks the rotation (then n just counts levels). The lattice
        knows the angular momentum only modulo p (:attr:`sector`): a level of sector m may
        continue the continuum level of angular momentum m, m - p, m + p, ...; the continuum
        (n, m) it continues is assigned by
        :func:`hyperlattice.compare.levels.continuum_labels` (what ``hyperlattice spectrum``
        prints).
    errors : ndarray, shape (K,)
        :math:`\|H\psi - E\psi\|` of each normalised state (also available as ``residuals``).
    error_kind : str
        Always ``"residual"``.
    method : str
        ``"dense"``, ``"sparse"``, ``"sector-dense"``, ``"sector-shift-invert"`` or ``"sector-sparse"``
        (what actually ran).
    description : str
        One sentence on what ran.
    p, q, rings, sites : int
        Schläfli symbol, rings and number of sites N of the lattice.
    kind : str
        ``"sites"`` or ``"line_graph"``.
    timings : dict
        Wall-clock seconds of the stages (``"setup"``, ``"solve"``, ``"total"``, per sector).
    eigenvectors : ndarray, shape (N, K), or None
        Normalised states (complex for m not in {0, p/2} or nonzero flux), column k belonging
        to ``energies[k]``; rows are sites, 0-based ring by ring as in the lattice.
    flux : float
        Flux quanta per p-gon face of a uniform field (0 without field).
    requested_sector : int or None
        The signed sector the levels were restricted to (``lowest_levels(..., sector=)``), or
        None when the K lowest states of all sectors were asked for.
    backend : str
        The sparse factorisation that ran (``"cholmod"`` or ``"superlu"``, see
        :mod:`hyperlattice.graph.factor`), or ``""`` when none did.

    Examples
    --------
    >>> from hyperlattice import lowest_levels, ring_lattice
    >>> spec = lowest_levels(ring_lattice(7, 3, 2), 4)
    >>> spec.method, [round(float(e), 4) for e in spec.energies]
    ('sector-dense', [-2.6364, -2.2833, -2.2833, -1.9281])
    >>> spec.n.tolist(), spec.m.tolist()
    ([1, 1, 1, 1], [0, 1, -1, 2])
    >>> bool(spec.residuals.max() < 1e-10)
    True
    """

    error_kind: str = "residual"
    description: str = ""
    rings: int
    sites: int
    kind: str = "sites"
    timings: dict = field(default_factory=dict)
    eigenvectors: np.ndarray | None = None
    flux: float = 0.0
    backend: str = ""
    requested_sector: int | None = None

    @property
    def residuals(self) -> np.ndarray:
        r""":math:`\|H\psi - E\psi\|` of each normalised state (the same array as ``errors``)."""
        return self.errors

    @property
    def sector(self) -> np.ndarray | None:
        r"""The rotation sector :math:`k = m \bmod p \in \{0, \dots, p-1\}` of each level (None without rotation).

        This is all the lattice knows of the angular momentum: the p-fold rotation multiplies a
        state of sector k by :math:`e^{2\pi\mathrm i k/p}`, the same phase for m = k, k - p, k + p, ...
        """
        return None if self.m is None else np.mod(self.m, self.p)

    def summary(self) -> dict:
        """p, q, rings, sites, method, energies, n, m (index within the sector and signed sector), residuals
        (+ flux if nonzero). The CLI prints the continuum-labelled form
        (:class:`hyperlattice.compare.levels.LabelledSpectrum`)."""
        out = {
            "p": self.p, "q": self.q, "rings": self.rings, "sites": self.sites, "method": self.method,
            "energies": [float(e) for e in self.energies],
            "n": [int(v) for v in self.n],
            "m": None if self.m is None else [int(v) for v in self.m],
            "residuals": [float(r) for r in self.errors],
        }
        if self.flux != 0.0:
            out["flux"] = float(self.flux)
        return out
