r"""Graph against continuum in a uniform magnetic field: where does the continuum describe the lattice?

:func:`magnetic_comparison` puts the lowest levels of the Peierls Hamiltonian of the
:math:`\ell`-ring {p,q} flake (:func:`~hyperlattice.graph.spectrum.lowest_levels` with ``flux=f``)
next to the Dirichlet levels of :math:`-q - \frac q4 h^2\Delta_B` on the disk of the same flake
(:func:`~hyperlattice.continuum.magnetic.magnetic_levels`, ``spec2`` with the field
:math:`B = 2\pi f/\mathcal A_p` of :func:`~hyperlattice.dictionary.field_from_flux`) on an
(f, l) grid. Levels are matched by their labels (n, m), not by their order: with flux the graph's
lowest two states can swap their m on large flakes while the continuum's do not.

The two length ratios that decide the agreement are reported with the errors:

* :math:`\ell_B/d_0`, magnetic length :math:`\ell_B = 1/\sqrt{|B|}` (:math:`\hbar = e = 1`) over
  the hyperbolic edge length :math:`d_0` (:func:`~hyperlattice.geometry.d0`): the continuum
  limit of the hops, :math:`A \approx q + \frac q4 h^2\Delta_g` (``eq10``), needs the wave
  function, and now the vector potential, to vary slowly on the scale of one edge;
* :math:`\ell_B/R`, the magnetic length over the hyperbolic radius :math:`R = \mathrm{artanh}\,L`
  of the Dirichlet disk: when it is small the lowest states sit deep inside the disk as
  Landau-like states and the disk edge no longer matters, but the total flux through the disk
  (which grows like its area) makes the phases wind fast near the boundary rings.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _validate
from ..cache import Cache, checkpoint_cache
from ..results import INDEX, Column, Grid, Result


__all__ = ["MagneticComparison", "magnetic_comparison"]

#: the agreement threshold of the plain statement
THRESHOLD = 1e-3

#: digits, point and minus as superscripts, for a power in a sentence (f^1.9 -> f¹·⁹)
_SUPERSCRIPT = str.maketrans("0123456789.-", "⁰¹²³⁴⁵⁶⁷⁸⁹·⁻")


def _superscript(text: str) -> str:
    return text.translate(_SUPERSCRIPT)


@dataclass(frozen=True, eq=False, kw_only=True)
class MagneticComparison(Result):
    r"""Graph and continuum lowest levels on an (f, l) grid.

    Energies are in units of t (:math:`H = -tA` with Peierls phases, t = 1); lengths in the
    paper's metric.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    fluxes : ndarray, shape (F,)
        Flux quanta per p-gon.
    rings : ndarray of int, shape (R,)
        The flake sizes l.
    n, m : ndarray of int, shape (R, F, K)
        Labels of the K lowest graph states at each (l, f).
    graph, continuum : ndarray, shape (R, F, K)
        Graph energies and the continuum energies of the same (n, m) (NaN if the continuum
        level with that label was not among the lowest ones computed).
    relative_error : ndarray, shape (R, F, K)
        :math:`|E_{\rm graph} - E_{\rm cont}|/|E_{\rm graph}|`.
    d0 : float
        Hyperbolic edge length (paper's metric).
    disk_radius : ndarray, shape (R,)
        Hyperbolic radius :math:`\mathrm{artanh}\,L` of each Dirichlet disk.
    magnetic_length : ndarray, shape (F,)
        :math:`1/\sqrt{|B|}` (inf at f = 0).
    timings : dict
        Wall-clock seconds of the stages.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> cmp = hl.magnetic_comparison(7, 3, rings=(3,), fluxes=[0.0, 0.1], levels=2)
    >>> cmp.graph.shape, cmp.m[0, 1].tolist()
    ((1, 2, 2), [0, 1])
    >>> [round(float(x), 4) for x in cmp.worst()[0]]        # largest relative error per flux
    [0.0186, 0.0158]
    >>> cmp.agreement_limit(0.01).tolist()                  # 3 rings never agree to 1 %
    [nan]
    """

    GRID = Grid(coords=(Column("rings", "rings", "1"), Column("flux", "fluxes", "flux quanta per p-gon"),
                        Column("state", INDEX, "1")),
                variables=tuple(Column(name, name, unit, ("rings", "flux", "state"))
                                for name, unit in (("graph", "t"), ("continuum", "t"), ("relative_error", "1"),
                                                   ("n", "1"), ("m", "1")))
                + (Column("disk_radius", "disk_radius", "1 (hyperbolic)", ("rings",)),
                   Column("magnetic_length", "magnetic_length", "1 (hyperbolic)", ("flux",))))

    p: int
    q: int
    fluxes: np.ndarray
    rings: np.ndarray
    n: np.ndarray
    m: np.ndarray
    graph: np.ndarray
    continuum: np.ndarray
    relative_error: np.ndarray
    d0: float
    disk_radius: np.ndarray
    magnetic_length: np.ndarray
    timings: dict = field(default_factory=dict)

    def columns(self) -> dict[str, np.ndarray]:
        """Long-format table: rings, flux, level, n, m, E_graph, E_continuum, rel_error, lB_over_d0, lB_over_R."""
        R, F, K = self.graph.shape
        ell, f, k = np.meshgrid(self.rings, self.fluxes, np.arange(K), indexing="ij")
        lb = np.broadcast_to(self.magnetic_length[None, :, None], (R, F, K))
        rad = np.broadcast_to(self.disk_radius[:, None, None], (R, F, K))
        return {"rings": ell.ravel(), "flux": f.ravel(), "level": k.ravel(), "n": self.n.ravel(),
                "m": self.m.ravel(), "E_graph": self.graph.ravel(), "E_continuum": self.continuum.ravel(),
                "rel_error": self.relative_error.ravel(), "lB_over_d0": (lb / self.d0).ravel(),
                "lB_over_R": (lb / rad).ravel()}

    def worst(self) -> np.ndarray:
        """Largest relative error over the K levels, shape (R, F) (NaN counts as no agreement)."""
        e = np.where(np.isfinite(self.relative_error), self.relative_error, np.inf)
        return e.max(axis=2)

    def agreement_limit(self, threshold: float = THRESHOLD) -> np.ndarray:
        """For each l, the largest flux of the grid up to which (from f = 0 on) every level agrees
        within ``threshold``; NaN if it fails already at the first flux.

        Parameters
        ----------
        threshold : float, optional
            Relative error, default 1e-3.

        Returns
        -------
        numpy.ndarray, shape (R,)
            Flux quanta per p-gon, one per l.
        """
        ok = self.worst() < threshold
        out = np.full(len(self.rings), np.nan)
        for i in range(len(self.rings)):
            bad = np.flatnonzero(~ok[i])
            upto = len(self.fluxes) if bad.size == 0 else bad[0]
            if upto > 0:
                out[i] = self.fluxes[upto - 1]
        return out

    def statement(self, threshold: float = THRESHOLD) -> str:
        """A plain sentence, from the data, of where the relative error stays below ``threshold`` and why it grows.

        Parameters
        ----------
        threshold : float, optional
            Relative error, default 1e-3.

        Returns
        -------
        str
            The statement (several sentences of plain text).
        """
        lim = self.agreement_limit(threshold)
        parts = []
        for ell, f in zip(self.rings.tolist(), lim.tolist()):
            parts.append(f"ℓ = {ell}: " + ("never" if math.isnan(f) else f"f ≤ {f:g}"))
        w = self.worst()
        j = int(np.argmax(self.fluxes))
        fmax, lb = float(self.fluxes[j]), float(self.magnetic_length[j])
        text = (f"Relative error of the {self.graph.shape[2]} lowest levels below {threshold:g}: "
                + "; ".join(parts) + ".")
        zero = np.flatnonzero(self.fluxes == 0.0)
        if zero.size:
            z = w[:, zero[0]]
            text += (f" At f = 0 the error is the zero-field flake-vs-disk error, {z[0]:.1e} at "
                     f"ℓ = {self.rings[0]} to {z[-1]:.1e} at ℓ = {self.rings[-1]}: the floor for small flakes.")
        if math.isfinite(lb):
            text += (f" At f = {fmax:g}, l_B = 1/√B = {lb:.3f} = {lb / self.d0:.2f} d₀ and "
                     f"l_B/R = {lb / self.disk_radius[0]:.3f} (ℓ = {self.rings[0]}) to "
                     f"{lb / self.disk_radius[-1]:.3f} (ℓ = {self.rings[-1]}); the error there is "
                     f"{np.min(w[:, j]):.1e} to {np.max(w[:, j]):.1e} over all ℓ")
            half = int(np.argmin(np.abs(self.fluxes - fmax / 2)))
            if 0 < self.fluxes[half] < fmax and np.all(np.isfinite(w[-1, [half, j]])):
                slope = math.log(w[-1, j] / w[-1, half]) / math.log(fmax / self.fluxes[half])
                power = _superscript(f"{slope:.1f}")
                text += f" and grows like f{power} from f = {self.fluxes[half]:g} (ℓ = {self.rings[-1]})"
            text += (". It grows with f because the hops approximate the covariant Laplacian only when "
                     "l_B ≫ d₀ (the Peierls phase of one p-gon, 2πf, is the field seen on the lattice "
                     "scale); once l_B ≪ R the lowest states are Landau-like states inside the disk, the "
                     "disk edge stops mattering and the error no longer depends on ℓ.")
        return text

    def summary(self) -> dict:
        """Short view: sizes, the agreement limits per l and the statement."""
        return {"p": self.p, "q": self.q, "rings": self.rings.tolist(), "fluxes": self.fluxes.tolist(),
                "max_relative_error": float(np.nanmax(self.relative_error)),
                "agreement_limit": [None if math.isnan(v) else float(v) for v in self.agreement_limit()],
                "statement": self.statement()}


def _point(p: int, q: int, ell: int, lattice, flux: float, K: int) -> dict:
    """The K lowest graph levels at one (l, f) and the continuum levels of the same (n, m).

    The graph knows m only modulo p: each state is matched to the continuum level it continues
    (:func:`hyperlattice.compare.levels.continuum_labels`, the magnetic levels of the same disk and
    flux), and that level's energy is the continuum side.
    """
    from ..graph.spectrum import lowest_levels
    from .levels import continuum_labels

    gs = continuum_labels(lowest_levels(lattice, K, flux=flux))
    n, m = [int(v) for v in gs.n[:K]], [int(v) for v in gs.m[:K]]
    return {"n": n, "m": m, "graph": [float(v) for v in gs.energies[:K]],
            "continuum": [float(v) for v in gs.continuum_energies[:K]]}


def magnetic_comparison(p: int = 7, q: int = 3, *, rings=(3, 4, 5, 6, 7), fluxes=None,
                        levels: int = 2, progress=None, checkpoint: Cache | Path | None = None
                        ) -> MagneticComparison:
    r"""Lowest graph and continuum levels with flux on an (f, l) grid, matched by (n, m).

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol of the lattice, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    rings : sequence of int, optional
        Flake sizes l (each >= 1; up to 8 for the continuum's order cap at f <= 0.2).
        Default ``(3, 4, 5, 6, 7)``.
    fluxes : array of float, optional
        Flux f in flux quanta through one p-gon face (the field B per unit area of the metric
        follows from :func:`~hyperlattice.dictionary.field_from_flux`); default
        ``linspace(0, 0.3, 7)``.
    levels : int, optional
        K lowest graph states compared. Default 2.
    progress : bool, None or callable, optional
        A bar over the (l, f) points on stderr (:mod:`hyperlattice._progress`; None: when stderr is
        a terminal), or a function receiving one-line messages.
    checkpoint : path or Cache, optional
        Keep every finished (l, f) point in this directory (a :class:`~hyperlattice.cache.Cache`,
        one JSON entry per point, keyed on p, q, l, f and K); points already there are read, not
        recomputed. A run stopped by Ctrl-C keeps what finished, and the same call resumes with
        the same result, bit for bit.

    Returns
    -------
    MagneticComparison
        Arrays of shape (R, F, K) over rings, fluxes and levels: the labels ``n``, ``m``, the
        ``graph`` and ``continuum`` energies (units of t; NaN where the continuum level with that
        label was not computed) and ``relative_error``; ``disk_radius`` (R,),
        ``magnetic_length`` (F,) and the edge length ``d0``.

    Raises
    ------
    ValueError
        For bad input: {p,q} not hyperbolic, empty ``rings`` or ``fluxes``, a ring count below 1,
        or a bad ``checkpoint``.

    See Also
    --------
    hyperlattice.lowest_levels : the graph side (``flux=f``).
    hyperlattice.continuum.magnetic.magnetic_levels : the continuum side.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (8) (source label ``eq10``),
       here with the vector potential of a uniform field.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> cmp = hl.magnetic_comparison(7, 3, rings=(3,), fluxes=[0.1], levels=2)
    >>> cmp.graph.shape
    (1, 1, 2)
    >>> cmp.n[0, 0].tolist(), cmp.m[0, 0].tolist()
    ([1, 1], [0, 1])
    >>> print(f"{cmp.graph[0, 0, 0]:.6f} {cmp.continuum[0, 0, 0]:.6f} {cmp.relative_error[0, 0, 0]:.4f}")
    -2.762083 -2.745551 0.0060
    """
    from .._progress import progress_bar
    from ..dictionary import disk_radius_for_rings, field_from_flux
    from ..geometry import d0 as edge_length
    from ..graph.lattice import ring_lattice

    t0 = time.perf_counter()
    p, q = _validate.pq(p, q)
    ells = np.array(_validate.int_list("rings", rings, minimum=1, maximum=12), dtype=np.int64)
    if ells.size == 0:
        raise ValueError("rings must hold at least one value.")
    f = np.linspace(0.0, 0.3, 7) if fluxes is None else _validate.real_array("fluxes", fluxes, ndim=1)
    if f.size == 0:
        raise ValueError("fluxes must hold at least one value.")
    K = _validate.positive_int("levels", levels, maximum=20)
    progress = _validate.progress("progress", progress)
    cache = checkpoint_cache(checkpoint)
    shape = (ells.size, f.size, K)
    n, m = np.zeros(shape, dtype=np.int64), np.zeros(shape, dtype=np.int64)
    g, c = np.full(shape, np.nan), np.full(shape, np.nan)
    with progress_bar(ells.size * f.size, "fluxmap", unit="point", progress=progress) as bar:
        for i, ell in enumerate(ells.tolist()):
            lattice = None
            for j, fj in enumerate(f.tolist()):
                bar.note(f"l={ell} f={fj:.4g}")

                def compute(ell=ell, fj=fj) -> dict:
                    nonlocal lattice
                    if lattice is None:  # built only when a point of this flake is missing
                        lattice = ring_lattice(p, q, ell)
                    return _point(p, q, ell, lattice, fj, K)

                if cache is None:
                    point = compute()
                else:
                    point = cache.get("fluxmap-point", {"p": p, "q": q, "rings": ell, "flux": fj, "levels": K},
                                      compute, expect=dict)
                n[i, j], m[i, j], g[i, j] = point["n"], point["m"], point["graph"]
                c[i, j] = [np.nan if v is None else v for v in point["continuum"]]
                bar.update()
    rel = np.abs(g - c) / np.abs(g)
    B = np.abs(np.asarray(field_from_flux(f, p, q), dtype=float))
    with np.errstate(divide="ignore"):
        lb = np.where(B > 0, 1.0 / np.sqrt(np.where(B > 0, B, 1.0)), np.inf)
    radius = np.array([math.atanh(disk_radius_for_rings(ell, p, q)[0]) for ell in ells.tolist()])
    return MagneticComparison(p=p, q=q, fluxes=f, rings=ells, n=n, m=m, graph=g, continuum=c,
                              relative_error=rel, d0=edge_length(p, q), disk_radius=radius,
                              magnetic_length=lb, timings={"total": time.perf_counter() - t0})


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
