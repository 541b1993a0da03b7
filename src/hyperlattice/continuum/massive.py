r"""The massive scalar in the paper's AdS₂: frequency ω ↔ λ ↔ mass² ↔ conformal dimension Δ.

Below the band, the graph propagator :math:`G = (H-\omega)^{-1}` is the lattice Klein–Gordon
propagator; through the dictionary (``eq21``, :func:`hyperlattice.dictionary.lambda_from_energy`)

.. math:: -\Delta_g - \lambda = -\Delta_g + m^2, \qquad m^2 = -\lambda = -\frac{4(\omega+q)}{qh^2},

i.e. a scalar of mass² :math:`m^2 = -\lambda` in the paper's metric
:math:`ds^2 = (dx^2+dy^2)/(1-|z|^2)^2`, which is Euclidean AdS₂ of radius :math:`R = \tfrac12`
(curvature :math:`-1/R^2 = -4`: the standard Poincaré disk :math:`4|dz|^2/(1-|z|^2)^2` has
curvature :math:`-1`, and ours is a quarter of it).

Derivation of :math:`\Delta(\Delta-1) = m^2R^2`
-----------------------------------------------
The radial part of :math:`\Delta_g = (1-r^2)^2(\partial_r^2 + r^{-1}\partial_r + r^{-2}\partial_\phi^2)`
near the boundary :math:`r \to 1` acts on :math:`\phi \sim (1-r)^a` as

.. math:: (1-r^2)^2\partial_r^2 (1-r)^a = (1+r)^2 (1-r)^2\, a(a-1)(1-r)^{a-2}
          = 4a(a-1)(1-r)^a\,[1 + O(1-r)],

while the first-derivative and angular terms carry an extra factor :math:`(1-r)`. So
:math:`(-\Delta_g + m^2)\phi = 0` forces :math:`4a(a-1) = m^2`, i.e.

.. math:: \Delta(\Delta - 1) = \frac{m^2}{4} = m^2R^2, \qquad
          \Delta_\pm = \frac12 \pm \frac12\sqrt{1 + m^2} = \frac12 \pm \frac12\sqrt{1-\lambda},

the AdS\ :sub:`d+1` relation :math:`\Delta(\Delta-d) = m^2R^2` at :math:`d = 1`. The proper distance
from the centre is :math:`\rho = \operatorname{artanh} r`, so :math:`1-r \approx 2e^{-2\rho} =
2e^{-\rho/R}`: the falloff :math:`(1-r)^\Delta \propto e^{-\Delta\rho/R}` is the usual one. The
Legendre degree of the continuum Green function (:func:`hyperlattice.continuum.green.green_nu`,
:math:`\lambda/4 = -\nu(\nu+1)`) is :math:`\nu = \Delta_+ - 1`: :math:`\nu(\nu+1) = \Delta(\Delta-1)`.

Breitenlohner–Freedman bound
----------------------------
:math:`\Delta` is real iff :math:`m^2R^2 \ge -\tfrac14`, i.e. :math:`m^2 \ge -1`, :math:`\lambda \le 1`:
the BF bound is the bottom :math:`\kappa = 1` of the continuous spectrum of :math:`-\Delta_g` on the
infinite disk, where :math:`\Delta = \tfrac12`. In lattice units it sits at
:math:`E_\infty = -q + \frac q4 h^2` (:func:`bf_bound`; ``spec2``, :math:`-2.94295` for {7,3}).
Above it (:math:`\omega > E_\infty`, :math:`m^2 < -1`) :math:`\Delta = \tfrac12 \pm \tfrac{\mathrm i}2
\sqrt{\lambda - 1}` is complex and the infinite-disk propagator oscillates in the radial direction:
the field is unstable. A finite lattice's propagator exists up to the bottom :math:`E_0(\ell)` of its
own spectrum (the lattice BF bound; :func:`hyperlattice.compare.boundary.lattice_bf_bound`). For
{7,3} the finite flakes have :math:`E_0(\ell) > E_\infty` (e.g. :math:`-2.8942` at :math:`\ell = 6`,
:math:`-2.9127` at :math:`\ell = 8`), so in the window :math:`E_\infty < \omega < E_0(\ell)` the
lattice propagator is positive and decays along the boundary while the continuum one on the
infinite disk has complex Δ; a continuum Dirichlet disk of radius :math:`L < 1` still has a
propagator there, up to its own lowest level.

Boundary two-point function
---------------------------
For :math:`L = 1` the continuum Green function is :math:`\frac1{2\pi}Q_\nu(y)`,
:math:`y = \cosh 2d = 1 + 2|z-z'|^2/(\epsilon\epsilon')`, :math:`\epsilon = 1-|z|^2`. The large-
:math:`y` form of :math:`Q_\nu` (DLMF 14.8.15 with :math:`\mu = 0`,
:math:`Q_\nu(y) \sim \pi^{1/2}\Gamma(\nu+1)/[\Gamma(\nu+\tfrac32)(2y)^{\nu+1}]`) gives, with both points
near the boundary,

.. math:: G \approx C_\Delta \Bigl[\frac{\epsilon\epsilon'}{4|z-z'|^2}\Bigr]^{\Delta}
          = C_\Delta \Bigl(\frac{\epsilon\epsilon'}{16 r r'}\Bigr)^{\Delta}
            \bigl[\sin\tfrac{\theta}{2}\bigr]^{-2\Delta}\ (r = r'),
          \qquad C_\Delta = \frac{\Gamma(\Delta)}{2\sqrt\pi\,\Gamma(\Delta + \frac12)},

the conformal two-point function of a boundary operator of dimension Δ (:func:`conformal_two_point`,
:func:`boundary_two_point`). Its relative difference from the exact form is
:math:`O(\epsilon\epsilon'/|z-z'|^2)` (tested to 1e-8 against
:func:`hyperlattice.continuum.green.continuum_green` at :math:`1-|z| = 10^{-10}`). Letting only
:math:`z'` approach the boundary gives the bulk-to-boundary propagator
:math:`C_\Delta(\epsilon'/4)^\Delta K_\Delta(z, \theta')` with
:math:`K_\Delta(z,\theta') = [(1-|z|^2)/|z - e^{\mathrm i\theta'}|^2]^\Delta`
(:func:`bulk_to_boundary_kernel`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import special as sc

from .. import _validate
from ..dictionary import energy_from_lambda, lambda_from_energy
from ..geometry import one_minus_abs2
from ..results import Result

__all__ = [
    "ADS_RADIUS",
    "ADS_RADII",
    "mass2_in_paper_metric",
    "delta_formulas",
    "BF_MASS2",
    "mass2_from_lambda",
    "lambda_from_mass2",
    "delta_from_mass2",
    "mass2_from_delta",
    "mass2_from_omega",
    "omega_from_mass2",
    "delta_from_omega",
    "omega_from_delta",
    "BFBound",
    "bf_bound",
    "conformal_prefactor",
    "conformal_two_point",
    "boundary_two_point",
    "bulk_to_boundary_kernel",
]

#: AdS radius of the paper's metric ``|dz|^2/(1-|z|^2)^2`` (curvature -1/R^2 = -4)
ADS_RADIUS = 0.5
#: Breitenlohner-Freedman bound m^2 R^2 = -1/4 in the paper's units: m^2 = -1 (lambda = 1)
BF_MASS2 = -1.0 / (4.0 * ADS_RADIUS**2)


_BF_SLACK = 1e-12

#: the AdS radii a mass² may be given in: 1 (the unit-radius AdS₂ most texts use,
#: :math:`ds^2 = 4|dz|^2/(1-|z|^2)^2`, :math:`\Delta(\Delta-1) = m^2`) and 1/2 (the paper's metric,
#: :math:`\Delta(\Delta-1) = m^2/4`)
ADS_RADII = (1.0, 0.5)


def _ads_radius(ads_radius) -> float:
    r = _validate.real("ads_radius", ads_radius)
    if r not in ADS_RADII:
        raise ValueError(f"ads_radius names the convention of the mass: 1 (unit-radius AdS2, Delta(Delta-1) = m^2) "
                         f"or 0.5 (the paper's metric, Delta(Delta-1) = m^2/4), got {r:g}.")
    return r


def mass2_in_paper_metric(m2, ads_radius) -> float | np.ndarray:
    r"""A mass² given in AdS₂ of radius ``ads_radius``, in the paper's metric (:math:`R = 1/2`).

    The dimensionless :math:`m^2R^2` fixes the physics (:math:`\Delta(\Delta-1) = m^2R^2`), so
    :math:`m^2_{\rm paper} = m^2 R^2 / (1/2)^2 = 4m^2R^2`: a mass² of 1 in unit-radius AdS₂ is 4 here.

    Parameters
    ----------
    m2 : float or array_like of float
        Mass² in units of :math:`1/R^2` of the named radius.
    ads_radius : {1, 0.5}
        The AdS radius the mass is given in (:data:`ADS_RADII`).

    Returns
    -------
    float or ndarray of float
        :math:`m^2` in the paper's metric, as :func:`delta_from_mass2` and :func:`omega_from_mass2` take it.

    Raises
    ------
    ValueError
        Bad input, or a radius other than 1 and 0.5.

    Examples
    --------
    >>> from hyperlattice.continuum.massive import delta_from_mass2, mass2_in_paper_metric
    >>> m2 = mass2_in_paper_metric(1.0, ads_radius=1)
    >>> m2, round(delta_from_mass2(m2), 6)
    (4.0, 1.618034)
    """
    r = _ads_radius(ads_radius)
    m2 = np.asarray(_scalar_or_array("mass2", m2))
    return _out(m2 * (r / ADS_RADIUS) ** 2)


def delta_formulas(m2) -> dict:
    r"""Both conventions' formula values of Δ at one number :math:`m^2`, side by side.

    ``"ads_radius_1"``: :math:`\frac12 + \sqrt{\frac14 + m^2}` (the number read as a mass² in unit-radius
    AdS₂); ``"ads_radius_0.5"``: :math:`\frac12 + \frac12\sqrt{1 + m^2}` (read in the paper's metric).
    The same number gives two different Δ (1.618 and 1.207 at :math:`m^2 = 1`); only the one of
    the convention the mass was given in applies. NaN below that convention's BF bound.

    Parameters
    ----------
    m2 : float
        The number.

    Returns
    -------
    dict
        ``{"ads_radius_1": float, "ads_radius_0.5": float}``.

    Examples
    --------
    >>> from hyperlattice.continuum.massive import delta_formulas
    >>> {k: round(v, 6) for k, v in delta_formulas(1.0).items()}
    {'ads_radius_1': 1.618034, 'ads_radius_0.5': 1.207107}
    """
    x = _validate.real("mass2", m2)
    return {"ads_radius_1": 0.5 + math.sqrt(0.25 + x) if x >= -0.25 else math.nan,
            "ads_radius_0.5": 0.5 + 0.5 * math.sqrt(1.0 + x) if x >= -1.0 else math.nan}


def _scalar_or_array(name: str, value) -> float | np.ndarray:
    """A finite real number or a real array (float64); complex input refused."""
    if isinstance(value, (np.ndarray, list, tuple)):
        return _validate.real_array(name, value)
    return _validate.real(name, value)


def _out(x):
    return float(x) if np.ndim(x) == 0 else np.asarray(x, dtype=float)


def mass2_from_lambda(lam) -> float | np.ndarray:
    r"""The mass² :math:`m^2 = -\lambda` of the Klein–Gordon operator :math:`-\Delta_g + m^2 = -\Delta_g - \lambda`.

    In the paper's metric (AdS₂ of radius :math:`R = 1/2`).

    Parameters
    ----------
    lam : float or array_like of float
        Eigenvalue variable :math:`\lambda` of :math:`-\Delta_g` (real).

    Returns
    -------
    float or ndarray of float
        :math:`m^2 = -\lambda`.

    Raises
    ------
    ValueError
        If ``lam`` is complex or not finite.

    See Also
    --------
    lambda_from_mass2, mass2_from_omega

    Examples
    --------
    >>> from hyperlattice.continuum.massive import mass2_from_lambda
    >>> mass2_from_lambda(0.5)
    -0.5
    """
    return _out(-np.asarray(_scalar_or_array("lambda", lam)))


def lambda_from_mass2(m2) -> float | np.ndarray:
    r""":math:`\lambda = -m^2`, the inverse of :func:`mass2_from_lambda`.

    Parameters
    ----------
    m2 : float or array_like of float
        Mass² :math:`m^2` in the paper's metric (:math:`R = 1/2`).

    Returns
    -------
    float or ndarray of float
        :math:`\lambda = -m^2`.

    Raises
    ------
    ValueError
        If ``m2`` is complex or not finite.

    Examples
    --------
    >>> from hyperlattice.continuum.massive import lambda_from_mass2
    >>> lambda_from_mass2(-0.5)
    0.5
    """
    return _out(-np.asarray(_scalar_or_array("mass2", m2)))


def delta_from_mass2(m2, *, branch: str = "plus") -> float | np.ndarray:
    r"""Conformal dimension :math:`\Delta_\pm = \frac12 \pm \frac12\sqrt{1 + m^2}` of a scalar of mass² :math:`m^2`.

    From :math:`\Delta(\Delta-1) = m^2R^2` with :math:`R = 1/2` (module docstring).

    Parameters
    ----------
    m2 : float or array_like
        Mass² in the paper's metric (:math:`m^2 = -\lambda`), at or above the BF bound
        :math:`m^2 = -1`.
    branch : {"plus", "minus"}, optional
        :math:`\Delta_+` (default; standard quantization, the falloff of the
        Dirichlet/normalizable propagator) or :math:`\Delta_- = 1 - \Delta_+` (alternate
        quantization, unitary only for :math:`-1 \le m^2 < 3`).

    Returns
    -------
    float or ndarray of float
        :math:`\Delta_\pm` (dimensionless).

    Raises
    ------
    ValueError
        Below the BF bound (:math:`m^2 < -1`, Δ complex) or on bad input.

    See Also
    --------
    mass2_from_delta, delta_from_omega, bf_bound

    Examples
    --------
    >>> from hyperlattice.continuum.massive import delta_from_mass2
    >>> delta_from_mass2(3.0), delta_from_mass2(3.0, branch="minus")
    (1.5, -0.5)
    >>> delta_from_mass2(-1.0)
    0.5
    """
    branch = _validate.choice("branch", branch, ("plus", "minus"))
    m2 = np.asarray(_scalar_or_array("mass2", m2))
    # m^2 = -1 reached through the dictionary rounds to -1 - 1e-16: within _BF_SLACK it is the bound
    if np.any(m2 < BF_MASS2 - _BF_SLACK):
        worst = float(np.min(m2))
        raise ValueError(f"mass2 = {worst:g} lies below the Breitenlohner-Freedman bound m^2 = -1 (m^2 R^2 = -1/4 "
                         "with R = 1/2): the conformal dimension is complex there.")
    # 1 + m^2 = 4(m^2 R^2 + 1/4) >= 0 above the bound; clip the rounding of m^2 = -1 exactly
    root = 0.5 * np.sqrt(np.maximum(1.0 + m2, 0.0))
    return _out(0.5 + root if branch == "plus" else 0.5 - root)


def mass2_from_delta(delta) -> float | np.ndarray:
    r"""The mass² :math:`m^2 = \Delta(\Delta-1)/R^2 = 4\Delta(\Delta-1)` of a conformal dimension.

    Either branch maps back to the same mass².

    Parameters
    ----------
    delta : float or array_like of float
        Conformal dimension :math:`\Delta` (real).

    Returns
    -------
    float or ndarray of float
        :math:`m^2` in the paper's metric.

    Raises
    ------
    ValueError
        If ``delta`` is complex or not finite.

    Examples
    --------
    >>> from hyperlattice.continuum.massive import mass2_from_delta
    >>> mass2_from_delta(1.5), mass2_from_delta(-0.5)
    (3.0, 3.0)
    """
    d = np.asarray(_scalar_or_array("delta", delta))
    return _out(d * (d - 1.0) / ADS_RADIUS**2)


def mass2_from_omega(omega, p: int = 7, q: int = 3) -> float | np.ndarray:
    r"""The mass² :math:`m^2 = -\lambda(\omega) = -4(\omega+q)/(qh^2)` of a lattice frequency.

    Through the dictionary of Eq. (19); real ω only (a mass is real).

    Parameters
    ----------
    omega : float or array_like of float
        Lattice frequency in units of t.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float or ndarray of float
        :math:`m^2` in the paper's metric.

    Raises
    ------
    ValueError
        If ``omega`` is complex or not finite, or {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    omega_from_mass2, hyperlattice.dictionary.lambda_from_energy

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19).

    Examples
    --------
    >>> from hyperlattice.continuum.massive import mass2_from_omega
    >>> print(f"{mass2_from_omega(-3.5):.6f}")
    8.764501
    """
    omega = _scalar_or_array("omega", omega)
    return _out(-np.asarray(lambda_from_energy(omega, p, q)))


def omega_from_mass2(m2, p: int = 7, q: int = 3) -> float | np.ndarray:
    r"""The lattice frequency :math:`\omega = -q - \frac q4 h^2 m^2` of a mass², the inverse of :func:`mass2_from_omega`.

    Parameters
    ----------
    m2 : float or array_like of float
        Mass² in the paper's metric.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float or ndarray of float
        :math:`\omega` in units of t.

    Raises
    ------
    ValueError
        If ``m2`` is complex or not finite, or {p,q} is not a hyperbolic tessellation.

    Examples
    --------
    >>> from hyperlattice.continuum.massive import omega_from_mass2
    >>> print(f"{omega_from_mass2(2.0):.6f}")
    -3.114097
    """
    m2 = _scalar_or_array("mass2", m2)
    return _out(energy_from_lambda(-np.asarray(m2) if np.ndim(m2) else -m2, p, q))


def delta_from_omega(omega, p: int = 7, q: int = 3, *, branch: str = "plus") -> float | np.ndarray:
    r"""Continuum conformal dimension Δ of a lattice frequency ω: :math:`\frac12 \pm \frac12\sqrt{1-\lambda(\omega)}`.

    Below the band the graph propagator is a massive scalar in AdS₂ (module docstring);
    :math:`\lambda(\omega) = 4(\omega + q)/(qh^2)` is the dictionary of Eq. (19).

    Parameters
    ----------
    omega : float or array_like of float
        Lattice frequency in units of t, at most :math:`E_\infty = -q + \frac q4 h^2`.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    branch : {"plus", "minus"}, optional
        :math:`\Delta_+` (default) or :math:`\Delta_- = 1 - \Delta_+`.

    Returns
    -------
    float or ndarray of float
        :math:`\Delta_\pm`.

    Raises
    ------
    ValueError
        For :math:`\omega > E_\infty` (beyond the continuum BF bound), complex or non-finite
        ``omega``, or an invalid {p,q} or ``branch``.

    See Also
    --------
    omega_from_delta, bf_bound, hyperlattice.compare.boundary.delta_curve

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.delta_from_omega(-3.5, 7, 3):.6f}")
    2.062410
    >>> print(f"{hl.delta_from_omega(-3.5, branch='minus'):.6f}")
    -1.062410
    """
    return delta_from_mass2(mass2_from_omega(omega, p, q), branch=branch)


def omega_from_delta(delta, p: int = 7, q: int = 3) -> float | np.ndarray:
    r"""The lattice frequency whose continuum dimension is Δ (either branch).

    Parameters
    ----------
    delta : float or array_like of float
        Conformal dimension :math:`\Delta`.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float or ndarray of float
        :math:`\omega` in units of t (at most :math:`E_\infty`).

    Raises
    ------
    ValueError
        If ``delta`` is complex or not finite, or {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    delta_from_omega

    Examples
    --------
    >>> from hyperlattice.continuum.massive import omega_from_delta
    >>> print(f"{omega_from_delta(1.5):.6f}")
    -3.171145
    """
    return omega_from_mass2(mass2_from_delta(delta), p, q)


@dataclass(frozen=True, eq=False, kw_only=True)
class BFBound(Result):
    r"""The continuum Breitenlohner–Freedman bound in every unit of the dictionary.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    mass2 : float
        :math:`m^2 = -1` (:math:`m^2R^2 = -1/4`, :math:`R = 1/2`: masses in units of the
        curvature scale of the paper's metric, curvature -4).
    lam : float
        :math:`\lambda = 1`, the bottom of the continuous spectrum of :math:`-\Delta_g` (``spec2``).
    omega : float
        :math:`E_\infty = -q + \frac q4 h^2` in units of t (:math:`-2.94295` for {7,3}).
    delta : float
        :math:`\Delta = 1/2`.

    Examples
    --------
    >>> from hyperlattice.continuum.massive import bf_bound
    >>> b = bf_bound(7, 3)
    >>> b.mass2, b.lam, round(b.omega, 5), b.delta
    (-1.0, 1.0, -2.94295, 0.5)
    """

    p: int
    q: int
    mass2: float
    lam: float
    omega: float
    delta: float


def bf_bound(p: int = 7, q: int = 3) -> BFBound:
    r"""The continuum Breitenlohner–Freedman bound in every unit of the dictionary.

    :math:`m^2 = -1` (:math:`m^2R^2 = -1/4`), :math:`\lambda = 1`, :math:`\omega = E_\infty`,
    :math:`\Delta = 1/2`.

    Parameters
    ----------
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    BFBound
        A frozen result with fields ``p``, ``q``, ``mass2``, ``lam``, ``omega`` (units of t)
        and ``delta``.

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> b = hl.bf_bound(7, 3)
    >>> print(b.mass2, b.lam, f"{b.omega:.6f}", b.delta)
    -1.0 1.0 -2.942952 0.5
    """
    p, q = _validate.pq(p, q)
    return BFBound(p=p, q=q, mass2=BF_MASS2, lam=-BF_MASS2, omega=float(energy_from_lambda(-BF_MASS2, p, q)),
                   delta=0.5)


def _delta(delta) -> float:
    return _validate.real("delta", delta, minimum=0.0, open_min=True)


def conformal_prefactor(delta) -> float:
    r"""The coefficient :math:`C_\Delta = \Gamma(\Delta)/[2\sqrt\pi\,\Gamma(\Delta+\frac12)]` of the boundary two-point function.

    Of the :math:`L = 1` propagator :math:`\frac1{2\pi}Q_{\Delta-1}(y)` (module docstring).

    Parameters
    ----------
    delta : float
        Conformal dimension :math:`\Delta > 0`.

    Returns
    -------
    float
        :math:`C_\Delta` (computed with log-gamma, finite for large Δ).

    Raises
    ------
    ValueError
        If ``delta`` is not a finite real number above 0.

    Examples
    --------
    >>> from hyperlattice.continuum.massive import conformal_prefactor
    >>> print(f"{conformal_prefactor(1.0):.6f}")
    0.318310
    """
    d = _delta(delta)
    # log-gamma: Gamma(Delta) alone overflows beyond Delta ~ 171
    return float(np.exp(sc.gammaln(d) - sc.gammaln(d + 0.5)) / (2.0 * math.sqrt(math.pi)))


def conformal_two_point(z, zp, delta) -> float | np.ndarray:
    r"""Leading near-boundary form :math:`C_\Delta[\epsilon\epsilon'/(4|z-z'|^2)]^\Delta` of the :math:`L = 1` propagator.

    The propagator is :math:`\frac1{2\pi}Q_{\Delta-1}(y)`, :math:`\epsilon = 1-|z|^2`. Relative
    accuracy against the exact propagator: :math:`O(\epsilon\epsilon'/|z-z'|^2)`.

    Parameters
    ----------
    z, zp : complex or array_like of complex
        Points inside the unit disk, not coincident; they broadcast against each other.
    delta : float
        Conformal dimension :math:`\Delta > 0`.

    Returns
    -------
    float or ndarray of float
        The conformal two-point function, with the broadcast shape.

    Raises
    ------
    ValueError
        If points coincide, lie outside the disk or do not broadcast, or ``delta`` is invalid.

    See Also
    --------
    boundary_two_point, conformal_prefactor

    Examples
    --------
    >>> from hyperlattice.continuum.massive import conformal_two_point
    >>> print(f"{float(conformal_two_point(0.99, -0.99, 1.0)):.4e}")
    8.0383e-06
    """
    d = _delta(delta)
    z = _validate.disk_points("z", z)
    zp = _validate.disk_points("z'", zp)
    try:
        z, zp = np.broadcast_arrays(z, zp)
    except ValueError:
        raise ValueError(f"z and z' must broadcast to one shape; got shapes {np.shape(z)} and {np.shape(zp)}.") \
            from None
    sep = np.abs(z - zp)
    if np.any(sep == 0):
        raise ValueError("z and z' coincide at some pair; the two-point function diverges there.")
    ratio = one_minus_abs2(z) * one_minus_abs2(zp) / (4.0 * sep * sep)
    out = conformal_prefactor(d) * np.exp(d * np.log(ratio))
    return _out(out)


def boundary_two_point(theta, delta, eps=1.0, eps_prime=None) -> float | np.ndarray:
    r"""The conformal form :math:`C_\Delta(\epsilon\epsilon'/16)^\Delta[\sin(\theta/2)]^{-2\Delta}` on the boundary circle.

    Equals :func:`conformal_two_point` for points on one circle up to the factor
    :math:`(rr')^{-\Delta}`.

    Parameters
    ----------
    theta : float or array_like of float
        Angle between the two points, in radians (not a multiple of :math:`2\pi`).
    delta : float
        Conformal dimension :math:`\Delta > 0`.
    eps : float, optional
        Cut-off :math:`\epsilon = 1 - r^2` of the first point (default 1: the bare
        :math:`C_\Delta 16^{-\Delta}|\sin\theta/2|^{-2\Delta}`).
    eps_prime : float, optional
        Cut-off of the second point (default ``eps``).

    Returns
    -------
    float or ndarray of float
        The two-point function, same shape as ``theta``.

    Raises
    ------
    ValueError
        If ``theta`` is a multiple of :math:`2\pi`, a cut-off is not positive, or ``delta`` is
        invalid.

    Examples
    --------
    >>> import math
    >>> from hyperlattice.continuum.massive import boundary_two_point
    >>> print(f"{boundary_two_point(math.pi, 1.0):.6f}")
    0.019894
    """
    d = _delta(delta)
    th = np.asarray(_scalar_or_array("theta", theta))
    e1 = _validate.positive_real("eps", eps)
    e2 = e1 if eps_prime is None else _validate.positive_real("eps_prime", eps_prime)
    s = np.abs(np.sin(0.5 * th))
    if np.any(s == 0):
        raise ValueError("theta is a multiple of 2 pi at some point; the two-point function diverges there.")
    return _out(conformal_prefactor(d) * np.exp(d * (math.log(e1 * e2 / 16.0) - 2.0 * np.log(s))))


def bulk_to_boundary_kernel(z, theta, delta) -> float | np.ndarray:
    r"""The bulk-to-boundary propagator :math:`K_\Delta(z, \theta) = [(1-|z|^2)/|z - e^{\mathrm i\theta}|^2]^\Delta`.

    Up to the normalization :math:`C_\Delta(\epsilon'/4)^\Delta` of a source at cut-off
    :math:`\epsilon'`.

    Parameters
    ----------
    z : complex or array_like of complex
        Bulk points in the open unit disk.
    theta : float or array_like of float
        Boundary angle(s) in radians; broadcasts against ``z``.
    delta : float
        Conformal dimension :math:`\Delta > 0`.

    Returns
    -------
    float or ndarray of float
        :math:`K_\Delta(z, \theta)`, with the broadcast shape.

    Raises
    ------
    ValueError
        If a point lies outside the disk, the shapes do not broadcast, or ``delta`` is invalid.

    Examples
    --------
    >>> from hyperlattice.continuum.massive import bulk_to_boundary_kernel
    >>> print(f"{bulk_to_boundary_kernel(0.5, 0.0, 1.0):.6f}")
    3.000000
    """
    d = _delta(delta)
    z = _validate.disk_points("z", z)
    th = np.asarray(_scalar_or_array("theta", theta))
    try:
        z, th = np.broadcast_arrays(z, th)
    except ValueError:
        raise ValueError(f"z and theta must broadcast to one shape; got {np.shape(z)} and {np.shape(th)}.") from None
    return _out(np.exp(d * (np.log(one_minus_abs2(z)) - 2.0 * np.log(np.abs(z - np.exp(1j * th))))))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
