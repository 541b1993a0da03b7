r"""Sums as integrals: lattice sums against continuum integrals, and the counting function.

Paper, ``eq11``–``eq14`` and App. ``AppSum``:

* :math:`\sum_{i\in G} f(z_i) \approx \frac{1}{\mathcal A}\int_{|z|\le L} dV_g\, f`, with
  :math:`dV_g = d^2z/(1-|z|^2)^2`, :math:`\mathcal A = \pi(pq-2p-2q)/(4p)` the area per site
  (:math:`\pi/28` for {7,3}) and :math:`L = \sqrt{N/(N + \pi/\mathcal A)}` (``eq12``);
* the counting function :math:`\mathcal N(r) = \sum_i\Theta(r - r_i)` (``sum2``) grows
  like :math:`s\rho + b` (``sum4``) with :math:`\rho = (1+r^2)/(1-r^2)` and
  :math:`s = \pi/(2\mathcal A) = 2p/(pq-2p-2q)` (14 for {7,3});

How the paper's :math:`b = -9.096` (Fig. FigS1, :math:`\ell = 4`) arises: an ordinary
least-squares line :math:`\mathcal N \approx s\rho + b` with *free* slope through the upper
corners of the staircase, one point :math:`(\rho(r_k), \mathcal N(r_k))` per distinct site
radius :math:`r_k` (24 points for :math:`\ell = 4`, :math:`\Theta(0) = 1`). It gives
s = 14.199 and b = -9.0954 from exact coordinates; b moves by 4e-4 when the radii are
rounded to 6 digits, which accounts for the last printed digit. Fixing s = 14 on the same
points gives b = -6.81, and fits through every site or the continuous staircase give
b between -12 and -14.9, so none of those is what the paper did.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy import integrate

from .. import _validate
from .. import geometry
from ..errors import ConvergenceWarning
from ..graph.lattice import Lattice
from ..results import Column, Result


__all__ = [
    "counting_function",
    "CountingFit",
    "fit_counting",
    "disk_integral",
    "SumCheck",
    "sum_check",
    "MAX_SLOPE",
]

#: Largest ``|slope|`` accepted by :func:`fit_counting`: the geometric slope pi/(2A) of every
#: hyperbolic {p,q} is at most 14 ({7,3}); beyond 1e6 the fitted intercept is round-off of s rho.
MAX_SLOPE = 1e6


# ----------------------------------------------------------------------------
# counting function, ``sum2``–``sum4``
# ----------------------------------------------------------------------------

def counting_function(lattice: Lattice, *, rtol: float = 1e-9) -> tuple[np.ndarray, np.ndarray]:
    r"""Distinct site radii :math:`r_k` and :math:`\mathcal N(r_k) = \#\{i: r_i \le r_k\}`, ``sum2``.

    Radii closer than ``rtol`` (relative) count as equal: symmetry-related sites agree to
    a few ulp, while distinct shells of the lattices built here differ by more than 1e-4.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} lattice embedded in the Poincaré disk (sites or line graph).
    rtol : float, optional
        Relative tolerance (>= 0) below which two radii count as one. Default 1e-9.

    Returns
    -------
    radii : ndarray of float
        The distinct Euclidean radii :math:`r_k = |z|` in the Poincaré disk, increasing.
    counts : ndarray of int64
        :math:`\mathcal N(r_k)`, the number of sites with :math:`|z_i| \le r_k`
        (right-continuous; the last entry is the number of sites).

    Raises
    ------
    ValueError
        If ``lattice`` is not a Lattice or ``rtol`` is negative.

    See Also
    --------
    fit_counting : the fit :math:`\mathcal N \approx s\rho + b`.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eqs. (8)
       and (9)" (source labels ``eq11``, ``eq12``, ``sum2``--``sum4``, Fig. ``FigS1``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.sums import counting_function
    >>> radii, counts = counting_function(hl.ring_lattice(7, 3, 4))
    >>> radii.size, counts[:4].tolist(), int(counts[-1])
    (24, [7, 14, 28, 35], 315)
    """
    _validate.lattice(lattice)
    rtol = _validate.real("rtol", rtol, minimum=0.0)
    r = np.sort(np.abs(lattice.z))
    last = np.r_[np.diff(r) > rtol * np.maximum(r[1:], 1.0), True]
    idx = np.flatnonzero(last)
    return r[idx], (idx + 1).astype(np.int64)


@dataclass(frozen=True, eq=False, kw_only=True)
class CountingFit(Result):
    r"""Least-squares fit :math:`\mathcal N(r) \approx s\rho + b` of ``sum4``.

    ``radii`` and ``counts`` are the fitted points :math:`(r_k, \mathcal N(r_k))`, one per
    distinct radius of the window; ``rms`` is the rms residual of the fit. Its table has one row
    per fitted point: ``r``, ``rho`` and ``count``.

    Attributes
    ----------
    p, q, rings : int
        The lattice fitted.
    slope, intercept : float
        s and b of :math:`\mathcal N \approx s\rho + b` (sites per unit of :math:`\rho`, sites).
    expected_slope : float
        The geometric slope :math:`\pi/(2\mathcal A)` (14 for {7,3}).
    slope_fixed : bool
        True when the slope was given, not fitted.
    window : str
        ``"all"`` or ``"complete"`` (see :func:`fit_counting`).
    radii : ndarray
        The distinct Euclidean site radii :math:`r_k` in the Poincaré disk (paper's metric;
        :attr:`rho` gives :math:`\rho = (1+r^2)/(1-r^2)`).
    counts : ndarray of int
        :math:`\mathcal N(r_k)`, the number of sites with :math:`r_i \le r_k`.
    rms : float
        Rms residual of the fit, in sites.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> fit = hl.fit_counting(hl.ring_lattice(7, 3, 4))
    >>> print(f"s = {fit.slope:.3f}, b = {fit.intercept:.4f}, expected {fit.expected_slope:g}")
    s = 14.199, b = -9.0954, expected 14
    >>> fit.window, fit.slope_fixed, fit.radii.size, fit.counts[:3].tolist()
    ('all', False, 24, [7, 14, 28])
    """

    COLUMNS = (Column("r", "radii", "1 (Poincare-disk radius)"), Column("rho", "rho", "1"),
               Column("count", "counts", "sites"))

    p: int
    q: int
    rings: int
    slope: float
    intercept: float
    expected_slope: float
    slope_fixed: bool
    window: str
    radii: np.ndarray
    counts: np.ndarray
    rms: float

    @property
    def rho(self) -> np.ndarray:
        """:math:`\\rho = (1+r^2)/(1-r^2)` at the fitted radii."""
        return geometry.rho(self.radii)

    def summary(self) -> dict:
        """The JSON printed by ``hyperlattice scaling counting --json``."""
        return {"p": self.p, "q": self.q, "rings": self.rings, "slope": self.slope,
                "intercept": self.intercept, "expected_slope": self.expected_slope,
                "slope_fixed": self.slope_fixed, "window": self.window, "points": int(self.radii.size), "rms": self.rms}


def fit_counting(lattice: Lattice, *, slope: float | None = None, window: str = "all",
                 slope_rtol: float = 0.1) -> CountingFit:
    r"""Fit :math:`\mathcal N(r) \approx s\rho + b` (``sum4``, Fig. FigS1).

    Procedure (the one that reproduces the paper's b = -9.096 for {7,3}, :math:`\ell=4`):
    ordinary least squares through one point :math:`(\rho(r_k), \mathcal N(r_k))` per
    distinct radius, :math:`\mathcal N` right-continuous. The slope is free unless ``slope``
    is given; the geometric value is :math:`s = \pi/(2\mathcal A) = 2p/(pq-2p-2q)`.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} ring lattice embedded in the Poincaré disk.
    slope : float, optional
        Fix the slope and fit only b (the mean residual); ``|slope|`` at most
        :data:`MAX_SLOPE`. Default None: a free slope.
    window : {"all", "complete"}, optional
        ``"all"``: every distinct radius (the paper's choice). ``"complete"``: only radii
        below the innermost site of ring :math:`\ell+1`, where :math:`\mathcal N` counts every
        site of the infinite tessellation. The outermost ring of a ring lattice is spread
        over a range of radii, so with ``"all"`` the free slope drifts below
        :math:`\pi/(2\mathcal A)` as :math:`\ell` grows (11.7 instead of 14 at {7,3},
        :math:`\ell = 8`); ``"complete"`` gives the geometric slope to about 2 % for every
        {p,q} tried. Default ``"all"``.
    slope_rtol : float, optional
        Relative tolerance (> 0) of a free slope against :math:`\pi/(2\mathcal A)` before a
        warning. Default 0.1.

    Returns
    -------
    CountingFit
        ``slope`` s and ``intercept`` b, the ``expected_slope`` :math:`\pi/(2\mathcal A)`,
        the fitted points ``radii``, ``counts`` (and ``rho``) and the rms residual ``rms``.

    Raises
    ------
    ValueError
        For bad input, or a free-slope fit on fewer than 3 distinct radii.

    Warns
    -----
    ConvergenceWarning
        If a free slope differs from :math:`\pi/(2\mathcal A)` by more than ``slope_rtol``.

    See Also
    --------
    counting_function : the points fitted.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eqs. (8)
       and (9)" (source labels ``eq11``, ``eq12``, ``sum2``--``sum4``, Fig. ``FigS1``).

    Examples
    --------
    The paper's b = -9.096 for {7,3} and four rings:

    >>> import hyperlattice as hl
    >>> fit = hl.fit_counting(hl.ring_lattice(7, 3, 4))
    >>> print(f"s = {fit.slope:.3f}, b = {fit.intercept:.4f}, pi/(2A) = {fit.expected_slope:g}")
    s = 14.199, b = -9.0954, pi/(2A) = 14
    >>> print(f"{hl.fit_counting(hl.ring_lattice(7, 3, 4), slope=14).intercept:.2f}")
    -6.81
    """
    _validate.lattice(lattice)
    window = _validate.choice("window", window, ("all", "complete"))
    if slope is not None:
        slope = _validate.real("slope", slope, minimum=-MAX_SLOPE, maximum=MAX_SLOPE)
    slope_rtol = _validate.positive_real("slope_rtol", slope_rtol)
    radii, counts = counting_function(lattice)
    if window == "complete":
        from ..graph.lattice import ring_lattice

        outer = ring_lattice(lattice.p, lattice.q, lattice.rings + 1)
        rcut = np.min(np.abs(outer.z[outer.ring == lattice.rings + 1]))
        keep = radii < rcut
        radii, counts = radii[keep], counts[keep]
    rho = geometry.rho(radii)
    expected = geometry.counting_slope(lattice.p, lattice.q)
    if slope is None:
        if radii.size < 3:
            raise ValueError(f"a free-slope fit needs at least 3 distinct radii; the lattice has "
                             f"{radii.size}: use more rings.")
        s, b = np.polyfit(rho, counts, 1)
        fixed = False
    else:
        s = slope
        b = float(np.mean(counts - s * rho))
        fixed = True
    rms = float(np.sqrt(np.mean((counts - s * rho - b) ** 2)))
    if not (math.isfinite(s) and math.isfinite(b) and math.isfinite(rms)):  # pragma: no cover - bounded above
        raise ValueError("the counting fit overflowed; the slope is too large.")
    if not fixed and abs(s - expected) > slope_rtol * expected:
        hint = " (the outer ring is incomplete: try window='complete')" if window == "all" else ""
        warnings.warn(f"fitted counting slope {s:.3f} differs from pi/(2A) = {expected:.3f} "
                      f"by more than {slope_rtol:.0%}{hint}.", ConvergenceWarning, stacklevel=2)
    return CountingFit(p=lattice.p, q=lattice.q, rings=lattice.rings, slope=float(s),
                       intercept=float(b), expected_slope=expected, slope_fixed=fixed,
                       window=window, radii=radii, counts=counts, rms=rms)


# ----------------------------------------------------------------------------
# sums as integrals, ``eq11``
# ----------------------------------------------------------------------------

def disk_integral(f: Callable, radius: float, *, angular_points: int = 64,
                  rtol: float = 1e-10) -> complex:
    r""":math:`\int_{|z|\le L} \frac{d^2z}{(1-|z|^2)^2} f(z)`.

    In geodesic polar coordinates :math:`z = \tanh(d)e^{i\phi}` the volume element is
    :math:`\tfrac12\sinh(2d)\,dd\,d\phi`, smooth up to :math:`L \to 1`. The angular integral
    of a smooth periodic function uses the trapezoidal rule (spectrally accurate), checked
    against twice the points; the radial one uses adaptive quadrature.

    Parameters
    ----------
    f : callable
        Maps a complex array of points z to an array of the same shape (real or complex),
        smooth on the disk.
    radius : float
        Euclidean radius L of the disk in the Poincaré disk, 0 < L < 1.
    angular_points : int, optional
        Trapezoidal points per circle (4 to 2**20); the check uses twice as many. Default 64.
    rtol : float, optional
        Tolerance in (0, 1] relative to :math:`\int|f|\,dV_g`. Default 1e-10.

    Returns
    -------
    complex
        The integral (area in units of the metric :math:`ds^2 = (dx^2+dy^2)/(1-|z|^2)^2`,
        curvature -4).

    Raises
    ------
    ValueError
        If ``f`` is not callable, L is not in (0, 1) or an option is out of range.

    Warns
    -----
    ConvergenceWarning
        If doubling the angular points or the radial quadrature's error estimate exceeds
        ``rtol`` relative to the result.

    Examples
    --------
    The area of the disk :math:`|z| \le L` is :math:`\pi L^2/(1-L^2)`:

    >>> import numpy as np
    >>> from hyperlattice.compare.sums import disk_integral
    >>> area = disk_integral(lambda z: np.ones(z.shape), 0.5)
    >>> print(f"{area.real:.10f} {np.pi * 0.25 / 0.75:.10f}")
    1.0471975512 1.0471975512
    """
    f = _validate.function("f", f)
    L = _validate.radius("radius", radius)
    # 2**20 points per ring is far past spectral accuracy for any f worth integrating
    angular_points = _validate.integer("angular_points", angular_points, minimum=4, maximum=2 ** 20)
    rtol = _validate.real("rtol", rtol, minimum=0.0, maximum=1.0, open_min=True)
    rtol = _validate.solver_tolerance("rtol", rtol)      # 1e-300 refined to the point cap (minutes)
    D = math.atanh(L)

    def ring_average(d, m, absolute=False):
        phi = 2 * np.pi * np.arange(m) / m
        v = np.asarray(f(np.tanh(d) * np.exp(1j * phi)), dtype=complex)
        return np.mean(np.abs(v)) if absolute else np.mean(v)

    def part(d, m, which):
        v = ring_average(d, m, absolute=which == 2) * math.pi * math.sinh(2 * d)
        return v.real if which != 1 else v.imag

    def quad(m, which, epsabs):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", integrate.IntegrationWarning)
            val, err = integrate.quad(part, 0.0, D, args=(m, which), epsabs=epsabs,
                                      epsrel=rtol / 10, limit=400)
        # quad's own complaint becomes an unbounded error, reported once below
        if any(issubclass(c.category, integrate.IntegrationWarning) for c in caught):
            err = math.inf
        return val, err

    # absolute scale: the integral of |f|. Tolerances are relative to it,
    # so that an integral which vanishes by symmetry (or the imaginary part of a real f)
    # does not send quad chasing zero to relative accuracy.
    scale, _ = integrate.quad(part, 0.0, D, args=(angular_points, 2), epsrel=1e-3, limit=200)
    scale = max(scale, 1e-300)
    out = []
    for m in (angular_points, 2 * angular_points):
        re, re_err = quad(m, 0, scale * rtol / 10)
        im, im_err = quad(m, 1, scale * rtol / 10)
        out.append((complex(re, im), re_err + im_err))
    (v1, e1), (v2, _) = out
    if abs(v1 - v2) > rtol * scale or e1 > rtol * scale:
        warnings.warn(f"disk integral converged only to {max(abs(v1 - v2), e1) / scale:.1e} "
                      f"of its scale, tolerance {rtol:.0e}.", ConvergenceWarning, stacklevel=2)
    return v2


@dataclass(frozen=True, eq=False, kw_only=True)
class SumCheck(Result):
    r"""One check of ``eq11``: lattice sum against :math:`(1/\mathcal A)\int_{|z|\le L} f\,dV_g`.

    Attributes
    ----------
    p, q, rings, sites : int
        The lattice summed over.
    radius : float
        L, the area-matched Euclidean disk radius (``eq12``), paper's metric.
    function : str
        Name of f.
    lattice_sum : complex
        :math:`\Sigma = \sum_i f(z_i)`.
    integral : complex
        :math:`I = (1/\mathcal A)\int_{|z|\le L} f\,dV_g` (:math:`\mathcal A` the area per site).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> chk = hl.sum_check(hl.ring_lattice(7, 3, 4), lambda z: np.abs(z) ** 2, name="|z|^2")
    >>> chk.function, chk.sites, round(chk.radius, 6)
    ('|z|^2', 315, 0.958315)
    >>> print(f"{chk.lattice_sum.real:.4f} {chk.integral.real:.4f} {chk.rel_error:.4f}")
    244.8141 244.8453 0.0001
    """

    p: int
    q: int
    rings: int
    sites: int
    radius: float
    function: str
    lattice_sum: complex
    integral: complex

    @property
    def rel_error(self) -> float:
        """:math:`|\\Sigma - I|/|I|`."""
        return float(abs(self.lattice_sum - self.integral) / abs(self.integral))

    def summary(self) -> dict:
        """One row of ``hyperlattice scaling sums --json`` (complex values only where not real)."""
        def num(c):
            return float(c.real) if abs(c.imag) <= 1e-12 * max(abs(c), 1e-300) else c
        return {"p": self.p, "q": self.q, "rings": self.rings, "sites": self.sites,
                "radius": self.radius, "function": self.function,
                "lattice_sum": num(self.lattice_sum), "integral": num(self.integral),
                "rel_error": self.rel_error}


def sum_check(lattice: Lattice, f: Callable, *, name: str | None = None) -> SumCheck:
    r"""Compare :math:`\sum_i f(z_i)` with :math:`\frac{1}{\mathcal A}\int_{|z|\le L}dV_g f`, ``eq11``.

    ``f`` maps complex arrays to arrays (e.g. a :class:`hyperlattice.scaling.SmoothFunction`).
    L is the effective radius of ``eq12`` generalised to {p,q}, which makes f = 1 exact.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} lattice embedded in the Poincaré disk; its ``radius`` is L.
    f : callable
        Maps the complex array of site positions z to one finite value per site.
    name : str, optional
        Label of f in the result (default: ``f.name`` or ``f.__name__``).

    Returns
    -------
    SumCheck
        ``lattice_sum`` :math:`\sum_i f(z_i)`, ``integral``
        :math:`\frac1{\mathcal A}\int_{|z|\le L}dV_g f` (both complex), the ``radius`` L and
        the ``rel_error`` between them.

    Raises
    ------
    ValueError
        If ``f`` is not callable or does not return one finite value per site, or ``name`` is
        not a string.

    See Also
    --------
    disk_integral : the continuum side.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eqs. (8)
       and (9)" (source labels ``eq11``, ``eq12``, ``sum2``--``sum4``, Fig. ``FigS1``).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 4)
    >>> chk = hl.sum_check(lat, lambda z: np.abs(z) ** 2, name="|z|^2")
    >>> print(f"{chk.lattice_sum.real:.4f} {chk.integral.real:.4f} {chk.rel_error:.4f}")
    244.8141 244.8453 0.0001
    """
    _validate.lattice(lattice)
    f = _validate.function("f", f)
    if name is not None and not isinstance(name, str):
        raise ValueError(f"name must be a string, got {name!r}.")
    vals = np.asarray(f(lattice.z), dtype=complex)
    if vals.shape != lattice.z.shape or not np.all(np.isfinite(vals)):
        raise ValueError("f must return one finite value per site.")
    L = lattice.radius
    integral = disk_integral(f, L) / geometry.site_area(lattice.p, lattice.q)
    label = name or getattr(f, "name", None) or getattr(f, "__name__", "f")
    return SumCheck(p=lattice.p, q=lattice.q, rings=lattice.rings, sites=lattice.sites,
                    radius=float(L), function=str(label), lattice_sum=complex(vals.sum()),
                    integral=complex(integral))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
