r"""Dirichlet spectrum of the hyperbolic Laplacian on a disk of radius :math:`L<1`.

Continuum approximation of the hopping Hamiltonian :math:`H=-A` of a {p,q} lattice
(``eq10``/``adj26`` generalised to any coordination number :math:`q`, see
:func:`level_energy`):

.. math:: H^{(\rm cont)} = -q - \frac{q}{4}h^2\Delta_g,\qquad
          E_{nm} = -q + \frac{q}{4}h^2\,(1 + k_{nm}^2),

with :math:`k_{nm}` the :math:`n`-th positive root of the Dirichlet condition ``spec2``

.. math:: P^{m}_{\frac12(-1+\mathrm{i}k)}\Bigl(\frac{1+L^2}{1-L^2}\Bigr) = 0 .

Root search
-----------
Write :math:`x = (1+L^2)/(1-L^2) = \cosh t` (:math:`t/2` is the hyperbolic radius of the disk).
Consecutive roots in :math:`k` are about :math:`2\pi/(t+\ln 8)` apart for large disks (``spec9``)
and about :math:`2\pi/t` for small ones (:math:`k_{nm} \approx 2 j_{m,n}/t`, Bessel zeros
:math:`j_{m,n}`, spaced by about :math:`\pi`); the grid step (:func:`_grid_step`) is a sixth of
:math:`2\pi/(t+\ln 8)` for :math:`t \ge t_* = \ln 8/(1+\ln 8)` and grows like :math:`t_*/t` below,
staying under a sixth of the spacing in both regimes, so no grid cell holds two roots and the
number of grid points per root is bounded for every radius (the fixed step used before needed
:math:`\sim 1/L` points for small disks: 23 GB for ``radius=0.001, levels=50``). Roots are bracketed by sign changes counted from :math:`k=0` (so the
:math:`n`-th bracket holds the :math:`n`-th root), refined by a vectorized Chandrupatla iteration
(:func:`scipy.optimize.elementwise.find_root`) and verified (residual at the root relative to the
bracket values, strict ordering in :math:`n` and :math:`|m|`, and on request the number
:math:`n-1` of radial nodes of the eigenfunction).

Error bound of each level
-------------------------
For each root :math:`k` the module finds the smallest :math:`\delta` of a ladder (starting at the
final Chandrupatla bracket, times 4 per step) such that :math:`P^m_\nu(x')` has opposite signs at
:math:`k-\delta` and :math:`k+\delta`, both values larger than ten times the Legendre module's
error estimate, for :math:`x' = x(1\pm 4\varepsilon)` (:math:`\varepsilon` the machine epsilon: the
rounding of :math:`x` computed from :math:`L` or from the ring count). The exact root for the given
disk therefore lies in :math:`[k-\delta, k+\delta]`, and since
:math:`|E(k\pm\delta) - E(k)| \le \frac q4 h^2(2k\delta + \delta^2)`, that is the bound stored in
``errors`` (``error_kind = "energy error bound"``).

Cost and size limits
--------------------
All evaluations of the Legendre module run in chunks of :data:`_CHUNK` values (bounded memory).
The number of evaluations a request needs is predicted before each scan and refused beyond
:data:`MAX_EVALUATIONS` with a ValueError; orders beyond :data:`MAX_ORDER` are refused outright.

Dictionary
----------
Every function that turns roots into energies takes ``dictionary="paper"`` (the default: the
paper's map above, the numbers of the paper) or ``"improved"``: the exact circle average of the
q-fold star, :math:`E = -q P_{\frac12(-1+\mathrm ik)}(\cosh 2d_0)`, and for a disk given by
``rings`` the Dirichlet wall half a bond beyond the area radius
(:mod:`hyperlattice.dictionary`, :func:`~hyperlattice.dictionary.improved_disk_for_rings`). The
roots themselves are those of ``spec2`` in both cases.

Also here: the asymptotic formulas ``spec10``/``spec16`` and ``eq19``/``spec11``/``spec17``,
:math:`E_\infty = -q + \frac{q}{4}h^2`, the eigenfunctions ``eig12`` and the radial functions
``eig17``/``eig19``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special as sc
from scipy.optimize import elementwise as _elementwise

from .. import _validate
from ..dictionary import (
    _check_dictionary,
    disk_radius_for_rings,
    energy_from_k,
    hopping_scale,
    improved_disk_for_rings,
    map_energy_from_k,
)
from .._ties import stable_order
from ..errors import ConvergenceError
from ..geometry import lattice_h, one_minus_abs2
from ..results import INDEX, Column, Grid, Levels, Result
from .special import check_order, evaluate_checked, legendre_p, legendre_p_log_parts

__all__ = [
    "disk_argument",
    "dirichlet_roots",
    "dirichlet_levels",
    "DirichletTable",
    "continuum_levels",
    "ContinuumSpectrum",
    "level_energy",
    "energy_infinity",
    "asymptotic_k0",
    "asymptotic_k1",
    "asymptotic_energies",
    "psi_K",
    "radial_g",
    "MAX_EVALUATIONS",
    "MAX_ORDER",
]

GOLDEN = (1.0 + math.sqrt(5.0)) / 2.0

#: values per call of the Legendre module: its temporaries stay below a few tens of MB
_CHUNK = 1 << 13
#: evaluations of P^m_nu one request may spend (about 30 s on one core); more is refused
MAX_EVALUATIONS = 4_000_000
#: largest order ``|m|`` accepted (the Legendre module is validated to m = 30 and works well beyond)
MAX_ORDER = 1000
#: relative rounding of x = (1+L^2)/(1-L^2) as computed from L or from a ring count
_X_ROUNDING = 4.0 * np.finfo(float).eps
#: Chandrupatla tolerances: the bracket shrinks to a few ulps of k
_TOLERANCES = {"xatol": 1e-15, "xrtol": 4.0 * np.finfo(float).eps, "fatol": 0.0, "frtol": 0.0}
#: largest node count of the eig17 quadrature in radial_g (16 MB of complex values)
_MAX_NODES = 1 << 20
#: largest ring count accepted for a disk (the site count of {7,3} passes 1e308 at 733 rings)
_MAX_RINGS = 1000


# ----------------------------------------------------------------------------
# the disk
# ----------------------------------------------------------------------------

def disk_argument(radius=None, *, p=7, q=3, rings=None, dictionary: str = "paper") -> tuple[float, float]:
    r"""The disk radius and the argument of the Dirichlet condition, ``(L, x_L)``.

    :math:`x_L = (1+L^2)/(1-L^2)` is the argument of :math:`P^m_\nu` in ``spec2``. Either
    ``radius`` (:math:`0<L<1`) or ``rings`` (the {p,q} ring lattice with N sites,
    :math:`L=\sqrt{N/(N+c_{pq})}` by :func:`hyperlattice.dictionary.disk_radius_for_rings`,
    Eq. (10)). For rings, :math:`x_L = (2N + c_{pq})/c_{pq}` exactly, which keeps full relative
    precision even when :math:`1-L \sim 10^{-9}` would lose digits in :math:`L` itself. With
    ``dictionary="improved"`` and rings, the Dirichlet disk of
    :func:`hyperlattice.dictionary.improved_disk_for_rings` (a given radius is used as it is).

    Parameters
    ----------
    radius : float, optional
        Euclidean disk radius :math:`L \in (0, 1)`; give exactly one of ``radius`` and ``rings``.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    rings : int, optional
        Number of rings of the {p,q} flake (at most 1000).
    dictionary : {'paper', 'improved'}, optional
        The map from Dirichlet roots to lattice energies: the paper's (default, ``spec1``) or the
        improved one (module docstring; for ``rings`` also its Dirichlet disk).

    Returns
    -------
    L : float
        The Euclidean disk radius.
    x_L : float
        :math:`(1+L^2)/(1-L^2) > 1`.

    Raises
    ------
    ValueError
        If both or neither of ``radius`` and ``rings`` are given, the radius is outside (0, 1),
        ``rings`` is not a positive integer up to 1000, ``dictionary`` is unknown, or {p,q} is
        not a hyperbolic tessellation.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (10) and Appendix F (``spec2``).

    Examples
    --------
    >>> from hyperlattice.continuum.spectrum import disk_argument
    >>> L, x = disk_argument(0.5)
    >>> print(f"{L:.6f} {x:.6f}")
    0.500000 1.666667
    >>> L, x = disk_argument(rings=2, p=7, q=3)
    >>> print(f"{L:.6f} {x:.6f}")
    0.745356 3.500000
    """
    p, q = _validate.pq(p, q)
    dictionary = _check_dictionary(dictionary)
    if (radius is None) == (rings is None):
        raise ValueError("give exactly one of radius or rings.")
    if rings is not None:
        rings = _validate.positive_int("rings", rings, maximum=_MAX_RINGS)
        if dictionary == "improved":
            return improved_disk_for_rings(rings, p, q)
        return disk_radius_for_rings(rings, p, q)
    r = _validate.radius("the disk radius L", radius)
    return r, (1.0 + r * r) / ((1.0 - r) * (1.0 + r))


# ----------------------------------------------------------------------------
# energies and asymptotics
# ----------------------------------------------------------------------------

def level_energy(k, p=7, q=3, *, dictionary: str = "paper") -> float | np.ndarray:
    r"""Continuum energy :math:`E = -q + \frac{q}{4}h^2(1+k^2)` of a Dirichlet level.

    Derivation of the :math:`q`-dependence (generalising Eq. (8) and Appendix B): move
    site :math:`i` to the origin by a Möbius map; its :math:`q` neighbours sit at
    :math:`w_a = h e^{\mathrm{i}(\chi+2\pi a/q)}`, :math:`a=0..q-1`, with :math:`h=\tanh d_0`.
    Expanding :math:`\sum_a f(z(w_a))` to second order in :math:`h` gives
    :math:`q f + (\text{first order}) \sum_a w_a + (\text{holomorphic 2nd order}) \sum_a w_a^2
    + (1-|z|^2)^2 \sum_a |w_a|^2\,\partial\bar\partial f`. For :math:`q \ge 3`,
    :math:`\sum_a w_a = \sum_a w_a^2 = 0` and :math:`\sum_a|w_a|^2 = q h^2`, so
    :math:`A f = q f + q h^2 (1-|z|^2)^2\partial\bar\partial f + O(h^3)
    = q f + \frac{q}{4}h^2\Delta_g f + O(h^3)` (using :math:`\Delta_g = 4(1-|z|^2)^2
    \partial\bar\partial`). Hence :math:`H=-A \approx -q - \frac{q}{4}h^2\Delta_g` and an
    eigenvalue :math:`-(1+k^2)` of :math:`\Delta_g` gives the energy above; for :math:`q=3` this
    is ``spec1``, :math:`-3 + \frac34 h^2(1+k^2)`. The map itself is
    :func:`hyperlattice.dictionary.energy_from_k`; ``dictionary="improved"`` uses
    :func:`hyperlattice.dictionary.improved_energy_from_k` instead.

    Parameters
    ----------
    k : float or array_like of float
        Dirichlet root(s) :math:`k_{nm}` (real).
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    dictionary : {'paper', 'improved'}, optional
        The map from k to energies (default ``"paper"``).

    Returns
    -------
    float or ndarray of float
        The energy E in units of t (:math:`H = -tA`), a float for scalar ``k``.

    Raises
    ------
    ValueError
        If ``k`` is not real and finite, {p,q} is not a hyperbolic tessellation, or
        ``dictionary`` is unknown.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (8) and Appendix F (``spec1``).

    Examples
    --------
    >>> from hyperlattice.continuum.spectrum import level_energy
    >>> print(f"{level_energy(1.0, 7, 3):.6f}")
    -2.885903
    >>> print(f"{level_energy(1.0, 7, 3, dictionary='improved'):.6f}")
    -2.882509
    """
    p, q = _validate.pq(p, q)
    out = map_energy_from_k(_validate.real_array("k", k), p, q, dictionary)
    return float(out) if np.ndim(out) == 0 else out


def energy_infinity(p=7, q=3, *, dictionary: str = "paper") -> float:
    r"""The band bottom :math:`E_\infty = -q + \frac{q}{4}h^2`, the :math:`k\to 0` limit.

    Main text after Eq. (17); :math:`-2.94295` for {7,3}. With ``dictionary="improved"``
    :math:`-q P_{-1/2}(\cosh 2d_0)` (:math:`-2.940961` for {7,3}).

    Parameters
    ----------
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    dictionary : {'paper', 'improved'}, optional
        The map from k to energies (default ``"paper"``).

    Returns
    -------
    float
        :math:`E_\infty` in units of t.

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation or ``dictionary`` is unknown.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (17).

    Examples
    --------
    >>> from hyperlattice.continuum.spectrum import energy_infinity
    >>> print(f"{energy_infinity(7, 3):.6f}")
    -2.942952
    >>> print(f"{energy_infinity(7, 3, dictionary='improved'):.6f}")
    -2.940961
    """
    return level_energy(0.0, p, q, dictionary=dictionary)


def _x_array(x) -> np.ndarray:
    x = _validate.real_array("x = (1+L^2)/(1-L^2)", x)
    if np.any(x <= 1.0):
        raise ValueError("x = (1+L^2)/(1-L^2) must be greater than 1.")
    return x


def asymptotic_k0(x) -> float | np.ndarray:
    r"""Large-disk asymptote of the lowest Dirichlet root, :math:`k_0 \sim 2\pi/\ln(8x)`.

    Valid for :math:`x = (1+L^2)/(1-L^2)\to\infty` (Appendix F, ``spec10``).

    Parameters
    ----------
    x : float or array_like of float
        :math:`x_L = (1+L^2)/(1-L^2) > 1`.

    Returns
    -------
    float or ndarray of float
        The asymptotic root :math:`k_0`, a float for scalar ``x``.

    Raises
    ------
    ValueError
        If ``x`` is not real and finite, or :math:`x \le 1`.

    See Also
    --------
    asymptotic_k1, asymptotic_energies

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix F (``spec10``).

    Examples
    --------
    >>> from hyperlattice.continuum.spectrum import asymptotic_k0
    >>> print(f"{asymptotic_k0(100.0):.6f}")
    0.939948
    """
    out = 2.0 * np.pi / np.log(8.0 * _x_array(x))
    return float(out) if out.ndim == 0 else out


def asymptotic_k1(x) -> float | np.ndarray:
    r"""Large-disk asymptote of the second Dirichlet root, :math:`k_1 \sim 2\pi/\ln(8x/e^2)`.

    Valid for :math:`x = (1+L^2)/(1-L^2)\to\infty` (Appendix F, ``spec16``).

    Parameters
    ----------
    x : float or array_like of float
        :math:`x_L = (1+L^2)/(1-L^2) > 1`.

    Returns
    -------
    float or ndarray of float
        The asymptotic root :math:`k_1`, a float for scalar ``x``.

    Raises
    ------
    ValueError
        If ``x`` is not real and finite, or :math:`x \le 1`.

    See Also
    --------
    asymptotic_k0, asymptotic_energies

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix F (``spec16``).

    Examples
    --------
    >>> from hyperlattice.continuum.spectrum import asymptotic_k1
    >>> print(f"{asymptotic_k1(100.0):.6f}")
    1.341239
    """
    out = 2.0 * np.pi / (np.log(8.0 * _x_array(x)) - 2.0)
    return float(out) if out.ndim == 0 else out


def asymptotic_energies(p=7, q=3, *, radius=None, rings=None, form="auto", dictionary: str = "paper") -> dict:
    r"""Large-disk asymptotics of the two lowest continuum levels.

    ``form="rings"`` (only {7,3} with ``rings``): Eq. (17) with ``spec11``/``spec17``,
    :math:`E_{0,1} \sim E_\infty + \frac{3\pi^2h^2}{4}[\ln\varphi\,\ell + c_{0,1}]^{-2}`,
    :math:`c_0=\ln 2`, :math:`c_1 = \ln 2 - 1` — the paper's "asymptotic" rows of ``SuppTab1``
    (they use :math:`N\sim 7\varphi^{2\ell}`; ``rings`` may be any real :math:`\ell \ge 1` here, to
    draw the formula as a curve). ``form="radius"`` (any {p,q}): ``spec10`` and
    ``spec16`` inserted in :func:`level_energy`, i.e. with the exact :math:`x_L`;
    ``"auto"`` picks ``"rings"`` for {7,3} with rings and ``"radius"`` otherwise.
    ``dictionary="improved"`` (only with ``form="radius"`` or ``"auto"``, which then means
    ``"radius"``) uses the improved map and, for rings, its Dirichlet disk.

    Parameters
    ----------
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    radius : float, optional
        Disk radius :math:`L \in (0, 1)`; give exactly one of ``radius`` and ``rings``.
    rings : int or float, optional
        Number of rings :math:`\ell` (a real :math:`\ell \ge 1` with ``form="rings"``).
    form : {'auto', 'rings', 'radius'}, optional
        Which asymptotic formula (default ``"auto"``, see above).
    dictionary : {'paper', 'improved'}, optional
        The map from Dirichlet roots to lattice energies: the paper's (default, ``spec1``) or the
        improved one (module docstring; for ``rings`` also its Dirichlet disk).

    Returns
    -------
    dict
        ``{"E0", "E1", "E_inf"}`` (floats, units of t): the asymptotic two lowest energies and
        the band bottom :math:`E_\infty`.

    Raises
    ------
    ValueError
        If the disk is not given by exactly one of ``radius`` and ``rings``, ``form="rings"`` is
        asked for without rings, for another lattice than {7,3} or with the improved dictionary,
        or another argument is invalid.

    See Also
    --------
    energy_infinity, continuum_levels

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (17) and Appendix F.

    Examples
    --------
    >>> from hyperlattice.continuum.spectrum import asymptotic_energies
    >>> a = asymptotic_energies(7, 3, rings=5)
    >>> print(f"{a['E0']:.6f} {a['E1']:.6f} {a['E_inf']:.6f}")
    -2.884332 -2.815181 -2.942952
    >>> a = asymptotic_energies(7, 3, radius=0.9)
    >>> print(f"{a['E0']:.6f} {a['E1']:.6f}")
    -2.823022 -2.529345
    """
    p, q = _validate.pq(p, q)
    form = _validate.choice("form", form, ("auto", "rings", "radius"))
    dictionary = _check_dictionary(dictionary)
    if dictionary == "improved":
        if form == "rings":
            raise ValueError("the ring form of eq19 belongs to the paper's dictionary; use form='radius'.")
        _, x = disk_argument(radius, p=p, q=q, rings=rings, dictionary=dictionary)
        return {"E0": level_energy(asymptotic_k0(x), p, q, dictionary=dictionary),
                "E1": level_energy(asymptotic_k1(x), p, q, dictionary=dictionary),
                "E_inf": energy_infinity(p, q, dictionary=dictionary)}
    e_inf = energy_infinity(p, q)
    if form == "auto":
        form = "rings" if (rings is not None and (p, q) == (7, 3)) else "radius"
    if form == "rings":
        if rings is None or (p, q) != (7, 3):
            raise ValueError("the ring form of eq19 is defined for {7,3} with a number of rings.")
        # eq19 is a smooth function of l: a real l >= 1 draws it as a curve (Fig2)
        rings = _validate.real("rings", rings, minimum=1.0, maximum=_MAX_RINGS)
        lnphi = math.log(GOLDEN)
        pref = math.pi**2 * hopping_scale(p, q)
        e0 = e_inf + pref / (lnphi * rings + math.log(2.0)) ** 2
        e1 = e_inf + pref / (lnphi * rings + math.log(2.0) - 1.0) ** 2
        return {"E0": e0, "E1": e1, "E_inf": e_inf}
    _, x = disk_argument(radius, p=p, q=q, rings=rings)
    return {"E0": level_energy(asymptotic_k0(x), p, q), "E1": level_energy(asymptotic_k1(x), p, q),
            "E_inf": e_inf}


# ----------------------------------------------------------------------------
# the Dirichlet function and its roots
# ----------------------------------------------------------------------------

def _evaluate(k, m, x) -> tuple[np.ndarray, np.ndarray]:
    r"""``(f, err)``: :math:`f = P^m_\nu(x)/|\prod_{n<m}(\nu-n)|`, :math:`\nu = (-1+\mathrm ik)/2`, and
    the Legendre module's estimate of its evaluation error, broadcast over ``k, m, x``.

    The normalisation is that of ``eig19`` (it makes f of the size of :math:`J_m`, so that
    neither large orders nor large k overflow); it does not change the sign, which carries the
    roots. Evaluated in chunks of :data:`_CHUNK` values so that memory stays bounded.
    """
    k, m, x = np.broadcast_arrays(np.asarray(k, dtype=float), np.asarray(m, dtype=np.int64),
                                  np.asarray(x, dtype=float))
    shape = k.shape
    kf, mf, xf = k.ravel(), m.ravel(), x.ravel()
    f = np.empty(kf.size)
    err = np.empty(kf.size)
    for a in range(0, kf.size, _CHUNK):
        sl = slice(a, a + _CHUNK)
        nu = -0.5 + 0.5j * kf[sl]
        mm = np.ascontiguousarray(mf[sl])
        s, mant, e = evaluate_checked(legendre_p_log_parts, nu, mm, np.ascontiguousarray(xf[sl]), warn=False)
        lp = _log_abs_product(nu, mm)
        with np.errstate(over="ignore", under="ignore"):
            scale = np.exp(s - lp)
            f[sl] = mant.real * scale
            err[sl] = e * scale
    return f.reshape(shape), err.reshape(shape)


def _log_abs_product(nu: np.ndarray, m: np.ndarray) -> np.ndarray:
    r""":math:`\ln\prod_{n<m}|\nu - n|`, the ``eig19`` normalisation of the Dirichlet function.

    A plain sum for small orders; :math:`\operatorname{Re}[\ln\Gamma(\nu+1) - \ln\Gamma(\nu+1-m)]`
    beyond (no pole: :math:`\operatorname{Re}\nu = -1/2`), which costs O(1) instead of O(m).
    """
    mmax = int(m.max()) if m.size else 0
    if mmax > 64:
        return (sc.loggamma(nu + 1.0) - sc.loggamma(nu + 1.0 - m)).real
    out = np.zeros(nu.shape)
    for j in range(mmax):
        out = np.where(j < m, out + np.log(np.abs(nu - j)), out)
    return out


def _dirichlet_function(k, m, x) -> np.ndarray:
    """The real function whose roots in k are the Dirichlet roots (see :func:`_evaluate`)."""
    return _evaluate(k, m, x)[0]


def _grid_step(t: float) -> float:
    r"""Grid step in k: a sixth of a lower estimate of the root spacing (module docstring).

    :math:`2\pi/(t+\ln 8)/6` (the spacing of ``spec9``) for :math:`t \ge t_* = \ln 8/(1+\ln 8)`,
    and that times :math:`t_*/t` below, so that the step follows the spacing :math:`\sim 2\pi/t`
    of small disks (at :math:`t\to0` it is :math:`2\pi/((1+\ln 8)t)/6`, a sixth of a third of
    the Bessel spacing).
    """
    t_star = math.log(8.0) / (1.0 + math.log(8.0))
    return 2.0 * math.pi / (t + math.log(8.0)) / 6.0 * max(1.0, t_star / t)


def _refuse_cost(evaluations: float, what: str) -> None:
    if evaluations > MAX_EVALUATIONS:
        raise ValueError(f"{what} needs about {evaluations:.3g} evaluations of P^m_nu, more than the "
                         f"limit of {MAX_EVALUATIONS:,} (about half a minute); ask for fewer levels or orders.")


def _scan(ms: np.ndarray, x: float, grid: np.ndarray) -> list:
    """Sign changes of f on ``grid`` for each order: a list of (lo, hi) index arrays."""
    nb = max(1, _CHUNK // grid.size)
    out = []
    for a in range(0, ms.size, nb):
        block = ms[a:a + nb]
        vals = _dirichlet_function(grid[None, :], block[:, None], x)
        sgn = np.sign(vals)
        # a root strictly inside a cell, or exactly on its left end
        hit = (sgn[:, :-1] * sgn[:, 1:] < 0) | (sgn[:, :-1] == 0)
        out.extend(np.flatnonzero(row) for row in hit)
    return out


def _refine(lo: np.ndarray, hi: np.ndarray, m: np.ndarray, x: float) -> tuple[np.ndarray, np.ndarray]:
    """Chandrupatla refinement of brackets (any shape); returns the roots and final bracket widths."""
    flo = _dirichlet_function(lo, m, x)
    fhi = _dirichlet_function(hi, m, x)
    res = _elementwise.find_root(lambda kk, mm: _dirichlet_function(kk, mm, x), (lo, hi), args=(m,),
                                 tolerances=_TOLERANCES)
    if not np.all(res.success):
        raise ConvergenceError("the Dirichlet root refinement did not converge "
                               f"(status {np.unique(res.status)}).")
    k = np.asarray(res.x, dtype=float)
    # verification 1: the residual at the root is at rounding level relative to the bracket values
    fk = _dirichlet_function(k, m, x)
    if np.any(np.abs(fk) > 1e-8 * np.maximum(np.abs(flo), np.abs(fhi))):
        raise ConvergenceError("a Dirichlet root failed its residual check.")
    width = np.abs(np.asarray(res.bracket[1]) - np.asarray(res.bracket[0]))
    return k, width


def _enclosure(k: np.ndarray, m: np.ndarray, x: float, width: np.ndarray, x_rounding: float) -> np.ndarray:
    r"""Half-width :math:`\delta` of a verified enclosure :math:`[k-\delta, k+\delta]` of each root.

    Verified means: f changes sign between :math:`k\pm\delta`, with :math:`|f|` above ten times its
    evaluation-error estimate at both ends, for both :math:`x(1\pm` ``x_rounding``:math:`)`. The
    exact root for any x in that interval (k decreases monotonically with x) lies inside.
    """
    shape = k.shape
    k, m, width = k.ravel(), np.broadcast_to(m, shape).ravel(), width.ravel()
    xs = [x] if x_rounding == 0 else [x * (1.0 - x_rounding), x * (1.0 + x_rounding)]
    delta = np.maximum(width, 4.0 * np.spacing(k))
    out = np.full(k.size, np.nan)
    todo = np.arange(k.size)
    for _ in range(20):           # delta grows by 4^20 ~ 1e12 at most: a failure is a real problem
        ok = np.ones(todo.size, bool)
        for xv in xs:
            fl, el = _evaluate(k[todo] - delta[todo], m[todo], xv)
            fr, er = _evaluate(k[todo] + delta[todo], m[todo], xv)
            ok &= (np.sign(fl) * np.sign(fr) < 0) & (np.abs(fl) > 10.0 * el) & (np.abs(fr) > 10.0 * er)
        out[todo[ok]] = delta[todo[ok]]
        todo = todo[~ok]
        if todo.size == 0:
            return out.reshape(shape)
        delta[todo] *= 4.0
    raise ConvergenceError("could not verify an enclosure of a Dirichlet root (the Legendre function is "
                           "not accurate enough there).")


def _check_order_values(m) -> tuple[np.ndarray, bool]:
    """``(|m| as a 1-d int64 array, whether m was a scalar)``; orders at most MAX_ORDER."""
    msg = "the order m must be an integer or a 1-d list of integers"
    try:
        m_arr = np.asarray(m)
    except (TypeError, ValueError):
        raise ValueError(f"{msg}.") from None
    if m_arr.dtype.kind not in "iuf" or m_arr.ndim > 1:
        raise ValueError(f"{msg}, got {m!r}."[:200])
    if m_arr.dtype.kind == "f" and not np.all(np.isfinite(m_arr)):
        raise ValueError(f"{msg}, got a NaN or infinite value.")
    scalar = m_arr.ndim == 0
    try:
        ms = check_order(np.abs(np.atleast_1d(m_arr)))
    except (TypeError, ValueError):
        raise ValueError(f"{msg}, got {m!r}."[:200]) from None
    if ms.size and int(ms.max()) > MAX_ORDER:
        raise ValueError(f"orders |m| up to {MAX_ORDER} are supported, got {int(ms.max())}.")
    return ms, scalar


def _roots_at_x(ms: np.ndarray, x: float, n_roots: int, *, check_nodes: bool = False,
                x_rounding: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """k_{n,m} for n = 1..n_roots and each m in ``ms``, with enclosure half-widths; arrays (len(ms), n_roots)."""
    t = math.acosh(x)
    dk = _grid_step(t)
    # upper end: Bessel/WKB estimate k ~ 2 (n + m/2 + 1) pi / t, enlarged until enough roots
    mmax = float(ms.max())
    kmax = 2.0 * math.pi * (n_roots + 0.5 * mmax + 1.0) / t + 4.0 * mmax / t + 1.0
    spent = 0.0
    for _attempt in range(8):
        npts = math.ceil(kmax / dk) + 1
        spent += npts * ms.size
        _refuse_cost(spent + 30.0 * n_roots * ms.size * (1 + check_nodes * 20),
                     f"{n_roots} roots for {ms.size} order(s)")
        grid = np.arange(npts) * dk
        cells = _scan(ms, x, grid)
        if all(c.size >= n_roots for c in cells):
            break
        kmax *= 2.0
    else:
        raise ConvergenceError(f"could not bracket {n_roots} Dirichlet roots below k = {kmax:.3g}.")
    idx = np.array([c[:n_roots] for c in cells])
    mgrid = np.broadcast_to(ms[:, None], idx.shape)
    k, width = _refine(grid[idx], grid[idx + 1], mgrid, x)
    _check_order_of_roots(k, ms)
    if check_nodes:
        _check_radial_nodes(k, ms, x)
    return k, _enclosure(k, mgrid, x, width, x_rounding)


def _check_order_of_roots(k: np.ndarray, ms: np.ndarray) -> None:
    """Verification 2: strict ordering in n (simple roots) and of the lowest roots in |m|."""
    if np.any(np.diff(k, axis=1) <= 0):
        raise ConvergenceError("Dirichlet roots are not strictly increasing in n.")
    first = np.array([k[ms == v, 0][0] for v in np.unique(ms)])      # ascending |m|
    if first.size > 1 and np.any(np.diff(first) <= 0):
        raise ConvergenceError("lowest Dirichlet roots are not increasing with |m|.")


def _check_radial_nodes(k, ms, x, npts: int = 600) -> None:
    """The n-th root's radial function P^m_nu(rho(r)) has n-1 sign changes on 0 < r < L."""
    t_l = math.acosh(x)
    rho = np.cosh(np.linspace(0.0, t_l, npts + 2)[1:-1])
    for a in range(k.shape[0]):
        vals = _dirichlet_function(k[a][:, None], ms[a], rho[None, :])
        sgn = np.sign(vals)
        nodes = (sgn[:, :-1] * sgn[:, 1:] < 0).sum(axis=-1)
        if np.any(nodes != np.arange(k.shape[1])):
            raise ConvergenceError("a Dirichlet eigenfunction has the wrong number of radial nodes.")


def dirichlet_roots(m, radius=None, n_roots: int = 5, *, x=None, check_nodes: bool = False) -> np.ndarray:
    r"""The first ``n_roots`` positive roots :math:`k_{nm}` of ``spec2`` for one or more orders.

    The roots of :math:`P^{m}_{\frac12(-1+\mathrm{i}k)}(x_L) = 0`, :math:`x_L = (1+L^2)/(1-L^2)`.

    Parameters
    ----------
    m : int or sequence of int
        Azimuthal quantum number(s); the roots depend on :math:`|m|` only (:math:`|m| \le`
        :data:`MAX_ORDER`).
    radius : float, optional
        Disk radius :math:`L \in (0,1)`. Alternatively pass ``x``.
    n_roots : int, optional
        Number of roots per order (n = 1..n_roots; default 5).
    x : float, optional
        :math:`x_L = (1+L^2)/(1-L^2) > 1` instead of ``radius`` (keyword only).
    check_nodes : bool, optional
        Also verify that the n-th eigenfunction has n-1 radial nodes (costs one extra
        evaluation on a radial grid). Default False.

    Returns
    -------
    ndarray of float
        Shape ``(n_roots,)`` for scalar ``m``, else ``(len(m), n_roots)``; increasing in n.

    Raises
    ------
    ValueError
        Radius outside (0, 1), both or neither of ``radius`` and ``x``, bad ``m`` or
        ``n_roots``, or a request beyond :data:`MAX_EVALUATIONS` evaluations.
    ConvergenceError
        If bracketing, refinement or verification fails.

    See Also
    --------
    dirichlet_levels, continuum_levels

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix F (``spec2``).

    Examples
    --------
    >>> from hyperlattice.continuum.spectrum import dirichlet_roots
    >>> [round(float(k), 6) for k in dirichlet_roots(0, 0.5, 3)]
    [4.41398, 10.064626, 15.763755]
    >>> k = dirichlet_roots([0, 1], 0.5, 2)
    >>> k.shape
    (2, 2)
    >>> print(f"{k[1, 0]:.6f}")
    6.908863
    """
    if x is None:
        if radius is None:
            raise ValueError("give the disk radius L (or x = (1+L^2)/(1-L^2)).")
        radius, x = disk_argument(radius)
        _check_disk_x(x, radius)
    else:
        if radius is not None:
            raise ValueError("give either radius or x, not both.")
        x = _validate.real("x = (1+L^2)/(1-L^2)", x, minimum=1.0, open_min=True)
    n_roots = _validate.positive_int("n_roots", n_roots, maximum=MAX_EVALUATIONS)
    check_nodes = _validate.flag("check_nodes", check_nodes)
    ms, scalar = _check_order_values(m)
    if ms.size == 0:
        return np.empty((0, n_roots))
    k, _ = _roots_at_x(ms, x, n_roots, check_nodes=check_nodes)
    return k[0] if scalar else k


# ----------------------------------------------------------------------------
# result types
# ----------------------------------------------------------------------------

def _energy_bound(k: np.ndarray, delta: np.ndarray, p: int, q: int, dictionary: str = "paper") -> np.ndarray:
    r"""Bound on the energy error of a level whose root is enclosed in :math:`[k-\delta, k+\delta]`.

    :math:`\max_{|k'-k|\le\delta}|E(k') - E(k)| = \frac q4 h^2(2k\delta + \delta^2)` (``spec1``),
    plus the rounding of :math:`E = -q + \frac q4 h^2(1+k^2)` itself (a few units in the last
    place of its terms). For the improved map (monotone in k on the levels' branch) the largest
    change of E between :math:`k\pm\delta` and k, plus the quadrature's rounding (a few ulps of q).
    """
    if dictionary == "improved":
        k = np.asarray(k, dtype=float)
        e = map_energy_from_k(k, p, q, dictionary)
        lo = map_energy_from_k(np.maximum(np.abs(k) - delta, 0.0), p, q, dictionary)
        hi = map_energy_from_k(np.abs(k) + delta, p, q, dictionary)
        return np.maximum(np.abs(hi - e), np.abs(e - lo)) + 16.0 * np.finfo(float).eps * q
    s = hopping_scale(p, q)
    k = np.abs(k)
    rounding = 4.0 * np.finfo(float).eps * (q + s * (1.0 + k * k))
    return s * (2.0 * k * delta + delta * delta) + rounding


def _check_disk_x(x: float, radius: float) -> None:
    """Refuse disks so small that x_L = (1+L^2)/(1-L^2) has no correct digits beyond the 1."""
    if x - 1.0 < 1e2 * _X_ROUNDING:
        raise ValueError(f"the disk radius L = {radius:g} is too small: x_L - 1 = 2L^2/(1-L^2) is lost to "
                         "rounding in double precision (the spectrum needs L >= 2e-7).")


@dataclass(frozen=True, eq=False, kw_only=True)
class DirichletTable(Result):
    r"""Roots :math:`k_{nm}` and energies :math:`E_{nm}` on a grid n = 1..n_max, m = 0..m_max.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    radius, x : float
        Disk radius L and :math:`x_L = (1+L^2)/(1-L^2)`.
    h : float
        :math:`\tanh d_0` of the lattice.
    k, energies, errors : ndarray, shape (n_max, m_max + 1)
        ``k[n - 1, m]``, the energies ``spec1`` and a bound on each energy's error (see the
        module docstring); energies and errors in units of t, the lattice's hopping
        (:math:`E_{nm} = -q + \frac q4 h^2(1 + k_{nm}^2)` for the paper's dictionary).

    Notes
    -----
    The disk radius L is Euclidean in the Poincaré disk of the paper's metric
    :math:`|dz|^2/(1-|z|^2)^2`; the hyperbolic radius is :math:`\operatorname{artanh} L`.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> t = hl.dirichlet_levels(7, 3, rings=2, n_max=2, m_max=2)
    >>> round(t.radius, 6), round(t.x, 6), t.radial_index.tolist()
    (0.745356, 3.5, [1, 2])
    >>> [round(float(k), 4) for k in t.k[0]], [round(float(e), 4) for e in t.energies[0]]
    ([2.5558, 3.8791, 4.9646], [-2.5703, -2.0845, -1.5368])
    """

    GRID = Grid(coords=(Column("n", "radial_index", "1"), Column("abs_m", INDEX, "1")),
                variables=(Column("energy", "energies", "t", ("n", "abs_m")),
                           Column("error", "errors", "t", ("n", "abs_m")),
                           Column("k", "k", "1", ("n", "abs_m"))))

    @property
    def radial_index(self) -> np.ndarray:
        """n = 1..n_max, the rows of the table."""
        return np.arange(1, self.energies.shape[0] + 1)

    p: int
    q: int
    radius: float
    x: float
    h: float
    k: np.ndarray
    energies: np.ndarray
    errors: np.ndarray


def dirichlet_levels(p=7, q=3, radius=None, rings=None, n_max: int = 5, m_max: int = 10,
                     *, check_nodes: bool = False, dictionary: str = "paper") -> DirichletTable:
    r"""Table of Dirichlet roots :math:`k_{nm}` and energies on a grid of (n, m).

    The roots of ``spec2`` and the energies :math:`E_{nm} = -q + \frac{q}{4}h^2(1+k_{nm}^2)`
    (``spec1``) for n = 1..n_max, m = 0..m_max (``dictionary="improved"``: the improved map and
    disk, module docstring).

    Parameters
    ----------
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    radius : float, optional
        Disk radius :math:`L \in (0, 1)`; give exactly one of ``radius`` and ``rings``.
    rings : int, optional
        Number of rings of the {p,q} lattice; :math:`L` from Eq. (10) with its exact site count.
    n_max : int, optional
        Largest radial index n (default 5).
    m_max : int, optional
        Largest order m, at most :data:`MAX_ORDER` (default 10).
    check_nodes : bool, optional
        Also verify the number of radial nodes of each eigenfunction (default False).
    dictionary : {'paper', 'improved'}, optional
        The map from Dirichlet roots to lattice energies: the paper's (default, ``spec1``) or the
        improved one (module docstring; for ``rings`` also its Dirichlet disk).

    Returns
    -------
    DirichletTable
        A frozen result with ``k``, ``energies`` (units of t) and ``errors`` (bounds on the
        energies), each of shape ``(n_max, m_max + 1)`` indexed ``[n - 1, m]``, and ``p``,
        ``q``, ``radius``, ``x``, ``h``.

    Raises
    ------
    ValueError
        Bad input, or a request beyond :data:`MAX_EVALUATIONS` evaluations.
    ConvergenceError
        If bracketing, refinement or verification of a root fails.

    See Also
    --------
    continuum_levels : the lowest states, sorted by energy.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix F (``spec1``, ``spec2``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> t = hl.dirichlet_levels(7, 3, rings=2, n_max=2, m_max=2)
    >>> t.energies.shape
    (2, 3)
    >>> [round(float(e), 6) for e in t.energies[0]]
    [-2.570293, -2.084519, -1.536849]
    """
    p, q = _validate.pq(p, q)
    dictionary = _check_dictionary(dictionary)
    radius, x = disk_argument(radius, p=p, q=q, rings=rings, dictionary=dictionary)
    n_max = _validate.positive_int("n_max", n_max, maximum=MAX_EVALUATIONS)
    m_max = _validate.integer("m_max", m_max, minimum=0, maximum=MAX_ORDER)
    check_nodes = _validate.flag("check_nodes", check_nodes)
    _check_disk_x(x, radius)
    k, delta = _roots_at_x(np.arange(m_max + 1), x, n_max, check_nodes=check_nodes, x_rounding=_X_ROUNDING)
    k, delta = k.T, delta.T
    return DirichletTable(p=p, q=q, radius=radius, x=x, h=lattice_h(p, q), k=k,
                          energies=level_energy(k, p, q, dictionary=dictionary),
                          errors=_energy_bound(k, delta, p, q, dictionary))


@dataclass(frozen=True, eq=False, kw_only=True)
class ContinuumSpectrum(Levels):
    r"""The lowest continuum levels, one row per state, ascending in energy (a :class:`Levels`).

    Labels follow the graph ``spectrum`` command: ``n`` is the radial index within
    :math:`|m|`, ``m`` is signed and a level with :math:`m\ne0` appears twice, first as
    :math:`+m`, then as :math:`-m`. ``errors`` bounds each energy's error (module docstring).
    The attributes below come in addition to those of :class:`Levels`.

    Attributes
    ----------
    rings : int or None
        Ring count the disk was derived from (``eq12``), or None for a given radius.
    radius, x : float
        L and :math:`x_L = (1+L^2)/(1-L^2)`.
    h : float
        :math:`\tanh d_0`.
    k : ndarray
        The Dirichlet roots of the levels.
    asymptotic : dict
        ``{"E0", "E1", "E_inf"}`` from :func:`asymptotic_energies`.
    dictionary : str
        ``"paper"`` or ``"improved"``: the map from roots to energies (and, for rings, the disk).
        Not part of :meth:`summary` (the CLI's JSON keys are the same for both).
    error_kind : str
        ``"energy error bound"``.
    method : str
        ``"dirichlet-roots"``.
    description : str
        One sentence on the root search.

    Notes
    -----
    Energies and errors are in units of t (the map from roots to energies of the chosen
    ``dictionary``); L is the Euclidean disk radius in the paper's Poincaré disk.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> s = hl.continuum_levels(7, 3, rings=2, levels=4)
    >>> [round(float(e), 4) for e in s.energies], s.m.tolist()
    ([-2.5703, -2.0845, -2.0845, -1.5368], [0, 1, -1, 2])
    >>> s.rings, round(s.radius, 6), s.error_kind, s.dictionary
    (2, 0.745356, 'energy error bound', 'paper')
    """

    error_kind: str = "energy error bound"
    method: str = "dirichlet-roots"
    description: str = "spec2 roots: grid bracketing + Chandrupatla (scipy.optimize.elementwise)"
    rings: int | None
    radius: float
    x: float
    h: float
    k: np.ndarray
    asymptotic: dict
    dictionary: str = "paper"

    def summary(self) -> dict:
        """The CLI contract: keys p, q, rings, radius, h, energies, n, m, k, asymptotic."""
        return {"p": self.p, "q": self.q, "rings": self.rings, "radius": self.radius,
                "h": self.h, "energies": self.energies.tolist(), "n": self.n.tolist(),
                "m": self.m.tolist(), "k": self.k.tolist(), "asymptotic": dict(self.asymptotic)}


def _lowest_states(x: float, K: int, *, check_nodes: bool, x_rounding: float):
    r"""Roots of the K lowest states: ``(k, n, m, delta)`` per state, ascending.

    Because :math:`k_{nm}` increases with :math:`n` and with :math:`|m|`, the state
    :math:`(n, m)` has at least :math:`n-1 + 2(|m|-1) + 1` states below it, so the K lowest
    states have :math:`|m| \le \lfloor K/2\rfloor` and :math:`n \le K` (m = 0) or
    :math:`n \le \lceil K/2 \rceil` (m != 0). Among those, every state with :math:`k` below a
    cutoff :math:`\kappa` is found (orders m = 0, 1, ... until one has no root below
    :math:`\kappa`, since the lowest root grows with :math:`|m|`); :math:`\kappa` grows until
    there are at least K such states, which then contain the K lowest. Small disks need few
    orders and roots, large ones few grid points per order: the work stays about linear in K.
    """
    t = math.acosh(x)
    dk = _grid_step(t)
    m_cap = K // 2
    n_cap = {0: K}
    kappa = 12.0 * dk                   # about two root spacings
    spent = 0.0
    what = f"the {K:,} lowest continuum levels on this disk"
    while True:
        npts = math.ceil(kappa / dk) + 1
        grid = np.arange(npts) * dk
        found, count, m0, done, nb = [], 0, 0, False, 2
        while not done and m0 <= m_cap:
            if m0 > MAX_ORDER:
                # the lowest root of order m0 may still lie below kappa: the states asked for reach
                # beyond the orders the Legendre functions are validated for (was: "the order m must
                # be at most 1,000", a parameter the user never gave)
                raise ValueError(f"{what} reach angular momenta |m| > {MAX_ORDER:,}, beyond the range in which "
                                 "the Legendre functions are validated; ask for fewer levels.")
            block = np.arange(m0, min(m0 + nb, m_cap + 1, MAX_ORDER + 1))
            spent += npts * block.size
            _refuse_cost(spent, what)
            for mm, cells in zip(block, _scan(block, x, grid)):
                cells = cells[: n_cap.get(int(mm), (K + 1) // 2)]
                if cells.size == 0:
                    done = True
                    break
                found.append((int(mm), cells))
                count += cells.size * (1 if mm == 0 else 2)
            m0 += block.size
            nb = min(2 * nb, max(1, _CHUNK // npts))
        if count >= K:
            break
        # the count grows about like kappa^2 (Weyl) for small disks, faster for large ones
        kappa *= 2.0 if count == 0 else min(3.0, max(1.25, 1.1 * math.sqrt(K / count)))
    ms = np.concatenate([np.full(c.size, mm) for mm, c in found])
    ns = np.concatenate([np.arange(1, c.size + 1) for _, c in found])
    idx = np.concatenate([c for _, c in found])
    k, width = _refine(grid[idx], grid[idx + 1], ms, x)
    # verification 2 (ordering in n and |m|), on the ragged per-order lists
    for mm, _ in found:
        if np.any(np.diff(k[ms == mm]) <= 0):
            raise ConvergenceError("Dirichlet roots are not strictly increasing in n.")
    first = k[ns == 1]
    if np.any(np.diff(first) <= 0):
        raise ConvergenceError("lowest Dirichlet roots are not increasing with |m|.")
    # the states: m = 0 once, m != 0 as +m then -m
    ks = np.concatenate([k, k[ms > 0]])
    nn = np.concatenate([ns, ns[ms > 0]])
    mm_ = np.concatenate([ms, -ms[ms > 0]])
    wd = np.concatenate([width, width[ms > 0]])
    # ascending k; roots within their bracket widths of each other (the exact +-m pairs, and
    # accidental degeneracies of different |m|) are ordered by (|m|, +m first, n), never by their
    # last bits, so the cut at K keeps the same states on every machine
    order = stable_order(ks, wd, np.abs(mm_), (mm_ < 0).astype(np.int64), nn)[:K]
    ks, nn, mm_, wd = ks[order], nn[order], mm_[order], wd[order]
    if check_nodes:
        for v in np.unique(np.abs(mm_)):
            sel = k[ms == v]
            _check_radial_nodes(sel[None, : int(nn[np.abs(mm_) == v].max())], np.array([v]), x)
    delta = _enclosure(ks, np.abs(mm_), x, wd, x_rounding)
    return ks, nn, mm_, delta


#: largest number of levels accepted by continuum_levels (the cost limit usually stops earlier)
MAX_LEVELS = 100_000


def continuum_levels(p=7, q=3, radius=None, rings=None, levels: int = 4,
                     *, check_nodes: bool = False, dictionary: str = "paper") -> ContinuumSpectrum:
    r"""The ``levels`` lowest states of :math:`H^{(\rm cont)} = -q - \frac q4 h^2\Delta_g` on a disk.

    Dirichlet conditions on the disk of radius L (``spec1``/``spec2``); energies in units of t.

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol (default {7,3}; hyperbolic: :math:`(p-2)(q-2) > 4`).
    radius : float, optional
        Disk radius :math:`L\in(0,1)`; give exactly one of ``radius`` and ``rings``.
    rings : int, optional
        Number of rings of the {p,q} lattice; :math:`L` from Eq. (10) with its exact site count.
    levels : int, optional
        Number of states (degenerate :math:`\pm m` levels count twice; default 4).
    check_nodes : bool, optional
        Also verify the number of radial nodes of each eigenfunction (default False).
    dictionary : {"paper", "improved"}, optional
        The map from Dirichlet roots to lattice energies: the paper's (default, ``spec1``) or
        the improved one (module docstring; for ``rings`` also its Dirichlet disk).

    Returns
    -------
    ContinuumSpectrum
        A :class:`~hyperlattice.results.Levels` with ``energies`` (ascending, units of t), labels
        ``n`` and signed ``m``, ``errors`` bounding each energy's error, the roots ``k``,
        ``radius``, ``x``, ``h`` and ``asymptotic`` (:func:`asymptotic_energies`).

    Raises
    ------
    ValueError
        Bad input, or a request beyond :data:`MAX_EVALUATIONS` evaluations (refused before the
        work is done; memory use is bounded by chunking).
    ConvergenceError
        If bracketing, refinement or verification of a root fails.

    See Also
    --------
    dirichlet_levels, hyperlattice.graph.spectrum.lowest_levels

    Notes
    -----
    Every state with :math:`k` below a cutoff is found, the cutoff growing until there are at
    least ``levels`` of them; :math:`k_{nm}` increases with :math:`n` and :math:`|m|`, so the
    scan over orders stops at the first one without a root below the cutoff.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix F (``spec1``, ``spec2``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> s = hl.continuum_levels(7, 3, rings=2, levels=4)
    >>> [round(float(e), 6) for e in s.energies]
    [-2.570293, -2.084519, -2.084519, -1.536849]
    >>> s.m.tolist()
    [0, 1, -1, 2]
    """
    p, q = _validate.pq(p, q)
    K = _validate.positive_int("levels", levels, maximum=MAX_LEVELS)
    check_nodes = _validate.flag("check_nodes", check_nodes)
    dictionary = _check_dictionary(dictionary)
    radius, x = disk_argument(radius, p=p, q=q, rings=rings, dictionary=dictionary)
    _check_disk_x(x, radius)
    ks, ns, ms_, delta = _lowest_states(x, K, check_nodes=check_nodes, x_rounding=_X_ROUNDING)
    extra = {} if dictionary == "paper" else {
        "dictionary": dictionary,
        "description": "spec2 roots (grid bracketing + Chandrupatla), improved map E = -q P_nu(cosh 2 d0)"}
    return ContinuumSpectrum(p=p, q=q, rings=None if rings is None else int(rings), radius=radius,
                             x=x, h=lattice_h(p, q), energies=level_energy(ks, p, q, dictionary=dictionary),
                             n=ns, m=ms_, errors=_energy_bound(ks, delta, p, q, dictionary), k=ks,
                             asymptotic=asymptotic_energies(p, q, radius=None if rings is not None else radius,
                                                            rings=rings, dictionary=dictionary), **extra)


# ----------------------------------------------------------------------------
# eigenfunctions
# ----------------------------------------------------------------------------

def psi_K(z, k, beta=0.0) -> np.ndarray:
    r"""Plane-wave eigenfunction of :math:`\Delta_g` with eigenvalue :math:`-(1+k^2)`.

    Eq. (13) (= ``eig12``):

    .. math:: \psi_K(z) = \Bigl(\frac{1-|z|^2}{|1-z e^{-\mathrm{i}\beta}|^2}\Bigr)^{\frac12(1+\mathrm{i}k)},
              \quad K = k e^{\mathrm{i}\beta}.

    Parameters
    ----------
    z : complex or array_like of complex
        Points of the open unit disk.
    k : float
        Wave number (real).
    beta : float, optional
        Direction :math:`\beta` of the wave in radians (default 0).

    Returns
    -------
    ndarray of complex
        :math:`\psi_K(z)`, same shape as ``z`` (0-d for a scalar).

    Raises
    ------
    ValueError
        If a point lies on or outside the unit circle, or ``k`` or ``beta`` is not a finite real
        number.

    See Also
    --------
    radial_g : its partial waves.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), ``eq16a`` and Appendix E (``eig12``).

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.continuum.spectrum import psi_K
    >>> v = psi_K(np.array([0.0, 0.5]), 1.0)
    >>> [round(float(a), 6) for a in np.abs(v)]
    [1.0, 1.732051]
    """
    z = _validate.disk_points("z", z)
    k = _validate.real("k", k)
    beta = _validate.real("beta", beta)
    base = one_minus_abs2(z) / np.abs(1.0 - z * np.exp(-1j * beta)) ** 2
    return np.exp(0.5 * (1.0 + 1j * k) * np.log(base))


def radial_g(k, m, r, method: str = "closed") -> complex | np.ndarray:
    r"""Radial function :math:`g_{km}(r)` of the partial-wave expansion ``eig15``.

    ``method="integral"``: the Fourier integral ``eig17``,
    :math:`g_{km}(r) = \mathrm{i}^{-m}\int_0^{2\pi}\frac{d\phi}{2\pi}e^{-\mathrm{i}m\phi}
    \psi_{k}(re^{\mathrm{i}\phi})`, by the trapezoidal rule (exponentially convergent for this
    periodic analytic integrand; the node count is doubled until two rules agree to 1e-13).

    ``method="closed"``: the Legendre form of ``eig18``/``eig19``,
    :math:`g_{km}(r) = \mathrm{i}^{-m}\,P^{|m|}_\nu(\rho)/\prod_{n=0}^{|m|-1}(\nu-n)`,
    :math:`\nu=\frac12(-1+\mathrm{i}k)`, :math:`\rho = (1+r^2)/(1-r^2)`.

    Parameters
    ----------
    k : float
        Wave number (real).
    m : int
        Order, :math:`|m| \le` :data:`MAX_ORDER`.
    r : float or array_like of float
        Radius (radii), :math:`0 \le r < 1`.
    method : {'closed', 'integral'}, optional
        Legendre closed form (default) or the Fourier quadrature.

    Returns
    -------
    complex or ndarray of complex
        :math:`g_{km}(r)`, a complex scalar for scalar ``r``.

    Raises
    ------
    ValueError
        If an argument is invalid, :math:`r` is outside [0, 1), or the quadrature would need
        more than :math:`2^{20}` nodes.
    ConvergenceError
        If the quadrature does not converge.

    See Also
    --------
    psi_K

    Notes
    -----
    On ``eig19``: the paper's closed form omits the factor :math:`\mathrm{i}^{-m}`; as
    printed it equals the Fourier coefficient :math:`\mathrm{i}^m g_{km}` of ``eig15``, not
    :math:`g_{km}` itself, so it disagrees with ``eig17`` by :math:`\mathrm{i}^{|m|}` (its
    :math:`m<0` rule :math:`g_{k,-m} = (-1)^m g_{k,m}` is consistent with both). With the factor
    included, both methods agree and :math:`g_{km}(r)\to J_m(kr)` in the Euclidean limit, as the
    paper states. The tests check this numerically.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), ``eq16b``, ``eq16`` and Appendix E (``eig15``-``eig19``).

    Examples
    --------
    >>> from hyperlattice.continuum.spectrum import radial_g
    >>> g = radial_g(1.0, 0, 0.5)
    >>> print(f"{g.real:.6f}")
    0.861409
    >>> print(f"{radial_g(1.0, 0, 0.5, method='integral').real:.6f}")
    0.861409
    """
    k = _validate.real("k", k)
    m = _validate.integer("m", m, minimum=-MAX_ORDER, maximum=MAX_ORDER)
    r = _validate.real_array("the radius r", r)
    method = _validate.choice("method", method, ("closed", "integral"))
    if np.any(r < 0) or np.any(r >= 1):
        raise ValueError("the radius r must satisfy 0 <= r < 1.")
    phase = (1j) ** (-m % 4)
    if method == "closed":
        am = abs(m)
        nu = -0.5 + 0.5j * k
        rho = (1.0 + r * r) / ((1.0 - r) * (1.0 + r))
        prod = np.prod([nu - n for n in range(am)]) if am else 1.0
        return phase * legendre_p(nu, am, rho) / prod
    rr = np.atleast_1d(r)
    out = np.empty(rr.shape, complex)
    for i, rv in enumerate(rr.ravel()):
        n = max(64, int(2 ** math.ceil(math.log2(8 * abs(m) + 4 * abs(k) + 40.0 / max(1e-12, 1 - rv)))))
        if n > _MAX_NODES:     # the rule needs about |k| + |m| + 1/(1-r) nodes
            raise ValueError(f"the eig17 quadrature would need {n:,} nodes (k = {k:g}, m = {m}, r = {rv:g}); "
                             "use method='closed'.")
        prev = None
        while n <= _MAX_NODES:
            phi = 2.0 * np.pi * np.arange(n) / n
            vals = psi_K(rv * np.exp(1j * phi), k)
            cur = np.mean(vals * np.exp(-1j * m * phi))
            if prev is not None and abs(cur - prev) <= 1e-13 * max(1.0, abs(cur)):
                break
            prev = cur
            n *= 2
        else:
            raise ConvergenceError(f"the eig17 quadrature did not converge with {_MAX_NODES:,} nodes.")
        out.ravel()[i] = phase * cur
    out = out.reshape(rr.shape)
    return out.reshape(r.shape)[()] if r.ndim == 0 else out


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
