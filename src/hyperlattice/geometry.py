r"""Geometry of the Poincaré disk and the constants of regular {p,q} tessellations.

Conventions (Boettcher et al., PRA 102, 032208, ``eq3``): the metric is

.. math:: ds^2 = \frac{dx^2 + dy^2}{(1-|z|^2)^2},

i.e. Gaussian curvature :math:`K=-4`. Distances are therefore half the usual
curvature :math:`-1` distances, the point at distance :math:`d` from the origin
has radius :math:`\tanh d`, and a geodesic polygon with :math:`n` vertices and
interior angles :math:`\gamma_j` has area :math:`[(n-2)\pi - \sum_j\gamma_j]/4`.

Everything here is a pure function of numbers or complex numpy arrays. The public functions
check their input through :mod:`hyperlattice._validate` (points must lie in the open disk);
the lattice builder calls the unchecked kernels ``_rotate_about`` and ``_geodesic_point``
on coordinates it made itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _validate
from .results import Result

__all__ = [
    "distance",
    "one_minus_abs2",
    "mobius",
    "mobius_inverse",
    "rotate_about",
    "geodesic_point",
    "midpoint",
    "TilingConstants",
    "tiling_constants",
    "r0",
    "d0",
    "lattice_h",
    "site_area",
    "radius_constant",
    "effective_radius",
    "counting_slope",
    "rho",
]


# ----------------------------------------------------------------------------
# maps and distances
# ----------------------------------------------------------------------------

def _two_prod(a, b):
    """Error-free product (Dekker): a*b = p + e exactly."""
    p = a * b
    c = 134217729.0 * a
    ahi = c - (c - a)
    alo = a - ahi
    c = 134217729.0 * b
    bhi = c - (c - b)
    blo = b - bhi
    e = ((ahi * bhi - p) + ahi * blo + alo * bhi) + alo * blo
    return p, e


def _two_sum(a, b):
    """Error-free sum (Knuth): a+b = s + e exactly."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


def one_minus_abs2(z) -> np.ndarray | float:
    r""":math:`1-|z|^2` to full relative accuracy, also for :math:`|z| \to 1`.

    The coordinates are exact binary numbers, so the only loss is cancellation in
    :math:`1 - x^2 - y^2`; compensated (double-double) arithmetic removes it. This is
    what keeps hyperbolic distances accurate near the boundary of large lattices.

    Parameters
    ----------
    z : complex or array_like of complex
        Any finite complex number or array (a point need not lie in the disk).

    Returns
    -------
    float or ndarray of float
        :math:`1-|z|^2`, same shape as ``z``; negative outside the unit disk.

    Raises
    ------
    ValueError
        If ``z`` is not numeric or contains NaN or infinite values.

    See Also
    --------
    distance : uses this for points near the boundary.

    Examples
    --------
    >>> from hyperlattice.geometry import one_minus_abs2
    >>> print(f"{float(one_minus_abs2(0.6)):.6f}")
    0.640000
    >>> print(f"{float(one_minus_abs2(0.6 + 0.799999j)):.6e}")
    1.599999e-06
    """
    return _one_minus_abs2(_validate.complex_array("z", z))


def _one_minus_abs2(z: np.ndarray) -> np.ndarray:
    x, y = z.real, z.imag
    x2, ex = _two_prod(x, x)
    y2, ey = _two_prod(y, y)
    s1, e1 = _two_sum(1.0, -x2)
    s2, e2 = _two_sum(s1, -y2)
    return s2 + ((e1 + e2) - (ex + ey))


def distance(z1, z2, *, check: bool = True) -> np.ndarray | float:
    r"""Hyperbolic distance between points of the Poincaré disk.

    Implements the paper's Eq. (3),

    .. math:: d(z,z') = \tfrac12\,\mathrm{arcosh}\Bigl(1 + \frac{2|z-z'|^2}{(1-|z|^2)(1-|z'|^2)}\Bigr),

    the distance of the metric :math:`ds^2 = (dx^2+dy^2)/(1-|z|^2)^2` (curvature -4), so a point
    at distance :math:`d` from the origin has radius :math:`\tanh d`. Evaluated in the equivalent
    form :math:`d = \mathrm{arcsinh}\bigl(|z-z'|/\sqrt{(1-|z|^2)(1-|z'|^2)}\bigr)`, which keeps
    full relative accuracy for nearby points (no ``arcosh`` near 1) and, with
    :func:`one_minus_abs2`, near the boundary :math:`|z| \to 1`.

    Parameters
    ----------
    z1, z2 : complex or array_like of complex
        Points of the open unit disk :math:`|z| < 1`; they broadcast against each other.
    check : bool, optional
        If True (default), check that the points are numeric and lie in the open disk.
        ``check=False`` skips the check (for points known to lie in the disk).

    Returns
    -------
    float or ndarray of float
        The hyperbolic distance :math:`d(z_1, z_2) \ge 0` in the paper's metric, with the
        broadcast shape of ``z1`` and ``z2``.

    Raises
    ------
    ValueError
        If ``check`` is True and a point is not a finite complex number or lies on or outside
        the unit circle, or if ``check`` is not True or False.

    See Also
    --------
    d0 : the edge length of a {p,q} lattice in this metric.
    mobius : the isometries that preserve this distance.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (3).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{float(hl.distance(0, 0.5)):.6f}")
    0.549306
    >>> print(f"{float(hl.distance(0.1 + 0.2j, -0.3j)):.6f}")
    0.524085
    """
    if check:
        z1 = _validate.disk_points("z1", z1)
        z2 = _validate.disk_points("z2", z2)
    else:
        z1 = np.asarray(z1, dtype=complex)
        z2 = np.asarray(z2, dtype=complex)
    s1 = _one_minus_abs2(z1)
    s2 = _one_minus_abs2(z2)
    # cosh(2d) - 1 = 2 sinh(d)^2 = 2|z-z'|^2 / (s1 s2)  =>  d = arcsinh(|z-z'| / sqrt(s1 s2))
    return np.arcsinh(np.abs(z1 - z2) / np.sqrt(s1 * s2))


def mobius(z, a, eta: float = 0.0) -> np.ndarray | complex:
    r"""The disk automorphism :math:`w(z) = e^{i\eta}(a - z)/(1 - z\bar a)`.

    This is the paper's Eq. (4), an isometry of the Poincaré disk. It exchanges ``a`` and the
    origin (for ``eta = 0`` it is an involution).

    Parameters
    ----------
    z : complex or array_like of complex
        Points of the open unit disk to map.
    a : complex or array_like of complex
        The point of the open unit disk that is sent to the origin; broadcasts against ``z``.
    eta : float, optional
        Rotation angle :math:`\eta` in radians applied after the exchange (default 0).

    Returns
    -------
    complex or ndarray of complex
        The images :math:`w(z)`, points of the open unit disk.

    Raises
    ------
    ValueError
        If a point lies on or outside the unit circle or is not a finite number, or if ``eta``
        is not a finite real number.

    See Also
    --------
    mobius_inverse : the inverse map.
    distance : invariant under this map.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (4).

    Examples
    --------
    >>> from hyperlattice.geometry import mobius
    >>> complex(mobius(0.5, 0.5))
    0j
    >>> w = mobius(0.3 + 0.1j, 0.5)
    >>> print(round(w.real, 6), round(w.imag, 6))
    0.241379 -0.103448
    """
    z = _validate.disk_points("z", z)
    a = _validate.disk_points("a", a)
    eta = _validate.real("eta", eta)
    return np.exp(1j * eta) * (a - z) / (1.0 - z * np.conj(a))


def mobius_inverse(w, a, eta: float = 0.0) -> np.ndarray | complex:
    r"""Inverse of :func:`mobius`: the point z with ``mobius(z, a, eta) == w``.

    Parameters
    ----------
    w : complex or array_like of complex
        Image points in the open unit disk.
    a : complex or array_like of complex
        The same point of the open unit disk as given to :func:`mobius`.
    eta : float, optional
        The same rotation angle in radians as given to :func:`mobius` (default 0).

    Returns
    -------
    complex or ndarray of complex
        The preimages z, points of the open unit disk.

    Raises
    ------
    ValueError
        If a point lies on or outside the unit circle or is not a finite number, or if ``eta``
        is not a finite real number.

    See Also
    --------
    mobius

    Examples
    --------
    >>> from hyperlattice.geometry import mobius, mobius_inverse
    >>> z = mobius_inverse(mobius(0.3 + 0.1j, 0.5, 1.0), 0.5, 1.0)
    >>> print(round(z.real, 6), round(z.imag, 6))
    0.3 0.1
    """
    w = _validate.disk_points("w", w) * np.exp(-1j * _validate.real("eta", eta))
    a = _validate.disk_points("a", a)
    return (a - w) / (1.0 - w * np.conj(a))


def rotate_about(z, center, angle) -> np.ndarray | complex:
    r"""Rotate ``z`` about ``center`` by ``angle``, a hyperbolic isometry.

    Parameters
    ----------
    z : complex or array_like of complex
        Points of the open unit disk to rotate.
    center : complex or array_like of complex
        Centre of the rotation, a point of the open unit disk.
    angle : float or array_like of float
        Rotation angle in radians, counterclockwise; ``z``, ``center`` and ``angle`` broadcast.

    Returns
    -------
    complex or ndarray of complex
        The rotated points; ``center`` itself is fixed and distances to it are preserved.

    Raises
    ------
    ValueError
        If a point lies on or outside the unit circle, or an input is not a finite number.

    Examples
    --------
    >>> from hyperlattice.geometry import rotate_about
    >>> import math
    >>> w = rotate_about(0.5, 0.0, math.pi / 2)
    >>> print(round(w.real, 6), round(w.imag, 6))
    0.0 0.5
    """
    return _rotate_about(_validate.disk_points("z", z), _validate.disk_points("center", center),
                         _validate.real_array("angle", angle))


def _rotate_about(z, center, angle):
    z = np.asarray(z, dtype=complex)
    c = np.asarray(center, dtype=complex)
    cc = np.conj(c)
    w = (z - c) / (1.0 - cc * z) * np.exp(1j * np.asarray(angle))
    return (w + c) / (1.0 + cc * w)


def geodesic_point(z1, z2, t) -> np.ndarray | complex:
    r"""Point at fraction ``t`` of the hyperbolic distance along the geodesic from z1 to z2.

    Parameters
    ----------
    z1, z2 : complex or array_like of complex
        End points of the geodesic segment, in the open unit disk.
    t : float or array_like of float
        Fraction of the hyperbolic distance :math:`d(z_1, z_2)`: 0 gives ``z1``, 1 gives ``z2``;
        values outside [0, 1] continue the geodesic. Arrays broadcast.

    Returns
    -------
    complex or ndarray of complex
        The point :math:`z` on the geodesic with :math:`d(z_1, z) = t\,d(z_1, z_2)`.

    Raises
    ------
    ValueError
        If a point lies on or outside the unit circle, or an input is not a finite number.

    See Also
    --------
    midpoint : ``t = 0.5``.

    Examples
    --------
    >>> from hyperlattice.geometry import geodesic_point
    >>> z = geodesic_point(0, 0.5, 0.5)
    >>> print(f"{z.real:.6f}")
    0.267949
    """
    return _geodesic_point(_validate.disk_points("z1", z1), _validate.disk_points("z2", z2),
                           _validate.real_array("t", t))


def _geodesic_point(z1, z2, t):
    z1 = np.asarray(z1, dtype=complex)
    z2 = np.asarray(z2, dtype=complex)
    c1 = np.conj(z1)
    w = (z2 - z1) / (1.0 - c1 * z2)  # z1 -> 0
    aw = np.abs(w)
    t = np.asarray(t, dtype=float)
    # scale factor tanh(t*artanh|w|)/|w|, which tends to t for |w| -> 0 (also for denormals)
    tiny = aw < 1e-150
    safe = np.where(tiny, 1.0, aw)
    factor = np.where(tiny, t, np.tanh(t * np.arctanh(np.where(tiny, 0.5, aw))) / safe)
    u = w * factor
    return (u + z1) / (1.0 + c1 * u)


def midpoint(z1, z2) -> np.ndarray | complex:
    r"""Hyperbolic midpoint of the geodesic segment between z1 and z2.

    Parameters
    ----------
    z1, z2 : complex or array_like of complex
        End points in the open unit disk; arrays broadcast.

    Returns
    -------
    complex or ndarray of complex
        The point at equal hyperbolic distance from ``z1`` and ``z2`` on their geodesic.

    Raises
    ------
    ValueError
        If a point lies on or outside the unit circle or is not a finite number.

    See Also
    --------
    geodesic_point

    Examples
    --------
    >>> from hyperlattice.geometry import midpoint
    >>> complex(midpoint(-0.5, 0.5))
    0j
    """
    return geodesic_point(z1, z2, 0.5)


def _midpoint(z1, z2):
    return _geodesic_point(z1, z2, 0.5)


def rho(r) -> np.ndarray | float:
    r"""The hyperbolic invariant :math:`\rho = (1+r^2)/(1-r^2) = \cosh 2d(r,0)`.

    Parameters
    ----------
    r : float or array_like of float
        Euclidean radius (or radii) in the disk, :math:`|r| < 1`.

    Returns
    -------
    float or ndarray of float
        :math:`\rho \ge 1`, same shape as ``r``.

    Raises
    ------
    ValueError
        If ``r`` is not a finite real number or array, or :math:`|r| \ge 1`.

    See Also
    --------
    counting_slope : the site count is linear in :math:`\rho`.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix D (the equation labelled ``sum3``).

    Examples
    --------
    >>> from hyperlattice.geometry import rho
    >>> print(f"{float(rho(0.5)):.6f}")
    1.666667
    """
    r = _validate.real_array("r", r)
    if np.any(np.abs(r) >= 1.0):
        raise ValueError(f"r must lie in -1 < r < 1 (a radius in the disk); the largest |r| is "
                         f"{float(np.max(np.abs(r))):.6g}.")
    return (1.0 + r * r) / ((1.0 - r) * (1.0 + r))


# ----------------------------------------------------------------------------
# {p,q} constants
# ----------------------------------------------------------------------------

def r0(p, q=3) -> float:
    r"""Euclidean radius of the vertices of the central p-gon of {p,q}.

    .. math:: r_0 = \sqrt{\frac{\cos(\pi/q+\pi/p)}{\cos(\pi/p-\pi/q)}},

    and 1 for p = inf. Site 0 of a flake lies at :math:`z = r_0`.

    Parameters
    ----------
    p : int or float
        Polygon size; ``math.inf`` for the limit :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        :math:`r_0` in (0, 1].

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix A (the equation labelled ``Eqr0``).

    Examples
    --------
    >>> from hyperlattice.geometry import r0
    >>> print(f"{r0(7, 3):.6f}")
    0.300743
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    if math.isinf(p):
        return 1.0
    return math.sqrt(math.cos(math.pi / q + math.pi / p) / math.cos(math.pi / p - math.pi / q))


def d0(p, q=3) -> float:
    r"""Hyperbolic edge length of {p,q} in the paper's metric.

    Closed form from the right triangle (polygon centre, vertex, edge midpoint) with
    angles :math:`\pi/p, \pi/q, \pi/2`: the half edge in curvature -1 satisfies
    :math:`\cosh a = \cos(\pi/p)/\sin(\pi/q)`, and since the paper's distances are half
    the curvature -1 ones, :math:`d_0 = a`. This equals :math:`d(r_0, r_0 e^{2\pi i/p})`
    (checked in the tests) and has the finite limit
    :math:`\tfrac12\mathrm{arcosh}(1 + 2\cot^2(\pi/q))` for p -> inf
    (:math:`\tfrac12\ln 3 = 0.549306` for q = 3).

    Parameters
    ----------
    p : int or float
        Polygon size; ``math.inf`` for the limit :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        :math:`d_0 > 0` (0.283128 for {7,3}).

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    lattice_h : :math:`h = \tanh d_0`.

    Examples
    --------
    >>> import math
    >>> from hyperlattice.geometry import d0
    >>> print(f"{d0(7, 3):.6f}")
    0.283128
    >>> print(f"{d0(math.inf):.6f}")
    0.549306
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    cp = 1.0 if math.isinf(p) else math.cos(math.pi / p)
    return math.acosh(cp / math.sin(math.pi / q))


def lattice_h(p, q=3) -> float:
    r"""The lattice parameter :math:`h = \tanh d_0 = \sqrt{1 - \sin^2(\pi/q)/\cos^2(\pi/p)}`.

    It is also the Euclidean distance from the origin of a neighbour of a site
    mapped to the origin. Limit p -> inf: :math:`\cos(\pi/q)` (1/2 for q = 3).

    Parameters
    ----------
    p : int or float
        Polygon size; ``math.inf`` for the limit :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        :math:`h` in (0, 1) (0.275798 for {7,3}).

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    d0, tiling_constants

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix B (the equation labelled ``adj6``).

    Examples
    --------
    >>> import math
    >>> import hyperlattice as hl
    >>> print(f"{hl.lattice_h(7, 3):.6f}")
    0.275798
    >>> print(f"{hl.lattice_h(math.inf, 3):.6f}")
    0.500000
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    cp = 1.0 if math.isinf(p) else math.cos(math.pi / p)
    s = math.sin(math.pi / q) / cp
    return math.sqrt((1.0 - s) * (1.0 + s))


def site_area(p, q=3) -> float:
    r"""Hyperbolic area per lattice site, :math:`\mathcal A = \frac{\pi}{4p}(pq-2p-2q)`.

    Each site of {p,q} is the centre of a face of the dual tessellation {q,p}: a
    regular q-gon with interior angles :math:`2\pi/p`, whose area in curvature -4 is
    :math:`[(q-2)\pi - 2\pi q/p]/4`. For q = 3 this is the paper's
    :math:`\frac{\pi}{4}(1-6/p)` (:math:`\pi/28` for {7,3}). Limit p -> inf:
    :math:`\pi(q-2)/4`.

    Parameters
    ----------
    p : int or float
        Polygon size; ``math.inf`` for the limit :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        :math:`\mathcal A > 0`, in units of the metric :math:`ds^2 = |dz|^2/(1-|z|^2)^2`.

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix D (the equation labelled ``sum1c``).

    Examples
    --------
    >>> import math
    >>> from hyperlattice.geometry import site_area
    >>> print(f"{site_area(7, 3):.6f}", f"{math.pi / 28:.6f}")
    0.112200 0.112200
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    if math.isinf(p):
        return math.pi * (q - 2) / 4.0
    return math.pi * (p * q - 2 * p - 2 * q) / (4.0 * p)


def radius_constant(p, q=3) -> float:
    r"""The constant :math:`c = \pi/\mathcal A = 4p/(pq-2p-2q)` in :math:`L = \sqrt{N/(N+c)}`.

    Derivation (Eq. (9) with f = 1): :math:`N = \frac{1}{\mathcal A}\frac{\pi L^2}{1-L^2}`,
    hence :math:`L^2 = N/(N+\pi/\mathcal A)`. For {p,3}: :math:`4p/(p-6)`, i.e. 28 for {7,3}.

    Parameters
    ----------
    p : int or float
        Polygon size; ``math.inf`` for the limit :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        :math:`c > 0`.

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    effective_radius, site_area

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eqs. (9) and (10).

    Examples
    --------
    >>> from hyperlattice.geometry import radius_constant
    >>> print(f"{radius_constant(7, 3):.6f}")
    28.000000
    """
    return math.pi / site_area(p, q)


def counting_slope(p, q=3) -> float:
    r"""Slope of the counting function :math:`\mathcal N(r) \approx s\rho + b`.

    From :math:`\mathcal N(r) = \frac{\pi}{\mathcal A}\frac{r^2}{1-r^2} = \frac{c}{2}(\rho-1)`:
    :math:`s = c/2 = 2p/(pq-2p-2q)` (14 for {7,3}).

    Parameters
    ----------
    p : int or float
        Polygon size; ``math.inf`` for the limit :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        The slope :math:`s` (sites per unit of :math:`\rho`).

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    See Also
    --------
    rho, radius_constant

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix D (the equation labelled ``sum4``).

    Examples
    --------
    >>> from hyperlattice.geometry import counting_slope
    >>> print(f"{counting_slope(7, 3):.6f}")
    14.000000
    """
    return radius_constant(p, q) / 2.0


def effective_radius(sites, p=7, q=3) -> float | np.ndarray:
    r"""Effective disk radius :math:`L = \sqrt{N/(N + c_{pq})}` of a flake with N sites.

    This is the paper's Eq. (10) with 28 replaced by :math:`c_{pq} = \pi/\mathcal A`
    (:func:`radius_constant`): the Euclidean radius of the disk whose hyperbolic area is N site
    areas.

    Parameters
    ----------
    sites : float or array_like of float
        Number of sites N (positive; an array gives one radius per entry).
    p : int, optional
        Polygon size (default 7); finite, since {p,q} is a lattice's symbol here.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float or ndarray of float
        The radius :math:`L` in (0, 1): a float for a scalar ``sites``, else an array.

    Raises
    ------
    ValueError
        If a number of sites is not positive or not finite, or {p,q} is not a hyperbolic
        tessellation.

    See Also
    --------
    radius_constant, hyperlattice.dictionary.disk_radius

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (10).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.effective_radius(35, 7, 3):.6f}")
    0.745356
    >>> [round(float(L), 6) for L in hl.effective_radius([7, 35])]
    [0.447214, 0.745356]
    """
    p, q = _validate.pq(p, q)
    n = _validate.real_array("the number of sites", sites)
    if np.any(n <= 0):
        raise ValueError("the number of sites must be positive.")
    c = radius_constant(p, q)
    out = np.sqrt(n / (n + c))
    return float(out) if out.ndim == 0 else out


@dataclass(frozen=True, eq=False, kw_only=True)
class TilingConstants(Result):
    r"""The geometric constants of a {p,q} tessellation in the paper's metric (a :class:`Result`).

    Attributes
    ----------
    p : int or float
        Polygon size (``math.inf`` for the limit p -> inf).
    q : int
        Coordination number.
    r0, d0, h, site_area, radius_constant : float
        :func:`r0`, :func:`d0`, :func:`lattice_h`, :func:`site_area`, :func:`radius_constant`:
        the Euclidean radius of the central p-gon's vertices in the Poincaré disk, the
        hyperbolic edge length and :math:`h = \tanh d_0`, the hyperbolic area per site (metric
        :math:`|dz|^2/(1-|z|^2)^2`, curvature -4), and :math:`c = \pi/\mathcal A` of
        :math:`L = \sqrt{N/(N+c)}`.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> c = hl.tiling_constants(7, 3)
    >>> round(c.r0, 6), round(c.d0, 6), round(c.h, 6)
    (0.300743, 0.283128, 0.275798)
    >>> round(c.site_area, 6), round(c.radius_constant, 6)     # pi/28 and 28
    (0.1122, 28.0)
    """

    p: float | int
    q: int
    r0: float
    d0: float
    h: float
    site_area: float
    radius_constant: float

    def summary(self) -> dict:
        """The CLI's JSON row: p (``"inf"`` for the limit), q, r0, d0, h, site_area."""
        p = "inf" if isinstance(self.p, float) and math.isinf(self.p) else self.p
        return {"p": p, "q": self.q, "r0": self.r0, "d0": self.d0, "h": self.h,
                "site_area": self.site_area}


def tiling_constants(p, q=3) -> TilingConstants:
    r"""All geometric constants of {p,q} at once.

    Parameters
    ----------
    p : int or float
        Polygon size; ``math.inf`` for the limit :math:`p \to \infty`.
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    TilingConstants
        A frozen :class:`~hyperlattice.results.Result` with fields ``p``, ``q``, ``r0``,
        ``d0``, ``h``, ``site_area`` and ``radius_constant`` (see :func:`r0`, :func:`d0`,
        :func:`lattice_h`, :func:`site_area`, :func:`radius_constant`).

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> c = hl.tiling_constants(7, 3)
    >>> print(f"{c.d0:.6f} {c.h:.6f} {c.radius_constant:.1f}")
    0.283128 0.275798 28.0
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    return TilingConstants(p=p, q=q, r0=r0(p, q), d0=d0(p, q), h=lattice_h(p, q),
                           site_area=site_area(p, q), radius_constant=radius_constant(p, q))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

# the {p,q} constants and the effective radius: a finite result, or a sentence
_guard_public(globals(), finite=("r0", "d0", "lattice_h", "site_area", "radius_constant", "counting_slope",
                                 "effective_radius"))
