r"""The graph <-> continuum dictionary: every map between the two sides, written once.

Both sides import this module; nothing else writes these formulas. A convention change (or an
improved dictionary) is one edit here.

From the small-h expansion of the adjacency operator on a {p,q} lattice (paper, ``eq10``/``adj26``
with 3 replaced by q: the q neighbours sit at :math:`h e^{\mathrm i(\chi + 2\pi k/q)}`, whose first
and second moments vanish),

.. math:: A \approx q + \frac q4 h^2 \Delta_g, \qquad h = \tanh d_0,

and from sums as integrals, :math:`\sum_i \approx \frac1{\mathcal A}\int dV_g` (``eq11``, area per
site :math:`\mathcal A`, :func:`hyperlattice.geometry.site_area`):

* energies and eigenvalues (``spec2``, ``eq21``): a lattice energy :math:`E` (or frequency
  :math:`\omega`) corresponds to the eigenvalue :math:`\lambda = \kappa` of :math:`-\Delta_g`,

  .. math:: \lambda = \frac{4(\omega + q)}{q h^2}, \qquad E = -q + \frac q4 h^2 \kappa,
            \qquad \kappa = 1 + k^2 \text{ on the continuum spectrum};

* Green functions (``eq21``): :math:`G_{ij}(\omega) \approx \frac{4\mathcal A}{q h^2}
  G(z_i, z_j, \lambda, L)` (:func:`green_prefactor`);
* the disk radius (``eq12``): :math:`L = \sqrt{N/(N + \pi/\mathcal A)}` for a lattice of N sites
  (:func:`disk_radius`);
* many-body parameters (``eq13`` -> ``eq14``): :math:`t' = \frac q4 h^2 t`, :math:`\mu' = \mu + qt`,
  :math:`U' = \mathcal A U` (:func:`continuum_parameters`).

The improved dictionary (``dictionary="improved"``; the paper's map stays the default)
---------------------------------------------------------------------------------------
The paper's map keeps the first two terms of the small-h expansion. For an eigenfunction
:math:`\Delta_g f = -\lambda f` the *isotropic* part of the star is summed exactly: expand f
about a site in geodesic polar coordinates, :math:`f = \sum_m c_m\,\Phi_{\lambda,m}(d)e^{\mathrm i m\theta}`.
The q neighbours at distance :math:`d_0` and angles :math:`\chi + 2\pi a/q` keep only the orders
:math:`m \equiv 0 \pmod q`, so

.. math:: (Af)(z_i) = q\,\varphi_\lambda(d_0)\,f(z_i) + [\text{orders } m = \pm q, \pm 2q, \dots],
          \qquad \varphi_\lambda(d) = P_\nu(\cosh 2d),\ \nu = \tfrac12(-1 + \mathrm i k),\ \lambda = 1 + k^2,

where :math:`\varphi_\lambda` is the spherical function (the radial eigenfunction with
:math:`\varphi(0) = 1`; the mean-value property: the average of f over the geodesic circle of
radius d about z is :math:`\varphi_\lambda(d) f(z)`; :math:`\cosh 2d` because the metric has
curvature -4). The orders :math:`\pm q` are the paper's anisotropic :math:`h^3 Q_3` term
(``adj32``, :math:`\mathcal D` of ``adj33``, for q = 3): they come with :math:`e^{\pm 3\mathrm i\chi_i}`
and would average to zero over uniformly spread orientations; on the ring lattice
:math:`\langle\cos 3(\chi_i - \phi_i)\rangle = 0.17` over the sites of coordination 3 at
:math:`\ell = 10` (0.04 weighted with the ground state's amplitude, −0.007 with its weight
:math:`\psi_i^2`; checked in docs/limits.md), so they move the levels weakly at first order and
at second order (net, measured: -1.9e-4 at the {7,3} band bottom, :mod:`hyperlattice.compare.limits`); they are left out. Hence

.. math:: E = -q\,P_{\frac12(-1+\mathrm i k)}\Bigl(\frac{1+h^2}{1-h^2}\Bigr)
          = -q + \frac q4 h^2\lambda + q\Bigl(\frac\lambda8 - \frac{\lambda^2}{64}\Bigr)h^4 + O(h^6),

which is the paper's map at order :math:`h^2` (:func:`improved_energy_from_lambda`). Second, the
Dirichlet condition: a flake's eigenvector vanishes on the missing neighbours outside it, while
``eq12`` gives the disk of the flake's *area* (each site's cell reaches half way to the next ring).
As for a chain of N sites (area length Na, Dirichlet walls at the two missing sites, length
(N + 1)a), the wall sits half a bond further out: the Dirichlet radius is the area radius plus
half the mean radial length of the bonds that leave the flake (:func:`dirichlet_radius_shift`,
0.13537 for {7,3}; :func:`improved_disk_for_rings`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from . import _validate, geometry
from ._ties import monotone_tolerance
from .results import Result

__all__ = [
    "improved_lambda_of_frequency",
    "laplacian_coefficient",
    "hopping_scale",
    "lambda_from_energy",
    "energy_from_lambda",
    "energy_from_k",
    "green_prefactor",
    "dictionary_parameters",
    "disk_radius",
    "disk_radius_for_rings",
    "ContinuumParameters",
    "continuum_parameters",
    "lattice_parameters",
    "field_from_flux",
    "flux_from_field",
    "DICTIONARIES",
    "spherical_function",
    "spherical_mean_energy",
    "improved_energy_from_lambda",
    "improved_energy_from_k",
    "improved_lambda_from_energy",
    "improved_band_bottom",
    "dirichlet_radius_shift",
    "improved_disk_for_rings",
    "map_energy_from_k",
]


# ----------------------------------------------------------------------------
# energies <-> eigenvalues of -Delta_g
# ----------------------------------------------------------------------------

def _value(name: str, value):
    """A real or complex scalar, or an array of them, all finite (arrays as float64/complex128)."""
    if isinstance(value, (np.ndarray, list, tuple)):
        a = _validate.complex_array(name, value)  # refuses ragged lists, strings, NaN and inf
        return a if np.asarray(value).dtype.kind == "c" else a.real.copy()
    if isinstance(value, (complex, np.complexfloating)):
        return _validate.complex_number(name, value)
    return _validate.real(name, value)


def laplacian_coefficient(q: int, h) -> float | np.ndarray:
    r"""The coefficient :math:`\frac q4 h^2` of :math:`\Delta_g` in :math:`A \approx q + \frac q4 h^2\Delta_g`.

    For a q-fold star of neighbours at Euclidean distance h (after a Möbius map to the origin).
    The one place this factor is written; :func:`hopping_scale` evaluates it at :math:`h = \tanh d_0`,
    and the h-expansion of :mod:`hyperlattice.compare.scaling` at any h.

    Parameters
    ----------
    q : int
        Number of neighbours in the star (coordination number), at least 3.
    h : float or array_like of float
        Euclidean radius of the star (the lattice parameter :math:`h = \tanh d_0` for a lattice).

    Returns
    -------
    float or ndarray of float
        :math:`\frac q4 h^2`, a float for scalar ``h``.

    Raises
    ------
    ValueError
        If ``q`` is not an integer of at least 3, or ``h`` is not finite and real.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (8) (with 3 replaced by q).

    Examples
    --------
    >>> from hyperlattice.dictionary import laplacian_coefficient
    >>> laplacian_coefficient(3, 0.5)
    0.1875
    """
    q = _validate.integer("q", q, minimum=3, maximum=_validate.PQ_MAX)
    h = _validate.real_array("h", h)
    out = 0.25 * q * h * h
    return float(out) if np.ndim(out) == 0 else out


def hopping_scale(p=7, q=3) -> float:
    r"""The factor :math:`\frac q4 h^2` of :math:`A \approx q + \frac q4 h^2\Delta_g`, at :math:`h = \tanh d_0`.

    It converts continuum eigenvalues into lattice energies (:math:`t'/t`, Eq. (12)):
    :math:`\frac34 h^2 = 0.0570...` for {7,3}.

    Parameters
    ----------
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        :math:`t'/t = \frac q4 \tanh^2 d_0`.

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    laplacian_coefficient, energy_from_lambda

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eqs. (8) and (12).

    Examples
    --------
    >>> from hyperlattice.dictionary import hopping_scale
    >>> print(f"{hopping_scale(7, 3):.6f}")
    0.057048
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    return laplacian_coefficient(q, geometry.lattice_h(p, q))


def lambda_from_energy(omega, p=7, q=3) -> float | complex | np.ndarray:
    r"""The eigenvalue :math:`\lambda = 4(\omega + q)/(q h^2)` of :math:`-\Delta_g` that matches a lattice energy.

    :math:`\omega` is a lattice energy or frequency (units of t, :math:`H = -tA`); the map is the
    argument of the continuum Green function in Eq. (19), generalised to {p,q}.

    Parameters
    ----------
    omega : float, complex or array_like
        Lattice energy or frequency in units of t; real or complex, scalar or array.
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float, complex or ndarray
        :math:`\lambda`, of the same kind and shape as ``omega``.

    Raises
    ------
    ValueError
        If ``omega`` is not a finite number or numeric array, {p,q} is not a hyperbolic
        tessellation, or the result overflows.

    See Also
    --------
    energy_from_lambda : the inverse map.
    improved_lambda_from_energy : the improved dictionary.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.lambda_from_energy(-2.9, 7, 3):.6f}")
    1.752900
    >>> lam = hl.lambda_from_energy(-2.9 + 0.01j)
    >>> print(f"{lam.real:.6f} {lam.imag:.6f}")
    1.752900 0.175290
    """
    omega = _value("omega", omega)
    scale = hopping_scale(p, q)
    q = _validate.pq(p, q, allow_infinite_p=True)[1]
    return (np.asarray(omega) + q) / scale if np.ndim(omega) else (omega + q) / scale


def energy_from_lambda(lam, p=7, q=3) -> float | complex | np.ndarray:
    r"""The lattice energy :math:`E = -q + \frac q4 h^2 \lambda` of an eigenvalue of :math:`-\Delta_g`.

    The inverse of :func:`lambda_from_energy` (the paper's map, Appendix F, ``spec2``).

    Parameters
    ----------
    lam : float, complex or array_like
        Eigenvalue :math:`\lambda` of :math:`-\Delta_g`; real or complex, scalar or array.
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float, complex or ndarray
        The energy E in units of t, of the same kind and shape as ``lam``.

    Raises
    ------
    ValueError
        If ``lam`` is not a finite number or numeric array, {p,q} is not a hyperbolic
        tessellation, or the result overflows.

    See Also
    --------
    lambda_from_energy, energy_from_k, improved_energy_from_lambda

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix F (``spec2``) and Eq. (19).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.energy_from_lambda(2.0, 7, 3):.6f}")
    -2.885903
    """
    lam = _value("lam", lam)
    scale = hopping_scale(p, q)
    q = _validate.pq(p, q, allow_infinite_p=True)[1]
    return -q + scale * (np.asarray(lam) if np.ndim(lam) else lam)


def energy_from_k(k, p=7, q=3) -> float | complex | np.ndarray:
    r"""Lattice energy of a continuum level with :math:`-\Delta_g\psi = (1 + k^2)\psi`.

    :math:`E = -q + \frac q4 h^2 (1 + k^2)`, the paper's map.

    Parameters
    ----------
    k : float, complex or array_like
        Wave number k of the level: real for Dirichlet levels; complex k allowed.
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float, complex or ndarray
        The energy E in units of t (an ndarray, 0-d for scalar ``k``).

    Raises
    ------
    ValueError
        If ``k`` is not a finite number or numeric array, or {p,q} is not a hyperbolic
        tessellation.

    See Also
    --------
    energy_from_lambda, improved_energy_from_k, map_energy_from_k

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix F (``spec2``).

    Examples
    --------
    >>> from hyperlattice.dictionary import energy_from_k
    >>> print(f"{float(energy_from_k(1.0)):.6f}")
    -2.885903
    >>> [round(float(e), 6) for e in energy_from_k([0.0, 1.0])]
    [-2.942952, -2.885903]
    """
    k = np.asarray(_value("k", k))
    return energy_from_lambda(1.0 + k * k, p, q)


def green_prefactor(p=7, q=3) -> float:
    r"""The prefactor :math:`4\mathcal A/(q h^2)` of the Green-function map.

    :math:`G_{ij}(\omega) \approx \frac{4\mathcal A}{q h^2} G(z_i, z_j, \lambda, L)`;
    :math:`\pi/(21 h^2)` for {7,3}.

    Parameters
    ----------
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        The prefactor (dimensionless; :math:`\mathcal A` is the area per site).

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    dictionary_parameters

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19).

    Examples
    --------
    >>> from hyperlattice.dictionary import green_prefactor
    >>> print(f"{green_prefactor(7, 3):.6f}")
    1.966750
    """
    return geometry.site_area(p, q) / hopping_scale(p, q)


def dictionary_parameters(omega, p=7, q=3) -> tuple[complex, float]:
    r"""The eigenvalue and prefactor of Eq. (19) for one lattice frequency.

    Parameters
    ----------
    omega : float or complex
        Lattice frequency :math:`\omega` in units of t (real or complex).
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    lam : complex
        :math:`\lambda = 4(\omega + q)/(q h^2)` (:func:`lambda_from_energy`).
    prefactor : float
        :math:`4\mathcal A/(q h^2)` (:func:`green_prefactor`).

    Raises
    ------
    ValueError
        If ``omega`` is not a finite number, or {p,q} is not a hyperbolic tessellation with
        finite p.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19).

    Examples
    --------
    >>> from hyperlattice.dictionary import dictionary_parameters
    >>> lam, pref = dictionary_parameters(-2.9)
    >>> print(f"{lam.real:.6f} {pref:.6f}")
    1.752900 1.966750
    """
    _validate.pq(p, q)  # a lattice's Green function: p finite
    om = _validate.complex_number("omega", omega)
    return complex(lambda_from_energy(om, p, q)), green_prefactor(p, q)


def disk_radius(sites, p=7, q=3) -> float:
    r"""The effective disk radius :math:`L = \sqrt{N/(N + \pi/\mathcal A)}` for N sites.

    Same as :func:`hyperlattice.geometry.effective_radius` (kept there for the geometry tables);
    ``sites`` is one positive integer here.

    Parameters
    ----------
    sites : int
        Number of lattice sites N (positive).
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        The Euclidean disk radius L in (0, 1).

    Raises
    ------
    ValueError
        If ``sites`` is not a positive integer, or {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    disk_radius_for_rings

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (10).

    Examples
    --------
    >>> from hyperlattice.dictionary import disk_radius
    >>> print(f"{disk_radius(35):.6f}")
    0.745356
    """
    p, q = _validate.pq(p, q)
    return geometry.effective_radius(_validate.positive_int("sites", sites), p, q)


def disk_radius_for_rings(rings, p=7, q=3) -> tuple[float, float]:
    r"""The disk radius ``(L, x_L)`` that stands for the ``rings``-ring {p,q} lattice.

    :math:`L = \sqrt{N/(N + c)}` (Eq. (10)) with the exact site count N and
    :math:`c = \pi/\mathcal A`, and :math:`x_L = (1 + L^2)/(1 - L^2) = (2N + c)/c` computed from
    N directly, which keeps full relative precision when :math:`1 - L \sim 10^{-9}` would lose
    digits in L itself. The site count is the graph side's combinatorics (counted, never built),
    so this is the one map from the graph to the continuum that needs it; it works up to
    :math:`N \approx 10^{308}`.

    Parameters
    ----------
    rings : int
        Number of rings l of the flake (ring 1 is the central p-gon).
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    L : float
        The Euclidean disk radius.
    x_L : float
        :math:`(1 + L^2)/(1 - L^2) = \cosh 2R`, R the geodesic radius.

    Raises
    ------
    ValueError
        If ``rings`` is not a positive integer, {p,q} is not a hyperbolic tessellation, or
        the site count overflows float64.

    See Also
    --------
    disk_radius, improved_disk_for_rings

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (10).

    Examples
    --------
    >>> from hyperlattice.dictionary import disk_radius_for_rings
    >>> L, x = disk_radius_for_rings(2, 7, 3)
    >>> print(f"{L:.6f} {x:.6f}")
    0.745356 3.500000
    """
    from .graph.lattice import site_count_float  # lazy: the continuum side imports this module

    p, q = _validate.pq(p, q)
    n_sites = site_count_float(p, q, rings)
    c = geometry.radius_constant(p, q)
    return math.sqrt(n_sites / (n_sites + c)), (2.0 * n_sites + c) / c


# ----------------------------------------------------------------------------
# magnetic flux f (quanta per p-gon face) <-> field B
# ----------------------------------------------------------------------------

def _face_area(p=7, q=3) -> float:
    r"""Hyperbolic area of one p-gon face in the paper's metric (curvature :math:`-4`):
    :math:`\frac14[(p-2)\pi - 2\pi p/q]` (Gauss-Bonnet: the curvature :math:`-1` area
    :math:`(p-2)\pi - p\cdot 2\pi/q` divided by 4); :math:`\pi/12` for {7,3}."""
    p, q = _validate.pq(p, q)
    return 0.25 * ((p - 2) * math.pi - 2.0 * math.pi * p / q)


def field_from_flux(f, p=7, q=3) -> float | np.ndarray:
    r"""Uniform field :math:`B = 2\pi f/\mathcal A_p` that puts ``f`` flux quanta through each p-gon face.

    :math:`\mathcal A_p = \frac14[(p-2)\pi - 2\pi p/q]` is the area of one p-gon face in the
    paper's metric (:math:`\pi/12` for {7,3}, so f = 1 gives B = 24); :math:`\hbar = e = 1`, one
    quantum is :math:`2\pi`; positive f and B point out of the disk (counterclockwise).

    Parameters
    ----------
    f : float or array_like of float
        Flux in flux quanta through one p-gon face.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float or ndarray of float
        The field B per unit area of the metric :math:`ds^2 = |dz|^2/(1-|z|^2)^2`.

    Raises
    ------
    ValueError
        If ``f`` is complex or not finite, {p,q} is not a hyperbolic tessellation, or the
        result overflows.

    See Also
    --------
    flux_from_field : the inverse map.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.field_from_flux(1.0, 7, 3):.6f}")
    24.000000
    """
    f = _value("f", f)
    if np.iscomplexobj(f):
        raise ValueError("the flux f must be real.")
    return 2.0 * math.pi * f / _face_area(p, q)


def flux_from_field(B, p=7, q=3) -> float | np.ndarray:
    r"""Inverse of :func:`field_from_flux`: :math:`f = B\mathcal A_p/(2\pi)`.

    Parameters
    ----------
    B : float or array_like of float
        Field per unit area of the paper's metric (:math:`\hbar = e = 1`).
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float or ndarray of float
        Flux f in flux quanta through one p-gon face.

    Raises
    ------
    ValueError
        If ``B`` is complex or not finite, or {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    field_from_flux

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.flux_from_field(24.0, 7, 3):.6f}")
    1.000000
    """
    B = _value("B", B)
    if np.iscomplexobj(B):
        raise ValueError("the field B must be real.")
    return B * _face_area(p, q) / (2.0 * math.pi)


# ----------------------------------------------------------------------------
# many-body dictionary, ``eq13``–``eq14``
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class ContinuumParameters(Result):
    r"""Parameters of ``eq14`` for a lattice model of ``eq13`` on {p,q}.

    ``field_scale`` is :math:`1/\sqrt{\mathcal A}`: :math:`\hat\alpha(z_i) = \hat a_i/\sqrt{\mathcal A}`
    (:math:`\sqrt{28/\pi}\,\hat a_i` for {7,3}).

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    t, mu, U : float
        The lattice hopping, chemical potential and on-site interaction (one energy unit, e.g. t).
    t_prime, mu_prime, U_prime : float
        The continuum ones, :math:`t' = \frac q4 h^2 t`, :math:`\mu' = \mu + qt`,
        :math:`U' = \mathcal A\,U`, in the same energy unit (:math:`U'` times an area of the
        paper's metric, since :math:`\hat\alpha` is a field per unit area).
    field_scale : float
        :math:`1/\sqrt{\mathcal A}`.
    h : float
        :math:`h = \tanh d_0`.
    site_area : float
        :math:`\mathcal A`, the hyperbolic area per site (paper's metric).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> c = hl.continuum_parameters(1.0, 0.0, 1.0, p=7, q=3)
    >>> print(f"{c.t_prime:.6f} {c.mu_prime:.6f} {c.U_prime:.6f} {c.field_scale:.6f}")
    0.057048 3.000000 0.112200 2.985411
    """

    p: int
    q: int
    t: float
    mu: float
    U: float
    t_prime: float
    mu_prime: float
    U_prime: float
    field_scale: float
    h: float
    site_area: float

    def summary(self) -> dict:
        """The JSON printed by ``hyperlattice dictionary``."""
        return {"p": self.p, "q": self.q,
                "lattice": {"t": self.t, "mu": self.mu, "U": self.U},
                "continuum": {"t_prime": self.t_prime, "mu_prime": self.mu_prime,
                              "U_prime": self.U_prime},
                "field_scale": self.field_scale, "h": self.h, "site_area": self.site_area}


def continuum_parameters(t: float, mu: float, U: float, p: int = 7, q: int = 3) -> ContinuumParameters:
    r"""Map the lattice Bose-Hubbard parameters to those of the continuum theory.

    The lattice model is Eq. (11),
    :math:`H = -t\sum_{\langle ij\rangle}(a_i^\dagger a_j + \mathrm{h.c.}) - \mu\sum_i n_i + \dots`, the
    continuum one Eq. (12). From :math:`A \approx q + \frac q4 h^2\Delta_g` (Eq. (8) generalised),
    :math:`\sum_i \to \frac1{\mathcal A}\int dV_g` (Eq. (9)) and
    :math:`\hat a_i = \sqrt{\mathcal A}\,\hat\alpha(z_i)`:

    .. math:: t' = \frac q4 h^2 t,\qquad \mu' = \mu + q t,\qquad U' = \mathcal A\, U,

    i.e. :math:`t' = \frac34 h^2 t`, :math:`\mu' = \mu + 3t`, :math:`U' = \frac{\pi}{28}U` for
    {7,3}. The hopping term :math:`-t\,a^\dagger A a` contributes :math:`-qt\,a^\dagger a`,
    which shifts the chemical potential; :math:`(a^\dagger a)^2 = \mathcal A^2(\alpha^\dagger\alpha)^2`
    and the measure :math:`1/\mathcal A` leave one factor :math:`\mathcal A` on U.

    Parameters
    ----------
    t : float
        Lattice hopping amplitude.
    mu : float
        Lattice chemical potential (same units as t).
    U : float
        Lattice on-site interaction (same units as t).
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    ContinuumParameters
        A frozen :class:`~hyperlattice.results.Result` with the lattice ``t``, ``mu``, ``U``, the
        continuum ``t_prime``, ``mu_prime``, ``U_prime``, ``field_scale``
        (:math:`1/\sqrt{\mathcal A}`), ``h`` and ``site_area``.

    Raises
    ------
    ValueError
        If a parameter is not a finite real number, {p,q} is not a hyperbolic tessellation,
        or a continuum parameter overflows.

    See Also
    --------
    lattice_parameters : the inverse map.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eqs. (8)-(12).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> c = hl.continuum_parameters(1.0, 0.0, 1.0, p=7, q=3)
    >>> print(f"{c.t_prime:.6f} {c.mu_prime:.6f} {c.U_prime:.6f}")
    0.057048 3.000000 0.112200
    """
    p, q = _validate.pq(p, q)
    t, mu, U = (_validate.real(name, v) for name, v in (("t", t), ("mu", mu), ("U", U)))
    area = geometry.site_area(p, q)
    values = {"t_prime": hopping_scale(p, q) * t, "mu_prime": mu + q * t, "U_prime": area * U}
    for name, v in values.items():
        if not math.isfinite(v):
            raise ValueError(f"the continuum {name} = {v} overflows: the lattice parameters are too large.")
    return ContinuumParameters(p=p, q=q, t=t, mu=mu, U=U, **values,
                               field_scale=1.0 / math.sqrt(area), h=geometry.lattice_h(p, q), site_area=area)


def lattice_parameters(t_prime: float, mu_prime: float, U_prime: float, p: int = 7,
                       q: int = 3) -> ContinuumParameters:
    r"""Inverse of :func:`continuum_parameters`: the lattice (t, mu, U) giving (t', mu', U').

    Parameters
    ----------
    t_prime : float
        Continuum hopping :math:`t'` (coefficient of :math:`-\Delta_g`).
    mu_prime : float
        Continuum chemical potential :math:`\mu'`.
    U_prime : float
        Continuum interaction :math:`U'`.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    ContinuumParameters
        The same result as ``continuum_parameters(t, mu, U, p, q)`` for the lattice parameters
        found (fields ``t``, ``mu``, ``U``, ``t_prime``, ``mu_prime``, ``U_prime``, ...).

    Raises
    ------
    ValueError
        If a parameter is not a finite real number, {p,q} is not a hyperbolic tessellation,
        or a lattice parameter overflows.

    See Also
    --------
    continuum_parameters

    Examples
    --------
    >>> import hyperlattice as hl
    >>> c = hl.lattice_parameters(0.057048, 3.0, 0.1122)
    >>> print(f"{c.t:.4f} {c.mu:.4f} {c.U:.4f}")
    1.0000 0.0000 1.0000
    """
    p, q = _validate.pq(p, q)
    tp, mp, up = (_validate.real(name, v)
                  for name, v in (("t_prime", t_prime), ("mu_prime", mu_prime), ("U_prime", U_prime)))
    t = tp / hopping_scale(p, q)
    values = {"t": t, "mu": mp - q * t, "U": up / geometry.site_area(p, q)}
    for name, v in values.items():
        if not math.isfinite(v):
            raise ValueError(f"the lattice {name} = {v} overflows: the continuum parameters are too large.")
    return continuum_parameters(values["t"], values["mu"], values["U"], p, q)


# ----------------------------------------------------------------------------
# the improved dictionary: the exact circle average of the star
# ----------------------------------------------------------------------------

#: The names accepted by every ``dictionary=`` keyword.
DICTIONARIES = ("paper", "improved")

#: Gauss-Legendre nodes on [0, 1] for the Mehler integral (more are used for large k)
_GL_BASE = 48


@functools.lru_cache(maxsize=32)
def _gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _check_dictionary(dictionary) -> str:
    return _validate.choice("dictionary", dictionary, DICTIONARIES)


def spherical_function(lam, d) -> float | np.ndarray:
    r"""The spherical function :math:`\varphi_\lambda(d) = P_\nu(\cosh 2d)` of :math:`-\Delta_g`.

    Eigenvalue :math:`\lambda = 1 + k^2`, :math:`\nu = \frac12(-1 + \mathrm i k)`, at geodesic
    distance :math:`d \ge 0` in the paper's metric (curvature -4).

    It is the radial eigenfunction with :math:`\varphi(0) = 1`, and the average of any
    eigenfunction over the geodesic circle of radius d about a point is :math:`\varphi_\lambda(d)`
    times its value there (mean-value property). Evaluated from Mehler's integral for the conical
    function (DLMF §14.20, :math:`t = 2d`, :math:`\tau = k/2`),

    .. math:: P_{-\frac12 + \mathrm i\tau}(\cosh t) = \frac{\sqrt2}{\pi}\int_0^t
              \frac{\cos \tau s}{\sqrt{\cosh t - \cosh s}}\,ds,

    with :math:`s = t(1 - w^2)`, which removes the endpoint singularity, and Gauss-Legendre
    quadrature in w (the integrand is then analytic; the node count grows with :math:`\tau t`).
    :math:`\lambda < 1` (imaginary :math:`\tau`) gives :math:`\cosh`.

    Parameters
    ----------
    lam : float or array_like of float
        Eigenvalue :math:`\lambda \ge 0` of :math:`-\Delta_g` (real only).
    d : float
        Geodesic distance, :math:`0 \le d \le 20`, in the paper's metric.

    Returns
    -------
    float or ndarray of float
        :math:`\varphi_\lambda(d)`, a float for scalar ``lam``.

    Raises
    ------
    ValueError
        If ``lam`` is negative or not finite, ``d`` is outside [0, 20], or ``lam`` is too large
        for the quadrature (more than 200 000 nodes).

    See Also
    --------
    spherical_mean_energy, hyperlattice.continuum.special.conical_p

    References
    ----------
    DLMF §14.20 (conical functions, Mehler's integral).

    Examples
    --------
    >>> from hyperlattice.dictionary import spherical_function
    >>> print(f"{spherical_function(1.0, 0.5):.6f}")
    0.940862
    >>> [round(float(v), 6) for v in spherical_function([0.0, 2.0], 0.3)]
    [1.0, 0.956153]
    """
    lam = _validate.real_array("lam", lam)
    if np.any(lam < 0):
        raise ValueError("the eigenvalue lam of -Delta_g must be >= 0.")
    d = _validate.real("d", d, minimum=0.0, maximum=20.0)
    t = 2.0 * d
    if t == 0.0:
        out = np.ones(lam.shape)
        return float(out) if out.ndim == 0 else out
    tau2 = (lam - 1.0) / 4.0                   # tau^2, negative below the continuum edge
    tau = np.sqrt(np.abs(tau2))
    n = _GL_BASE + int(2.0 * float(np.max(tau, initial=0.0)) * t)
    if n > 200_000:
        raise ValueError(f"lam = {float(np.max(lam)):.3g} is too large for the quadrature of the spherical function.")
    w, wt = _gauss_legendre(n)
    s = t * (1.0 - w * w)
    # cosh t - cosh s = 2 sinh((t+s)/2) sinh((t-s)/2); (t-s)/2 = t w^2/2: no cancellation near w = 0
    den = np.sqrt(2.0 * np.sinh(0.5 * (t + s)) * np.sinh(0.5 * t * w * w))
    with np.errstate(invalid="ignore", divide="ignore"):
        jac = np.where(w > 0, 2.0 * t * w / den, 2.0 * t / np.sqrt(np.sinh(t) * t))
    ts = np.multiply.outer(tau, s)
    kern = np.where(np.asarray(tau2)[..., None] >= 0, np.cos(ts), np.cosh(ts))
    out = math.sqrt(2.0) / math.pi * (kern * (jac * wt)).sum(axis=-1)
    return float(out) if out.ndim == 0 else out


def spherical_mean_energy(lam, q: int, h) -> float | np.ndarray:
    r"""The improved map at any star radius h.

    :math:`E = -q\,\varphi_\lambda(\operatorname{artanh} h) = -q P_\nu\bigl(\frac{1+h^2}{1-h^2}\bigr)`,
    the analogue of :func:`laplacian_coefficient`. Its expansion,
    :math:`-q + \frac q4 h^2\lambda + q(\frac\lambda8 - \frac{\lambda^2}{64})h^4 + O(h^6)`,
    starts with the paper's map (``spec2``); the tests check both orders.

    Parameters
    ----------
    lam : float or array_like of float
        Eigenvalue :math:`\lambda \ge 0` of :math:`-\Delta_g`.
    q : int
        Number of neighbours of the star, at least 3.
    h : float
        Euclidean radius of the star, :math:`0 \le h \le 0.999`.

    Returns
    -------
    float or ndarray of float
        The lattice energy E in units of t.

    Raises
    ------
    ValueError
        If ``q`` is not an integer of at least 3, ``h`` is outside [0, 0.999], or ``lam`` is
        invalid for :func:`spherical_function`.

    See Also
    --------
    improved_energy_from_lambda

    Examples
    --------
    >>> from hyperlattice.dictionary import spherical_mean_energy
    >>> print(f"{spherical_mean_energy(2.0, 3, 0.275798):.6f}")
    -2.882509
    """
    q = _validate.integer("q", q, minimum=3, maximum=_validate.PQ_MAX)
    h = _validate.real("h", h, minimum=0.0, maximum=0.999)
    return -q * spherical_function(lam, math.atanh(h))


def improved_energy_from_lambda(lam, p=7, q=3) -> float | np.ndarray:
    r"""Lattice energy of a continuum eigenvalue with the improved map :math:`E = -q\,\varphi_\lambda(d_0)`.

    See the module docstring for the derivation (the isotropic part of the star summed exactly).

    Parameters
    ----------
    lam : float or array_like of float
        Eigenvalue :math:`\lambda \ge 0` of :math:`-\Delta_g` (real).
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float or ndarray of float
        The energy E in units of t.

    Raises
    ------
    ValueError
        If ``lam`` is negative or not finite, or {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    energy_from_lambda : the paper's map.
    improved_lambda_from_energy : the inverse.

    Examples
    --------
    >>> from hyperlattice.dictionary import improved_energy_from_lambda
    >>> print(f"{improved_energy_from_lambda(2.0, 7, 3):.6f}")
    -2.882509
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    return -q * spherical_function(lam, geometry.d0(p, q))


def improved_energy_from_k(k, p=7, q=3) -> float | np.ndarray:
    r""":func:`improved_energy_from_lambda` at :math:`\lambda = 1 + k^2`.

    Parameters
    ----------
    k : float or array_like of float
        Real wave number k of the level.
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float or ndarray of float
        The energy E in units of t, a float for scalar ``k``.

    Raises
    ------
    ValueError
        If ``k`` is not real and finite, or {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    energy_from_k : the paper's map.

    Examples
    --------
    >>> from hyperlattice.dictionary import improved_energy_from_k
    >>> print(f"{improved_energy_from_k(1.0):.6f}")
    -2.882509
    """
    k = _validate.real_array("k", k)
    out = improved_energy_from_lambda(1.0 + k * k, p, q)
    return float(out) if np.ndim(out) == 0 else out


def improved_lambda_from_energy(energy, p=7, q=3) -> float:
    r"""Inverse of :func:`improved_energy_from_lambda` for one real energy.

    On the branch :math:`0 \le \lambda \le \lambda_*` where E rises monotonically
    (:math:`\lambda_*` is the first maximum of :math:`-\varphi_\lambda(d_0)`, beyond the first
    zero of the conical function).

    Parameters
    ----------
    energy : float
        Lattice energy E in units of t.
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        :math:`\lambda \ge 0` with ``improved_energy_from_lambda(lam) == energy``.

    Raises
    ------
    ValueError
        If ``energy`` is not a finite real number or lies outside the range of the improved
        map on that branch, or {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    lambda_from_energy : the paper's map.

    Examples
    --------
    >>> from hyperlattice.dictionary import improved_lambda_from_energy
    >>> print(f"{improved_lambda_from_energy(-2.9):.6f}")
    1.699711
    """
    from scipy.optimize import brentq

    p, q = _validate.pq(p, q, allow_infinite_p=True)
    e = _validate.real("energy", energy)
    d0 = geometry.d0(p, q)
    # the first maximum of -phi: its first zero is near tau t = j_{0,1}; scan a grid beyond it
    lam_hi = 1.0 + 4.0 * (3.9 / (2.0 * d0)) ** 2
    grid = np.linspace(0.0, lam_hi, 400)
    vals = -q * spherical_function(grid, d0)
    # steps within rounding of zero (at the maximum) count as not rising: the branch end does
    # not move with the last bits of the spherical function
    flat = np.diff(vals) <= monotone_tolerance(vals)
    top = int(np.argmax(flat)) if np.any(flat) else grid.size - 1
    lo, hi = float(vals[0]), float(vals[top])
    if not lo <= e <= hi:
        raise ValueError(f"the energy {e:g} is outside the range [{lo:.6g}, {hi:.6g}] of the improved map for "
                         f"{{{p},{q}}}.")
    if e == lo:
        return 0.0
    return float(brentq(lambda x: -q * spherical_function(x, d0) - e, 0.0, float(grid[top]), xtol=1e-14,
                        rtol=4 * np.finfo(float).eps))


def improved_lambda_of_frequency(omega, p=7, q=3) -> float:
    r"""The improved map's :math:`\lambda` of a real frequency, below the band (:math:`\lambda < 0`) included.

    The improved map :math:`\omega = -q\,\varphi_\lambda(d_0)` (module docstring) holds for any
    eigenfunction of :math:`-\Delta_g`, also for the growing ones of :math:`\lambda < 0` that the
    propagator below the band is made of. There :math:`\nu = -\frac12 + \frac12\sqrt{1-\lambda}`
    is real and :math:`\varphi_\lambda(d_0) = P_\nu(\cosh 2d_0) = {}_2F_1(-\nu, \nu+1; 1;
    (1 - \cosh 2d_0)/2)` (DLMF 14.3.1 with :math:`\mu = 0`), which rises monotonically as
    :math:`\lambda` falls; :math:`\lambda` is its root (real :math:`\nu` up to :math:`\lambda = 1`).
    Above the improved band bottom (:func:`improved_band_bottom`) this is
    :func:`improved_lambda_from_energy`. The paper's map :func:`lambda_from_energy` is the first
    order of the same expansion in :math:`h^2`; the difference of the two is the size of the
    neglected orders, i.e. of the lattice-spacing error of the dictionary at that frequency
    (:func:`hyperlattice.compare.boundary.boundary_correlator` uses it so).

    Parameters
    ----------
    omega : float
        Real frequency in units of t, with :math:`\lambda(\omega) \ge -10^6`.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        :math:`\lambda`, negative below the band bottom :math:`-q`.

    Raises
    ------
    ValueError
        If ``omega`` is not a finite real number, lies above the monotone branch of the improved
        map, or so far below the band that :math:`\lambda < -10^6`.

    See Also
    --------
    lambda_from_energy, improved_lambda_from_energy

    Examples
    --------
    >>> from hyperlattice.dictionary import improved_lambda_of_frequency, lambda_from_energy
    >>> print(f"{improved_lambda_of_frequency(-3.5):.4f} {lambda_from_energy(-3.5):.4f}")
    -8.0941 -8.7645
    """
    from scipy.optimize import brentq
    from scipy.special import hyp2f1

    p, q = _validate.pq(p, q)
    w = _validate.real("omega", omega)
    if w > improved_band_bottom(p, q):
        return improved_lambda_from_energy(w, p, q)
    x = (1.0 - math.cosh(2.0 * geometry.d0(p, q))) / 2.0

    def energy(lam: float) -> float:
        nu = -0.5 + 0.5 * math.sqrt(1.0 - lam)
        return -q * float(hyp2f1(-nu, nu + 1.0, 1.0, x))

    # nu is real for lambda <= 1 (up to the improved map's band bottom, where the Mehler form of
    # improved_lambda_from_energy takes over); the two forms agree there to rounding
    if energy(1.0) <= w:
        return 1.0
    lo = -1.0
    while energy(lo) > w:
        lo *= 2.0
        if lo < -1e6:
            raise ValueError(f"omega = {w:g} lies too far below the band for the improved map (lambda < -1e6).")
    return float(brentq(lambda lam: energy(lam) - w, lo, 1.0, xtol=1e-13, rtol=4 * np.finfo(float).eps))


def improved_band_bottom(p=7, q=3) -> float:
    r""":math:`E_\infty` of the improved map, :math:`-q\,\varphi_1(d_0) = -q P_{-1/2}(\cosh 2d_0)`.

    The :math:`k \to 0` limit (:math:`-2.940961` for {7,3}, against the paper's
    :math:`-3 + \frac34 h^2 = -2.942952`).

    Parameters
    ----------
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        The band bottom in units of t.

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    Examples
    --------
    >>> from hyperlattice.dictionary import improved_band_bottom
    >>> print(f"{improved_band_bottom(7, 3):.6f}")
    -2.940961
    """
    return float(improved_energy_from_lambda(1.0, p, q))


@functools.lru_cache(maxsize=64)
def _radius_shift(p: int, q: int) -> float:
    from .graph.lattice import ring_lattice, site_count  # lazy: the continuum side imports this module

    rings = 2
    while rings < 7 and site_count(p, q, rings + 2) <= 60_000:
        rings += 1
    lat = ring_lattice(p, q, rings + 1)
    a, b = lat.edges[:, 0], lat.edges[:, 1]
    ra, rb = lat.ring[a], lat.ring[b]
    inner = np.concatenate([a[(ra == rings) & (rb == rings + 1)], b[(rb == rings) & (ra == rings + 1)]])
    outer = np.concatenate([b[(ra == rings) & (rb == rings + 1)], a[(rb == rings) & (ra == rings + 1)]])
    radial = np.arctanh(np.abs(lat.z[outer])) - np.arctanh(np.abs(lat.z[inner]))
    return 0.5 * float(radial.mean())


def dirichlet_radius_shift(p=7, q=3) -> float:
    r"""How far the Dirichlet wall of a flake lies beyond its area radius, in geodesic distance.

    The area radius is that of Eq. (10); the shift is half the mean radial length
    :math:`d(0, z_{\rm out}) - d(0, z_{\rm in})` of the bonds from the outermost ring to the
    missing next ring (module docstring).

    Measured on the ring lattice (the graph side's geometry; the mean is the same for every outer
    ring to 1e-8 from ring 6 on, to 1e-4 from ring 3 on): 0.1353749 for {7,3}.

    Parameters
    ----------
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        The geodesic shift :math:`\delta > 0` (cached per {p,q}).

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation with finite p.

    See Also
    --------
    improved_disk_for_rings

    Examples
    --------
    >>> from hyperlattice.dictionary import dirichlet_radius_shift
    >>> print(f"{dirichlet_radius_shift(7, 3):.6f}")
    0.135375
    """
    p, q = _validate.pq(p, q)
    return _radius_shift(p, q)


def improved_disk_for_rings(rings, p=7, q=3) -> tuple[float, float]:
    r"""The Dirichlet disk ``(L, x_L)`` of the improved dictionary for an l-ring flake.

    The geodesic radius of :func:`disk_radius_for_rings` plus :func:`dirichlet_radius_shift`.
    With :math:`x_A = \cosh 2R_A` from the exact site count and :math:`\delta` the shift,
    :math:`x = x_A\cosh 2\delta + \sqrt{x_A^2 - 1}\,\sinh 2\delta` (no cancellation) and
    :math:`L = \tanh(R_A + \delta)`.

    Parameters
    ----------
    rings : int
        Number of rings l of the flake.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    L : float
        Euclidean radius of the Dirichlet disk.
    x_L : float
        :math:`(1 + L^2)/(1 - L^2)`.

    Raises
    ------
    ValueError
        If ``rings`` is not a positive integer, or {p,q} is not a hyperbolic tessellation.

    Examples
    --------
    >>> from hyperlattice.dictionary import improved_disk_for_rings
    >>> L, x = improved_disk_for_rings(2, 7, 3)
    >>> print(f"{L:.6f} {x:.6f}")
    0.799707 4.548328
    """
    _, xa = disk_radius_for_rings(rings, p, q)
    delta = dirichlet_radius_shift(p, q)
    x = xa * math.cosh(2.0 * delta) + math.sqrt((xa - 1.0) * (xa + 1.0)) * math.sinh(2.0 * delta)
    # L from x: L^2 = (x - 1)/(x + 1)
    return math.sqrt((x - 1.0) / (x + 1.0)), x


def map_energy_from_k(k, p=7, q=3, dictionary: str = "paper") -> float | np.ndarray:
    r"""Lattice energy of the Dirichlet level with :math:`-\Delta_g\psi = (1+k^2)\psi`, either dictionary.

    Parameters
    ----------
    k : float or array_like of float
        Wave number k of the level.
    p : int or float, optional
        Polygon size of the {p,q} lattice (default 7); ``math.inf`` for the limit
        :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    dictionary : {'paper', 'improved'}, optional
        ``"paper"`` (default) uses :func:`energy_from_k`; ``"improved"`` uses
        :func:`improved_energy_from_k`.

    Returns
    -------
    float or ndarray of float
        The energy E in units of t.

    Raises
    ------
    ValueError
        If ``dictionary`` is not one of ``DICTIONARIES``, or the chosen map refuses its input.

    Examples
    --------
    >>> from hyperlattice.dictionary import map_energy_from_k
    >>> print(f"{float(map_energy_from_k(1.0)):.6f}")
    -2.885903
    >>> print(f"{float(map_energy_from_k(1.0, dictionary='improved')):.6f}")
    -2.882509
    """
    if _check_dictionary(dictionary) == "paper":
        return energy_from_k(k, p, q)
    return improved_energy_from_k(k, p, q)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

# and every map's result is finite, or a sentence says why not (f = 1e308 used to give B = inf)
_guard_public(globals(), finite=True)
