r"""Continuum Green function of the hyperbolic Helmholtz operator on a disk of radius :math:`L`.

:math:`G(z, z', \lambda, L)` solves (``green1``)

.. math:: (\lambda + \Delta_g)\,G(z,z',\lambda,L) = -(1-|z|^2)^2\,\delta^{(2)}(z-z'),
          \qquad G = 0 \text{ for } |z| = L \text{ or } |z'| = L,

with :math:`\Delta_g = (1-|z|^2)^2(\partial_x^2+\partial_y^2)` (``eq7``). It is the continuum
side of the dictionary ``eq21`` (see :mod:`hyperlattice.green`).

Forms implemented
-----------------
* :math:`\lambda = 0`: the image-charge closed form ``eq23``/``green6``.
* :math:`L = 1`: :math:`G = \frac{1}{2\pi}Q_\nu(y)`, :math:`y = \cosh 2d(z,z')` (``green30``), for
  :math:`\lambda \in \mathbb{C}\setminus[1,\infty)`. This *is* the paper's
  :math:`\frac{1}{2\pi}[Q_{\nu_p}(y) - \mathcal C P_{\nu_p}(y)]` written with the other root
  :math:`\nu = -\nu_p - 1` of :math:`\lambda/4 = -\nu(\nu+1)`: since
  :math:`P_{\nu_p} = P_{-\nu_p-1}` and :math:`Q_{\nu_p} - Q_{-\nu_p-1} = \pi\cot(\pi\nu_p)\,P_{\nu_p}`
  (A&S 8.2.3 with :math:`m = 0`), :math:`\mathcal C = \pi\cot(\pi\nu_p)`.
  :func:`boundary_constant` evaluates the paper's printed expression for :math:`\mathcal C`;
  it equals :math:`\pi\cot(\pi\nu_p) - \mathrm i\pi/2` (checked in the tests), i.e. the paper's
  :math:`Q_\nu` there is the type-3 one minus :math:`\frac{\mathrm i\pi}2 P_\nu`, and both
  conventions give the same :math:`Q_{\nu_p} - \mathcal C P_{\nu_p}`.
* :math:`0 < L < 1`: ``green33`` = ``green34`` :math:`-` ``green36``, the fundamental solution
  minus the Dirichlet correction as a Fourier series in the angle, truncated adaptively.

Branch of :math:`\nu`
---------------------
:math:`\nu = -\tfrac12 + \tfrac12\sqrt{1-\lambda}` with the principal root
(:func:`hyperlattice.special.nu_from_lambda`), i.e. :math:`\operatorname{Re}\nu \ge -\tfrac12`.
For real :math:`\lambda < 1` this is the root :math:`\nu > -\tfrac12` (the paper's ``green35``
picks :math:`\nu_p = -\nu - 1 < -\tfrac12`); for :math:`\lambda > 1` it is the paper's
:math:`\tfrac12(-1+\mathrm i\sqrt{\lambda-1})`. With this root :math:`Q_\nu^m(x)` is the solution
that *decays* as :math:`x\to\infty` (:math:`|Q_\nu| \sim x^{-\operatorname{Re}\nu-1}`), so the
:math:`L=1` Green function needs no boundary term, and :math:`Q_\nu^m` never meets its poles
(:math:`\nu+m+1 \in \{0,-1,\dots\}`), which the paper's root hits at :math:`\lambda = 0`
(:math:`\nu_p = -1`). For :math:`L < 1` the Dirichlet Green function does not depend on the root:
both :math:`\mathcal G_0` and :math:`\delta\mathcal G` change, their difference does not.

The coefficient :math:`C_m` and the convention of :math:`Q_\nu^m`
-----------------------------------------------------------------
The jump condition of ``green22`` with :math:`G_m = C_m u_m(\rho_>)v_m(\rho_<)` gives
:math:`C_m = 1/[(1-\rho^2)\,W\{P_\nu^m, Q_\nu^m\}]` (the Wronskian times :math:`p(\rho)` is
constant). :mod:`hyperlattice.special` uses DLMF/mpmath type-3 :math:`Q_\nu^m`, which carries
the phase :math:`e^{\mathrm i m\pi} = (-1)^m`; its Wronskian is
:math:`(-1)^m\Gamma(\nu+m+1)/[(1-x^2)\Gamma(\nu-m+1)]`, hence

.. math:: C_m = (-1)^m\,\frac{\Gamma(\nu-m+1)}{\Gamma(\nu+m+1)}
              = (-1)^m \times \texttt{legendre\_cm}(\nu, m).

The paper's ``green38`` (= ``legendre_cm``) lacks the :math:`(-1)^m`: it belongs to a
:math:`Q_\nu^m` without the phase. Using it with type-3 :math:`Q` flips the sign of every odd
term of ``green36``; the tests catch this through the addition theorem
:math:`Q_\nu(y) = \sum_m \epsilon_m C_m Q_\nu^m(\rho_>)P_\nu^m(\rho_<)\cos m\Delta\phi` and through
the boundary values. :func:`coefficient_cm` returns the correct :math:`C_m`.

Evaluation of ``green36``
-------------------------
Write :math:`\tilde P_\nu^m = P_\nu^m\,\Gamma(\nu-m+1)/\Gamma(\nu+m+1)` (entire in :math:`\nu`;
no zero factor at integer :math:`\nu < m`). Then the :math:`m`-th term of ``green36`` is

.. math:: t_m = \frac{\epsilon_m}{2\pi}(-1)^m Q_\nu^m(\rho_L)\,
          \frac{\tilde P_\nu^m(\rho)\tilde P_\nu^m(\rho')}{\tilde P_\nu^m(\rho_L)}\cos m(\phi-\phi'),
          \qquad \epsilon_0 = 1,\ \epsilon_{m>0} = 2 .

:math:`\tilde P^m` obeys DLMF 14.10.6 divided by :math:`\Gamma(\nu+m+2)/\Gamma(\nu-m)`,

.. math:: \tilde P^m = 2(m+1)\frac{x}{\sqrt{x^2-1}}\tilde P^{m+1}
                       + (\nu-m-1)(\nu+m+2)\tilde P^{m+2},

which has no division and in which :math:`\tilde P^m` is the *dominant* solution going down in
:math:`m` (:math:`\tilde P^m\sim r^m/m!` against :math:`\sim r^{-m}` for the :math:`Q` branch).
Radii :math:`r \le r_{\rm split}` (0.9, raised up to 0.995 for sources near the boundary) use
Miller's backward recurrence, normalised to the Legendre module's :math:`m = 0, 1` values; its
contamination :math:`\sim r^{2(M_s-m)}` sets the extra start depth. Larger radii use the upward
recurrence of :math:`P^m` (relative error growth :math:`\sim r^{-2m}`, harmless near
:math:`r = 1`), divided by :math:`\Gamma(\nu+m+1)/\Gamma(\nu-m+1)`; near integer
:math:`\nu \ge 1` (where that cancels) Miller is used throughout. All distinct radii (targets,
sources and :math:`L`) run in one vectorized recurrence, with per-point logarithmic scales so
that :math:`m!`-sized factors neither overflow nor underflow (the Legendre module itself stops
at :math:`m \approx 100`). Cost: two Legendre evaluations per distinct radius plus
:math:`O(M)` vector steps.

Edge cases
----------
* Points on the circle :math:`|z| = L` (or :math:`|z'| = L`): :math:`G = 0` exactly (the
  boundary condition), without the series.
* :math:`\lambda` so small that :math:`\nu` rounds to 0, or a disk so small that
  :math:`|\lambda| L^2 \le 10^{-18}`: ``eq23``, whose difference from the Helmholtz Green function
  is :math:`O(|\lambda|L^2)` relative, below rounding. Elsewhere small :math:`|\nu|` needs no
  special care: :math:`\tilde P^m` is computed without dividing by :math:`\nu` (the factor
  :math:`\nu` of :math:`\Gamma(\nu+m+1)/\Gamma(\nu-m+1)` is formed exactly as :math:`\nu + 0`).
* Disks so small that :math:`x_L - 1 = 2L^2/(1-L^2)` is below 16 ulps (:math:`L < 4\cdot10^{-8}`)
  with :math:`|\lambda| L^2` not negligible are refused (ValueError).

Truncation
----------
:math:`|t_m| \sim (r r'/L^2)^m/m` for large :math:`m`. :math:`M` is first chosen from that
bound, then the neglected tail is estimated per pair as :math:`|t_M|\,\varrho/(1-\varrho)` with
:math:`\varrho = \max(rr'/L^2, |t_M|/|t_{M-1}|)` (envelopes without the cosine) and required to be
below ``tol`` times the scale :math:`|\mathcal G_0| + |\delta\mathcal G|` of the two cancelling
terms; if not, :math:`M` is doubled (up to ``max_terms``). The largest relative estimate is
reported in :class:`GreenInfo`; a :class:`~hyperlattice.errors.ConvergenceWarning` is issued
when the tolerance is not met. The estimate also contains the Miller contamination; the growth
:math:`\sim\varepsilon r^{-2m}` of rounding errors in the upward recurrence, which more terms
cannot reduce, is estimated separately (``GreenInfo.rounding_estimate``, warned about above
``tol``).

Small radii: the Legendre module takes :math:`x = (1+r^2)/(1-r^2)`, whose :math:`x - 1` keeps
only :math:`\sim\varepsilon/r^2` relative accuracy after rounding; the module's values are
corrected to the exact :math:`w = r^2` through their leading dependence :math:`w^{\pm m/2}`
(:func:`_log_eta`), and the recurrences use :math:`x/\sqrt{x^2-1} = (1+r^2)/2r` from the exact
radius. Without this a disk of radius :math:`10^{-4}` was accurate to only :math:`10^{-8}`.

When the plain sum would need more than :math:`M = 400` orders (both points near the
circle, :math:`rr'/L^2 \to 1`), the :math:`\lambda = 0` series is subtracted term by term and
added back in closed form (``eq23``):

.. math:: \delta\mathcal G = \delta\mathcal G_0
          + \sum_m \bigl(t_m - t_m^{(0)}\bigr),\qquad
          t_m^{(0)} = \frac{1}{2\pi m}\Bigl[\Bigl(\frac{rr'}{L^2}\Bigr)^m - (rr')^m\Bigr]\cos m\Delta\phi,
          \qquad \delta\mathcal G_0 = \frac1{4\pi}\ln\frac{L^2|1-z\bar z'|^2}{|L^2 - z\bar z'|^2},

(:math:`t_0^{(0)} = -\ln L/2\pi`): the differences fall like :math:`|\nu(\nu+1)|\,(rr'/L^2)^m/m^2`
instead of :math:`(rr'/L^2)^m/m`. :math:`Q_\nu^m(\rho_L)` beyond :math:`m = 30` comes from its
upward recurrence (DLMF 14.10.6, stable since :math:`Q` is the dominant solution), which has no
limit in :math:`m`. Pairs are processed in chunks, so that the :math:`(M+1)\times n` tables stay
within :data:`_TABLE_BYTES`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy import special as sc

from .. import _validate
from ..errors import ConvergenceError, ConvergenceWarning
from ..geometry import one_minus_abs2
from ..results import Result
from .special import legendre_cm, legendre_log_p, legendre_log_q, legendre_p, legendre_q, nu_from_lambda

__all__ = [
    "continuum_green",
    "GreenInfo",
    "green_nu",
    "coefficient_cm",
    "boundary_constant",
    "fundamental_solution",
    "green_laplace",
    "green_infinite_disk",
    "MAX_TERMS",
    "MAX_LAMBDA",
]

MAX_LAMBDA = 1e10       # |lambda| beyond this is refused (|nu| > 5e4: the Legendre module's quadratures grow ~|nu|)
_MAX_TERMS = 4000       # default cap on the m-sum; (rr'/L^2)^4000 < 1e-12 needs rr'/L^2 < 0.9931
MAX_TERMS = 100_000     # largest max_terms accepted (the tables are chunked, the time is ~ M x pairs)
_RESCALE = 1e30         # renormalize recurrence values beyond this magnitude (per point)
_EIGEN_REL = 1e-12      # |P~^m(rho_L)| below this times its recurrence envelope: Dirichlet eigenvalue
_TABLE_BYTES = 1 << 28  # memory for the (M+1) x radii tables of one chunk of pairs (256 MB)
_MAX_PAIRS = 1 << 25    # largest number of (z, z') pairs of one call (~3 GB of inputs, output, work)
_PLAIN_TERMS = 400      # the plain sum up to this order; beyond it the lambda = 0 series is subtracted
_Q_DIRECT = 30          # Q^m(rho_L) from the Legendre module up to this order, by recurrence beyond
_SMALL_DISK = 1e-18     # |lambda| L^2 below this: eq23 (the O(lambda L^2) correction is below rounding)
_EPS = np.finfo(float).eps


@dataclass(frozen=True, eq=False, kw_only=True)
class GreenInfo(Result):
    r"""How a continuum Green function was evaluated.

    Attributes
    ----------
    method : str
        ``"laplace"`` (``eq23``), ``"infinite_disk"`` (:math:`L = 1`), ``"series"``
        (``green34`` - ``green36``) or ``"series-accelerated"`` (with the :math:`\lambda = 0`
        series subtracted, see the module docstring).
    nu : complex
        The degree used (branch :math:`\operatorname{Re}\nu \ge -1/2`).
    terms : int
        Number of Fourier orders :math:`m = 0..M` summed (0 for closed forms).
    tail_estimate : float
        Largest estimated truncation error relative to :math:`|\mathcal G_0|+|\delta\mathcal G|`.
    tol : float
        Requested tolerance.
    rounding_estimate : float
        Largest estimated rounding error that more terms cannot reduce, on the same relative
        scale: amplified by the upward recurrence of :math:`P^m` (beyond a factor 100), or by a
        :math:`\tilde P^m(\rho_L)` close to zero (:math:`\lambda` near a Dirichlet eigenvalue,
        ubiquitous for large :math:`\lambda`, where the spectrum is dense).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> g, info = hl.continuum_green(0.1, 0.3j, 2.0, 0.8, return_info=True)
    >>> info.method, complex(info.nu), info.converged
    ('series', (-0.5+0.5j), True)
    """

    method: str
    nu: complex
    terms: int
    tail_estimate: float
    tol: float
    rounding_estimate: float = 0.0

    @property
    def converged(self) -> bool:
        """Whether the estimated truncation and amplified rounding errors both meet ``tol``."""
        return self.tail_estimate <= self.tol and self.rounding_estimate <= self.tol


# ----------------------------------------------------------------------------
# parameters and constants
# ----------------------------------------------------------------------------

def green_nu(lam) -> complex:
    r"""Degree :math:`\nu` with :math:`\lambda/4 = -\nu(\nu+1)` and :math:`\operatorname{Re}\nu\ge-\frac12`.

    The principal-root branch :math:`\nu = -\frac12+\frac12\sqrt{1-\lambda}` (see the module
    docstring for why this root and how it relates to ``green35``).

    Parameters
    ----------
    lam : float or complex
        Helmholtz parameter :math:`\lambda` (eigenvalue variable of :math:`-\Delta_g`).

    Returns
    -------
    complex
        The degree :math:`\nu`; :math:`\nu = \frac12(-1+\mathrm i\sqrt{\lambda-1})` for real
        :math:`\lambda > 1`.

    Raises
    ------
    ValueError
        If ``lam`` is not a finite number.

    See Also
    --------
    hyperlattice.continuum.special.nu_from_lambda

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green35``).

    Examples
    --------
    >>> from hyperlattice.continuum.green import green_nu
    >>> print(f"{green_nu(-8.0).real:.6f}")
    1.000000
    >>> nu = green_nu(5.0)
    >>> print(f"{nu.real:.6f} {nu.imag:.6f}")
    -0.500000 1.000000
    """
    lam = _check_lambda(lam)
    return complex(nu_from_lambda(lam))


def coefficient_cm(nu, m) -> complex | np.ndarray:
    r""":math:`C_m` of ``green23`` for the type-3 :math:`Q_\nu^m` of :mod:`hyperlattice.continuum.special`.

    :math:`C_m = 1/[(1-x^2)W\{P^m_\nu,Q^m_\nu\}] = (-1)^m\Gamma(\nu-m+1)/\Gamma(\nu+m+1)`
    (the Wronskian of A&S 8.1.9, :func:`hyperlattice.continuum.special.legendre_wronskian`);
    the paper's ``green38`` without :math:`(-1)^m` matches a phase-free :math:`Q_\nu^m`.

    Parameters
    ----------
    nu : complex or array_like of complex
        Degree :math:`\nu`.
    m : int or array_like of int
        Non-negative order(s); broadcasts against ``nu``.

    Returns
    -------
    complex or ndarray of complex
        :math:`C_m`.

    Raises
    ------
    ValueError
        If ``nu`` is not numeric and finite, or ``m`` is not a non-negative integer (array).

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green23``, ``green38``); Abramowitz & Stegun 8.1.9.

    Examples
    --------
    >>> from hyperlattice.continuum.green import coefficient_cm
    >>> [round(complex(c).real, 6) for c in coefficient_cm(0.3, [0, 1, 2])]
    [1.0, -2.564103, -1.59261]
    """
    nu = _validate.complex_array("nu", nu)
    val = legendre_cm(nu, m)          # validates m (non-negative integers)
    sign = np.where(np.asarray(m) % 2 == 0, 1.0, -1.0)
    return sign * val


def boundary_constant(lam) -> complex:
    r"""The constant :math:`\mathcal C` of App. ``AppGreen`` as printed in the paper.

    .. math:: \mathcal C = \frac{2^{\nu}\mathrm i^{-\nu}\pi^{3/2}\Gamma(-\nu)}
              {\Gamma(1+\frac\nu2)\Gamma(\frac{1+\nu}2)}\Bigl[-\cos\frac{\pi\nu}{2}
              \frac{\Gamma(1+\frac\nu2)^2}{\Gamma(\frac{1-\nu}2)^2}
              + \mathrm i\sin\frac{\pi\nu}{2}\frac{\Gamma(\frac{1+\nu}2)^2}{\Gamma(-\frac\nu2)^2}\Bigr]

    with the paper's root :math:`\nu_p = -\frac12 - \frac12\sqrt{1-\lambda}` (:math:`\nu_p < -1/2`
    for real :math:`\lambda < 1`), for :math:`\lambda\in\mathbb C\setminus[1,\infty)`. The
    :math:`L=1` Green function is :math:`\frac1{2\pi}[Q_{\nu_p}(y) - \mathcal C P_{\nu_p}(y)]`; it
    is evaluated in :func:`green_infinite_disk` through the equivalent decaying form
    :math:`\frac1{2\pi}Q_{-\nu_p-1}(y)`, which has no pole at :math:`\lambda = 0`. This
    function exists so that the printed constant can be checked (tests compare it with
    :math:`\lim_{y\to\infty}Q_{\nu_p}/P_{\nu_p}` and with :math:`\pi\cot\pi\nu_p`).

    Parameters
    ----------
    lam : float or complex
        Helmholtz parameter :math:`\lambda`, off the continuous spectrum :math:`[1, \infty)`.

    Returns
    -------
    complex
        :math:`\mathcal C`, equal to :math:`\pi\cot(\pi\nu_p) - \mathrm i\pi/2`.

    Raises
    ------
    ValueError
        If ``lam`` is not a finite number, lies on :math:`[1, \infty)`, or the printed
        expression cannot be evaluated in double precision there.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``AppGreen``).

    Examples
    --------
    >>> from hyperlattice.continuum.green import boundary_constant
    >>> c = boundary_constant(0.5)
    >>> print(f"{c.real:.6f} {c.imag:.6f}")
    6.339698 -1.570796
    """
    lam = _check_lambda(lam)
    if lam.imag == 0 and lam.real >= 1:
        raise ValueError("the constant C exists only for lambda off the continuous spectrum [1, inf).")
    nu = -1.0 - green_nu(lam)
    g = sc.gamma
    with np.errstate(all="ignore"):
        pre = 2.0**nu * np.exp(-1j * np.pi / 2 * nu) * np.pi**1.5 * g(-nu) / (g(1 + nu / 2) * g((1 + nu) / 2))
        br = (-np.cos(np.pi * nu / 2) * g(1 + nu / 2) ** 2 / g((1 - nu) / 2) ** 2
              + 1j * np.sin(np.pi * nu / 2) * g((1 + nu) / 2) ** 2 / g(-nu / 2) ** 2)
        val = complex(pre * br)
    if not (math.isfinite(val.real) and math.isfinite(val.imag)):
        raise ValueError(f"the printed constant C cannot be evaluated at lambda = {lam} in double precision "
                         "(its Gamma functions overflow or sit at a pole).")
    return val


# ----------------------------------------------------------------------------
# input handling
# ----------------------------------------------------------------------------

def _check_lambda(lam, *, evaluated: bool = False) -> complex:
    """lambda as a finite complex number; ``evaluated``: also within the range where the Legendre
    functions of degree nu ~ sqrt(-lambda)/2 are evaluated (|lambda| <= MAX_LAMBDA)."""
    lam = _validate.complex_number("lambda", lam)
    if evaluated and abs(lam) > MAX_LAMBDA:
        raise ValueError(f"|lambda| = {abs(lam):.3g} is beyond the range |lambda| <= {MAX_LAMBDA:g} of the Legendre "
                         "functions of degree nu = (-1 + sqrt(1 - lambda))/2 used here.")
    return lam


def _check_radius(radius) -> float:
    return _validate.radius("the disk radius L", radius, allow_one=True)


def _check_points(name: str, z, L: float, extend: bool) -> np.ndarray:
    z = _validate.complex_array(name, z)
    r = np.abs(z)
    if L == 1.0:
        if np.any(r >= 1.0):
            raise ValueError(f"{name} must lie inside the unit disk |z| < 1.")
    elif np.any(r > L * (1.0 + 4e-16)) and not extend:     # |z| = L up to rounding is allowed
        raise ValueError(
            f"{name} has points outside the disk |z| <= L = {L:.12g} (largest |z| = {r.max():.12g}); "
            "pass extend=True to evaluate the analytic continuation of green33 there.")
    elif extend and np.any(r >= 1.0):
        raise ValueError(f"{name} must lie inside the unit disk |z| < 1 (extend=True continues green33 "
                         "up to there).")
    return z


def _pairs(z: np.ndarray, zp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Broadcast the two point sets, refusing a size that would not fit before allocating it."""
    try:
        shape = np.broadcast_shapes(z.shape, zp.shape)
    except ValueError:
        raise ValueError(f"z and z' must broadcast to one shape; got shapes {z.shape} and {zp.shape}.") from None
    size = math.prod(shape)
    if size > _MAX_PAIRS:
        raise ValueError(f"z and z' broadcast to {size:,} pairs; at most {_MAX_PAIRS:,} are evaluated in one "
                         "call (split the request).")
    return np.broadcast_arrays(z, zp)


def _cosh2d(z, zp):
    """:math:`y - 1 = 2|z-z'|^2/((1-|z|^2)(1-|z'|^2))` with compensated :math:`1-|z|^2`."""
    return 2.0 * np.abs(z - zp) ** 2 / (one_minus_abs2(z) * one_minus_abs2(zp))


# ----------------------------------------------------------------------------
# closed forms
# ----------------------------------------------------------------------------

def _q0_of_ym1(nu: complex, ym1: np.ndarray) -> np.ndarray:
    r""":math:`Q_\nu(1 + y_{m1})`, inf at coincident points, and the logarithmic expansion
    :math:`-\frac12\ln(y_{m1}/2) - \gamma - \psi(\nu+1)` (DLMF 14.8.9 for x>1) where
    :math:`1 + y_{m1}` rounds too close to 1 for a direct evaluation."""
    shape = np.shape(ym1)
    ym1 = np.ravel(ym1)
    out = np.empty(ym1.shape, complex)
    coincide = ym1 == 0.0
    tiny = (ym1 < 1e-12) & ~coincide
    normal = ~(coincide | tiny)
    out[coincide] = complex(np.inf, 0.0)
    if np.any(tiny):
        out[tiny] = -0.5 * np.log(ym1[tiny] / 2.0) - np.euler_gamma - sc.psi(nu + 1.0)
    if np.any(normal):
        y = 1.0 + ym1[normal]
        out[normal] = legendre_q(nu, 0, y)
        # y - 1 after rounding differs from ym1 by ~eps: near y = 1, Q_nu = -P_nu ln(y-1)/2 + ...,
        # so correct by -P_nu/2 ln(ym1/(y-1)) (first order; otherwise an error ~eps/(y-1))
        close = ym1[normal] < 1e-2
        if np.any(close):
            idx = np.flatnonzero(normal)[close]
            le = np.log(ym1[idx]) - np.log(y[close] - 1.0)
            out[idx] -= 0.5 * le * legendre_p(nu, 0, y[close])
    return out.reshape(shape)


def fundamental_solution(z, zp, lam) -> complex | np.ndarray:
    r"""Fundamental solution ``green34``: :math:`\mathcal G_0 = \frac1{2\pi}Q_\nu(\cosh 2d(z,z'))`.

    Branch of :math:`\nu` as in :func:`green_nu` (the decaying solution).

    Parameters
    ----------
    z, zp : complex or array_like of complex
        Points of the open unit disk; they broadcast against each other.
    lam : float or complex
        Helmholtz parameter :math:`\lambda`, :math:`|\lambda| \le` :data:`MAX_LAMBDA`.

    Returns
    -------
    complex or ndarray of complex
        :math:`\mathcal G_0(z, z')`; ``inf`` where :math:`z = z'`.

    Raises
    ------
    ValueError
        If a point lies outside the unit disk, the shapes do not broadcast (or give more than
        ``2**25`` pairs), or ``lam`` is not finite or too large.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green34``).

    Examples
    --------
    >>> from hyperlattice.continuum.green import fundamental_solution
    >>> print(f"{fundamental_solution(0.0, 0.5, 0.5).real:.6f}")
    0.142675
    """
    lam = _check_lambda(lam, evaluated=True)
    z = _check_points("z", z, 1.0, False)
    zp = _check_points("z'", zp, 1.0, False)
    z, zp = _pairs(z, zp)
    val = _q0_of_ym1(green_nu(lam), _cosh2d(z, zp))
    val.real *= 1.0 / (2.0 * np.pi)     # part-wise: inf at coincident points stays inf + 0j
    val.imag *= 1.0 / (2.0 * np.pi)
    return val[()] if val.ndim == 0 else val


def _laplace(z: np.ndarray, zp: np.ndarray, L: float) -> np.ndarray:
    r"""``eq23`` in the scaled coordinates :math:`u = z/L`: :math:`-\frac1{2\pi}\ln|(u-u')/(1-u\bar u')|`
    (the same function; no overflow or underflow of :math:`L^2` for tiny disks)."""
    u, up = z / L, zp / L
    with np.errstate(divide="ignore"):
        return -np.log(np.abs(u - up) / np.abs(1.0 - u * np.conj(up))) / (2.0 * np.pi)


def green_laplace(z, zp, radius=1.0) -> float | np.ndarray:
    r"""The :math:`\lambda = 0` Green function in closed form (the paper's ``eq23``).

    .. math:: G(z,z',0,L) = -\frac1{4\pi}\ln\Bigl|\frac{L(z-z')}{L^2-z\bar z'}\Bigr|^2.

    Points with :math:`L < |z| < 1` are allowed (the continuation of the closed form).

    Parameters
    ----------
    z, zp : complex or array_like of complex
        Points of the open unit disk; they broadcast against each other.
    radius : float, optional
        Disk radius :math:`0 < L \le 1` (default 1).

    Returns
    -------
    float or ndarray of float
        :math:`G(z, z', 0, L)` (real); ``inf`` at coincident points, 0 on :math:`|z| = L`.

    Raises
    ------
    ValueError
        If the radius is outside (0, 1], a point lies outside the unit disk, or the shapes do
        not broadcast.

    See Also
    --------
    continuum_green

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (21).

    Examples
    --------
    >>> from hyperlattice.continuum.green import green_laplace
    >>> print(f"{green_laplace(0.0, 0.5, 0.8):.6f}")
    0.074803
    """
    L = _check_radius(radius)
    z = _check_points("z", z, L, True)
    zp = _check_points("z'", zp, L, True)
    z, zp = _pairs(z, zp)
    val = _laplace(z, zp, L)
    return val[()] if val.ndim == 0 else val


def green_infinite_disk(z, zp, lam) -> complex | np.ndarray:
    r"""The Green function of the whole disk, :math:`L = 1`: :math:`G = \frac1{2\pi}Q_\nu(y)`.

    :math:`y = \cosh 2d(z,z')`, with the decaying root (``green30``). Equal to the paper's
    :math:`\frac1{2\pi}[Q_{\nu_p}(y)-\mathcal C P_{\nu_p}(y)]`; requires
    :math:`\lambda\notin[1,\infty)` (there the infinite disk has continuous spectrum).

    Parameters
    ----------
    z, zp : complex or array_like of complex
        Points of the open unit disk; they broadcast against each other.
    lam : float or complex
        Helmholtz parameter :math:`\lambda`, not on :math:`[1, \infty)`.

    Returns
    -------
    complex or ndarray of complex
        :math:`G(z, z', \lambda, 1)`; ``inf`` at coincident points.

    Raises
    ------
    ValueError
        If ``lam`` lies on :math:`[1, \infty)`, is not finite or exceeds :data:`MAX_LAMBDA`, or
        the points are invalid.

    See Also
    --------
    continuum_green, fundamental_solution

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green30``).

    Examples
    --------
    >>> from hyperlattice.continuum.green import green_infinite_disk
    >>> print(f"{green_infinite_disk(0.0, 0.5, 0.5).real:.6f}")
    0.142675
    """
    lam = _check_lambda(lam, evaluated=True)
    if lam.imag == 0 and lam.real >= 1.0:
        raise ValueError(f"lambda = {lam.real:g} lies on the continuous spectrum [1, inf) of -Delta_g "
                         "on the infinite disk (L = 1); give it an imaginary part or use L < 1.")
    return fundamental_solution(z, zp, lam)


# ----------------------------------------------------------------------------
# the boundary correction green36
# ----------------------------------------------------------------------------

def _logpoch(nu: complex, m: int) -> complex:
    """log Gamma(nu+m+1)/Gamma(nu-m+1) = sum_{j=1-m}^{m} log(nu+j) (complex, no overflow)."""
    if m == 0:
        return 0j
    return complex(np.sum(np.log(nu + np.arange(1 - m, m + 1) + 0j)))


def _ptilde_log0(nu, m, x):
    """log-scaled P~^m(x) from the Legendre module (m <= 1 here): (real scale, complex mantissa)."""
    s, mt = legendre_log_p(nu, m, x)
    lp = _logpoch(nu, m)
    return s - lp.real, mt * np.exp(-1j * lp.imag)


def _rescale(a, b, sig):
    """Divide the pair (a, b) by |a| where |a| > _RESCALE; keep the log in sig (per point)."""
    big = np.abs(a) > _RESCALE
    if np.any(big):
        f = np.where(big, np.abs(a), 1.0)
        return a / f, b / f, sig + np.log(f)
    return a, b, sig


def _log_eta(r: np.ndarray, rho: np.ndarray) -> np.ndarray:
    r""":math:`\ln(w_{\rm exact}/w)` with :math:`w = (\rho-1)/(\rho+1)` of the rounded argument
    :math:`\rho` and :math:`w_{\rm exact} = r^2`.

    The Legendre module takes :math:`x = \rho`, whose :math:`x - 1 = 2r^2/(1-r^2)` is only
    :math:`\sim\varepsilon/r^2` accurate after rounding. Near :math:`x = 1` the values depend on
    :math:`w` through :math:`w^{\pm m/2}` (and :math:`\ln w` for :math:`Q_\nu`), so
    multiplying by :math:`(w_{\rm exact}/w)^{\pm m/2}` restores full accuracy to first order;
    the remainder is :math:`O(\varepsilon|\nu|^2)`. (Without it a disk of radius
    :math:`L = 10^{-4}` was only accurate to :math:`10^{-8}`.)
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((rho > 1.0) & (r > 0), np.log(r * r) - np.log((rho - 1.0) / (rho + 1.0)), 0.0)


def _miller_start(nu: complex, c: float, M: int, Ms_min: int, target: float = 1e-17,
                  max_extra: int = 20000) -> tuple[int, float]:
    r"""Start :math:`M_s` of Miller's recurrence and the contamination it leaves at order ``M``.

    Going down, :math:`f_m = A_m f_{m+1} + B_m f_{m+2}` (:math:`A_m = 2(m+1)c`,
    :math:`B_m = (\nu-m-1)(\nu+m+2)`, :math:`c = (1+r^2)/2r`) has local ratios :math:`u =
    f_{m+1}/f_m` solving :math:`B_m u^2 + A_m u - 1 = 0`; the unwanted solution shrinks by
    :math:`|u_<|/|u_>|` per step (:math:`\to r^2` for :math:`m \gg |\nu|\sinh t`, but 1 in the
    oscillatory range :math:`m \lesssim |\nu|\sinh t` of large :math:`|\nu|`, where a start
    depth fixed by :math:`r` alone left errors up to :math:`10^{-3}` at :math:`\lambda = 3000`).
    The start is the first order beyond ``Ms_min`` where the product of these factors from ``M``
    reaches ``target``, at most ``max_extra`` orders above that.
    """
    if not math.isfinite(c):
        return Ms_min, 0.0
    log_target = math.log(target)
    acc = 0.0
    m = M
    top = max(Ms_min, M) + max_extra
    while m < top and (acc > log_target or m < Ms_min):
        A = 2.0 * (m + 1) * c
        B = (nu - m - 1) * (nu + m + 2)
        if B == 0:
            acc = -math.inf
        else:
            disc = complex(np.sqrt(complex(A * A + 4.0 * B)))
            u1, u2 = abs((-A + disc) / (2.0 * B)), abs((-A - disc) / (2.0 * B))
            small, big = min(u1, u2), max(u1, u2)
            acc += math.log(small / big) if small > 0 else -math.inf
        m += 1
    return m, math.exp(acc)


def _ptilde_table(nu: complex, rho: np.ndarray, M: int, r_split: float, r: np.ndarray | None = None):
    r"""Table of :math:`\tilde P^m_\nu(\rho_k)`, m = 0..M, as (mantissa, log-scale), each (M+1, n).

    Radii :math:`r \le` ``r_split``: Miller's backward recurrence (``P~`` dominant downward)
    from :math:`M_s = M + \lceil\ln 10^{-17}/(2\ln r_{\max})\rceil`, normalised to the module's
    :math:`\tilde P^0, \tilde P^1`; its contamination by the other solution is
    :math:`\sim r^{2(M_s-m)}`, which fixes the extra steps. Radii above ``r_split``: upward
    recurrence of :math:`P^m` (no division, module values at m = 0, 1) divided by
    :math:`\Gamma(\nu+m+1)/\Gamma(\nu-m+1)`; its relative error grows like :math:`r^{-2m}`,
    harmless where :math:`r` is close to 1. ``r`` are the exact radii (:math:`\rho` rounded from
    them, see :func:`_log_eta`); radii so small that :math:`\rho` rounds to 1 get
    :math:`\tilde P^m = r^m/m!` (exact to :math:`O(|\nu|^2r^2)`). Returns also the Miller
    contamination bound and the mask of the radii that ran upward.
    """
    n = rho.size
    mant = np.zeros((M + 1, n), complex)
    logs = np.zeros((M + 1, n))
    if r is None:
        r = np.sqrt((rho - 1.0) / (rho + 1.0))
    at_one = rho == 1.0
    rho_run = np.where(at_one, 2.0, rho)
    r_run = np.where(at_one, 1.0 / math.sqrt(3.0), r)
    # x / sqrt(x^2 - 1) = (1 + r^2)/(2r) from the exact radius
    c = (1.0 + r_run * r_run) / (2.0 * r_run)
    s0, m0 = _ptilde_log0(nu, 0, rho_run)
    s1, m1 = _ptilde_log0(nu, 1, rho_run) if M >= 1 else (s0, m0)
    s1 = s1 + 0.5 * _log_eta(r_run, rho_run)          # P~^1 ~ w^(1/2)
    contamination = 0.0

    down = r <= r_split
    if np.any(down):
        idx = np.flatnonzero(down)
        rmax = float(r[idx].max())
        extra = 0 if rmax < 1e-3 else int(math.ceil(math.log(1e-17) / (2.0 * math.log(rmax))))
        extra = min(max(extra, 8), 6000)
        # turning point of the recurrence at the outermost radius: below it the two solutions
        # oscillate with equal size and Miller's start must lie well beyond it
        m_turn = abs(nu) * 2.0 * rmax / ((1.0 - rmax) * (1.0 + rmax))
        if 3.0 * m_turn <= M + extra:
            # small |nu|: the unwanted solution shrinks like r^2 per step (measured: 1e-14 at r = 0.9)
            Ms, contamination = M + extra, rmax ** (2 * extra)
        else:
            Ms, contamination = _miller_start(nu, (1.0 + rmax * rmax) / (2.0 * rmax), M, M + extra)
        cc = c[idx]
        a_hi = np.zeros(idx.size, complex)        # f_{Ms+1}
        a = np.ones(idx.size, complex)            # f_{Ms}
        # log of the rescaling applied at order m (m <= M): the log-scale of f_m relative to f_0
        # is minus the sum of these below m, summed from m = 0 upwards so that it is exact to
        # rounding where the terms are large (a running scale from M_s down would carry an
        # absolute error ~ eps * ln(M_s!) ~ 1e-12 into every low order)
        step_log = np.zeros((M + 1, idx.size))
        for m in range(Ms, -1, -1):
            if m < Ms:
                new = 2.0 * (m + 1) * cc * a + (nu - m - 1) * (nu + m + 2) * a_hi
                a_hi, a = a, new
                big = np.abs(a) > _RESCALE
                if np.any(big):
                    f = np.where(big, np.abs(a), 1.0)
                    a, a_hi = a / f, a_hi / f
                    if m <= M:
                        step_log[m] = np.log(f)
            if m <= M:
                mant[m, idx] = a
        rel = np.zeros((M + 1, idx.size))
        if M >= 1:
            rel[1:] = -np.cumsum(step_log[:-1], axis=0)
        logs[:, idx] = rel
        # normalise with the accurate m = 0, 1 values (least squares over the two, so that a
        # zero of P~^0 does not spoil the scale)
        base = logs[0, idx].copy()
        f0 = mant[0, idx]
        f1 = mant[1, idx] * np.exp(logs[1, idx] - base) if M >= 1 else f0
        t0 = m0[idx]
        t1 = m1[idx] * np.exp(s1[idx] - s0[idx]) if M >= 1 else t0
        norm = (np.conj(f0) * t0 + np.conj(f1) * t1) / (np.abs(f0) ** 2 + np.abs(f1) ** 2)
        mant[:, idx] *= norm
        logs[:, idx] += s0[idx] - base

    up = ~down
    if np.any(up):
        idx = np.flatnonzero(up)
        cc = c[idx]
        # P^m = g_m P~^m with g_0 = 1, g_1 = nu(nu+1): start from the module's P^0, P^1
        lg1 = _logpoch(nu, 1)
        sig = s0[idx].copy()
        a_lo = m0[idx].copy()                                          # P^0 / e^sig
        a = m1[idx] * np.exp(s1[idx] + lg1.real - sig) * np.exp(1j * lg1.imag)   # P^1 / e^sig
        mant[0, idx], logs[0, idx] = a_lo, sig
        lg = 0j
        for m in range(1, M + 1):
            if m > 1:
                k = m - 2
                new = -2.0 * (k + 1) * cc * a + (nu - k) * (nu + k + 1) * a_lo
                a_lo, a = a, new
                a, a_lo, sig = _rescale(a, a_lo, sig)
            # log g_m; nu + (1 - m) with the integer formed first: (nu - m) + 1 would cancel
            # to O(eps) for |nu| << 1 (nu - m + 1 = 0 + nu exactly at m = 1)
            lg += np.log(nu + m + 0j) + np.log(nu + (1 - m) + 0j)
            mant[m, idx] = a * np.exp(-1j * lg.imag)
            logs[m, idx] = sig - lg.real
    if np.any(at_one):
        mant[:, at_one] = 0.0
        mant[0, at_one] = 1.0
        logs[:, at_one] = 0.0
        tiny = at_one & (r > 0)
        if np.any(tiny):
            m = np.arange(M + 1)[:, None]
            mant[:, tiny] = 1.0
            logs[:, tiny] = m * np.log(r[tiny])[None, :] - sc.gammaln(m + 1.0)
    return mant, logs, contamination, up & ~at_one


def _q_boundary(nu: complex, x_L: float, M: int, L: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    r""":math:`Q_\nu^m(x_L)`, m = 0..M, as (log-scale, mantissa).

    The Legendre module's values up to :data:`_Q_DIRECT`, then the upward recurrence DLMF 14.10.6,
    :math:`Q^{m+2} = -2(m+1)\frac{x}{\sqrt{x^2-1}}Q^{m+1} + (\nu-m)(\nu+m+1)Q^m`, in which
    :math:`Q` is the dominant solution (stable), with a running log-scale. With the exact radius
    ``L`` the module's values are corrected for the rounding of :math:`x_L` (:func:`_log_eta`):
    :math:`Q^m \propto w^{-m/2}` for m >= 1, :math:`Q^0 \approx -\frac12 P_\nu\ln w + \dots`.
    """
    m_direct = min(M, _Q_DIRECT)
    sq = np.empty(M + 1)
    mq = np.empty(M + 1, complex)
    sq[: m_direct + 1], mq[: m_direct + 1] = legendre_log_q(nu, np.arange(m_direct + 1), x_L)
    c = x_L / math.sqrt((x_L - 1.0) * (x_L + 1.0))
    if L is not None:
        c = (1.0 + L * L) / (2.0 * L)
        le = float(_log_eta(np.array([L]), np.array([x_L]))[0])
        if le != 0.0:
            sp, mp_ = legendre_log_p(nu, 0, x_L)
            q0 = complex(mq[0]) - 0.5 * le * complex(mp_) * math.exp(float(sp) - sq[0])
            mq[0] = q0
            sq[1: m_direct + 1] -= 0.5 * le * np.arange(1, m_direct + 1)
    if M > m_direct:
        sig = float(sq[m_direct])
        a = complex(mq[m_direct])
        a_lo = complex(mq[m_direct - 1]) * math.exp(sq[m_direct - 1] - sig)
        for j in range(m_direct - 1, M - 1):          # Q^{j+2} from Q^{j+1}, Q^j
            new = -2.0 * (j + 1) * c * a + (nu - j) * (nu + j + 1) * a_lo
            a_lo, a = a, new
            f = abs(a)
            if f > _RESCALE:
                a, a_lo, sig = a / f, a_lo / f, sig + math.log(f)
            sq[j + 2], mq[j + 2] = sig, a
    return sq, mq


def _series(nu, rho_u, r_u, iu, ju, dphi, x_L, L, M, r_split, *, accel, rpair):
    """Sum green36 over m = 0..M for pairs (iu, ju) of distinct radii ``r_u`` (L last; ``rho_u``
    their arguments (1+r^2)/(1-r^2)).

    With ``accel`` the lambda = 0 terms are subtracted (``rpair`` = (r r', r r'/L^2) per pair);
    the caller adds their closed form. Returns (sum, envelope of term M, envelope of term M-1,
    Miller contamination bound, rounding estimate of the upward recurrence).
    """
    mant, logs, contamination, up = _ptilde_table(nu, rho_u, M, r_split, r_u)
    # a vanishing P~^m(rho_L) makes the boundary factor infinite: lambda is a Dirichlet
    # eigenvalue; compare each P~^m(rho_L) with the terms of the recurrence that produce it, on
    # its own scale, to decide "zero to rounding"
    pL, sL = mant[:, -1], logs[:, -1]
    if M >= 2:
        c_L = (1.0 + L * L) / (2.0 * L)
        m = np.arange(M - 1)
        with np.errstate(over="ignore", under="ignore"):
            env = (np.abs(2.0 * (m + 1) * c_L * pL[1:-1]) * np.exp(sL[1:-1] - sL[:-2])
                   + np.abs((nu - m - 1) * (nu + m + 2) * pL[2:]) * np.exp(sL[2:] - sL[:-2]))
        small = np.abs(pL[:-2]) <= _EIGEN_REL * env
        with np.errstate(divide="ignore", invalid="ignore"):
            cond = np.concatenate([env / np.abs(pL[:-2]), [1.0, 1.0]])
    else:
        small = np.abs(pL) == 0
        cond = np.ones(M + 1)
    if np.any(small) or not np.all(np.isfinite(pL)):
        m_bad = int(np.argmax(small)) if np.any(small) else -1
        raise ValueError(f"lambda is (within rounding of) a Dirichlet eigenvalue of the disk of radius L "
                         f"(P_nu^m(rho_L) = 0 for m = {m_bad}); the Green function does not exist there.")
    sq, mq = _q_boundary(nu, x_L, M, L)
    # relative rounding growth of the upward recurrence, per radius: log of r^-2 (0 for Miller radii)
    grow = np.where(up, -2.0 * np.log(np.where(up, r_u, 1.0)), 0.0)
    w_up = up.astype(float)
    any_up = bool(np.any(up))
    c1 = np.cos(dphi)
    cm_prev, cm = np.ones_like(dphi), np.ones_like(dphi)
    total = np.zeros(iu.shape, complex)
    rounding = np.zeros(iu.shape)
    env_M = env_M1 = None
    if accel:
        rr, qq = rpair
        with np.errstate(divide="ignore"):
            log_rr, log_qq = np.log(rr), np.log(qq)
    for m in range(M + 1):
        if m == 1:
            cm_prev, cm = cm, c1
        elif m > 1:
            cm_prev, cm = cm, 2.0 * c1 * cm - cm_prev
        expo = logs[m, iu] + logs[m, ju] - logs[m, -1] + sq[m]
        with np.errstate(over="ignore", under="ignore", invalid="ignore"):
            mag = (mq[m] / mant[m, -1]) * mant[m, iu] * mant[m, ju] * np.exp(expo)
        mag = mag * ((2.0 if m else 1.0) * (-1.0 if m % 2 else 1.0) / (2.0 * np.pi))
        if any_up:
            with np.errstate(over="ignore"):
                g = (w_up[iu] * np.exp(np.minimum(m * grow[iu], 700.0))
                     + w_up[ju] * np.exp(np.minimum(m * grow[ju], 700.0))
                     + w_up[-1] * math.exp(min(m * grow[-1], 700.0)))
            # only an amplification beyond 100x counts: plain rounding (a few eps of the largest
            # term) is below every tolerance accepted and is not part of the estimate
            rounding += 4.0 * _EPS * np.abs(mag) * np.maximum(g - 100.0, 0.0)
        if cond[m] > 100.0:
            # P~^m(rho_L) near one of its zeros (lambda near a Dirichlet eigenvalue of order m):
            # its relative error, ~1e-13 of the recurrence envelope (measured), grows like env/|P~^m|
            rounding += 3e-13 * cond[m] * np.abs(mag)
        if accel:
            # t_m at lambda = 0 (module docstring), the terms of the eq23 correction
            if m == 0:
                mag = mag + math.log(L) / (2.0 * np.pi)
            else:
                with np.errstate(under="ignore"):
                    mag = mag - (np.exp(m * log_qq) - np.exp(m * log_rr)) / (2.0 * np.pi * m)
        if m == M:
            env_M = np.abs(mag)
        elif m == M - 1:
            env_M1 = np.abs(mag)
        total += mag * cm
    if env_M1 is None:
        env_M1 = env_M
    return total, env_M, env_M1, contamination, rounding


def _laplace_correction(z, zp, L):
    r""":math:`\delta\mathcal G_0 = \frac1{4\pi}\ln\frac{L^2|1-z\bar z'|^2}{|L^2-z\bar z'|^2}`, the
    ``green36`` correction at :math:`\lambda = 0` (``green34`` minus ``eq23``)."""
    a = z * np.conj(zp)
    return (np.log(np.abs(1.0 - a)) - np.log(np.abs(1.0 - (z / L) * np.conj(zp / L))) - math.log(L)) / (2.0 * np.pi)


def _boundary_correction(nu, z, zp, L, tol, max_terms, g0_abs):
    """delta G of green36 for flattened pair arrays: (dG, absolute tail estimate, absolute rounding
    estimate of the upward recurrence, M, accelerated)."""
    r, rp = np.abs(z), np.abs(zp)
    ratio = (r / L) * (rp / L)
    qmax = float(ratio.max()) if ratio.size else 0.0
    if qmax >= 1.0:
        raise ValueError("the Fourier series of green36 diverges for these points (|z||z'| >= L^2); "
                         "at least one of z, z' must lie well inside the disk.")
    # a-priori order from |t_m| ~ qmax^m / m
    if qmax > 0:
        M = int(math.ceil(math.log(tol) / math.log(qmax))) + 3
    else:
        M = 2
    accel = M > _PLAIN_TERMS
    if accel:
        # the differences t_m - t_m^(0) fall like qmax^m / m^2: solve qmax^M / M^2 = tol
        for _ in range(4):
            M = int(math.ceil(math.log(tol * M * M) / math.log(qmax))) + 3
    # large |nu|: the terms oscillate without decaying up to the turning point m ~ |nu| sinh t of
    # the inner point of each pair (sinh t = 2r/(1-r^2)), whatever q says; never stop before it
    r_in = np.minimum(r, rp)
    floor = np.ceil(abs(nu) * 2.0 * r_in / ((1.0 - r_in) * (1.0 + r_in)))
    M = max(M, int(floor.max()) if floor.size else 0)
    M = max(4, min(M, max_terms))
    # Miller below r_split, upward recurrence above (see _ptilde_table): the upward error
    # (r'/(r L^2))^m stays O(1) for r >= r'/L^2, so r_split follows the outermost source.
    r_split = min(max(0.9, float(rp.max()) / (L * L) if rp.size else 0.0), 0.995)
    if abs(nu.imag) < 1e-3 and nu.real > 0.5 and abs(nu.real - round(nu.real)) < 1e-3:
        # near nu = n >= 1 the upward recurrence of P^m cancels to O(nu - n): Miller only
        r_split = 1.0
    return _correction_pairs(nu, z, zp, r, rp, ratio, L, tol, max_terms, g0_abs, M, r_split, accel, floor)


def _correction_pairs(nu, z, zp, r, rp, ratio, L, tol, max_terms, g0_abs, M, r_split, accel, floor):
    """The doubling loop of :func:`_boundary_correction` on one set of pairs, split in halves
    whenever its (M+1) x radii tables would exceed :data:`_TABLE_BYTES`."""
    x_L = (1.0 + L * L) / ((1.0 - L) * (1.0 + L))
    # distinct radii (not arguments: tiny radii may round to the same rho = 1), L last
    r_u, inv = np.unique(np.concatenate([r, rp]), return_inverse=True)
    r_u = np.append(r_u, L)
    rho_u = (1.0 + r_u * r_u) / ((1.0 - r_u) * (1.0 + r_u))
    rho_u[-1] = x_L
    iu, ju = inv[: len(r)], inv[len(r):]
    dphi = np.angle(z) - np.angle(zp)
    rpair = ((r * rp), ratio)
    while True:
        if (M + 1) * rho_u.size * 48 > _TABLE_BYTES and z.size > 1:
            h = z.size // 2
            parts = [_correction_pairs(nu, z[s], zp[s], r[s], rp[s], ratio[s], L, tol, max_terms, g0_abs[s],
                                       M, r_split, accel, floor[s]) for s in (slice(0, h), slice(h, None))]
            return (np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts]),
                    np.concatenate([p[2] for p in parts]), max(p[3] for p in parts), any(p[4] for p in parts))
        dG, env_M, env_M1, contamination, rounding = _series(nu, rho_u, r_u, iu, ju, dphi, x_L, L, M, r_split,
                                                             accel=accel, rpair=rpair)
        if accel:
            dG = dG + _laplace_correction(z, zp, L)
        with np.errstate(divide="ignore", invalid="ignore"):
            measured = np.where(env_M1 > 0, env_M / env_M1, 0.0)
        rate = np.minimum(np.maximum(ratio, measured), 0.999)
        tail = env_M * rate / (1.0 - rate) + contamination * np.abs(dG)
        # before the turning point the envelope says nothing: no accuracy is claimed there
        tail = np.where(M >= floor, tail, np.maximum(tail, g0_abs + np.abs(dG)))
        if np.all(tail <= tol * (g0_abs + np.abs(dG))) or M >= max_terms:
            # the amplified rounding is reported separately: more terms would not reduce it
            return dG, tail, rounding, M, accel
        if not accel and M < _PLAIN_TERMS:
            M = min(2 * M, _PLAIN_TERMS, max_terms)
        elif not accel:
            # slow convergence (both points near the circle): subtract the lambda = 0 series
            accel = True
        else:
            M = min(2 * M, max_terms)


def continuum_green(z, zp, lam, radius=1.0, *, tol: float = 1e-12, extend: bool = False,
                    max_terms: int = _MAX_TERMS,
                    return_info: bool = False) -> complex | np.ndarray | tuple[complex | np.ndarray, GreenInfo]:
    r"""Dirichlet Green function :math:`G(z, z', \lambda, L)` of :math:`\lambda + \Delta_g` (``green1``).

    Vectorized over ``z`` and ``zp`` (broadcast against each other). Forms (see module
    docstring): Eq. (21) for :math:`\lambda = 0`, :math:`\frac1{2\pi}Q_\nu(y)` for :math:`L=1`
    (``green30``), ``green33`` = ``green34`` - ``green36`` otherwise.

    Parameters
    ----------
    z, zp : complex or array_like
        Points of the disk (:math:`|z| \le L`). At coincident points the value is ``inf``;
        on the circle :math:`|z| = L` it is 0.
    lam : complex
        Helmholtz parameter :math:`\lambda` (Eq. (19): :math:`4(\omega+q)/(qh^2)`).
    radius : float, optional
        Disk radius :math:`0 < L \le 1` (default 1).
    tol : float, optional
        Target for the truncation error of the ``green36`` sum, relative to
        :math:`|\mathcal G_0| + |\delta\mathcal G|` at each pair (the size of the terms that
        cancel near the boundary); ``1e-15 <= tol < 1`` (default 1e-12).
    extend : bool, optional
        Allow points with :math:`L < |z| < 1` (analytic continuation of ``green33`` across the
        Dirichlet circle, needed to compare with the outermost sites of a lattice, which may lie
        slightly outside the area-matched radius of Eq. (10)). Requires :math:`|z||z'| < L^2`.
        Default False.
    max_terms : int, optional
        Cap on the number of Fourier orders (default 4000, at most :data:`MAX_TERMS`).
    return_info : bool, optional
        Also return a :class:`GreenInfo` with the truncation order and tail estimate
        (default False).

    Returns
    -------
    G : complex or ndarray of complex
        :math:`G(z, z', \lambda, L)`, with the broadcast shape of ``z`` and ``zp``. Multiply by
        :func:`hyperlattice.dictionary.green_prefactor` to compare with the lattice
        :math:`G_{ij}(\omega)`.
    info : GreenInfo
        Only if ``return_info``: ``method``, ``nu``, ``terms``, ``tail_estimate``, ``tol`` and
        ``rounding_estimate``.

    Raises
    ------
    ValueError
        NaN input, :math:`L\notin(0,1]`, points outside the disk, :math:`\lambda` on
        :math:`[1,\infty)` for :math:`L=1`, :math:`\lambda` a Dirichlet eigenvalue,
        :math:`|\lambda|` > :data:`MAX_LAMBDA`, more than ``2**25`` pairs, or a disk too small for
        double precision (module docstring).
    ConvergenceError
        If the ``green36`` series overflows double precision for points too close to the
        boundary.

    Warns
    -----
    ConvergenceWarning
        If the estimated truncation error exceeds ``tol`` after ``max_terms`` orders.

    See Also
    --------
    green_laplace, green_infinite_disk, hyperlattice.graph.green.graph_green,
    hyperlattice.compare.green.compare_green

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eqs. (19) and (21), Appendices H and I.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.continuum_green(0.0, 0.5, 0.5, 0.8).real:.6f}")
    0.083223
    >>> g, info = hl.continuum_green(0.1, 0.3j, 2.0, 0.8, return_info=True)
    >>> print(f"{g.real:.6f}", info.method)
    0.217139 series
    >>> print(f"{hl.continuum_green(0.0, 0.5, 0.0, 0.8).real:.6f}")
    0.074803
    """
    lam = _check_lambda(lam, evaluated=True)
    L = _check_radius(radius)
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1.0, open_max=True)
    extend = _validate.flag("extend", extend)
    max_terms = _validate.positive_int("max_terms", max_terms, maximum=MAX_TERMS)
    return_info = _validate.flag("return_info", return_info)
    z = _check_points("z", z, L, extend)
    zp = _check_points("z'", zp, L, extend)
    zb, zpb = _pairs(z, zp)
    shape = zb.shape
    zf, zpf = zb.ravel(), zpb.ravel()
    nu = green_nu(lam)

    def finish(val, info):
        val = val.reshape(shape)
        val = val[()] if val.ndim == 0 else val
        return (val, info) if return_info else val

    # lambda = 0, nu rounded to 0 (|lambda| < ~4e-16), or a disk so small that the O(lambda L^2)
    # difference from eq23 is below rounding: the closed form
    if lam == 0 or nu == 0 or (L < 1.0 and abs(lam) * L * L <= _SMALL_DISK):
        val = _laplace(zf, zpf, L).astype(complex)
        return finish(val, GreenInfo(method="laplace", nu=nu, terms=0, tail_estimate=0.0, tol=tol))
    if L == 1.0:
        val = green_infinite_disk(zf, zpf, lam)
        return finish(np.asarray(val, complex),
                      GreenInfo(method="infinite_disk", nu=nu, terms=0, tail_estimate=0.0, tol=tol))
    if (1.0 + L * L) / ((1.0 - L) * (1.0 + L)) - 1.0 < 16 * _EPS:
        raise ValueError(f"the disk radius L = {L:g} is too small for lambda = {lam:g}: x_L - 1 = 2L^2/(1-L^2) "
                         "is lost to rounding in double precision, while |lambda| L^2 is not negligible.")

    # green34 at all pairs (the continuation beyond |z| = L stays inside the unit disk)
    g0 = _q0_of_ym1(nu, _cosh2d(zf, zpf))
    g0.real *= 1.0 / (2.0 * np.pi)      # part-wise: inf at coincident points stays inf + 0j
    g0.imag *= 1.0 / (2.0 * np.pi)
    # on the circle G = 0 exactly (the boundary condition): no series there
    on_circle = (np.abs(np.abs(zf) - L) <= 4e-16 * L) | (np.abs(np.abs(zpf) - L) <= 4e-16 * L)
    val = np.zeros(zf.shape, complex)
    tail = np.zeros(zf.shape)
    rounding = np.zeros(zf.shape)
    dG = np.zeros(zf.shape, complex)
    M, accel = 0, False
    inner = np.flatnonzero(~on_circle)
    if inner.size:
        with np.errstate(over="ignore", invalid="ignore"):
            dGi, tail[inner], rounding[inner], M, accel = _boundary_correction(nu, zf[inner], zpf[inner], L, tol,
                                                                               max_terms, np.abs(g0[inner]))
        # terms of a series with up to max_terms orders can overflow double precision for points
        # very close to the circle; a NaN there must not pass as a value (or as a NaN error estimate)
        bad = np.isfinite(g0[inner]) & ~(np.isfinite(dGi) & np.isfinite(tail[inner]) & np.isfinite(rounding[inner]))
        if np.any(bad):
            k = inner[np.flatnonzero(bad)[0]]
            ratio = abs(zf[k]) * abs(zpf[k]) / (L * L)
            raise ConvergenceError(f"green36 overflows double precision at m <= {M} for points this close to the "
                                   f"circle (|z||z'|/L^2 = {ratio:.6f}); the Fourier series cannot be summed there.")
        dG[inner] = dGi
        val[inner] = g0[inner] - dGi
    finite = np.isfinite(g0) & ~on_circle
    scale = np.where(finite, np.abs(g0) + np.abs(dG), np.inf)
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(finite, tail / np.maximum(scale, 1e-300), 0.0)
        rel_round = np.where(finite, rounding / np.maximum(scale, 1e-300), 0.0)
    worst = float(rel.max()) if rel.size else 0.0
    worst_round = float(rel_round.max()) if rel.size else 0.0
    if worst > tol:
        warnings.warn(f"green36 truncated at m = {M} with estimated relative error {worst:.1e} > tol = {tol:.1e} "
                      "(points too close to the boundary for the Fourier series); raise max_terms.",
                      ConvergenceWarning, stacklevel=2)
    if worst_round > tol:
        warnings.warn(f"green36: rounding errors amplified to an estimated relative error {worst_round:.1e} > "
                      f"tol = {tol:.1e} (lambda close to a Dirichlet eigenvalue, or the upward recurrence of "
                      f"P^m near the circle with m up to {M}).", ConvergenceWarning, stacklevel=2)
    method = "series-accelerated" if accel else "series"
    return finish(val, GreenInfo(method=method, nu=nu, terms=M + 1 if inner.size else 0, tail_estimate=worst,
                                 tol=tol, rounding_estimate=worst_round))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
