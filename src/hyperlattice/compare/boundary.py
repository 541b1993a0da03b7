r"""Holography on the lattice: boundary correlators of the massive scalar, lattice vs continuum.

For :math:`\omega` below the band the graph propagator :math:`G_{ij}(\omega) = [(H-\omega)^{-1}]_{ij}`
(``eq20``) is the lattice Klein–Gordon propagator of a scalar of mass² :math:`m^2 = -\lambda`,
:math:`\lambda = 4(\omega+q)/(qh^2)` (``eq21``), in AdS₂ of radius :math:`R = 1/2`
(:mod:`hyperlattice.continuum.massive`). With source and probe on the outermost ring,
:math:`G_{ij}` against the boundary angle :math:`\theta_{ij}` is the boundary two-point function
:math:`\propto[\sin(\theta_{ij}/2)]^{-2\Delta}`.

Continuum side
--------------
``continuum`` is the right-hand side of ``eq21`` at the outer-ring sites, with (``continuum_disk``)
the propagator of the whole disk (default ``"whole"``: :math:`L = 1`, :math:`\frac1{2\pi}Q_{\Delta-1}(\cosh 2d)`),
or of the Dirichlet disk of the dictionary radius :math:`L` (``eq12``) at the site positions
(``"dirichlet"``; NaN for the 8–19 % of sites beyond L) or with the ring moved onto the circle of its
mean depth (``"mapped"``). Measured at ℓ = 5, 6 the Dirichlet disk at the sites is closest to the lattice
(relative L2 0.14–0.25 against 0.26–0.50 for L = 1), but its ``green36`` series needs ~1/(1 - ``|z||z'|``/L²)
orders and is refused beyond 10⁴ (ℓ ≥ 7 for {7,3}); hence the default. Beyond the continuum BF bound
(:math:`\omega > E_\infty`, :math:`\lambda > 1`) the :math:`L = 1` propagator does not exist: ``continuum``
and ``delta_continuum`` are NaN there.

Fit of Δ and its window
-----------------------
:math:`\ln G_{ij} = a - 2\Delta\ln\sin(\theta_{ij}/2) + \beta\ln(1 - |z_i|^2)` by least squares over
the window, one source j. The covariate :math:`\ln(1-|z_i|^2)` absorbs the ragged radius of the outer
ring (in the continuum :math:`\beta = \Delta` exactly, :func:`~hyperlattice.continuum.massive.conformal_two_point`);
without it the radial scatter biases the slope by ~1 %. **Window**: pairs whose connecting geodesic
dips at least ``depth`` rings (default 2) below the outer ring, i.e.
:math:`1 - r_{\min}(\theta) \ge` the median :math:`1-|z|` of ring :math:`\ell -` ``depth``, with
:math:`r_{\min} = \tan(\pi/4 - \theta/4)` the closest approach to the centre of the geodesic between
:math:`e^{\pm\mathrm i\theta/2}`. Closer pairs are connected along the ragged edge rather than through the
bulk, where the conformal form does not apply; the window extends to :math:`\theta = \pi`.
**Uncertainty** ``delta_lattice_err``: the standard error of the slope from the residual scatter,
added in quadrature to the window systematic (largest change of Δ when ``depth`` moves by ±1, among
windows with at least 10 pairs). The residuals are lattice structure, not noise, so the systematic
dominates.

**Systematic errors of the lattice Δ as a measurement of the continuum Δ** (``delta_lattice_sys``,
beside ``delta_lattice_err``; both derived from the computation itself):

* *finite ℓ* (``delta_lattice_sys_rings``): :math:`|\Delta(\ell) - \Delta(\ell-1)|`, the same fit
  (same ω, window depth, first outer-ring source) on the flake with one ring less;
* *lattice spacing* (``delta_lattice_sys_spacing``): which mass a lattice frequency represents is
  known only to the order of the dictionary. The paper's map :math:`\lambda = 4(\omega+q)/(qh^2)` is
  the first order in :math:`h^2` of the improved map :math:`\omega = -q\,\varphi_\lambda(d_0)`
  (:func:`~hyperlattice.dictionary.improved_lambda_of_frequency`); the difference of the continuum
  Δ of the two, :math:`|\Delta(\lambda_{\rm paper}) - \Delta(\lambda_{\rm improved})|`, is the size
  of the neglected orders at this ω.

``delta_lattice_sys`` adds the two in quadrature. Measured ({7,3}, ω = -3.5, ℓ = 10): Δ_lattice =
2.0194 with fit error 0.0006, finite-ℓ 0.00005 and lattice-spacing 0.055, against Δ_continuum =
2.0624 (paper's map) and 2.0078 (improved map): the lattice Δ lies between the two maps, and its
2 % offset from the paper's Δ is the dictionary's own order, not a 76σ disagreement.

**Masses in either convention.** ``mass2`` with ``ads_radius`` (1: unit-radius AdS₂,
:math:`\Delta = \frac12 + \sqrt{\frac14 + m^2}`; 0.5: the paper's metric, :math:`\Delta = \frac12 +
\frac12\sqrt{1 + m^2}`) instead of ``omega``: the mass is converted to the paper's metric
(:func:`~hyperlattice.continuum.massive.mass2_in_paper_metric`) and then to ω; the result keeps the
number as given (``mass2_input``, ``ads_radius``) and both conventions' formula values at it
(``delta_formulas``).

Measured ({7,3}, source = first outer-ring site): Δ_lattice changes by less than 1 % between
:math:`\ell = 6, 8, 10` and differs from Δ_continuum by 1–5 % (largest near the BF bound); see
``docs/below-band.md`` for the tables and :func:`delta_curve`.
"""

from __future__ import annotations

import dataclasses
import math
import time
import weakref
from dataclasses import dataclass, field

import numpy as np

from .. import _validate
from ..continuum.massive import (ADS_RADIUS, _ads_radius, bf_bound, delta_formulas, delta_from_mass2,
                                 mass2_from_omega, mass2_in_paper_metric, omega_from_mass2)
from ..dictionary import green_prefactor, improved_lambda_of_frequency, lambda_from_energy
from ..geometry import distance, one_minus_abs2
from ..graph.lattice import Lattice, ring_lattice
from ..graph.qubits import BelowBandResolvent, _real_omega, _resolvent_for
from ..results import Column, Result


__all__ = [
    "outer_ring",
    "fit_window",
    "fit_delta",
    "BoundaryCorrelator",
    "boundary_correlator",
    "DeltaCurve",
    "delta_curve",
    "LatticeBFBound",
    "lattice_bf_bound",
    "BulkToBoundary",
    "bulk_to_boundary",
    "continuum_boundary_column",
    "CONTINUUM_DISKS",
]

_MIN_PAIRS = 10
_MAX_OMEGAS = 1000


def _site_lattice(lattice) -> Lattice:
    lat = _validate.lattice(lattice)
    if lat.kind != "sites":
        raise ValueError("boundary correlators are defined on a site lattice (ring_lattice), not a line graph.")
    return lat


def outer_ring(lattice: Lattice) -> np.ndarray:
    """Indices of the sites of the outermost ring (counterclockwise).

    Parameters
    ----------
    lattice : Lattice
        A {p,q} flake (sites or line graph).

    Returns
    -------
    ndarray of int
        The 0-based site indices of ring ``lattice.rings``, in counterclockwise order.

    Raises
    ------
    ValueError
        If ``lattice`` is not a Lattice.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.boundary import outer_ring
    >>> ring = outer_ring(hl.ring_lattice(7, 3, 5))
    >>> ring[:3].tolist(), ring.size
    ([315, 316, 317], 532)
    """
    lat = _validate.lattice(lattice)
    off = lat.ring_offsets
    return np.arange(off[-2], off[-1])


def _depth(depth) -> int:
    return _validate.positive_int("depth", depth, maximum=100)


def fit_window(lattice: Lattice, depth: int = 2) -> float:
    r"""Smallest boundary angle :math:`\theta_{\min}` of the fit window (module docstring).

    Pairs with :math:`\theta \ge \theta_{\min}` are joined by a geodesic that reaches at least
    ``depth`` rings inside the outer ring.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} site lattice (not a line graph).
    depth : int, optional
        Window depth in rings, 1 to 100. Default 2.

    Returns
    -------
    float
        :math:`\theta_{\min}` in radians, at most :math:`\pi`.

    Raises
    ------
    ValueError
        If the lattice is a line graph or has fewer than ``depth + 1`` rings.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.boundary import fit_window
    >>> lat = hl.ring_lattice(7, 3, 5)
    >>> round(fit_window(lat), 6), round(fit_window(lat, depth=3), 6)
    (0.304826, 0.812853)
    """
    lat = _site_lattice(lattice)
    depth = _depth(depth)
    if lat.rings <= depth:
        raise ValueError(f"a fit window of depth {depth} needs at least {depth + 1} rings (got {lat.rings}).")
    off = lat.ring_offsets
    k = lat.rings - depth            # the ring the geodesic must reach
    gap = float(np.median(1.0 - np.abs(lat.z[off[k - 1]:off[k]])))
    if gap >= 1.0:
        return math.pi
    # 1 - tan(pi/4 - theta/4) = gap
    return float(min(math.pi, math.pi - 4.0 * math.atan(1.0 - gap)))


def fit_delta(theta, values, eps, theta_min) -> tuple[float, float, int, float, float]:
    r"""Least-squares fit of :math:`\ln G = a - 2\Delta\ln\sin(\theta/2) + \beta\ln\epsilon` for :math:`|\theta| \ge \theta_{\min}`.

    Parameters
    ----------
    theta : array_like
        Boundary angles (radians, any branch; :math:`|\sin(\theta/2)|` is used).
    values : array_like
        Positive correlator values.
    eps : array_like
        :math:`1 - |z_i|^2` of the probes.
    theta_min : float
        Window edge (:func:`fit_window`).

    Returns
    -------
    (delta, stderr, pairs, amplitude, beta)
        Δ, its standard error from the residual scatter, the number of pairs in the window,
        :math:`e^a` and β.

    Raises
    ------
    ValueError
        Mismatched arrays, non-positive values in the window, fewer than 10 pairs.

    Examples
    --------
    Exact data :math:`G = 2\,[\sin(\theta/2)]^{-3}\epsilon^{1/2}` give Δ = 1.5, β = 0.5:

    >>> import numpy as np
    >>> from hyperlattice.compare.boundary import fit_delta
    >>> theta = np.linspace(0.5, 3.0, 20)
    >>> eps = np.linspace(0.01, 0.02, 20)
    >>> values = 2.0 * np.sin(theta / 2) ** -3.0 * eps ** 0.5
    >>> [round(float(x), 6) for x in fit_delta(theta, values, eps, 0.4)]
    [1.5, 0.0, 20.0, 2.0, 0.5]
    """
    th = _validate.real_array("theta", theta, ndim=1)
    v = _validate.real_array("values", values, ndim=1)
    e = _validate.real_array("eps", eps, ndim=1)
    if not th.shape == v.shape == e.shape:
        raise ValueError(f"theta, values and eps must have one length, got {th.size}, {v.size}, {e.size}.")
    theta_min = _validate.real("theta_min", theta_min, minimum=0.0, maximum=math.pi)
    s = np.abs(np.sin(0.5 * th))
    sel = (s >= math.sin(0.5 * theta_min)) & (s > 0)
    n = int(np.count_nonzero(sel))
    if n < _MIN_PAIRS:
        raise ValueError(f"only {n} boundary pairs lie in the fit window theta >= {theta_min:.3g}; at least "
                         f"{_MIN_PAIRS} are needed (use more rings or a smaller depth).")
    if np.any(v[sel] <= 0) or np.any(e[sel] <= 0):
        raise ValueError("the correlator must be positive in the fit window (omega below the band).")
    X = np.column_stack([np.ones(n), -2.0 * np.log(s[sel]), np.log(e[sel])])
    y = np.log(v[sel])
    if np.ptp(X[:, 2]) == 0:          # all probes on one circle: beta is not identifiable
        X = X[:, :2]
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    resid = y - X @ coef
    dof = max(n - X.shape[1], 1)
    cov = np.linalg.pinv(X.T @ X) * float(resid @ resid) / dof
    beta = float(coef[2]) if X.shape[1] == 3 else math.nan
    return float(coef[1]), float(math.sqrt(max(cov[1, 1], 0.0))), n, float(math.exp(coef[0])), beta


#: continuum models of the outer ring (``continuum_disk``), see :func:`continuum_boundary_column`
CONTINUUM_DISKS = ("whole", "dirichlet", "mapped")
_MAX_DIRICHLET_ORDERS = 10_000


def continuum_boundary_column(lattice: Lattice, omega, source: int, targets, *, disk: str = "whole") -> np.ndarray:
    r"""The continuum side of ``eq21`` at the targets for one source: :math:`\frac{4\mathcal A}{qh^2}G(z_i, z_j)`.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} site lattice.
    omega : float
        Real frequency (units of t), below the band.
    source : int
        Source site j (0-based).
    targets : array_like of int
        Any sites i (0-based).
    disk : {"whole", "dirichlet", "mapped"}
        ``"whole"`` (default): the whole-disk propagator :math:`\frac1{2\pi}Q_\nu(y)` (L = 1) at the site
        positions; NaN beyond the continuum BF bound :math:`\lambda \ge 1`. ``"dirichlet"``: the Dirichlet
        disk of the dictionary radius L (``eq12``, :func:`~hyperlattice.dictionary.disk_radius_for_rings`) at
        the site positions, NaN for targets with :math:`|z| \ge L` (the source must lie inside L).
        ``"mapped"``: the Dirichlet disk with source and targets moved radially onto one circle at the
        mean hyperbolic depth :math:`\bar\delta` of the outer ring below L,
        :math:`|z| = \tanh(\operatorname{artanh}L - \bar\delta)`, angles kept. Both Dirichlet variants
        sum the ``green36`` series; its length grows like :math:`1/(1 - |z||z'|/L^2)` and they are
        refused (ValueError, before any work) when it would exceed 10,000 orders, i.e. for
        {7,3} beyond ℓ = 6 (ℓ = 7 needs about 3·10⁴ orders and minutes, and the series overflowed
        there in a measured run; ℓ = 10 would need 6·10⁵).

    Returns
    -------
    ndarray of float
        One value per target (units of 1/t): inf at the source itself, NaN where the model has
        no value.

    Raises
    ------
    ValueError
        Bad input, a line-graph lattice, or a Dirichlet series that would need more than 10,000
        orders.

    See Also
    --------
    boundary_correlator, hyperlattice.compare.green.continuum_column

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19) (source label ``eq21``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.boundary import continuum_boundary_column
    >>> lat = hl.ring_lattice(7, 3, 5)
    >>> col = continuum_boundary_column(lat, -3.5, 315, [315, 316, 317])
    >>> float(col[0]), [round(float(x), 6) for x in col[1:]]
    (inf, [0.148693, 0.056158])
    """
    from ..continuum.green import continuum_green
    from ..dictionary import disk_radius_for_rings

    lat = _site_lattice(lattice)
    omega = _real_omega("omega", omega)
    source = _validate.site_index("source", source, lat.sites)
    tg = _validate.site_indices("targets", targets, lat.sites)
    disk = _validate.choice("disk", disk, CONTINUUM_DISKS)
    lam = float(lambda_from_energy(omega, lat.p, lat.q))
    out = np.full(tg.size, math.nan)
    same = tg == source
    z, zs = lat.z[tg], complex(lat.z[source])
    if disk == "whole":
        if lam >= 1.0:
            return out
        use = ~same
    else:
        L = disk_radius_for_rings(lat.rings, lat.p, lat.q)[0]
        if disk == "mapped":
            ring = outer_ring(lat)
            depth = float(np.mean(np.arctanh(L) - np.arctanh(np.abs(lat.z[ring]))))
            r_star = math.tanh(math.atanh(L) - depth)
            with np.errstate(invalid="ignore", divide="ignore"):
                z = np.where(z != 0, r_star * z / np.abs(z), z)
            zs = r_star * zs / abs(zs) if zs != 0 else zs
        elif abs(zs) >= L:
            raise ValueError(f"source {source} lies outside the Dirichlet disk of radius L = {L:.9g} "
                             f"(|z| = {abs(zs):.9g}); use disk='whole' or 'mapped'.")
        use = ~same & (np.abs(z) < L)
        if np.any(use):
            # orders of the green36 series for a relative tail of 1e-12 at the closest pair
            x = float(np.max(np.abs(z[use]))) * abs(zs) / (L * L)
            need = math.inf if x >= 1.0 else 27.7 / -math.log(x)
            if need > _MAX_DIRICHLET_ORDERS:
                raise ValueError(f"the Dirichlet-disk continuum ({disk!r}) needs about {need:.3g} Fourier orders at "
                                 f"{lat.rings} rings (more than {_MAX_DIRICHLET_ORDERS}); use disk='whole'.")
            max_terms = max(4000, math.ceil(1.5 * need) + 100)
    out[same] = math.inf
    if np.any(use):
        if disk == "whole":
            vals = continuum_green(z[use], zs, lam, 1.0)
        else:
            vals = continuum_green(z[use], zs, lam, L, max_terms=max_terms)
        vals = green_prefactor(lat.p, lat.q) * np.real(vals)
        if not np.all(np.isfinite(vals)):
            raise ValueError(f"the Dirichlet-disk continuum ({disk!r}) lost all precision at {lat.rings} rings "
                             "(non-finite series); use disk='whole'.")
        out[use] = vals
    return out


def _delta_continuum(omega: float, p: int, q: int) -> float:
    m2 = float(mass2_from_omega(omega, p, q))
    return float(delta_from_mass2(m2)) if m2 >= -1.0 else math.nan


def _delta_improved(omega: float, p: int, q: int) -> float:
    """Continuum Delta at the improved map's lambda of omega (NaN beyond its BF bound or range)."""
    try:
        lam = improved_lambda_of_frequency(omega, p, q)
    except ValueError:
        return math.nan
    return float(delta_from_mass2(-lam)) if lam <= 1.0 else math.nan


def _frequency(omega, mass2, ads_radius, p: int, q: int) -> tuple[float, float, float]:
    """(omega, the AdS radius of the mass as given, the mass2 as given) from omega or from mass2 with ads_radius."""
    if mass2 is None:
        if ads_radius is not None:
            raise ValueError("ads_radius names the convention of mass2; give it with mass2, not with omega.")
        if omega is None:
            raise ValueError("give the frequency omega, or mass2 with ads_radius.")
        w = _real_omega("omega", omega)
        return w, ADS_RADIUS, float(mass2_from_omega(w, p, q))
    if omega is not None:
        raise ValueError("give either omega or mass2 (with ads_radius), not both.")
    m2 = _validate.real("mass2", mass2)
    if ads_radius is None:
        raise ValueError("mass2 needs ads_radius, the convention it is given in: 1 (unit-radius AdS2, "
                         "Delta(Delta-1) = m^2) or 0.5 (the paper's metric, Delta(Delta-1) = m^2/4).")
    r = _ads_radius(ads_radius)
    return float(omega_from_mass2(mass2_in_paper_metric(m2, r), p, q)), r, m2


def _smaller_flake(lat: Lattice, depth: int) -> tuple[Lattice, np.ndarray, int] | None:
    """The flake with one ring less, its outer ring and first outer-ring site, or None if too small for the window."""
    if lat.rings - 1 <= depth:
        return None
    small = ring_lattice(lat.p, lat.q, lat.rings - 1)
    ring = outer_ring(small)
    return small, ring, int(ring[0])


@dataclass(frozen=True, eq=False, kw_only=True)
class BoundaryCorrelator(Result):
    r"""Boundary two-point function on the outer ring for one source, with the fitted Δ.

    Frequencies are in units of t (:math:`H = -tA`), :math:`m^2` in units of the curvature scale of
    the paper's metric, angles in radians.

    Attributes
    ----------
    p, q, rings : int
        The flake.
    source : int
        Source site j on the outer ring (0-based).
    omega, lam, mass2 : float
        Frequency, :math:`\lambda` of ``eq21``, :math:`m^2 = -\lambda`.
    delta_continuum : float
        :math:`\frac12 + \frac12\sqrt{1-\lambda}` (NaN beyond the continuum BF bound).
    delta_lattice, delta_lattice_err : float
        Fitted Δ and its uncertainty (module docstring).
    delta_lattice_stat, delta_lattice_window : float
        The two parts of the uncertainty: standard error and window systematic.
    delta_lattice_sys : float
        Systematic error of Δ_lattice as a measurement of the continuum Δ (module docstring):
        ``delta_lattice_sys_rings`` (finite ℓ, :math:`|\Delta(\ell) - \Delta(\ell-1)|`) and
        ``delta_lattice_sys_spacing`` (lattice spacing, paper's against improved dictionary) in
        quadrature; NaN where a part is not available (``systematic=False``, too few rings).
    delta_lattice_sys_rings, delta_lattice_sys_spacing : float
        The two parts of ``delta_lattice_sys`` (finite ℓ and lattice spacing).
    delta_continuum_improved : float
        The continuum Δ at the improved dictionary's :math:`\lambda(\omega)`.
    ads_radius, mass2_input : float
        The AdS radius the mass was given in (0.5 when ω was given) and the mass² as given.
    delta_formulas : dict
        Both conventions' formula values at ``mass2_input``
        (:func:`~hyperlattice.continuum.massive.delta_formulas`).
    beta : float
        Fitted exponent of :math:`1-|z_i|^2`.
    theta_min : float
        Window edge (radians).
    depth : int
        The window's depth in rings.
    pairs : int
        The number of pairs fitted.
    sites : ndarray of int
        Outer-ring sites (the probes i), counterclockwise.
    theta : ndarray
        :math:`\theta_{ij}\in(-\pi,\pi]`, angle of probe i relative to the source.
    graph : ndarray
        :math:`G_{ij}(\omega)`.
    continuum : ndarray
        ``eq21`` with the :math:`L = 1` propagator (inf at the source, NaN beyond the BF bound).
    solver : str
        What solved for ``graph`` (backend, factor kind, full H or its mirror-even block).
    continuum_disk : str
        Which continuum model fills ``continuum`` (``"whole"``, ``"dirichlet"`` or ``"mapped"``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> bc = hl.boundary_correlator(hl.ring_lattice(7, 3, 5), -3.5)
    >>> bc.source, bc.pairs, bc.depth, bc.sites.size, bc.continuum_disk
    (315, 483, 2, 532, 'whole')
    >>> print(f"{bc.mass2:.4f} {bc.delta_lattice:.3f} {bc.delta_continuum:.3f}")
    8.7645 2.030 2.062
    """

    #: one row per outer-ring probe i (the CLI's ``boundary`` table)
    COLUMNS = (Column("site", "sites", "1"), Column("theta", "theta", "rad"), Column("graph", "graph", "1/t"),
               Column("continuum", "continuum", "1/t"))

    p: int
    q: int
    rings: int
    source: int
    omega: float
    lam: float
    mass2: float
    delta_continuum: float
    delta_lattice: float
    delta_lattice_err: float
    delta_lattice_stat: float
    delta_lattice_window: float
    beta: float
    theta_min: float
    depth: int
    pairs: int
    sites: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    graph: np.ndarray = field(repr=False)
    continuum: np.ndarray = field(repr=False)
    #: which continuum model fills ``continuum`` ("whole", "dirichlet" or "mapped")
    continuum_disk: str = "whole"
    #: what solved for ``graph``: backend, factor kind, full H or its mirror-even block ("" when unknown)
    solver: str = ""
    delta_lattice_sys: float = math.nan
    delta_lattice_sys_rings: float = math.nan
    delta_lattice_sys_spacing: float = math.nan
    delta_continuum_improved: float = math.nan
    ads_radius: float = ADS_RADIUS
    mass2_input: float = math.nan
    delta_formulas: dict = field(default_factory=dict)

    @property
    def delta_lattice_total_err(self) -> float:
        """Fit error and systematic error in quadrature (the fit error alone when the systematic is unknown)."""
        sys = 0.0 if math.isnan(self.delta_lattice_sys) else self.delta_lattice_sys
        return math.hypot(self.delta_lattice_err, sys)

    def summary(self) -> dict:
        """The ``boundary --json`` contract: p, q, rings, omega, lambda, mass2 (paper's metric), delta_continuum,
        delta_lattice, delta_lattice_err (fit: stat and window), then mass2_ads_radius_1, ads_radius and
        mass2_input (the mass as given), delta_formulas, delta_continuum_improved, delta_lattice_stat,
        delta_lattice_window, delta_lattice_sys (with _rings and _spacing) and delta_lattice_total_err."""
        return {"p": self.p, "q": self.q, "rings": self.rings, "omega": self.omega, "lambda": self.lam,
                "mass2": self.mass2, "delta_continuum": self.delta_continuum, "delta_lattice": self.delta_lattice,
                "delta_lattice_err": self.delta_lattice_err,
                "mass2_ads_radius_1": self.mass2 * ADS_RADIUS**2, "ads_radius": self.ads_radius,
                "mass2_input": self.mass2_input, "delta_formulas": dict(self.delta_formulas),
                "delta_continuum_improved": self.delta_continuum_improved,
                "delta_lattice_stat": self.delta_lattice_stat, "delta_lattice_window": self.delta_lattice_window,
                "delta_lattice_sys": self.delta_lattice_sys, "delta_lattice_sys_rings": self.delta_lattice_sys_rings,
                "delta_lattice_sys_spacing": self.delta_lattice_sys_spacing,
                "delta_lattice_total_err": self.delta_lattice_total_err}


class _RingFit:
    r"""The omega-independent part of the Δ fits of one source: angles, covariates, window solvers.

    :func:`fit_delta` rebuilds the design matrix :math:`X = [1, -2\ln\sin(\theta/2), \ln\epsilon]`
    and factorises it at every call; on one lattice with one source only the values change with
    omega, so the reduced QR of X of each window (``depth`` and ``depth`` ± 1) is computed once and
    every fit is two products with it (the same least-squares solution to rounding). Used by
    :func:`boundary_correlator` and, once for all masses, by :func:`delta_curve`.
    """

    def __init__(self, lat: Lattice, source: int, ring: np.ndarray, depth: int) -> None:
        self.source, self.ring, self.depth = source, ring, depth      # no reference to lat: see _ring_fit
        self.theta = np.angle(lat.z[ring] * np.conj(lat.z[source]))
        self.eps = one_minus_abs2(lat.z[ring])
        self.keep = ring != source
        th, e = self.theta[self.keep], self.eps[self.keep]
        s = np.abs(np.sin(0.5 * th))
        # the windows are nested (s >= sin(theta_min / 2), theta_min growing with depth): with the
        # pairs sorted by decreasing s, each window is a prefix, and one pass serves all three
        self.order = np.argsort(-s, kind="stable")
        s_sorted, e_sorted = s[self.order], e[self.order]
        bad_e = np.flatnonzero(~(e_sorted > 0))
        first_bad_e = int(bad_e[0]) if bad_e.size else s.shape[0]
        self.windows = {}
        for d in (depth - 1, depth, depth + 1):
            if d < 1 or d >= lat.rings:
                continue
            thmin = fit_window(lat, d)
            n = int(np.count_nonzero((s_sorted >= math.sin(0.5 * thmin)) & (s_sorted > 0)))
            self.windows[d] = [thmin, n, None]
        self.n_max = max((w[1] for w in self.windows.values()), default=0)
        #: the outer-ring sites the fits read, in their order (a Delta curve reads the column there only)
        self.fit_sites = ring[self.keep][self.order][:self.n_max]
        log_s = np.log(np.where(s_sorted[:self.n_max] > 0, s_sorted[:self.n_max], 1.0))
        log_e = np.log(np.where(e_sorted[:self.n_max] > 0, e_sorted[:self.n_max], 1.0))
        X_all = np.column_stack([np.ones(self.n_max), -2.0 * log_s, log_e])
        self._X_all = X_all
        for d, w in self.windows.items():
            thmin, n, _ = w
            if n < _MIN_PAIRS:
                continue
            X = X_all[:n]
            if np.ptp(X[:, 2]) == 0:          # all probes on one circle: beta is not identifiable
                X = np.ascontiguousarray(X[:, :2])
            # normal equations of the column-scaled X (condition ~1e2 here, so ~1e-12 relative in
            # the coefficients, against the 1e-3 the fit claims); einsum keeps BLAS threads out
            scale = np.sqrt(np.einsum("ij,ij->j", X, X))
            gram = np.einsum("ij,ik->jk", X, X) / np.outer(scale, scale)
            w[2] = (X, scale, np.linalg.inv(gram), np.linalg.pinv(X.T @ X), n <= first_bad_e)

    def fit(self, d: int, y: np.ndarray, first_bad: int, xty: np.ndarray | None = None,
            residual: bool = True) -> tuple[float, float, int, float, float]:
        """:func:`fit_delta` in window ``d`` from the logs ``y`` of the sorted values (same returns and refusals).

        ``first_bad``: index of the first non-positive sorted value (their logs are not used);
        ``xty``: :math:`X^Ty` of the window when already summed; ``residual=False`` skips the
        standard error (NaN), for the windows that only shift Δ.
        """
        thmin, n, solver = self.windows[d]
        if solver is None:
            raise ValueError(f"only {n} boundary pairs lie in the fit window theta >= {thmin:.3g}; at least "
                             f"{_MIN_PAIRS} are needed (use more rings or a smaller depth).")
        X, scale, gram_inv, xtx, eps_ok = solver
        if n > first_bad or not eps_ok:
            raise ValueError("the correlator must be positive in the fit window (omega below the band).")
        y = y[:n]
        # einsum, not BLAS: a level-1/2 BLAS call on ~10^5 entries waits for OpenBLAS's threads to
        # wake (measured 4 ms for one dot on a loaded 2-core machine, against 0.1 ms here)
        if xty is None:
            xty = np.einsum("ij,i->j", X, y)
        coef = gram_inv @ (xty[:X.shape[1]] / scale) / scale
        if residual:
            resid = y - np.einsum("ij,j->i", X, coef)
            dof = max(n - X.shape[1], 1)
            var = xtx[1, 1] * float(np.einsum("i,i->", resid, resid)) / dof
        else:
            var = math.nan
        beta = float(coef[2]) if X.shape[1] == 3 else math.nan
        return float(coef[1]), float(math.sqrt(max(var, 0.0))), n, float(math.exp(coef[0])), beta

    def fit_with_window(self, g: np.ndarray, *, sorted_: bool = False) -> tuple[float, float, float, float, int, float]:
        """(delta, stderr, beta, theta_min, pairs, window systematic) from the outer-ring column ``g``.

        ``sorted_``: ``g`` holds only the values at :attr:`fit_sites`, in that order (what the fits read).
        """
        v = g if sorted_ else g[self.keep][self.order][:self.n_max]
        bad = np.flatnonzero(~(v > 0))
        first_bad = int(bad[0]) if bad.size else v.shape[0]
        y = np.log(np.where(v > 0, v, 1.0))
        # X^T y of the nested windows in one pass: sums over the segments between their ends
        ends = sorted({w[1] for w in self.windows.values() if w[2] is not None and w[1] <= first_bad})
        xty, acc, start = {}, np.zeros(3), 0
        for end in ends:
            acc = acc + np.einsum("ij,i->j", self._X_all[start:end], y[start:end])
            xty[end], start = acc, end
        delta, se, n, _, beta = self.fit(self.depth, y, first_bad, xty.get(self.windows[self.depth][1]))
        shifts = []
        for d in (self.depth - 1, self.depth + 1):
            if d not in self.windows:
                continue
            try:
                shifts.append(abs(self.fit(d, y, first_bad, xty.get(self.windows[d][1]), residual=False)[0] - delta))
            except ValueError:            # fewer than 10 pairs: that window does not count
                continue
        return delta, se, beta, self.windows[self.depth][0], n, max(shifts) if shifts else 0.0


#: the omega-independent fit geometry per lattice (held weakly by it) and per (source, depth), at
#: most _FIT_CACHE sources per lattice: a second correlator of the same source (another omega, a
#: Delta curve) skips the angles, covariates and window solvers (about 10 ms at l = 10)
_FITS: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()
_FIT_CACHE = 8


def _ring_fit(lat: Lattice, source: int, ring: np.ndarray, depth: int) -> _RingFit:
    """The :class:`_RingFit` of (lat, source, depth), built once and kept while the lattice lives."""
    try:
        fits = _FITS.setdefault(lat, {})
    except TypeError:               # pragma: no cover - a lattice that cannot be weakly referenced
        return _RingFit(lat, source, ring, depth)
    key = (source, depth)
    fit = fits.pop(key, None)
    if fit is None:
        fit = _RingFit(lat, source, ring, depth)
    fits[key] = fit                 # most recent last
    while len(fits) > _FIT_CACHE:
        fits.pop(next(iter(fits)))
    return fit


def boundary_correlator(lattice: Lattice, omega=None, source: int | None = None, *, mass2=None, ads_radius=None,
                        depth: int = 2, resolvent: BelowBandResolvent | None = None, continuum: bool = True,
                        continuum_disk: str = "whole", systematic: bool = True) -> BoundaryCorrelator:
    r"""Outer-ring correlators :math:`G_{ij}(\omega)` for one source j, the continuum, and the fitted Δ.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} ring lattice (site lattice).
    omega : float, optional
        Real frequency below the band (:math:`\omega < E_0(\ell)`, checked exactly). Give it or
        ``mass2``.
    source : int, optional
        A site of the outer ring (default: its first site).
    mass2 : float, optional
        The scalar's mass² instead of ω, in the convention ``ads_radius`` names.
    ads_radius : {1, 0.5}, required with ``mass2``
        1: unit-radius AdS₂ (:math:`\Delta = \frac12 + \sqrt{\frac14 + m^2}`, most texts); 0.5: the
        paper's metric (:math:`\Delta = \frac12 + \frac12\sqrt{1 + m^2}`, the package's ``mass2``).
    depth : int
        Window depth in rings (module docstring).
    resolvent : BelowBandResolvent, optional
        Reuse a factorization (several sources at one omega).
    continuum : bool
        Also evaluate the continuum column (cheap: one closed form per site).
    continuum_disk : {"whole", "dirichlet", "mapped"}
        Continuum model of the ``continuum`` column (:func:`continuum_boundary_column`): the whole-disk
        propagator (default), the Dirichlet disk of radius L at the site positions (NaN beyond L; closest
        to the lattice where it can be summed, ℓ ≤ 6-8, see ``docs/below-band.md``), or the Dirichlet disk
        with the ring mapped onto the circle of its mean depth. Does not change the fit.
    systematic : bool
        Also estimate the systematic error of Δ_lattice (module docstring): the same fit on the
        flake with one ring less (about 40 % more work for {7,3}) and the improved dictionary.
        Default True.

    Returns
    -------
    BoundaryCorrelator
        The outer-ring ``sites`` (counterclockwise), their angles ``theta`` to the source, the
        graph column ``graph`` (:math:`G_{ij}(\omega)`, units of 1/t) and the ``continuum`` column,
        the fitted ``delta_lattice`` with ``delta_lattice_err`` (fit) and ``delta_lattice_sys``
        (finite ℓ and lattice spacing), and ``delta_continuum`` (:math:`\frac12 +
        \frac12\sqrt{1-\lambda}`, NaN beyond the continuum BF bound).

    Raises
    ------
    ValueError
        Bad input, a line-graph lattice, a source off the outer ring, omega not below the band,
        too few rings for the window (``depth + 1``) or too few pairs; both or neither of
        ``omega`` and ``mass2``, ``mass2`` without ``ads_radius``.

    See Also
    --------
    delta_curve : the fitted Δ for many frequencies at once.
    hyperlattice.continuum.massive.conformal_two_point : the continuum boundary form.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020): the graph Green function
       (source label ``eq20``) and its continuum limit, Eq. (19) (label ``eq21``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 5)
    >>> bc = hl.boundary_correlator(lat, -3.5)
    >>> bc.source, bc.pairs
    (315, 483)
    >>> print(f"{bc.delta_lattice:.3f} {bc.delta_continuum:.3f}")
    2.030 2.062

    A mass² of 1 in unit-radius AdS₂ is 4 in the paper's metric:

    >>> bc = hl.boundary_correlator(lat, mass2=1.0, ads_radius=1)
    >>> round(bc.mass2, 12), round(bc.delta_continuum, 6), {k: round(v, 6) for k, v in bc.delta_formulas.items()}
    (4.0, 1.618034, {'ads_radius_1': 1.618034, 'ads_radius_0.5': 1.207107})
    """
    lat = _site_lattice(lattice)
    omega, radius, m2_input = _frequency(omega, mass2, ads_radius, lat.p, lat.q)
    depth = _depth(depth)
    continuum = _validate.flag("continuum", continuum)
    systematic = _validate.flag("systematic", systematic)
    continuum_disk = _validate.choice("continuum_disk", continuum_disk, CONTINUUM_DISKS)
    ring = outer_ring(lat)
    source = _outer_source(lat, ring, source, depth)
    res = _resolvent_for(resolvent, lat)
    bc = _boundary_correlator(lat, omega, source, ring, depth, res, continuum, continuum_disk)
    extra = {"ads_radius": radius, "mass2_input": m2_input, "delta_formulas": delta_formulas(m2_input)}
    if systematic:
        d_imp = _delta_improved(omega, lat.p, lat.q)
        spacing = abs(bc.delta_continuum - d_imp)
        rings_sys = math.nan
        small = _smaller_flake(lat, depth)
        if small is not None:
            slat, sring, ssrc = small
            try:
                g = BelowBandResolvent(slat).column(omega, ssrc)[sring]
                rings_sys = abs(bc.delta_lattice - _ring_fit(slat, ssrc, sring, depth).fit_with_window(g)[0])
            except ValueError:        # fewer than 10 pairs in the smaller flake's window
                pass
        extra.update(delta_continuum_improved=d_imp, delta_lattice_sys_spacing=spacing,
                     delta_lattice_sys_rings=rings_sys, delta_lattice_sys=math.hypot(spacing, rings_sys))
    return dataclasses.replace(bc, **extra)


def _outer_source(lat: Lattice, ring: np.ndarray, source, depth: int) -> int:
    """The source checked (default: the first outer-ring site); too few rings for the window refused before work."""
    if source is None:
        source = int(ring[0])
    source = _validate.site_index("source", source, lat.sites)
    if lat.ring[source] != lat.rings:
        raise ValueError(f"source {source} is not on the outer ring (sites {ring[0]}..{ring[-1]}).")
    fit_window(lat, depth)          # refuse too few rings before the solve
    return source


def _boundary_correlator(lat, omega, source, ring, depth, res, continuum, continuum_disk,
                         fit: _RingFit | None = None) -> BoundaryCorrelator:
    """:func:`boundary_correlator` after its checks; ``fit`` reuses the omega-independent part of the fits."""
    g = res.column(omega, source)[ring]
    if fit is None:
        fit = _ring_fit(lat, source, ring, depth)
    theta = fit.theta
    delta, se, beta, thmin, n, sysw = fit.fit_with_window(g)
    lam = float(lambda_from_energy(omega, lat.p, lat.q))
    cont = (continuum_boundary_column(lat, omega, source, ring, disk=continuum_disk) if continuum
            else np.full(ring.size, math.nan))
    return BoundaryCorrelator(p=lat.p, q=lat.q, rings=lat.rings, source=source, omega=omega, lam=lam, mass2=-lam,
                              delta_continuum=_delta_continuum(omega, lat.p, lat.q), delta_lattice=delta,
                              delta_lattice_err=math.hypot(se, sysw), delta_lattice_stat=se,
                              delta_lattice_window=sysw, beta=beta, theta_min=thmin, depth=depth, pairs=n,
                              sites=ring, theta=theta, graph=g, continuum=cont, continuum_disk=continuum_disk,
                              solver=res.route)


@dataclass(frozen=True, eq=False, kw_only=True)
class DeltaCurve(Result):
    r"""Δ(m²) on one lattice: fitted lattice Δ and continuum Δ for a list of frequencies.

    Attributes
    ----------
    p, q, rings, source, depth : int
        The flake, the source site (0-based, outer ring) and the fit window's depth in rings.
    omegas, mass2 : ndarray
        Frequencies (units of t) and :math:`m^2 = -\lambda(\omega)` (curvature units).
    delta_continuum : ndarray
        NaN beyond the continuum BF bound.
    delta_lattice, delta_lattice_err : ndarray
        The fitted lattice Δ and its uncertainty (see :class:`BoundaryCorrelator`).
    delta_lattice_sys : ndarray
        Systematic error (finite ℓ and lattice spacing in quadrature, see :class:`BoundaryCorrelator`);
        NaN without ``systematic``.
    delta_continuum_improved : ndarray
        The continuum Δ at the improved dictionary's :math:`\lambda(\omega)`.
    omega_bf : float
        Continuum BF bound :math:`E_\infty`.
    seconds : float
        Wall time of the whole curve.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> dc = hl.delta_curve(hl.ring_lattice(7, 3, 5), [-3.5, -4.0])
    >>> [round(float(m), 4) for m in dc.mass2], round(dc.omega_bf, 6)
    ([8.7645, 17.529], -2.942952)
    >>> [round(float(d), 3) for d in dc.delta_lattice], [round(float(d), 3) for d in dc.delta_continuum]
    ([2.03, 2.578], [2.062, 2.652])
    """

    COLUMNS = (Column("omega", "omegas", "t"), Column("mass2", "mass2", "curvature units"),
               Column("delta_continuum", "delta_continuum", "1"), Column("delta_lattice", "delta_lattice", "1"),
               Column("delta_lattice_err", "delta_lattice_err", "1"), Column("delta_lattice_sys", "delta_lattice_sys", "1"),
               Column("delta_continuum_improved", "delta_continuum_improved", "1"))

    p: int
    q: int
    rings: int
    source: int
    depth: int
    omegas: np.ndarray
    mass2: np.ndarray
    delta_continuum: np.ndarray
    delta_lattice: np.ndarray
    delta_lattice_err: np.ndarray
    delta_lattice_sys: np.ndarray
    delta_continuum_improved: np.ndarray
    omega_bf: float
    seconds: float


def delta_curve(lattice: Lattice, omegas=None, *, source: int | None = None, depth: int = 2, mass2=None,
                ads_radius=None, systematic: bool = True) -> DeltaCurve:
    r"""Fitted :math:`\Delta_{\rm lattice}` and :math:`\Delta_{\rm continuum}` for each frequency.

    One fill-reducing order per call (CHOLMOD's AMD of the mirror-even block, 10-20 ms at
    :math:`\ell = 10`), then per frequency one numeric :math:`LDL^T` with its inertia check (3-4 ms),
    the solve and the three window fits on the outer-ring values they use (about 2 ms);
    :class:`~hyperlattice.graph.qubits.BelowBandResolvent`. The fit geometry of the source is kept per
    lattice, so a second curve of the same source skips it.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} ring lattice (site lattice, not a line graph) with more than ``depth`` rings.
    omegas : array_like of float, optional
        Real frequencies (units of t), each below the band (:math:`\omega < E_0(\ell)`);
        1 to 1000 of them. Give them or ``mass2``.
    source : int, optional
        A site of the outer ring (0-based; default: its first site).
    depth : int, optional
        Window depth in rings (module docstring). Default 2.
    mass2 : array_like of float, optional
        Masses² instead of frequencies, in the convention ``ads_radius`` names (1: unit-radius
        AdS₂; 0.5: the paper's metric); see :func:`boundary_correlator`.
    ads_radius : {1, 0.5}, required with ``mass2``
    systematic : bool, optional
        Also the systematic errors (the same fits on the flake with one ring less, and the
        improved dictionary; :func:`boundary_correlator`). Default True.

    Returns
    -------
    DeltaCurve
        ``omegas``, ``mass2`` (:math:`m^2 = -\lambda(\omega)`), ``delta_lattice`` with
        ``delta_lattice_err``, ``delta_continuum`` (NaN beyond the BF bound), the continuum BF
        bound ``omega_bf`` and the wall time ``seconds``.

    Raises
    ------
    ValueError
        Bad input, a line-graph lattice, no or more than 1000 frequencies, a frequency not below
        the band, a source off the outer ring or too few rings for the window.

    See Also
    --------
    boundary_correlator : one frequency, with the correlators themselves.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 5)
    >>> dc = hl.delta_curve(lat, [-3.5, -4.0])
    >>> [round(float(d), 3) for d in dc.delta_lattice]
    [2.03, 2.578]
    >>> [round(float(d), 3) for d in dc.delta_continuum]
    [2.062, 2.652]
    """
    lat = _site_lattice(lattice)
    if mass2 is not None:
        if omegas is not None:
            raise ValueError("give either omegas or mass2 (with ads_radius), not both.")
        m2 = _validate.real_array("mass2", mass2, ndim=1)
        if ads_radius is None:
            raise ValueError("mass2 needs ads_radius, the convention it is given in: 1 (unit-radius AdS2, "
                             "Delta(Delta-1) = m^2) or 0.5 (the paper's metric, Delta(Delta-1) = m^2/4).")
        if m2.size == 0 or m2.size > _MAX_OMEGAS:
            raise ValueError(f"give between 1 and {_MAX_OMEGAS} masses, got {m2.size}.")
        omegas = np.asarray(omega_from_mass2(mass2_in_paper_metric(m2, ads_radius), lat.p, lat.q), float).reshape(-1)
    elif ads_radius is not None:
        raise ValueError("ads_radius names the convention of mass2; give it with mass2, not with omegas.")
    elif omegas is None:
        raise ValueError("give the frequencies omegas, or mass2 with ads_radius.")
    systematic = _validate.flag("systematic", systematic)
    om = _validate.real_array("omegas", omegas, ndim=1)
    if om.size == 0 or om.size > _MAX_OMEGAS:
        raise ValueError(f"give between 1 and {_MAX_OMEGAS} frequencies, got {om.size}.")
    t0 = time.perf_counter()
    res = BelowBandResolvent(lat)
    dl, de, dc = (np.empty(om.size) for _ in range(3))
    src = None
    depth = _depth(depth)
    ring = outer_ring(lat)
    src = _outer_source(lat, ring, source, depth)
    fit = _ring_fit(lat, src, ring, depth)           # the omega-independent part, once for all masses
    for k, w in enumerate(om):
        # what boundary_correlator computes for Delta, without building its result object per mass
        w = _real_omega("omega", float(w))
        delta, se, _, _, _, sysw = fit.fit_with_window(res._column_at(w, src, fit.fit_sites), sorted_=True)
        dl[k], de[k], dc[k] = delta, math.hypot(se, sysw), _delta_continuum(w, lat.p, lat.q)
    ds, di = np.full(om.size, math.nan), np.full(om.size, math.nan)
    if systematic:
        di[:] = [_delta_improved(float(w), lat.p, lat.q) for w in om]
        rings_sys = np.full(om.size, math.nan)
        small = _smaller_flake(lat, depth)
        if small is not None:
            slat, sring, ssrc = small
            sres, sfit = BelowBandResolvent(slat), _ring_fit(slat, ssrc, sring, depth)
            for k, w in enumerate(om):
                try:
                    rings_sys[k] = abs(dl[k] - sfit.fit_with_window(sres._column_at(float(w), ssrc, sfit.fit_sites),
                                                                   sorted_=True)[0])
                except ValueError:    # fewer than 10 pairs in the smaller flake's window
                    pass
        ds = np.hypot(np.abs(dc - di), rings_sys)
    return DeltaCurve(p=lat.p, q=lat.q, rings=lat.rings, source=src, depth=_depth(depth), omegas=om,
                      mass2=np.asarray(mass2_from_omega(om, lat.p, lat.q), float).reshape(om.shape),
                      delta_continuum=dc, delta_lattice=dl, delta_lattice_err=de, delta_lattice_sys=ds,
                      delta_continuum_improved=di, omega_bf=bf_bound(lat.p, lat.q).omega,
                      seconds=time.perf_counter() - t0)


@dataclass(frozen=True, eq=False, kw_only=True)
class LatticeBFBound(Result):
    r"""The lattice BF bound :math:`E_0(\ell)` (bottom of the flake's spectrum) against the continuum :math:`E_\infty`.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    rings : ndarray of int
        The flakes ℓ.
    e0 : ndarray
        Lowest level of :math:`H = -A` per ℓ (units of t).
    mass2 : ndarray
        :math:`m^2 = -\lambda(E_0)`: the lightest mass the lattice propagator reaches.
    omega_continuum, mass2_continuum : float
        :math:`E_\infty` and :math:`-1`.

    Examples
    --------
    >>> from hyperlattice.compare.boundary import lattice_bf_bound
    >>> bf = lattice_bf_bound(7, 3, rings=(3, 4))
    >>> [round(float(e), 6) for e in bf.e0], round(bf.omega_continuum, 6)
    ([-2.786702, -2.846633], -2.942952)
    >>> [round(float(m), 4) for m in bf.mass2], bf.mass2_continuum
    ([-3.7389, -2.6884], -1.0)
    """

    COLUMNS = (Column("rings", "rings", "1"), Column("e0", "e0", "t"), Column("mass2", "mass2", "curvature units"))

    p: int
    q: int
    rings: np.ndarray
    e0: np.ndarray
    mass2: np.ndarray
    omega_continuum: float
    mass2_continuum: float

    def statement(self) -> str:
        """One sentence on the window between the two bounds, from the numbers."""
        above = self.e0 > self.omega_continuum
        r = self.rings
        def num(x, spec):  # a true minus sign in the sentence
            return format(float(x), spec).replace("-", "−")

        if np.all(above):
            return (f"For ℓ = {r[0]}–{r[-1]} the lattice bound E₀(ℓ) = {num(self.e0[0], '.5f')} to "
                    f"{num(self.e0[-1], '.5f')} lies above the continuum bound E∞ = {num(self.omega_continuum, '.5f')} "
                    f"(m² = {num(self.mass2[0], '.3f')} to {num(self.mass2[-1], '.3f')} against −1) and moves down "
                    "towards it as ℓ grows: in the window E∞ < ω < E₀(ℓ) the lattice propagator exists and decays "
                    "along the boundary, while the infinite-disk continuum has complex Δ.")
        return ("E₀(ℓ) − E∞ = " + ", ".join(num(e - self.omega_continuum, "+.4f") for e in self.e0)
                + f" for ℓ = {r[0]}–{r[-1]}.")


def lattice_bf_bound(p: int = 7, q: int = 3, rings=(3, 4, 5, 6, 7, 8)) -> LatticeBFBound:
    """:math:`E_0(\\ell)` of the {p,q} flakes (:func:`hyperlattice.graph.spectrum.lowest_levels`) and the continuum bound.

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol of the lattice, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    rings : int or sequence of int, optional
        Flake sizes l, 1 to 14 each. Default ``(3, 4, 5, 6, 7, 8)``.

    Returns
    -------
    LatticeBFBound
        ``e0`` (lowest level of :math:`H = -A` per l, units of t), ``mass2``
        (:math:`m^2 = -\\lambda(E_0)`), and the continuum bound ``omega_continuum``
        (:math:`E_\\infty`) with ``mass2_continuum`` (-1).

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic or ``rings`` is empty or out of range.

    Examples
    --------
    >>> from hyperlattice.compare.boundary import lattice_bf_bound
    >>> bf = lattice_bf_bound(7, 3, rings=(3, 4))
    >>> [round(float(e), 6) for e in bf.e0], round(bf.omega_continuum, 6)
    ([-2.786702, -2.846633], -2.942952)
    """
    from ..graph.lattice import ring_lattice
    from ..graph.spectrum import lowest_levels

    p, q = _validate.pq(p, q)
    if not isinstance(rings, (list, tuple, np.ndarray)):
        rings = [rings]
    rr = [_validate.positive_int("rings", r, maximum=14) for r in rings]
    if not rr:
        raise ValueError("give at least one number of rings.")
    e0 = np.array([lowest_levels(ring_lattice(p, q, r), 1).energies[0] for r in rr])
    bf = bf_bound(p, q)
    return LatticeBFBound(p=p, q=q, rings=np.array(rr), e0=e0,
                          mass2=np.asarray(mass2_from_omega(e0, p, q), float).reshape(e0.shape),
                          omega_continuum=bf.omega, mass2_continuum=bf.mass2)


@dataclass(frozen=True, eq=False, kw_only=True)
class BulkToBoundary(Result):
    r"""Bulk-to-boundary propagator: a source on the outer ring, probes everywhere.

    Attributes
    ----------
    p, q, rings, source : int
        The flake and the source site (0-based, outer ring).
    omega, delta_continuum : float
        Frequency (units of t) and the continuum :math:`\Delta`.
    delta_fit, delta_fit_err : float
        Δ from :math:`\ln G_{ij} = a + \Delta\ln K_1(z_i, \theta_j)`,
        :math:`K_1 = (1-|z|^2)/|z - e^{\mathrm i\theta_j}|^2`, over bulk sites (rings
        :math:`\le \ell - 2`, at least two edge lengths from the source); the error is the
        standard error.
    rel_l2 : float
        Relative L2 distance between the graph column and the continuum column (``eq21``, L = 1)
        on the same bulk sites (NaN beyond the BF bound). Large (0.2-0.9, depending on how far the
        source sits from the ragged edge): the whole-disk propagator does not know the edge next to
        the source, which sets the amplitude; the shape is ``kernel_rel_l2``.
    kernel_rel_l2 : float
        Relative L2 distance between the graph column and :math:`aK_\Delta` (continuum Δ, one fitted
        amplitude a) on the bulk sites.
    graph, continuum, kernel : ndarray, shape (N,)
        :math:`G_{ij}`, the continuum column, :math:`K_\Delta(z_i, \theta_j)` with the continuum Δ
        scaled by the fitted amplitude (NaN beyond the BF bound).
    bulk : ndarray of bool
        The sites used in the fit.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.boundary import bulk_to_boundary
    >>> b2b = bulk_to_boundary(hl.ring_lattice(7, 3, 5), -3.5)
    >>> b2b.source, int(b2b.bulk.sum()), b2b.graph.shape
    (315, 112, (847,))
    >>> print(f"{b2b.delta_fit:.3f} {b2b.delta_continuum:.3f}")
    2.023 2.062
    """

    #: one row per site i of the column
    COLUMNS = (Column("graph", "graph", "1/t"), Column("continuum", "continuum", "1/t"),
               Column("kernel", "kernel", "1/t"), Column("bulk", "bulk", "true/false"))

    p: int
    q: int
    rings: int
    source: int
    omega: float
    delta_continuum: float
    delta_fit: float
    delta_fit_err: float
    rel_l2: float
    kernel_rel_l2: float
    graph: np.ndarray = field(repr=False)
    continuum: np.ndarray = field(repr=False)
    kernel: np.ndarray = field(repr=False)
    bulk: np.ndarray = field(repr=False)


def bulk_to_boundary(lattice: Lattice, omega, source: int | None = None, *,
                     resolvent: BelowBandResolvent | None = None) -> BulkToBoundary:
    r"""The column :math:`G_{\cdot j}(\omega)` of an outer-ring source j against :math:`K_\Delta` and ``eq21``.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} site lattice with at least 4 rings.
    omega : float
        Real frequency (units of t), below the band (:math:`\omega < E_0(\ell)`).
    source : int, optional
        A site of the outer ring (0-based; default: its first site).
    resolvent : BelowBandResolvent, optional
        Reuse a factorization (several sources at one omega).

    Returns
    -------
    BulkToBoundary
        The fitted ``delta_fit`` with ``delta_fit_err`` against ``delta_continuum``, the
        distances ``rel_l2`` and ``kernel_rel_l2``, and the columns ``graph``, ``continuum``,
        ``kernel`` with the ``bulk`` mask of the sites fitted.

    Raises
    ------
    ValueError
        Bad input, a line-graph lattice, a source off the outer ring, fewer than 4 rings, omega
        not below the band, or too few bulk sites.

    See Also
    --------
    boundary_correlator : source and probes on the outer ring.
    hyperlattice.continuum.massive.bulk_to_boundary_kernel

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.boundary import bulk_to_boundary
    >>> b2b = bulk_to_boundary(hl.ring_lattice(7, 3, 5), -3.5)
    >>> b2b.source, int(b2b.bulk.sum())
    (315, 112)
    >>> print(f"{b2b.delta_fit:.3f} {b2b.delta_continuum:.3f}")
    2.023 2.062
    """
    from ..continuum.massive import bulk_to_boundary_kernel

    lat = _site_lattice(lattice)
    omega = _real_omega("omega", omega)
    ring = outer_ring(lat)
    source = int(ring[0]) if source is None else _validate.site_index("source", source, lat.sites)
    if lat.ring[source] != lat.rings:
        raise ValueError(f"source {source} is not on the outer ring (sites {ring[0]}..{ring[-1]}).")
    if lat.rings < 4:
        raise ValueError(f"a bulk-to-boundary fit needs at least 4 rings (got {lat.rings}).")
    res = _resolvent_for(resolvent, lat)
    g = res.column(omega, source)
    th = float(np.angle(lat.z[source]))
    d = distance(lat.z, lat.z[source])
    bulk = (lat.ring <= lat.rings - 2) & (d >= 2 * lat.d0)
    if np.count_nonzero(bulk) < _MIN_PAIRS:
        raise ValueError("too few bulk sites for a bulk-to-boundary fit; use more rings.")
    k1 = np.asarray(bulk_to_boundary_kernel(lat.z, th, 1.0))
    X = np.column_stack([np.ones(np.count_nonzero(bulk)), np.log(k1[bulk])])
    y = np.log(g[bulk])
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    resid = y - X @ coef
    cov = np.linalg.pinv(X.T @ X) * float(resid @ resid) / max(y.size - 2, 1)
    dc = _delta_continuum(omega, lat.p, lat.q)
    cont = continuum_boundary_column(lat, omega, source, np.arange(lat.sites))
    if math.isnan(dc):
        kern = np.full(lat.sites, math.nan)
        rel = krel = math.nan
    else:
        kd = k1**dc
        amp = math.exp(float(np.mean(y - dc * np.log(k1[bulk]))))
        kern = amp * kd
        rel = float(np.linalg.norm(g[bulk] - cont[bulk]) / np.linalg.norm(g[bulk]))
        krel = float(np.linalg.norm(g[bulk] - kern[bulk]) / np.linalg.norm(g[bulk]))
    return BulkToBoundary(p=lat.p, q=lat.q, rings=lat.rings, source=source, omega=omega, delta_continuum=dc,
                          delta_fit=float(coef[1]), delta_fit_err=float(math.sqrt(max(cov[1, 1], 0.0))), rel_l2=rel,
                          kernel_rel_l2=krel,
                          graph=g, continuum=cont, kernel=kern, bulk=bulk)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
