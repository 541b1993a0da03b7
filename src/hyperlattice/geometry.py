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
    ``z`` may be any finite complex number or array (outside the disk the result is negative).
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
    r"""Hyperbolic distance of ``eq4``,

    .. math:: d(z,z') = \tfrac12\,\mathrm{arcosh}\Bigl(1 + \frac{2|z-z'|^2}{(1-|z|^2)(1-|z'|^2)}\Bigr).

    Evaluated in the equivalent form
    :math:`d = \mathrm{arcsinh}\bigl(|z-z'|/\sqrt{(1-|z|^2)(1-|z'|^2)}\bigr)`, which keeps
    full relative accuracy for nearby points (no ``arcosh`` near 1) and, with
    :func:`one_minus_abs2`, near the boundary ``|z| -> 1``. Broadcasts over numpy arrays.

    ``check=False`` skips the input check (points known to lie in the open disk).
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
    r"""The disk automorphism of ``eq5``, :math:`w(z) = e^{i\eta}(a - z)/(1 - z\bar a)`.

    It exchanges ``a`` and the origin (for ``eta = 0`` it is an involution). ``z`` and ``a``
    lie in the open unit disk; ``eta`` is a real angle.
    """
    z = _validate.disk_points("z", z)
    a = _validate.disk_points("a", a)
    eta = _validate.real("eta", eta)
    return np.exp(1j * eta) * (a - z) / (1.0 - z * np.conj(a))


def mobius_inverse(w, a, eta: float = 0.0) -> np.ndarray | complex:
    """Inverse of :func:`mobius`: returns z with ``mobius(z, a, eta) == w``."""
    w = _validate.disk_points("w", w) * np.exp(-1j * _validate.real("eta", eta))
    a = _validate.disk_points("a", a)
    return (a - w) / (1.0 - w * np.conj(a))


def rotate_about(z, center, angle) -> np.ndarray | complex:
    """Rotate ``z`` about ``center`` by ``angle`` (counterclockwise, hyperbolic isometry).

    ``z`` and ``center`` lie in the open unit disk; ``angle`` is real (arrays broadcast).
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
    """Point at fraction ``t`` of the hyperbolic distance along the geodesic from z1 to z2.

    ``z1`` and ``z2`` lie in the open unit disk; ``t`` is real (0 gives z1, 1 gives z2;
    values outside [0, 1] continue the geodesic). Arrays broadcast.
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
    """Hyperbolic midpoint of the geodesic segment between z1 and z2 (points of the open disk)."""
    return geodesic_point(z1, z2, 0.5)


def _midpoint(z1, z2):
    return _geodesic_point(z1, z2, 0.5)


def rho(r) -> np.ndarray | float:
    r"""The hyperbolic invariant :math:`\rho = (1+r^2)/(1-r^2) = \cosh 2d(r,0)` of ``sum3``.

    ``r`` is a real radius (or array of radii) with :math:`|r| < 1`.
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
    r"""Euclidean radius of the central p-gon's vertices, ``Eqr0``:
    :math:`r_0 = \sqrt{\cos(\pi/q+\pi/p)/\cos(\pi/p-\pi/q)}` (1 for p = inf)."""
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
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    cp = 1.0 if math.isinf(p) else math.cos(math.pi / p)
    return math.acosh(cp / math.sin(math.pi / q))


def lattice_h(p, q=3) -> float:
    r""":math:`h = \tanh d_0 = \sqrt{1 - \sin^2(\pi/q)/\cos^2(\pi/p)}`, ``adj6``.

    It is also the Euclidean distance from the origin of a neighbour of a site
    mapped to the origin. Limit p -> inf: :math:`\cos(\pi/q)` (1/2 for q = 3).
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    cp = 1.0 if math.isinf(p) else math.cos(math.pi / p)
    s = math.sin(math.pi / q) / cp
    return math.sqrt((1.0 - s) * (1.0 + s))


def site_area(p, q=3) -> float:
    r"""Hyperbolic area per lattice site, :math:`\mathcal A = \frac{\pi}{4p}(pq-2p-2q)`.

    Each site of {p,q} is the centre of a face of the dual tessellation {q,p}: a
    regular q-gon with interior angles :math:`2\pi/p`, whose area in curvature -4 is
    :math:`[(q-2)\pi - 2\pi q/p]/4`. For q = 3 this is ``sum1c``,
    :math:`\frac{\pi}{4}(1-6/p)` (:math:`\pi/28` for {7,3}). Limit p -> inf:
    :math:`\pi(q-2)/4`.
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    if math.isinf(p):
        return math.pi * (q - 2) / 4.0
    return math.pi * (p * q - 2 * p - 2 * q) / (4.0 * p)


def radius_constant(p, q=3) -> float:
    r"""The constant :math:`c = \pi/\mathcal A = 4p/(pq-2p-2q)` in :math:`L = \sqrt{N/(N+c)}`.

    Derivation (``eq11`` with f = 1): :math:`N = \frac{1}{\mathcal A}\frac{\pi L^2}{1-L^2}`,
    hence :math:`L^2 = N/(N+\pi/\mathcal A)`. For {p,3}: :math:`4p/(p-6)`, i.e. 28 for {7,3}.
    """
    return math.pi / site_area(p, q)


def counting_slope(p, q=3) -> float:
    r"""Slope of the counting function :math:`\mathcal N(r) \approx s\rho + b`, ``sum4``.

    From :math:`\mathcal N(r) = \frac{\pi}{\mathcal A}\frac{r^2}{1-r^2} = \frac{c}{2}(\rho-1)`:
    :math:`s = c/2 = 2p/(pq-2p-2q)` (14 for {7,3})."""
    return radius_constant(p, q) / 2.0


def effective_radius(sites, p=7, q=3) -> float | np.ndarray:
    r"""Effective disk radius of ``eq12``, :math:`L = \sqrt{N/(N + c_{pq})}`.

    ``sites`` (N) may be a positive number or an array of them; :math:`c_{pq}` is
    :func:`radius_constant`. {p,q} is a lattice's symbol, so p is finite here.
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
    """The geometric constants of a {p,q} tessellation in the paper's metric (a :class:`Result`).

    Attributes
    ----------
    p : int or float
        Polygon size (``math.inf`` for the limit p -> inf).
    q : int
        Coordination number.
    r0, d0, h, site_area, radius_constant : float
        :func:`r0`, :func:`d0`, :func:`lattice_h`, :func:`site_area`, :func:`radius_constant`.
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
    """All constants of {p,q} at once (p may be ``math.inf``)."""
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    return TilingConstants(p=p, q=q, r0=r0(p, q), d0=d0(p, q), h=lattice_h(p, q),
                           site_area=site_area(p, q), radius_constant=radius_constant(p, q))


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

# the {p,q} constants and the effective radius: a finite result, or a sentence
_guard_public(globals(), finite=("r0", "d0", "lattice_h", "site_area", "radius_constant", "counting_slope",
                                 "effective_radius"))
