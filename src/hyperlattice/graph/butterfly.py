r"""The hyperbolic Hofstadter butterfly: all levels of a flake against the flux, sector by sector.

Built on :mod:`hyperlattice.graph.flux` (the Peierls phases), :mod:`hyperlattice.graph.symmetry`
(the angular-momentum blocks) and :mod:`hyperlattice.graph.solvers` (the one-thread BLAS guard);
it sits above them, so that ``flux`` stays a leaf of the graph layer (it imports only the lattice).
"""

from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.linalg as sla

from .. import _validate
from .._ties import eigenvalue_tolerance, stable_order
from .._progress import progress_bar
from ..cache import Cache, checkpoint_cache
from ..results import INDEX, Column, Grid, Result
from .flux import _flux
from .lattice import Lattice
from .operators import onsite_values
from .solvers import single_threaded_blas
from .symmetry import rotation_invariant, rotation_orbits, sector_table

__all__ = ["Butterfly", "butterfly"]


# ----------------------------------------------------------------------------
# the hyperbolic Hofstadter butterfly
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class Butterfly(Result):
    """All levels of a flake against the flux: the hyperbolic Hofstadter butterfly.

    Attributes
    ----------
    fluxes : ndarray, shape (F,)
        Flux quanta per p-gon, in the order given.
    energies : ndarray, shape (F, N)
        All N levels of :math:`H = -tA` with the Peierls phases of the flux (plus any on-site
        term) at each flux, ascending along each row, in the unit in which ``t`` was given.
    m : ndarray of int, shape (F, N)
        Signed angular momentum (rotation sector) of each level.
    p, q, rings, sites : int
        Schläfli symbol, number of rings and number of sites N of the flake.
    kind : str
        ``"sites"`` or ``"line_graph"``.
    t : float
        Hopping amplitude.
    method : str
        ``"sector-dense"``: LAPACK eigvalsh of each of the p blocks at each flux.
    description : str
        One sentence on what ran.
    timings : dict
        Wall-clock seconds (``"total"``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> b = hl.butterfly(hl.ring_lattice(7, 3, 2), [0.0, 0.25])
    >>> b.energies.shape, b.method
    ((2, 35), 'sector-dense')
    >>> [round(e, 4) for e in b.energies[:, 0].tolist()], b.m[:, 0].tolist()   # ground state
    ([-2.6364, -2.5585], [0, 0])
    """

    GRID = Grid(coords=(Column("flux", "fluxes", "flux quanta per p-gon"), Column("state", INDEX, "1")),
                variables=(Column("energy", "energies", "t", ("flux", "state")),
                           Column("m", "m", "1", ("flux", "state"))))

    fluxes: np.ndarray
    energies: np.ndarray
    m: np.ndarray
    p: int
    q: int
    rings: int
    sites: int
    kind: str = "sites"
    t: float = 1.0
    method: str = "sector-dense"
    description: str = ""
    timings: dict = field(default_factory=dict)

    def columns(self) -> dict[str, np.ndarray]:
        """Long-format columns ``flux``, ``m``, ``energy`` (one row per level and flux), for a table."""
        n = self.energies.shape[1]
        return {"flux": np.repeat(self.fluxes, n), "m": self.m.ravel().copy(),
                "energy": self.energies.ravel().copy()}

    def summary(self) -> dict:
        """Short view: sizes, flux range and energy range (the levels themselves are in ``columns``)."""
        return {"p": self.p, "q": self.q, "rings": self.rings, "sites": self.sites, "kind": self.kind,
                "method": self.method, "fluxes": int(self.fluxes.shape[0]),
                "flux_min": float(np.min(self.fluxes)), "flux_max": float(np.max(self.fluxes)),
                "energy_min": float(np.min(self.energies)), "energy_max": float(np.max(self.energies))}


def _lattice_key(lattice: Lattice, onsite) -> dict:
    """What identifies the operator of a butterfly point on disk: the lattice's arrays (digest) and
    the on-site values (digest), so a checkpoint entry never serves another lattice."""
    h = hashlib.sha256()
    for a in (np.ascontiguousarray(lattice.z, dtype=np.complex128),
              np.ascontiguousarray(lattice.edges, dtype=np.int64)):
        h.update(a.tobytes())
    v = onsite_values(lattice, onsite)
    site = None if v is None else hashlib.sha256(np.ascontiguousarray(v, dtype=np.float64).tobytes()).hexdigest()
    return {"p": int(lattice.p), "q": int(lattice.q), "rings": int(lattice.rings), "kind": str(lattice.kind),
            "sites": int(lattice.sites), "lattice": h.hexdigest(), "onsite": site}


def butterfly(lattice: Lattice, fluxes, *, t: float = 1.0, onsite=None, max_sites: int = 50_000,
              progress=None, checkpoint: Cache | Path | None = None) -> Butterfly:
    """All levels of a flake at each flux, sector by sector (the hyperbolic Hofstadter butterfly).

    At each flux f the p angular-momentum blocks :math:`H_m` (size N/p; the gauge of this
    module keeps the rotation symmetry) are diagonalised densely: about :math:`p^2` less work
    than the full N x N Peierls matrix.

    Parameters
    ----------
    lattice : Lattice
        Site lattice or line graph.
    fluxes : array of float
        Flux quanta per p-gon (positive = counterclockwise, see the module docstring); at
        least one value, each at most 1e6 in magnitude.
    t : float, optional
        Hopping amplitude, the energy unit; default 1.
    onsite : scalar, array or callable, optional
        Rotation-invariant on-site term in units of t; default None.
    max_sites : int, optional
        Largest N accepted (a dense computation per sector); default 50,000.
    progress : bool, None or callable, optional
        A bar over the flux values on stderr (:mod:`hyperlattice._progress`; None: when stderr is a
        terminal), or a function receiving one-line messages.
    checkpoint : path or Cache, optional
        Keep the levels of every finished flux value in this directory (a
        :class:`~hyperlattice.cache.Cache`: one entry per flux, keyed on the lattice's arrays, t,
        the on-site values and f); values already there are read, not recomputed, so a run stopped
        by Ctrl-C resumes with the same result, bit for bit.

    Returns
    -------
    Butterfly
        ``fluxes`` (F,), ``energies`` (F, N) ascending along each row in units of t, ``m``
        (F, N) the signed angular momentum of each level, ``method == "sector-dense"``.

    Raises
    ------
    ValueError
        Bad input, N above ``max_sites``, a rotation-breaking on-site term, or a result
        (flux values x N levels) above 2e8 numbers.

    See Also
    --------
    hyperlattice.graph.spectrum.full_spectrum, hyperlattice.continuum.magnetic.magnetic_levels

    Examples
    --------
    >>> import hyperlattice as hl
    >>> b = hl.butterfly(hl.ring_lattice(7, 3, 2), [0.0, 0.25])
    >>> b.energies.shape
    (2, 35)
    >>> [round(e, 6) for e in b.energies[:, 0].tolist()], b.m[:, 0].tolist()
    ([-2.636405, -2.558476], [0, 0])
    """
    t0 = time.perf_counter()
    _validate.lattice(lattice)
    f = _validate.real_array("fluxes", fluxes, ndim=1)
    if f.shape[0] == 0:
        raise ValueError("fluxes must hold at least one value.")
    for value in (float(np.min(f)), float(np.max(f))):
        _flux(value)
    t = _validate.real("the hopping t", t)
    max_sites = _validate.positive_int("max_sites", max_sites)
    progress = _validate.progress("progress", progress)
    cache = checkpoint_cache(checkpoint)
    n = lattice.sites
    if n > max_sites:
        raise ValueError(f"the butterfly of {n:,} sites is a dense computation per sector; "
                         f"raise max_sites (now {max_sites:,}) if that is intended.")
    if f.shape[0] * n > 2e8:
        raise ValueError(f"{f.shape[0]:,} flux values x {n:,} levels is too large a result; use fewer fluxes.")
    if not rotation_invariant(lattice, onsite):
        raise ValueError("the on-site term is not invariant under the p-fold rotation, so H has no "
                         "angular-momentum sectors.")
    p = lattice.p
    orbits = rotation_orbits(lattice)
    energies = np.empty((f.shape[0], n))
    labels = np.empty((f.shape[0], n), dtype=np.int64)
    sectors = [int(m - p) if m > p / 2 else int(m) for m in range(p)]

    def levels(fk: float) -> dict:
        parts, ms, tols = [], [], []
        for m in sectors:
            block = sector_table(lattice, m, t, onsite, orbits=orbits, flux=fk).to_csr().toarray()
            parts.append(sla.eigvalsh(block))
            ms.append(np.full(orbits.size, m, dtype=np.int64))
            tols.append(np.full(orbits.size, eigenvalue_tolerance(np.abs(block).sum(axis=1).max(), orbits.size)))
        e, mm, tol = np.concatenate(parts), np.concatenate(ms), np.concatenate(tols)
        # levels of different sectors within their error bounds of each other (the +-m pairs at
        # f = 0, and the pairs f = 1/2 and 1 bring together) are one degenerate group: its labels
        # are listed by |m|, +m first, not in the order the last bits of the energies would put
        # them, and the energies stay ascending (a group's values are equal to rounding)
        order = stable_order(e, tol, np.abs(mm), (mm < 0).astype(np.int64))
        return {"energies": np.sort(e).tolist(), "m": mm[order].tolist()}

    key = None if cache is None else dict(_lattice_key(lattice, onsite), t=t)
    # the blocks are small (N/p = 121 rows at l = 5): a multi-threaded BLAS spends more on its
    # threads than on the arithmetic; on the loaded 2-core machine one thread was 15-30x faster
    # (l = 5: 21 against 330-520 ms per flux; l = 6: 140-220 against 1,900-4,600 ms)
    with progress_bar(f.shape[0], "butterfly", unit="flux", progress=progress) as bar, single_threaded_blas():
        for k, fk in enumerate(f.tolist()):
            if cache is None:
                point = levels(fk)
            else:
                point = cache.get("butterfly-point", dict(key, flux=fk), lambda fk=fk: levels(fk), expect=dict)
            if len(point["energies"]) != n or len(point["m"]) != n:
                raise ValueError(f"the checkpoint entry for f = {fk!r} holds {len(point['energies'])} levels, "
                                 f"not {n}; delete it or use another checkpoint directory.")
            energies[k], labels[k] = point["energies"], point["m"]
            bar.update()
    total = time.perf_counter() - t0
    description = (f"LAPACK eigvalsh of the {p} angular-momentum blocks ({orbits.size:,} x {orbits.size:,}) "
                   f"at each of {f.shape[0]:,} flux values.")
    return Butterfly(fluxes=f, energies=energies, m=labels, p=p, q=lattice.q, rings=lattice.rings, sites=n,
                     kind=lattice.kind, t=t, description=description, timings={"total": total})


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
