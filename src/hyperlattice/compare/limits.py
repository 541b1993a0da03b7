r"""The infinite lattice: the band bottom :math:`-\rho(p,q)`, why the graph-continuum error has a
plateau, and the improved dictionary against the graph levels.

Band bottom, route (a): extrapolation in the ring number l
----------------------------------------------------------
The ground state of an l-ring flake is a Dirichlet state of a disk whose geodesic radius grows
linearly in l (:math:`x_L \propto \varphi^{2\ell}` for {7,3}, so :math:`R = \frac12\operatorname{arcosh}x_L
= \ell\ln\varphi + O(1)`). For the lowest Dirichlet root of ``spec2`` on a large disk,
:math:`P_\nu(\cosh 2R) \approx \frac{\Gamma(\mathrm ik/2)}{\sqrt\pi\,\Gamma(\frac12 + \mathrm ik/2)}
(2\cosh 2R)^{\nu} + {\rm c.c.}` (``spec9``) vanishes where
:math:`k(R + c) + O(k^3) = \pi`, so :math:`k_0 = \pi/(R + c) + O(R^{-4})` — the exponent is 2, as in a
flat disk (the hyperbolic :math:`\frac14` is the band edge itself, not a correction). The lattice
only fixes three numbers: the band bottom :math:`E_b = -\rho`, the band curvature
:math:`M = dE/d\lambda` there and the position of the Dirichlet wall. Hence two fit models,

* ``"disk"``: :math:`E(\ell) = E_b + M\,k_m(R_A(\ell) + s)^2` with the exact Dirichlet root
  :math:`k_m` (m = 0 for E0, m = 1 for E1) of the disk of radius :math:`R_A + s`, :math:`R_A` the
  area radius of ``eq12`` (all orders in 1/R of the disk are kept);
* ``"rational"``: :math:`E(\ell) = E_b + A/(\ell + c)^2 + B/(\ell + c)^4`, the same expansion
  truncated (no :math:`(\ell+c)^{-3}` term once c absorbs the wall; :math:`B` collects
  :math:`k^4` terms of the disk and of :math:`E(\lambda)`).

:func:`band_bottom` fits both models to E0 and E1 on the last 5, 6 and 7 flakes; the estimate is
the disk model on E0 over the last 6, the error bar the largest deviation of the eleven other
variants (and at least the change when the largest flake is dropped).

Route (b): rigorous bounds
--------------------------
* :math:`\rho \ge \lambda_{\max}(A_{\rm flake})`: a flake is a finite subgraph (Cauchy interlacing /
  Rayleigh quotient of the flake's Perron vector extended by zero), so :math:`-\rho \le E_0(\ell)`.
* :math:`\rho \le c` whenever some :math:`f > 0` has :math:`(Af)(v) \le c f(v)` at every vertex of the
  infinite lattice (the Schur test: :math:`|\langle g, A g\rangle| \le \sum_{uv} A_{uv}|g_u||g_v|
  \le \sum_{uv}A_{uv}\frac12(\frac{f_v}{f_u}g_u^2 + \frac{f_u}{f_v}g_v^2) \le c\|g\|^2`).
  :func:`schur_bound` takes :math:`f(v) = w(\tau_v)\,x^{r_v}`, :math:`r_v` the ring of v and
  :math:`\tau_v` the word of inner/outer bond counts of the 2W + 1 sites around v on its ring,
  finds the weights w by linear programming (feasibility of :math:`Af \le cf` for fixed c and x, by
  bisection in c) and certifies c as the largest ratio :math:`(Af)(v)/f(v)` over all local
  patterns. The ratio depends only on the local pattern (v's word, its neighbours' words and ring
  offsets). The patterns are collected from a flake; each ring's word is produced from the
  previous ring's by the same local growth step, so once the pattern set does not grow from one
  ring to the next it never does: ``closed`` records that check. W = 0 gives 2.9655 for {7,3}
  (the known upper end 2.966 of the paper's interval), larger W tighten it slowly.

Why the plateau
---------------
The graph levels go to :math:`-\rho`, the continuum levels of the paper's map to
:math:`E_\infty = -q + \frac q4 h^2`, so :math:`(E_{\rm graph} - E_{\rm cont})/|E_{\rm graph}| \to
(E_\infty + \rho)/\rho`... with the sign of the report's relative error, :math:`(-\rho -
E_\infty)/\rho`. :func:`plateau_analysis` splits :math:`-\rho - E_\infty` into the terms of the
expansion of the star (:mod:`hyperlattice.dictionary`): the isotropic :math:`h^4` term
:math:`q(\frac\lambda8 - \frac{\lambda^2}{64})h^4` at :math:`\lambda = 1` (:math:`\frac{7q}{64}h^4`),
the isotropic rest (:math:`h^6` and beyond, the exact :math:`-q P_{-1/2}(\cosh 2d_0)`), and the
remainder: the anisotropic orders :math:`m = \pm q` (the paper's :math:`h^3\mathcal D` term,
``adj32``/``adj33``, and higher orders m = ±2q, ...), which would average to zero over uniformly
spread star orientations (on the ring lattice :math:`\langle\cos 3(\chi_i - \phi_i)\rangle = 0.17`)
and act weakly at first and at second order.

The improved dictionary against the graph
-----------------------------------------
:func:`compare_dictionaries` gives the relative error of E0 and E1 for both maps
(``continuum_levels(..., dictionary=...)``), and the improved map's :math:`\ell\to\infty` limit
:math:`(-\rho - E_\infty^{\rm impr})/\rho`, the part of the plateau it does not remove.

Stored graph levels
-------------------
:data:`REFERENCE_LEVELS` holds E0, E1 of the l-ring flakes (``lowest_levels``, residuals below
4e-13) so that tests and quick looks need no eigensolver; :data:`REFERENCE_COMMAND` regenerates
them, and the tests recompute the small ones.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .. import _validate
from ..dictionary import (
    disk_radius_for_rings,
    energy_from_k,
    hopping_scale,
    improved_band_bottom,
    improved_energy_from_lambda,
)
from ..geometry import lattice_h
from ..results import Column, Result

if TYPE_CHECKING:
    from ..cache import Cache

__all__ = [
    "REFERENCE_LEVELS",
    "REFERENCE_COMMAND",
    "REFERENCE_DATE",
    "reference_command",
    "reference_levels",
    "flake_levels",
    "BandBottomFit",
    "fit_band_bottom",
    "SchurBound",
    "schur_bound",
    "BandBottom",
    "band_bottom",
    "PlateauAnalysis",
    "plateau_analysis",
    "DictionaryComparison",
    "compare_dictionaries",
]

def reference_command(p: int = 7, q: int = 3, rings=range(1, 15)) -> str:
    """The shell command that recomputes the :data:`REFERENCE_LEVELS` of {p,q} for ``rings``, runnable as written.

    Flakes up to ℓ = 14 go through ``lowest_levels`` (one Python call printing ``(ℓ, E0, E1)``
    tuples); ℓ >= 15 through ``hyperlattice spectrum --method pair`` (the sector-only solver,
    which never builds the 13M+ site lattice), one command per flake.

    Parameters
    ----------
    p, q : int, optional
        The tiling {p,q}; default {7,3}.
    rings : iterable of int, optional
        The flakes ℓ (1 to 17) whose E0, E1 (units of t, H = -tA with t = 1) the command
        recomputes; default 1 to 14.

    Returns
    -------
    str
        One shell line (commands joined by semicolons), printed by the report beside the stored levels.

    Raises
    ------
    ValueError
        If p, q do not make a hyperbolic tiling or a ring count is outside 1 to 17.

    Examples
    --------
    >>> from hyperlattice.compare.limits import reference_command
    >>> print(reference_command(7, 3, [14, 15]))  # doctest: +NORMALIZE_WHITESPACE
    python -c "from hyperlattice import ring_lattice, lowest_levels; print([(l,
    *lowest_levels(ring_lattice(7, 3, l), 2).energies.tolist()) for l in (14,)])";
    hyperlattice spectrum -p 7 -q 3 --rings 15 --method pair
    """
    p, q = _validate.pq(p, q)
    rings = _validate.int_list("rings", rings, minimum=1, maximum=17)
    small = [r for r in rings if r <= 14]
    parts = []
    if small:
        parts.append("python -c \"from hyperlattice import ring_lattice, lowest_levels; "
                     f"print([(l, *lowest_levels(ring_lattice({p}, {q}, l), 2).energies.tolist()) "
                     f"for l in {tuple(small)!r}])\"")
    parts += [f"hyperlattice spectrum -p {p} -q {q} --rings {r} --method pair" for r in rings if r > 14]
    return "; ".join(parts)


#: How :data:`REFERENCE_LEVELS` of {7,3} up to l = 14 were computed (~1 min; :func:`reference_command`).
REFERENCE_COMMAND = reference_command(7, 3, range(1, 15))
#: When :data:`REFERENCE_LEVELS` were computed and stored (l = 15, 16 of {7,3} the same day).
REFERENCE_DATE = "2026-11-22"

#: E0, E1 of the l-ring {p,q} flakes (H = -A), by (p, q) and l: lowest_levels, residuals <= 4e-13
#: (REFERENCE_COMMAND); {7,3} l = 15, 16 (13.0M, 34.1M sites) from the sector-only shift-invert solver
#: of hyperlattice.graph.sectors (residuals <= 7e-15; ``python benchmarks/table_e0e1.py --flakes 15 16``).
REFERENCE_LEVELS: dict = {
    (7, 3): {
        1: (-2.0, -1.246979603717467),
        2: (-2.6364049372104934, -2.283334703096212),
        3: (-2.786701838024485, -2.6268960584212273),
        4: (-2.8466330868164005, -2.762158410466457),
        5: (-2.876770661107686, -2.827091460001197),
        6: (-2.894196944768138, -2.862642575029471),
        7: (-2.9052530439235205, -2.8840139114531094),
        8: (-2.9127439314844312, -2.8977878752036372),
        9: (-2.918072938641515, -2.9071547570329495),
        10: (-2.9220091583033367, -2.913800872177415),
        11: (-2.9250046557950578, -2.918681116815997),
        12: (-2.927340261425818, -2.9223673315125227),
        13: (-2.9291984097009798, -2.9252181866492206),
        14: (-2.9307020646806765, -2.9274675618622017),
        15: (-2.931936706435444, -2.9292730872135992),
        16: (-2.9329633385457172, -2.9307440634818835),
    },
    (8, 3): {
        1: (-2.0, -1.414213562373095),
        2: (-2.6180339887498945, -2.326419333314168),
        3: (-2.759370216360908, -2.6345511675473974),
        4: (-2.8157599205926114, -2.752431961046917),
        5: (-2.8442248943877, -2.808035520618765),
        6: (-2.8607317186185974, -2.8382151249117777),
        7: (-2.8712164715206665, -2.8562927464078554),
        8: (-2.878317713599115, -2.8679337212857137),
        9: (-2.883362366865475, -2.875853814601205),
        10: (-2.887080760136356, -2.881479577882121),
    },
    (9, 3): {
        1: (-2.0, -1.5320888862379558),
        2: (-2.6092255963225854, -2.362351785385835),
        3: (-2.743833988882507, -2.6404687621465297),
        4: (-2.7973608951328814, -2.7458774182064176),
        5: (-2.824363132266678, -2.7953248807256514),
        6: (-2.8400020078065293, -2.822106595503541),
        7: (-2.8499161101366934, -2.838141032826838),
        8: (-2.8566151017853283, -2.848468466714953),
        9: (-2.861362099706776, -2.855498262119947),
    },
    (10, 3): {
        1: (-2.0, -1.618033988749895),
        2: (-2.6050164419001365, -2.394188566223464),
        3: (-2.7344427580201627, -2.645911792262249),
        4: (-2.785737602763546, -2.7419964668887893),
        5: (-2.8115700343157632, -2.787063127077283),
        6: (-2.8265012525606052, -2.811476520607758),
        7: (-2.8359455121030357, -2.826099510641047),
        8: (-2.8423124730447773, -2.835522646898814),
    },
    (5, 4): {
        1: (-2.0, -0.6180339887498947),
        2: (-3.0494811777353164, -2.4277003388082163),
        3: (-3.366925236821676, -3.0748029412218303),
        4: (-3.5039801535566983, -3.3482253113943474),
        5: (-3.575950888877502, -3.484289013797242),
        6: (-3.618661020248044, -3.560534435621439),
        7: (-3.646197526673725, -3.607160000058077),
        8: (-3.665042604079542, -3.6376167543464195),
        9: (-3.678532612074275, -3.658555101941945),
        10: (-3.6885343990392796, -3.673545482617157),
    },
}


def reference_levels(p: int = 7, q: int = 3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The stored lowest two levels of the l-ring {p,q} flakes, as arrays.

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol of the lattice (p-gon faces, q at each vertex), :math:`(p-2)(q-2) > 4`.
        Default {7,3}.

    Returns
    -------
    rings : ndarray of int64
        The ring counts l stored for {p,q}, increasing.
    E0, E1 : ndarray of float
        The two lowest eigenvalues of :math:`H = -A` (t = 1, energies in units of t) of each
        flake, from :data:`REFERENCE_LEVELS`.

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic lattice or no levels are stored for it.

    See Also
    --------
    flake_levels : the same levels computed afresh.

    Examples
    --------
    >>> from hyperlattice.compare.limits import reference_levels
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> rings[:3].tolist()
    [1, 2, 3]
    >>> print(f"{E0[2]:.6f}")
    -2.786702
    """
    p, q = _validate.pq(p, q)
    table = REFERENCE_LEVELS.get((p, q))
    if table is None:
        raise ValueError(f"no stored flake levels for {{{p},{q}}}; stored: "
                         + ", ".join(f"{{{a},{b}}}" for a, b in REFERENCE_LEVELS) + ".")
    ell = np.array(sorted(table), dtype=np.int64)
    return ell, np.array([table[x][0] for x in ell]), np.array([table[x][1] for x in ell])


def flake_levels(p: int = 7, q: int = 3, rings=(1, 2, 3), *, cache: Cache | None = None) -> dict:
    """E0, E1 and residuals of the l-ring flakes for each l in ``rings`` (``lowest_levels``).

    With a :class:`~hyperlattice.cache.Cache` the spectra are stored under the same key as the
    report's (``graph_levels``), so nothing is computed twice.

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol of the lattice, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    rings : sequence of int, optional
        Ring counts l of the flakes, strictly increasing positive integers. Default ``(1, 2, 3)``.
    cache : hyperlattice.cache.Cache, optional
        Where spectra are looked up and stored (key ``"graph_levels"``). Default None: compute.

    Returns
    -------
    dict
        ``{"rings", "E0", "E1", "residual"}``, each a list with one entry per flake: the ring
        count, the two lowest eigenvalues of :math:`H = -A` (units of t) and the largest
        eigenpair residual.

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic, ``rings`` is empty or not strictly increasing positive
        integers, or ``cache`` is not a Cache.

    See Also
    --------
    reference_levels : stored levels up to large l, no eigensolver.
    hyperlattice.lowest_levels : the eigensolver used.

    Examples
    --------
    >>> from hyperlattice.compare.limits import flake_levels
    >>> out = flake_levels(7, 3, rings=(1, 2))
    >>> out["rings"]
    [1, 2]
    >>> [round(e, 6) for e in out["E0"]]
    [-2.0, -2.636405]
    """
    from ..graph.lattice import ring_lattice
    from ..graph.spectrum import lowest_levels

    from ..cache import Cache

    p, q = _validate.pq(p, q)
    ell = _validate.real_array("rings", rings, ndim=1)
    if ell.size == 0 or np.any(ell != np.round(ell)) or np.any(ell < 1) or np.any(np.diff(ell) <= 0):
        raise ValueError("rings must be strictly increasing positive integers.")
    if cache is not None and not isinstance(cache, Cache):
        raise ValueError(f"cache must be a hyperlattice.cache.Cache or None, got {type(cache).__name__}.")
    out = {"rings": [], "E0": [], "E1": [], "residual": []}
    for x in ell.astype(int).tolist():
        def compute(x=x):
            return lowest_levels(ring_lattice(p, q, x), levels=2)
        spec = compute() if cache is None else cache.get(
            "graph_levels", {"p": p, "q": q, "rings": x, "levels": 2}, compute)
        out["rings"].append(x)
        out["E0"].append(float(spec.energies[0]))
        out["E1"].append(float(spec.energies[1]))
        out["residual"].append(float(np.max(spec.errors)))
    return out


# ----------------------------------------------------------------------------
# route (a): extrapolation in l
# ----------------------------------------------------------------------------

_MODELS = ("disk", "rational")


def _area_radius(p: int, q: int, rings: np.ndarray) -> np.ndarray:
    """Geodesic area radius R_A = arcosh(x_L)/2 of ``eq12`` for each ring count."""
    return np.array([0.5 * math.acosh(disk_radius_for_rings(int(x), p, q)[1]) for x in rings])


def _disk_k_direct(m: int, radius: np.ndarray) -> np.ndarray:
    """The lowest Dirichlet root k_{1m} of ``spec2`` for each disk radius, all at once.

    The same function and tolerances as :func:`hyperlattice.continuum.spectrum.dirichlet_roots`
    (bracket on a grid finer than the root spacing, then Chandrupatla), vectorized over the radii.
    """
    from scipy.optimize import elementwise

    from ..continuum.spectrum import _TOLERANCES, _dirichlet_function, _grid_step

    r = np.asarray(radius, dtype=float)
    x = np.cosh(2.0 * r)
    t = 2.0 * r
    dk = np.array([_grid_step(v) for v in t])
    kmax = 2.0 * math.pi * (2.0 + 0.5 * m) / t + 4.0 * m / t + 1.0
    npts = int(np.max(np.ceil(kmax / dk))) + 1
    grid = np.arange(npts)[None, :] * dk[:, None]
    vals = _dirichlet_function(grid, m, x[:, None])
    change = np.sign(vals[:, :-1]) * np.sign(vals[:, 1:]) <= 0
    if not np.all(change.any(axis=1)):
        from ..errors import ConvergenceError

        raise ConvergenceError("could not bracket the lowest Dirichlet root.")
    j = np.argmax(change, axis=1)
    lo, hi = grid[np.arange(r.size), j], grid[np.arange(r.size), j + 1]
    res = elementwise.find_root(lambda k, xx: _dirichlet_function(k, m, xx), (lo, hi), args=(x,),
                                tolerances=_TOLERANCES)
    return np.asarray(res.x, dtype=float)


#: radii covered by the interpolant of the lowest roots (x = cosh 2R stays below 1e261)
_R_RANGE = (0.5, 300.0)


@functools.lru_cache(maxsize=4)
def _root_interpolant(m: int):
    r"""Barycentric interpolant of :math:`(R + 1)k_{1m}(R)` in :math:`u = 1/(R+1)` on 48 Chebyshev
    nodes: the function is smooth in u (:math:`k \approx \pi/(R + c)`), and the interpolant agrees
    with :func:`~hyperlattice.continuum.spectrum.dirichlet_roots` to 1e-15 relative on the whole
    range (checked in the tests). The fits call it thousands of times."""
    from scipy.interpolate import BarycentricInterpolator

    umin, umax = 1.0 / (_R_RANGE[1] + 1.0), 1.0 / (_R_RANGE[0] + 1.0)
    j = np.arange(48)
    u = 0.5 * (umin + umax) + 0.5 * (umax - umin) * np.cos(np.pi * (j + 0.5) / 48)
    return BarycentricInterpolator(u, _disk_k_direct(m, 1.0 / u - 1.0) / u)


def _disk_k(m: int, radius: np.ndarray) -> np.ndarray:
    """Lowest Dirichlet roots for each radius in :data:`_R_RANGE` (interpolated)."""
    r = np.asarray(radius, dtype=float)
    if np.any(r < _R_RANGE[0]) or np.any(r > _R_RANGE[1]):
        raise ValueError(f"disk radii must lie in [{_R_RANGE[0]}, {_R_RANGE[1]}] for the band fits.")
    u = 1.0 / (r + 1.0)
    return _root_interpolant(int(m))(u) * u


def _model(model: str, level: int, p: int, q: int, ell: np.ndarray, params: np.ndarray) -> np.ndarray:
    if model == "disk":
        eb, mass, shift = params
        r = _area_radius(p, q, ell) + shift
        if np.any(r < _R_RANGE[0]) or np.any(r > _R_RANGE[1]):
            return np.full(ell.shape, 1e3)      # outside the model's range: a large residual
        return eb + mass * _disk_k(level, r) ** 2
    eb, a, c, b = params
    u = 1.0 / (ell + c)
    return eb + a * u * u + b * u ** 4


@dataclass(frozen=True, eq=False, kw_only=True)
class BandBottomFit(Result):
    r"""One fit of a flake level against l (module docstring, route (a)).

    Energies are those of :math:`H = -tA` in units of t.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    level : int
        0 (E0, m = 0) or 1 (E1, m = 1).
    model : str
        ``"disk"`` (params E_b, M, s) or ``"rational"`` (params E_b, A, c, B).
    rings, energies : ndarray
        The flakes fitted.
    params : ndarray
        The fitted parameters, in the order the model names them.
    band_bottom : float
        The fitted :math:`E_b = -\rho`.
    residuals : ndarray
        Fit minus data at each fitted l.

    Examples
    --------
    >>> from hyperlattice.compare.limits import fit_band_bottom, reference_levels
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> fit = fit_band_bottom(rings[-6:], E0[-6:], p=7, q=3)
    >>> fit.model, fit.rings.tolist(), f"{fit.band_bottom:.4f}"
    ('disk', [11, 12, 13, 14, 15, 16], '-2.9412')
    >>> [round(float(e), 4) for e in fit.predict([20, 40])]
    [-2.9357, -2.9397]
    """

    COLUMNS = (Column("rings", "rings", "1"), Column("energy", "energies", "t"),
               Column("residual", "residuals", "t"))

    p: int
    q: int
    level: int
    model: str
    rings: np.ndarray
    energies: np.ndarray
    params: np.ndarray
    band_bottom: float
    residuals: np.ndarray

    def predict(self, rings) -> np.ndarray:
        """The fitted level at other ring counts (an extrapolation beyond the fitted ones).

        Parameters
        ----------
        rings : array_like
            Ring counts l >= 1 (real numbers are accepted: the model is smooth in l).

        Returns
        -------
        numpy.ndarray
            The level at each l, units of t.
        """
        ell = _validate.real_array("rings", rings, ndim=1)
        if np.any(ell < 1):
            raise ValueError("rings must be >= 1.")
        return _model(self.model, self.level, self.p, self.q, ell, self.params)

    def summary(self) -> dict:
        """Model, fitted rings, band bottom, params and the largest residual."""
        return {"p": self.p, "q": self.q, "level": self.level, "model": self.model,
                "rings": self.rings.tolist(), "band_bottom": self.band_bottom, "params": self.params.tolist(),
                "max_residual": float(np.max(np.abs(self.residuals)))}


def fit_band_bottom(rings, energies, *, p: int = 7, q: int = 3, level: int = 0,
                    model: str = "disk") -> BandBottomFit:
    r"""Fit one flake level against l with the model derived in the module docstring.

    Parameters
    ----------
    rings, energies : array
        Ring counts (strictly increasing integers, at least 4 of them; 5 for ``"rational"``)
        and the level (E0 or E1, units of t) of each flake.
    p, q : int, optional
        The lattice (the disk model needs its site counts). Default {7,3}.
    level : {0, 1}, optional
        Which level: the disk model uses the m = 0 or m = 1 Dirichlet root. Default 0 (E0).
    model : {"disk", "rational"}, optional
        The fit model of the module docstring. Default ``"disk"``.

    Returns
    -------
    BandBottomFit
        The fit: ``params``, ``band_bottom`` (:math:`E_b = -\rho`, units of t) and the
        ``residuals`` (fit minus data) at the fitted ``rings``.

    Raises
    ------
    ValueError
        If ``rings`` are not strictly increasing positive integers, ``energies`` does not match
        them, there are too few flakes for the model, or ``level``/``model`` is unknown.
    hyperlattice.errors.ConvergenceError
        If the least-squares fit does not converge.

    See Also
    --------
    band_bottom : all fit variants together, with an error bar.

    Examples
    --------
    >>> from hyperlattice.compare.limits import fit_band_bottom, reference_levels
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> fit = fit_band_bottom(rings[-6:], E0[-6:], p=7, q=3)
    >>> print(f"{fit.band_bottom:.4f}")
    -2.9412
    """
    from scipy.optimize import least_squares

    p, q = _validate.pq(p, q)
    model = _validate.choice("model", model, _MODELS)
    level = _validate.integer("level", level, minimum=0, maximum=1)
    ell = _validate.real_array("rings", rings, ndim=1)
    if np.any(ell != np.round(ell)) or np.any(ell < 1) or np.any(np.diff(ell) <= 0):
        raise ValueError("rings must be strictly increasing positive integers.")
    e = _validate.real_array("energies", energies, shape=ell.shape)
    need = 4 if model == "disk" else 5
    if ell.size < need:
        raise ValueError(f"the {model} model needs at least {need} flakes, got {ell.size}.")
    s = hopping_scale(p, q)
    if model == "disk":
        p0, scale = [float(e[-1]) - 0.01 * s, s, 0.1], [0.01, s, 0.1]
    else:
        p0, scale = [float(e[-1]) - 0.01 * s, 2.0, 1.0, 0.0], [0.01, 1.0, 1.0, 10.0]
    res = least_squares(lambda prm: _model(model, level, p, q, ell, prm) - e, p0, x_scale=scale,
                        xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=2000)
    if not res.success or not np.all(np.isfinite(res.fun)):
        from ..errors import ConvergenceError

        raise ConvergenceError(f"the {model} fit of the band bottom did not converge ({res.message}).")
    return BandBottomFit(p=p, q=q, level=level, model=model, rings=ell.astype(np.int64), energies=e,
                         params=res.x, band_bottom=float(res.x[0]), residuals=res.fun)


def _variants(ell, e0, e1, p, q, windows=(5, 6, 7)) -> list[BandBottomFit]:
    fits = []
    for level, e in ((0, e0), (1, e1)):
        for model in _MODELS:
            for n in windows:
                if n <= ell.size and n >= (4 if model == "disk" else 5):
                    fits.append(fit_band_bottom(ell[-n:], e[-n:], p=p, q=q, level=level, model=model))
    return fits


# ----------------------------------------------------------------------------
# route (b): the Schur test with a ring-word test function
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class SchurBound(Result):
    r"""A certified upper bound :math:`\rho \le c` from :math:`Af \le cf`, :math:`f > 0` (module docstring).

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    window : int
        W: the type of a site is the word of the 2W + 1 sites around it on its ring.
    rings : int
        The flake the local patterns were collected from.
    x : float
        The ring factor of :math:`f = w(\tau)x^r`.
    bound : float
        The certified c (largest pattern ratio with the weights found).
    patterns, types : int
        How many local patterns and site types.
    closed : bool
        Whether the pattern set did not grow from the second-to-last usable ring to the last
        (then it holds on the whole infinite lattice, and the bound is rigorous there).

    Notes
    -----
    ``bound`` is a bound on :math:`\rho = \|A\|`, so :math:`-t\,c` bounds the band bottom of
    :math:`H = -tA` from below.

    Examples
    --------
    >>> from hyperlattice.compare.limits import schur_bound
    >>> sb = schur_bound(7, 3, window=0, rings=5)
    >>> f"{sb.bound:.4f}", sb.patterns, sb.types, sb.closed
    ('2.8615', 7, 5, False)
    """

    p: int
    q: int
    window: int
    rings: int
    x: float
    bound: float
    patterns: int
    types: int
    closed: bool

    def summary(self) -> dict:
        """All fields as plain JSON."""
        return super().summary()


#: largest sites x (2W + 2) of the ring-word array of :func:`schur_bound` (about 4 GB with its copy)
_MAX_WORD_ENTRIES = 250_000_000


def _local_patterns(p: int, q: int, rings: int, window: int) -> tuple[np.ndarray, np.ndarray, int]:
    """``(patterns, last_ring, n_types)``: one row per site (type, q neighbour codes) for the sites
    whose neighbours' words are complete (rings <= rings - 2), and each row's ring."""
    from ..graph.lattice import ring_lattice

    lat = ring_lattice(p, q, rings)
    ring = lat.ring.astype(np.int64)
    n = lat.sites
    a, b = lat.edges[:, 0].astype(np.int64), lat.edges[:, 1].astype(np.int64)
    inner = np.zeros(n, np.int64)
    outer = np.zeros(n, np.int64)
    for u, v in ((a, b), (b, a)):
        np.add.at(inner, u[ring[v] < ring[u]], 1)
        np.add.at(outer, u[ring[v] > ring[u]], 1)
    label = inner * (q + 1) + outer
    off = lat.ring_offsets
    words = np.empty((n, 2 * window + 2), np.int64)
    for r in range(1, rings + 1):
        ids = np.arange(off[r - 1], off[r])
        m = ids.size
        for j, s in enumerate(range(-window, window + 1)):
            words[ids, j] = label[ids[(np.arange(m) + s) % m]]
        # the two central rings get types of their own (their words are short periodic ones)
        words[ids, -1] = r if r <= 2 else 0
    _, typ = np.unique(words, axis=0, return_inverse=True)
    typ = typ.ravel()
    indptr, nbr = lat.neighbours()
    keep = np.nonzero(ring <= rings - 2)[0]
    deg = np.diff(indptr)[keep]
    if np.any(deg != q):
        raise ValueError("an interior site does not have q neighbours.")
    cols = nbr[indptr[keep][:, None] + np.arange(q)[None, :]]
    codes = np.sort(typ[cols] * 3 + (ring[cols] - ring[keep][:, None] + 1), axis=1)
    rows = np.column_stack([typ[keep], codes])
    return rows, ring[keep], int(typ.max()) + 1


def _certify(pats: np.ndarray, x: float, n_types: int, q: int = 3) -> tuple[float, np.ndarray]:
    """Smallest c (bisection to 1e-8 relative) with a feasible w >= 1 for A f <= c f; returns the
    certified c and w. The bisection starts at 2 sqrt(q - 1): no infinite q-regular graph has a
    smaller spectral radius (Kesten), so nothing below can be feasible."""
    from scipy.optimize import linprog

    used = np.unique(np.concatenate([pats[:, 0], (pats[:, 1:] // 3).ravel()]))
    index = np.full(n_types, -1)
    index[used] = np.arange(used.size)
    tv = index[pats[:, 0]]
    tu = index[pats[:, 1:] // 3]
    xu = x ** (pats[:, 1:] % 3 - 1.0)
    base = np.zeros((pats.shape[0], used.size))
    for j in range(tu.shape[1]):
        np.add.at(base, (np.arange(pats.shape[0]), tu[:, j]), xu[:, j])

    def weights(c):
        mat = base.copy()
        mat[np.arange(pats.shape[0]), tv] -= c
        res = linprog(np.ones(used.size), A_ub=mat, b_ub=np.zeros(pats.shape[0]),
                      bounds=[(1.0, 1e9)] * used.size, method="highs")
        return res.x if res.status == 0 else None

    def ratio(w):
        return float(np.max((w[tu] * xu).sum(axis=1) / w[tv]))

    hi = float(base.sum(axis=1).max())   # w = 1 everywhere: c = the largest row sum
    lo = min(2.0 * math.sqrt(q - 1.0), hi)
    best = np.ones(used.size)
    while hi - lo > 1e-8 * hi:
        mid = 0.5 * (lo + hi)
        w = weights(mid)
        if w is None:
            lo = mid
        else:
            hi, best = min(mid, ratio(w)), w
    # the certificate: the exact largest ratio (A f)(v)/f(v) over the patterns with these weights
    return ratio(best) * (1.0 + 4.0 * np.finfo(float).eps), best


def schur_bound(p: int = 7, q: int = 3, *, window: int = 8, rings: int | None = None) -> SchurBound:
    r"""Certified upper bound on the spectral radius :math:`\rho` of the infinite {p,q} lattice.

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol of the lattice, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    window : int, optional
        W, 0 <= W <= 256 (module docstring); the bound tightens slowly with W (W = 32: 2.9459
        for {7,3}). Default 8.
    rings : int, optional
        Flake the patterns are collected from, 5 to 14 rings (default: the largest with at most
        400 000 sites, at least 7 rings).

    Returns
    -------
    SchurBound
        ``bound`` (the certified c with :math:`\rho \le c`, units of t), the ring factor ``x``,
        the number of ``patterns`` and ``types``, and ``closed`` (whether the pattern set had
        stopped growing, which makes the bound hold on the infinite lattice).

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic, ``window`` or ``rings`` is out of range, or the flake (more
        than 2 000 000 sites) or its ring words would be too large.

    See Also
    --------
    band_bottom : uses this bound as the lower end of its rigorous interval.

    Examples
    --------
    >>> from hyperlattice.compare.limits import schur_bound
    >>> sb = schur_bound(7, 3, window=0, rings=5)
    >>> print(f"{sb.bound:.4f}")
    2.8615
    >>> sb.closed
    False
    """
    from scipy.optimize import minimize_scalar

    from ..graph.lattice import site_count

    p, q = _validate.pq(p, q)
    window = _validate.integer("window", window, minimum=0, maximum=256)
    if rings is None:
        rings = 7
        while rings < 12 and site_count(p, q, rings + 1) <= 400_000:
            rings += 1
    rings = _validate.integer("rings", rings, minimum=5, maximum=14)
    n_sites = site_count(p, q, rings)
    if n_sites > 2_000_000:
        raise ValueError(f"the {rings}-ring {{{p},{q}}} flake is too large for the pattern scan; use fewer rings.")
    # the ring words take sites x (2W + 2) int64 (twice, with np.unique): refuse before allocating
    if n_sites * (2 * window + 2) > _MAX_WORD_ENTRIES:
        raise ValueError(f"window {window} on the {rings}-ring {{{p},{q}}} flake needs "
                         f"{n_sites * (2 * window + 2) * 16 / 1e9:.1f} GB of ring words (limit "
                         f"{_MAX_WORD_ENTRIES * 16 / 1e9:.0f} GB); use fewer rings or a smaller window.")
    rows, ring, n_types = _local_patterns(p, q, rings, window)
    pats = np.unique(rows, axis=0)
    closed = np.unique(rows[ring <= rings - 3], axis=0).shape[0] == pats.shape[0]
    growth = 1.0 / math.sqrt(max(site_count(p, q, rings) / site_count(p, q, rings - 1), 1.0))
    # the bound is certified for every x; x only tightens it (flat near the optimum: xatol 1e-3)
    res = minimize_scalar(lambda x: _certify(pats, x, n_types, q)[0], bounds=(0.5 * growth, min(1.0, 1.5 * growth)),
                          method="bounded", options={"xatol": 1e-3})
    x = float(res.x)
    bound, w = _certify(pats, x, n_types, q)
    return SchurBound(p=p, q=q, window=window, rings=rings, x=x, bound=bound, patterns=int(pats.shape[0]),
                      types=int(w.size), closed=bool(closed))


# ----------------------------------------------------------------------------
# the band bottom from both routes
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class BandBottom(Result):
    r"""The band bottom :math:`-\rho` of the infinite {p,q} lattice from both routes.

    All energies are in units of t (:math:`H = -tA`).

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    rings : ndarray
        The flakes used.
    estimate, error : float
        Route (a): the disk-model fit of E0 over the last six flakes, and the largest deviation
        of the other fit variants (models, windows, E1) from it, at least the change when the
        largest flake is dropped.
    variants : list of dict
        ``{"level", "model", "rings", "band_bottom", "max_residual", "params", "central",
        "fit_rings", "residuals"}`` of every fit (``rings`` = first and last flake fitted,
        ``residuals`` = fit minus data at ``fit_rings``).
    lower, upper : float
        Route (b), rigorous: :math:`-c \le -\rho \le E_0(\ell_{\max})` (c from :func:`schur_bound`;
        ``lower`` is NaN when no Schur bound was asked for).
    schur : dict or None
        The :class:`SchurBound` summary.
    paper_edge, improved_edge : float
        :math:`E_\infty = -q + \frac q4h^2` (the paper's map) and :math:`-qP_{-1/2}(\cosh 2d_0)`
        (the improved map's isotropic band bottom).
    band_mass : float
        Band curvature :math:`M = dE/d\lambda` of the central fit, against :math:`\frac q4h^2`.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> band = hl.band_bottom(7, 3, schur_window=None)
    >>> print(f"{band.estimate:.5f} +- {band.error:.0e}, upper {band.upper:.6f}")
    -2.94116 +- 6e-05, upper -2.932963
    >>> print(f"{band.paper_edge:.5f} {band.improved_edge:.5f}")
    -2.94295 -2.94096
    >>> value, error = band.predict([17])
    >>> print(f"{value[0]:.5f}")
    -2.93383
    """

    p: int
    q: int
    rings: np.ndarray
    estimate: float
    error: float
    variants: list
    lower: float
    upper: float
    schur: dict | None
    paper_edge: float
    improved_edge: float
    band_mass: float

    @property
    def rho(self) -> float:
        """The spectral radius :math:`\\rho = -E_b` (route (a))."""
        return -self.estimate

    @property
    def consistent(self) -> bool:
        """Whether the extrapolated interval lies inside the rigorous one."""
        lo = self.lower if math.isfinite(self.lower) else -math.inf
        return bool(lo <= self.estimate - self.error and self.estimate + self.error <= self.upper)

    def predict(self, rings, level: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """``(value, error)`` of E0 (``level=0``) or E1 at other ring counts: the central fit's
        model (for E1 the disk fit over the same flakes) and the largest deviation of the other
        variants of that level. An extrapolation beyond the fitted flakes is the test of the fit.

        Parameters
        ----------
        rings : array_like
            Ring counts l >= 1.
        level : int, optional
            0 for E0 (default), 1 for E1.

        Returns
        -------
        value, error : numpy.ndarray
            The predicted level and its spread over the fit variants, units of t.
        """
        ell = _validate.real_array("rings", rings, ndim=1)
        level = _validate.integer("level", level, minimum=0, maximum=1)
        if np.any(ell < 1):
            raise ValueError("rings must be >= 1.")
        mine = [v for v in self.variants if v["level"] == level]
        central = next((v for v in mine if v["central"]), None) or next(
            v for v in mine if v["model"] == "disk" and v["rings"] == next(c for c in self.variants if c["central"])["rings"])
        value = _model(central["model"], level, self.p, self.q, ell, np.array(central["params"]))
        err = np.zeros(ell.shape)
        for v in mine:
            err = np.maximum(err, np.abs(_model(v["model"], level, self.p, self.q, ell, np.array(v["params"])) - value))
        return value, err

    def summary(self) -> dict:
        """Estimate, error, rigorous interval, the two maps' edges and the fit variants."""
        return {"p": self.p, "q": self.q, "rings": self.rings.tolist(), "band_bottom": self.estimate,
                "error": self.error, "rho": self.rho, "rigorous": [float(self.lower), float(self.upper)],
                "consistent": self.consistent, "paper_edge": self.paper_edge,
                "improved_edge": self.improved_edge, "band_mass": self.band_mass,
                "paper_mass": self.paper_edge + self.q, "schur": self.schur, "variants": self.variants}


def _band_from(ell, e0, e1, p, q) -> tuple[float, float, list, float]:
    fits = _variants(ell, e0, e1, p, q)
    central = next(f for f in fits if f.level == 0 and f.model == "disk" and f.rings.size == min(6, ell.size))
    spread = max(abs(f.band_bottom - central.band_bottom) for f in fits)
    if ell.size >= 5:
        dropped = fit_band_bottom(ell[-min(6, ell.size - 1) - 1:-1], e0[-min(6, ell.size - 1) - 1:-1], p=p, q=q)
        spread = max(spread, abs(dropped.band_bottom - central.band_bottom))
    table = [{"level": f.level, "model": f.model, "rings": [int(f.rings[0]), int(f.rings[-1])],
              "band_bottom": f.band_bottom, "max_residual": float(np.max(np.abs(f.residuals))),
              "params": f.params.tolist(), "central": f is central,
              "fit_rings": f.rings.tolist(), "residuals": f.residuals.tolist()} for f in fits]
    return central.band_bottom, spread, table, float(central.params[1])


def band_bottom(p: int = 7, q: int = 3, rings=None, E0=None, E1=None, *, schur_window: int | None = 8,
                max_rings: int | None = None) -> BandBottom:
    r"""The band bottom :math:`-\rho(p,q)` with an error bar (route (a)) and a rigorous interval (route (b)).

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol of the lattice, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    rings, E0, E1 : array, optional
        Flake levels (ring counts, strictly increasing positive integers, and the two lowest
        eigenvalues of :math:`H = -A`, units of t; at least 6 flakes); default
        :data:`REFERENCE_LEVELS` from l = 3 on (the fits use the last 5 to 7 of them: the
        smallest flakes are far from the asymptotic regime). Give all three or none.
    schur_window : int or None, optional
        W of :func:`schur_bound` (None: no upper bound on rho, ``lower`` is NaN). Default 8.
    max_rings : int, optional
        Use only flakes up to this l (to test the extrapolation on larger flakes).

    Returns
    -------
    BandBottom
        ``estimate`` and ``error`` (route (a), units of t), the rigorous interval ``lower``,
        ``upper`` (route (b)), the fit ``variants``, the two maps' edges ``paper_edge`` and
        ``improved_edge`` and the band curvature ``band_mass``; ``rho`` is :math:`-E_b`.

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic or has no stored levels, only some of ``rings, E0, E1`` are
        given, the rings are not strictly increasing positive integers, fewer than 6 flakes
        remain, or E1 lies below E0.
    hyperlattice.errors.ConvergenceError
        If one of the fits does not converge.

    See Also
    --------
    fit_band_bottom : one fit variant.
    schur_bound : the rigorous upper bound on :math:`\rho`.
    plateau_analysis : what the band bottom implies for the paper's map.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> band = hl.band_bottom(7, 3, schur_window=None)
    >>> print(f"{band.estimate:.5f} +- {band.error:.0e}")
    -2.94116 +- 6e-05
    >>> print(f"{band.upper:.6f}")
    -2.932963
    """
    p, q = _validate.pq(p, q)
    if rings is None:
        if E0 is not None or E1 is not None:
            raise ValueError("give rings together with E0 and E1.")
        ell, e0, e1 = reference_levels(p, q)
        keep = ell >= 3
        ell, e0, e1 = ell[keep], e0[keep], e1[keep]
    else:
        ell = _validate.real_array("rings", rings, ndim=1)
        e0 = _validate.real_array("E0", E0, shape=ell.shape)
        e1 = _validate.real_array("E1", E1, shape=ell.shape)
        if np.any(ell != np.round(ell)) or np.any(ell < 1) or np.any(np.diff(ell) <= 0):
            raise ValueError("rings must be strictly increasing positive integers.")
    if max_rings is not None:
        max_rings = _validate.positive_int("max_rings", max_rings)
        keep = ell <= max_rings
        ell, e0, e1 = ell[keep], e0[keep], e1[keep]
    if ell.size < 6:
        raise ValueError(f"the band bottom needs at least 6 flakes, got {ell.size}.")
    if np.any(e1 < e0):
        raise ValueError("E1 must not lie below E0.")
    estimate, error, table, mass = _band_from(ell, e0, e1, p, q)
    schur = None
    lower = float("nan")
    if schur_window is not None:
        sb = schur_bound(p, q, window=schur_window)
        schur = sb.summary()
        lower = -sb.bound
    return BandBottom(p=p, q=q, rings=ell.astype(np.int64), estimate=estimate, error=error, variants=table,
                      lower=lower, upper=float(np.min(e0)), schur=schur,
                      paper_edge=-q + hopping_scale(p, q), improved_edge=improved_band_bottom(p, q),
                      band_mass=mass)


# ----------------------------------------------------------------------------
# why the plateau
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class PlateauAnalysis(Result):
    r"""The paper map's relative error and its limit :math:`(-\rho - E_\infty)/\rho` (module docstring).

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    rings : ndarray
        The flakes l.
    relative_E0, relative_E1 : ndarray
        :math:`(E_{\rm graph} - E_{\rm cont})/|E_{\rm graph}|` with the paper's map.
    limit, limit_error : float
        :math:`(-\rho - E_\infty)/\rho` from :class:`BandBottom` (its error propagated).
    fitted_limit_E0, fitted_limit_E1 : float
        The same limit from the fitted flake levels: the disk fits of E0 and E1 continued to the
        l where the area radius reaches 200 (l ~ 415 for {7,3}), against the paper's continuum
        levels there.
    peak_rings, peak_value : float
        Where the E0 relative error of the fitted curve is largest and its value: the computed
        values rise to it and then fall back to ``limit`` like :math:`1/\ell^2`.
    curve_rings, curve : ndarray
        That curve: the relative error of the fitted E0 (disk model) against the paper's
        continuum E0, for l from the first flake to 60.
    terms : dict
        :math:`-\rho - E_\infty` split into ``isotropic_h4`` (:math:`\frac{7q}{64}h^4`),
        ``isotropic_rest`` (exact :math:`-qP_{-1/2}(\cosh 2d_0)` minus the first two orders) and
        ``anisotropic`` (the rest: the :math:`m=\pm q, \pm 2q, \dots` part of the star), each with
        its share of the total.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> pa = hl.plateau_analysis(hl.band_bottom(7, 3, schur_window=None))
    >>> print(f"{pa.limit:.4f}")
    0.0006
    >>> sorted(pa.terms)[:3]
    ['anisotropic', 'anisotropic_error', 'isotropic_h4']
    """

    COLUMNS = (Column("rings", "rings", "1"), Column("relative_E0", "relative_E0", "1"),
               Column("relative_E1", "relative_E1", "1"))

    p: int
    q: int
    rings: np.ndarray
    relative_E0: np.ndarray
    relative_E1: np.ndarray
    limit: float
    limit_error: float
    fitted_limit_E0: float
    fitted_limit_E1: float
    peak_rings: float
    peak_value: float
    curve_rings: np.ndarray
    curve: np.ndarray
    terms: dict

    def summary(self) -> dict:
        """All fields as plain JSON."""
        return super().summary()


def plateau_analysis(band: BandBottom, rings=None, E0=None, E1=None) -> PlateauAnalysis:
    r"""Why the relative error of the paper's map saturates, from a :class:`BandBottom`.

    The graph levels go to :math:`-\rho`, the paper's continuum levels to
    :math:`E_\infty = -q + \frac q4 h^2`, so the relative error tends to
    :math:`(-\rho - E_\infty)/\rho`; this splits that difference into the isotropic and
    anisotropic terms of the star (module docstring, "Why the plateau").

    Parameters
    ----------
    band : BandBottom
        The band bottom of the lattice, from :func:`band_bottom`.
    rings, E0, E1 : array, optional
        Flake levels (ring counts, strictly increasing positive integers, and the two lowest
        eigenvalues of :math:`H = -A`, units of t; at least 6 flakes). Default
        :data:`REFERENCE_LEVELS` of the band's lattice (all flakes from l = 3 on). Give all
        three or none.

    Returns
    -------
    PlateauAnalysis
        The relative errors ``relative_E0``, ``relative_E1`` of the paper's map at each flake,
        their ``limit`` (with ``limit_error``), the fitted curve continued to large l with its
        ``peak_rings`` and ``peak_value``, and the split ``terms``.

    Raises
    ------
    ValueError
        If ``band`` is not a BandBottom, only some of ``rings, E0, E1`` are given, the rings are
        not strictly increasing positive integers or fewer than 6 flakes are given.

    See Also
    --------
    band_bottom, compare_dictionaries

    References
    ----------
    .. [1] I. Boettcher et al., "Quantum simulation of hyperbolic space with circuit quantum
       electrodynamics: From graphs to geometry", Phys. Rev. A 102, 032208 (2020): Eq. (8)
       (:math:`A \approx 3 + \frac34 h^2\Delta_g`, source label ``eq10``), which gives
       :math:`E_\infty`, and the appendix on the :math:`h^3` correction (``adj32``, ``adj33``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> band = hl.band_bottom(7, 3, schur_window=None)
    >>> pa = hl.plateau_analysis(band)
    >>> print(f"{pa.limit:.4f}")
    0.0006
    >>> sorted(pa.terms)[:3]
    ['anisotropic', 'anisotropic_error', 'isotropic_h4']
    """
    from ..continuum.spectrum import continuum_levels

    if not isinstance(band, BandBottom):
        raise ValueError("band must be a BandBottom (from band_bottom).")
    p, q = band.p, band.q
    if rings is None:
        if E0 is not None or E1 is not None:
            raise ValueError("give rings together with E0 and E1.")
        ell, e0, e1 = reference_levels(p, q)
        keep = ell >= 3
        ell, e0, e1 = ell[keep], e0[keep], e1[keep]
    else:
        ell = _validate.real_array("rings", rings, ndim=1)
        e0 = _validate.real_array("E0", E0, shape=ell.shape)
        e1 = _validate.real_array("E1", E1, shape=ell.shape)
        if np.any(ell != np.round(ell)) or np.any(ell < 1) or np.any(np.diff(ell) <= 0):
            raise ValueError("rings must be strictly increasing positive integers.")
    if ell.size < 6:
        raise ValueError(f"the plateau analysis needs at least 6 flakes, got {ell.size}.")
    cont = [continuum_levels(p, q, rings=int(x), levels=3) for x in ell]
    c0 = np.array([c.energies[0] for c in cont])
    c1 = np.array([c.energies[1] for c in cont])
    eb, err = band.estimate, band.error
    e_inf = band.paper_edge
    limit = (eb - e_inf) / abs(eb)
    # d/d(eb) of (eb - e_inf)/(-eb) = -e_inf/eb^2 ... propagate the error bar by evaluating both ends
    ends = [((eb + s * err) - e_inf) / abs(eb + s * err) for s in (-1.0, 1.0)]
    limit_error = max(abs(v - limit) for v in ends)
    # the fitted levels continued to large l (disk model, last six flakes)
    n = min(6, ell.size)
    fits = [fit_band_bottom(ell[-n:], e[-n:], p=p, q=q, level=lv) for lv, e in ((0, e0), (1, e1))]
    far = int(ell[-1])
    while _area_radius(p, q, np.array([far + 1]))[0] < 200.0:
        far += 1
    lim_fit = []
    for lv, f in enumerate(fits):
        g = float(f.predict(np.array([float(far)]))[0])
        c = continuum_levels(p, q, rings=far, levels=3).energies[lv]
        lim_fit.append((g - c) / abs(g))
    grid = np.arange(float(ell[0]), 61.0)
    g0 = fits[0].predict(grid)
    # the paper's continuum E0 on the eq12 disk of each l (the interpolated root equals
    # dirichlet_roots to 1e-15, tested; continuum_levels per l would cost 50x more)
    cg = energy_from_k(_disk_k(0, _area_radius(p, q, grid)), p, q)
    rel_curve = (g0 - cg) / np.abs(g0)
    i = int(np.argmax(rel_curve))
    h = lattice_h(p, q)
    total = eb - e_inf
    iso4 = 7.0 * q / 64.0 * h ** 4
    iso_rest = band.improved_edge - e_inf - iso4
    aniso = eb - band.improved_edge
    terms = {"total": total, "total_error": err,
             "isotropic_h4": iso4, "isotropic_rest": iso_rest, "anisotropic": aniso, "anisotropic_error": err,
             "share_isotropic": (iso4 + iso_rest) / total, "share_anisotropic": aniso / total}
    return PlateauAnalysis(p=p, q=q, rings=ell.astype(np.int64), relative_E0=(e0 - c0) / np.abs(e0),
                           relative_E1=(e1 - c1) / np.abs(e1), limit=limit, limit_error=limit_error,
                           fitted_limit_E0=lim_fit[0], fitted_limit_E1=lim_fit[1], peak_rings=float(grid[i]),
                           peak_value=float(rel_curve[i]), curve_rings=grid.astype(np.int64), curve=rel_curve,
                           terms=terms)


# ----------------------------------------------------------------------------
# the improved dictionary against the graph
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class DictionaryComparison(Result):
    r"""Relative error :math:`(E_{\rm graph} - E_{\rm cont})/|E_{\rm graph}|` of E0 and E1 for the
    paper's and the improved dictionary.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    rings : ndarray
        The flakes l.
    graph_E0, graph_E1 : ndarray
        The graph levels, units of t.
    paper_E0, paper_E1, improved_E0, improved_E1 : ndarray
        The relative errors.
    improved_limit : float
        :math:`(-\rho - E_\infty^{\rm impr})/\rho`, the l -> infinity limit of the improved
        relative error (NaN without a band bottom).
    improved_limit_error : float
        Its error, propagated from the band bottom.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.limits import reference_levels
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> dc = hl.compare_dictionaries(rings[-2:], E0[-2:], E1[-2:], p=7, q=3)
    >>> dc.rings.tolist(), f"{dc.paper_E0[-1]:.4f}", f"{dc.gain(15)['E0']:.1f}"
    ([15, 16], '0.0007', '106.8')
    """

    COLUMNS = (Column("rings", "rings", "1"), Column("graph_E0", "graph_E0", "t"),
               Column("graph_E1", "graph_E1", "t"), Column("paper_E0", "paper_E0", "1"),
               Column("paper_E1", "paper_E1", "1"), Column("improved_E0", "improved_E0", "1"),
               Column("improved_E1", "improved_E1", "1"))

    p: int
    q: int
    rings: np.ndarray
    graph_E0: np.ndarray
    graph_E1: np.ndarray
    paper_E0: np.ndarray
    paper_E1: np.ndarray
    improved_E0: np.ndarray
    improved_E1: np.ndarray
    improved_limit: float
    improved_limit_error: float

    def gain(self, rings: int | None = None) -> dict:
        """``{"E0", "E1"}``: ``|paper error| / |improved error|`` at ``rings`` (default: the largest l).

        Parameters
        ----------
        rings : int, optional
            One of :attr:`rings`; default the largest.

        Returns
        -------
        dict
            ``{"E0": float, "E1": float}``.

        Raises
        ------
        ValueError
            If ``rings`` is not in the comparison.
        """
        i = -1 if rings is None else int(np.nonzero(self.rings == rings)[0][0]) if rings in self.rings else None
        if i is None:
            raise ValueError(f"l = {rings} is not in the comparison.")
        return {"E0": float(abs(self.paper_E0[i]) / abs(self.improved_E0[i])),
                "E1": float(abs(self.paper_E1[i]) / abs(self.improved_E1[i]))}

    def table(self) -> list[dict]:
        """One dict per l."""
        return [{"rings": int(x), "paper_E0": float(a), "improved_E0": float(b), "paper_E1": float(c),
                 "improved_E1": float(d)}
                for x, a, b, c, d in zip(self.rings, self.paper_E0, self.improved_E0, self.paper_E1,
                                         self.improved_E1)]

    def summary(self) -> dict:
        """The table, the gain at the largest l and the improved map's limit."""
        return {"p": self.p, "q": self.q, "table": self.table(), "gain": self.gain(),
                "improved_limit": self.improved_limit, "improved_limit_error": self.improved_limit_error}


def compare_dictionaries(rings=None, E0=None, E1=None, *, p: int = 7, q: int = 3,
                         band: BandBottom | None = None) -> DictionaryComparison:
    r"""Graph levels against the continuum levels of both dictionaries (``continuum_levels``).

    Parameters
    ----------
    rings, E0, E1 : array, optional
        Flake levels: ring counts (strictly increasing positive integers) and the two lowest
        eigenvalues of :math:`H = -A` (units of t, nonzero). Default :data:`REFERENCE_LEVELS`
        for l = 6..(largest stored). Give all three or none.
    p, q : int, optional
        Schläfli symbol of the lattice, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    band : BandBottom, optional
        The band bottom of the same lattice (:func:`band_bottom`); adds the improved map's
        l -> infinity limit. Default None (``improved_limit`` is NaN).

    Returns
    -------
    DictionaryComparison
        The relative errors :math:`(E_{\rm graph} - E_{\rm cont})/|E_{\rm graph}|` of E0 and E1
        for the ``paper`` and ``improved`` maps at each l, and ``improved_limit`` (with
        ``improved_limit_error``); ``gain()`` gives the ratio of the two errors.

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic or has no stored levels, only some of ``rings, E0, E1`` are
        given, the rings are not strictly increasing positive integers, a graph energy is zero,
        or ``band`` belongs to another lattice.

    See Also
    --------
    hyperlattice.continuum_levels : the continuum levels, ``dictionary="paper"`` or
        ``"improved"``.
    plateau_analysis

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.limits import reference_levels
    >>> rings, E0, E1 = reference_levels(7, 3)
    >>> dc = hl.compare_dictionaries(rings[-2:], E0[-2:], E1[-2:], p=7, q=3)
    >>> dc.rings.tolist()
    [15, 16]
    >>> print(f"{dc.paper_E0[-1]:.4f} {dc.gain()['E0']:.1f}")
    0.0007 47.1
    """
    from ..continuum.spectrum import continuum_levels

    p, q = _validate.pq(p, q)
    if rings is None:
        if E0 is not None or E1 is not None:
            raise ValueError("give rings together with E0 and E1.")
        ell, e0, e1 = reference_levels(p, q)
        keep = ell >= 6
        ell, e0, e1 = ell[keep], e0[keep], e1[keep]
    else:
        ell = _validate.real_array("rings", rings, ndim=1)
        e0 = _validate.real_array("E0", E0, shape=ell.shape)
        e1 = _validate.real_array("E1", E1, shape=ell.shape)
        if ell.size == 0 or np.any(ell != np.round(ell)) or np.any(ell < 1) or np.any(np.diff(ell) <= 0):
            raise ValueError("rings must be strictly increasing positive integers.")
    if np.any(e0 == 0) or np.any(e1 == 0):
        raise ValueError("a graph energy is zero; the relative error is undefined there.")
    rel = {}
    for d in ("paper", "improved"):
        c = [continuum_levels(p, q, rings=int(x), levels=2, dictionary=d).energies for x in ell]
        rel[d] = ((e0 - np.array([v[0] for v in c])) / np.abs(e0), (e1 - np.array([v[1] for v in c])) / np.abs(e1))
    lim, lim_err = float("nan"), float("nan")
    if band is not None:
        if not isinstance(band, BandBottom) or (band.p, band.q) != (p, q):
            raise ValueError("band must be a BandBottom of the same {p,q}.")
        lim = (band.estimate - band.improved_edge) / abs(band.estimate)
        lim_err = band.error / abs(band.estimate)
    return DictionaryComparison(p=p, q=q, rings=ell.astype(np.int64), graph_E0=e0, graph_E1=e1,
                                paper_E0=rel["paper"][0], paper_E1=rel["paper"][1], improved_E0=rel["improved"][0],
                                improved_E1=rel["improved"][1], improved_limit=lim, improved_limit_error=lim_err)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
