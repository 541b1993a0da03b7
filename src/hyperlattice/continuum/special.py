r"""Associated Legendre functions of complex degree for real argument :math:`x \ge 1`.

The continuum theory of the paper (``eq16``, ``eig18``, ``spec2``, ``green17``/``green18``)
needs :math:`P_\nu^m(x)` and :math:`Q_\nu^m(x)` for integer order :math:`m \ge 0`, real
:math:`x = (1+r^2)/(1-r^2) \ge 1` and complex degree :math:`\nu`; most often
:math:`\nu = \tfrac12(-1 + \mathrm{i}k)` (conical functions, :math:`\lambda = 1+k^2 > 1`),
real :math:`\nu` (:math:`\lambda < 1`), or general complex :math:`\nu` (complex :math:`\lambda`).
SciPy offers none of these and mpmath needs milliseconds per value, so this module evaluates
them vectorized in double precision.

Convention
----------
Both functions follow DLMF §14.3 for :math:`x > 1` ("type 3", also mpmath's ``type=3`` and
Abramowitz & Stegun §8), with :math:`\mu = m` an integer:

.. math::

    P_\nu^m(x) = (x^2-1)^{m/2} \frac{d^m P_\nu(x)}{dx^m}
               = \Bigl(\frac{x+1}{x-1}\Bigr)^{m/2}\,
                 \mathbf{F}\bigl(\nu+1, -\nu; 1-m; \tfrac{1-x}{2}\bigr),

    Q_\nu^m(x) = e^{\mathrm{i}m\pi}\,\Gamma(\nu+m+1)\,\boldsymbol{Q}_\nu^m(x)
               = (-1)^m \Gamma(\nu+m+1)\,\boldsymbol{Q}_\nu^m(x),

with Olver's :math:`\boldsymbol{Q}_\nu^\mu` of DLMF 14.3.10. There is no Condon–Shortley phase in
:math:`P` (it is positive for real :math:`\nu > m-1` and large :math:`x`), and :math:`Q_\nu^m`
carries the factor :math:`(-1)^m`. With these conventions the Wronskian is (A&S 8.1.9 with the
duplication formula)

.. math::

    W\{P_\nu^m, Q_\nu^m\}(x) = P Q' - Q P'
        = \frac{(-1)^m}{1-x^2}\,\frac{\Gamma(\nu+m+1)}{\Gamma(\nu-m+1)},

which :func:`legendre_wronskian` returns and the tests check. The constant :math:`C_m` of
``green25b``/``green26b`` is :math:`\Gamma(\nu-m+1)/\Gamma(\nu+m+1)` (:func:`legendre_cm`).

Methods and why
---------------
Write :math:`x = \cosh t`, :math:`q = e^{-2t}` and :math:`w = (x-1)/(x+1) = \tanh^2(t/2)`.
:math:`P_\nu^m = P_{-\nu-1}^m`, so :math:`P` is always evaluated with
:math:`\operatorname{Re}\nu \ge -\tfrac12`.

* :math:`P`, :math:`x \le 3` (:math:`w \le \tfrac12`): the Pfaff-transformed series
  (DLMF 14.3.1 with 15.8.1)

  .. math:: P_\nu^m(x) = \frac{w^{m/2}}{m!}\frac{\Gamma(\nu+m+1)}{\Gamma(\nu-m+1)}
            \Bigl(\frac{1+x}{2}\Bigr)^{\nu} F(-\nu, m-\nu; m+1; w),

  which converges geometrically, terminates for integer :math:`\nu \ge 0`, and has
  positive :math:`c = m+1` (no degenerate cases). For large :math:`|\nu|\sqrt{w}` its terms
  behave like those of the Bessel series and cancel; the running sum of :math:`|{\rm term}|`
  measures that loss, and where it is too large the Laplace integral (DLMF 14.12.4 analogue
  for :math:`x>1`)

  .. math:: P_\nu^m(x) = \frac{(\nu+1)_m}{\pi}\int_0^\pi
            \bigl(x + \sqrt{x^2-1}\cos\phi\bigr)^{\nu}\cos(m\phi)\,d\phi

  is used instead: its integrand is analytic and periodic, so the trapezoidal rule converges
  exponentially (with about :math:`m + 1.5|\nu| t` nodes), and the integral only cancels when
  :math:`m` is large and :math:`|\nu|t` small — exactly where the series is good. The
  evaluation with the smaller error estimate wins.
* :math:`P`, :math:`x > 3` (:math:`q < 0.03`): the connection formula
  :math:`P_\nu^m = \tfrac{\tan\nu\pi}{\pi}(Q_\nu^m - Q_{-\nu-1}^m)` (A&S 8.2.3 for integer
  :math:`m`) with both :math:`Q` from the quadratically transformed series in :math:`q`
  (DLMF 14.3.10 with 15.8.13)

  .. math:: Q_\nu^m(\cosh t) = (-1)^m\sqrt{\pi}\,\Gamma(\nu+m+1)\,(1-q)^m e^{-(\nu+1)t}\,
            \mathbf{F}\bigl(\nu+m+1, m+\tfrac12; \nu+\tfrac32; q\bigr),

  written so that integer :math:`\nu` is not singular (reflection formulas). This series has
  no large-:math:`|\nu|` growth (:math:`\nu` appears in both :math:`a` and :math:`c`) and
  reaches :math:`x = 10^{12}` in a handful of terms, where a quadrature of the Laplace integral
  would need :math:`\sim x` nodes. At half-integer :math:`\nu` (including the conical point
  :math:`k = 0`) the two terms have poles that cancel (the logarithmic case); there the value
  is obtained from Cauchy's integral formula in :math:`\nu` on a circle of radius
  :math:`R = \min(1/4, 1/t)` around the half-integer, where the formula is well conditioned
  (values on the circle exceed the centre value by at most :math:`e^{Rt} \le e`; the
  trapezoidal rule on the circle converges like :math:`(|\nu-\nu_0|/R)^{M}`). For
  :math:`m \ge 6` and large :math:`m/x` the two terms cancel (the series grow like
  :math:`e^{m/x}`); up to :math:`x = 300` the :math:`w`-series above is tried as well.
* :math:`P`, :math:`m > 30` where all of the above cancel (large :math:`m` together with
  large :math:`|\nu|`, moderate :math:`x \le 300`): the ratio :math:`P^{m+1}/P^m` from the
  continued fraction of the order recurrence DLMF 14.10.6 (:math:`P` is its minimal solution
  beyond :math:`j \approx |\nu|\sinh t`; Gautschi's/Miller's method), combined with the
  Wronskian (A&S 8.1.9) into :math:`P^m = -(-1)^m\,\Gamma(\nu+m+1)/\Gamma(\nu-m+1)\,
  (x^2-1)^{-1/2} / (Q^{m+1} - (P^{m+1}/P^m)\,Q^m)`.
* :math:`Q`, :math:`x` near 1 (:math:`1-q \le z_*`): the same :math:`q`-series continued to
  :math:`q\to 1` by the logarithmic-case formula DLMF 15.8.10 (here
  :math:`c-a-b = -2m`), which is a convergent series in :math:`1-q` containing
  :math:`\ln(1-q)` and digamma functions and is free of degenerate cases; elsewhere the
  :math:`q`-series above.
* :math:`Q` within :math:`1/16` of :math:`\nu = -\tfrac32, -\tfrac52, \dots` (where
  :math:`\nu+\tfrac32` is a pole of :math:`\Gamma` and the leading :math:`x^{-\nu-1}`
  behaviour drops out, leaving a value smaller than each term by :math:`x^{2n+1}`): the
  reflection :math:`Q_\nu^m = Q_{-\nu-1}^m + \pi\cot(\nu\pi)\,P_\nu^m` (A&S 8.2.2 with
  integer order), which splits :math:`Q` into its decaying and growing parts without
  cancellation.
* :math:`Q`, :math:`m > 30`: upward recurrence in the order (DLMF 14.10.6) from the direct
  values at :math:`m = 29, 30`; :math:`Q` is its dominant solution, so it is stable.

Every series checks its own truncation (tail bound from the term ratio) and raises
:class:`~hyperlattice.errors.ConvergenceError` if it does not converge. Values are carried as
``(log_scale, mantissa)`` pairs internally (rescaled by exact powers of two) so that orders up
to :data:`MAX_ORDER` and arguments up to :math:`10^{12}` neither overflow nor underflow;
:func:`legendre_q_over_p` and :func:`legendre_log_p` / :func:`legendre_log_q` expose that.

Error estimates
---------------
Each method returns an estimate of its absolute error: rounding of its sums
(:math:`\varepsilon\sum|\text{terms}|`), of its exponents and phases
(:math:`\varepsilon` times the size of the logarithms that make them), the truncation of
quadratures (squared half-step difference) and continued fractions (a second start), and
the propagation of start errors through recurrences (tangent solution). Where two methods
apply, the smaller estimate wins. :func:`legendre_q` warns
(:class:`~hyperlattice.errors.ConvergenceWarning`) when its estimate exceeds :math:`10^{-8}`
relative; the tests check that estimates are upper estimates up to a factor 3 (or
:math:`10^{-12}`). :func:`legendre_p` does not warn, because near its zeros every method
loses relative accuracy while staying accurate relative to the local envelope.

Supported domain
----------------
Orders :math:`0 \le m \le` ``MAX_ORDER`` = 1000 (larger orders are refused with a
``ValueError`` before any work), degrees :math:`|\nu| \le` ``MAX_DEGREE`` = 1e6 (likewise),
:math:`1 \le x` (validated to :math:`10^{12}`), complex
:math:`\nu` validated for conical :math:`k \le 600`, real :math:`\nu \in [-6, 5]` and complex
:math:`|\nu| \lesssim 50`; up to :math:`|\nu| \approx 10^3` spot checks agree to
:math:`10^{-10}`. At most :math:`2^{24}` points per call.

Accuracy (measured against mpmath at 30 digits; ``tests/test_special.py`` over regions,
``tests/test_special_seams.py`` at every method switch, ``tests/test_special_defects.py``):
relative error below :math:`10^{-13}` away from zeros for :math:`x \in [1, 10^{12}]`,
:math:`m \le 30`, conical :math:`k \le 600` and complex :math:`|\nu| \lesssim 50` (near zeros
at that level relative to the local envelope), including exactly at and next to every
switch (worst measured there 5e-14); for :math:`30 < m \le 1000` below
:math:`3\cdot10^{-12}` for :math:`P` with :math:`x \le 300` and below :math:`4\cdot10^{-11}`
for :math:`Q` (the log-scale of size :math:`\sim 7000` alone has an ulp of :math:`10^{-12}`).
Known weak spot: :math:`P` with :math:`m` near 1000 just beyond :math:`x = 300`
(:math:`1.5\cdot10^{-10}`, marked ``xfail`` in the seam tests).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy import special as sc

from .. import _validate
from ..errors import ConvergenceError, ConvergenceWarning, RangeWarning

__all__ = [
    "MAX_ORDER",
    "MAX_DEGREE",
    "legendre_p",
    "legendre_q",
    "legendre_log_p",
    "legendre_log_q",
    "legendre_q_over_p",
    "legendre_wronskian",
    "legendre_cm",
    "conical_p",
    "nu_from_lambda",
    "check_order",
    "legendre_p_log_parts",
    "evaluate_checked",
]

MAX_ORDER = 1000         # largest order m accepted (validated against mpmath up to here)
MAX_DEGREE = 1e6         # largest |nu| accepted (spot checks to 1e3; 1e6 costs ~1 s, 1e300 minutes)
_MAX_POINTS = 2**24      # largest broadcast size accepted (refused before allocating)
_CHUNK = 2**14           # points evaluated at once (bounds the working memory of every method)
_QUAD_CELLS = 2**21      # points x nodes of the Laplace quadrature held in memory at once

_EPS = 2.0**-54          # target relative size of the neglected tail of every series
_NMAX = 20000            # hard cap on series terms (never reached in the documented domain)
_X_NEAR_P = 3.0          # P: w-series for x <= 3 (w <= 1/2), q-series beyond (q < 0.03)
_X_FAR_FALLBACK = 300.0  # P, m >= 6: the w-series backs up the q-series up to here (<= 7000 terms)
_X_CF_MAX = 300.0        # P, m > 30: the Casoratian method is the last resort up to here
_Z_NEAR_Q = 0.5          # Q: log-case series in z = 1-q for z <= _Z_NEAR_Q (x <= 1.0607) ...
_Z_NEAR_Q_LARGE_M = 0.75  # ... and up to z = 0.75 (x <= 1.25) for m >= 4, where the q-series is slow
_Q_CONNECT = 0.0625      # Q: |nu - (-n-3/2)| below this uses Q_nu = Q_{-nu-1} + pi cot(nu pi) P_nu
_M_DIRECT_Q = 30         # Q: direct series for m <= 30, upward recurrence in m beyond
_CAUCHY_M = 32           # nodes on the Cauchy circle around half-integer degrees
_SERIES_LOSS = 1e2       # if sum|terms|/|sum| exceeds this, try the Laplace quadrature too
_WARN_REL = 1e-8         # Q warns when its estimated relative error exceeds this
_ROUND = 4e-16           # rounding error of one operation, with a safety factor of about 4


# ----------------------------------------------------------------------------
# input handling
# ----------------------------------------------------------------------------

def _order_array(value) -> np.ndarray:
    """``value`` as an int64 array of orders 0 <= m <= MAX_ORDER.

    A local helper because :mod:`hyperlattice._validate` has scalar integers but no integer
    arrays; it follows the same rules (no bool, no strings, no None, integral floats accepted).
    """
    name = "the order m"
    if value is None or isinstance(value, (str, bytes)):
        raise ValueError(f"{name} must be a non-negative integer, got {value!r}.")
    try:
        a = np.asarray(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a non-negative integer or an array of them "
                         "(a ragged or mixed list is not).") from None
    if a.dtype.kind == "O":
        # Python ints beyond int64 (or mixed objects): check each through the scalar door
        flat = [_validate.integer(name, v, minimum=0, maximum=MAX_ORDER) for v in a.ravel()]
        return np.array(flat, dtype=np.int64).reshape(a.shape)
    if a.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be a non-negative integer, got values of type {a.dtype}.")
    if a.dtype.kind == "f":
        if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
            raise ValueError(f"{name} must be a non-negative integer.")
    if np.any(a < 0):
        raise ValueError(f"{name} must be non-negative; use P^m = P^{{|m|}} up to the "
                         "documented factors for negative m.")
    if np.any(a > MAX_ORDER):
        top = np.max(a)
        shown = f"{int(top):,}" if a.dtype.kind != "f" else f"{float(top):g}"
        raise ValueError(f"{name} must be at most {MAX_ORDER:,} (the validated range of these "
                         f"functions), got {shown}.")
    return a.astype(np.int64)


def check_order(m) -> np.ndarray:
    r"""Validate Legendre orders: ``m`` as an int64 array with :math:`0 \le m \le` :data:`MAX_ORDER`.

    Parameters
    ----------
    m : int or array_like of int
        Integral floats (``3.0``) are accepted; bool, strings, None, NaN, negative or
        non-integral values are not.

    Returns
    -------
    ndarray of int64
        Same shape as ``m``.

    Raises
    ------
    ValueError
        With a plain sentence, for anything that is not a valid order.

    Examples
    --------
    >>> from hyperlattice.continuum.special import check_order
    >>> check_order(3.0).tolist()
    3
    >>> check_order([0, 2]).tolist()
    [0, 2]
    """
    return _order_array(m)


def _check_x(x, *, allow_one: bool = True) -> np.ndarray:
    name = "the argument x"
    if x is not None and not isinstance(x, (str, bytes)) and np.iscomplexobj(x):
        x_c = _validate.complex_array(name, x)
        if np.any(x_c.imag != 0):
            raise ValueError("the argument x must be real (x >= 1); complex x is not supported.")
        x_arr = np.ascontiguousarray(x_c.real)
    else:
        x_arr = _validate.real_array(name, x)
    if np.any(x_arr < 1.0):
        raise ValueError("the argument x must satisfy x >= 1 (the functions are of type 3, x > 1).")
    if not allow_one and np.any(x_arr == 1.0):
        raise ValueError("Q_nu^m(x) is singular at x = 1; pass x > 1.")
    return x_arr


def _check_nu(nu) -> np.ndarray:
    nu = _validate.complex_array("the degree nu", nu)
    if nu.size and float(np.max(np.abs(nu))) > MAX_DEGREE:
        # nu = 1e300 ran its series for minutes (the validated domain ends near |nu| = 1e3)
        raise ValueError(f"the degree nu must have |nu| <= {MAX_DEGREE:g} (validated to about 1e3), got "
                         f"|nu| = {float(np.max(np.abs(nu))):g}.")
    return nu


def _broadcast(nu, m, x, *, allow_one=True):
    nu_a = _check_nu(nu)
    m_a = check_order(m)
    x_a = _check_x(x, allow_one=allow_one)
    try:
        shape = np.broadcast_shapes(nu_a.shape, m_a.shape, x_a.shape)
    except ValueError:
        raise ValueError(f"nu, m and x must broadcast to one shape; got shapes {nu_a.shape}, "
                         f"{m_a.shape} and {x_a.shape}.") from None
    size = math.prod(shape)
    if size > _MAX_POINTS:
        raise ValueError(f"nu, m and x broadcast to {size:,} points; at most {_MAX_POINTS:,} are "
                         "evaluated in one call (split the request).")
    nu_b, m_b, x_b = np.broadcast_arrays(nu_a, m_a, x_a)
    return (nu_b.ravel().copy(), m_b.ravel().astype(np.int64), x_b.ravel().astype(float), shape)


def _geom(x):
    """t = arccosh x, d = x - 1, q = e^{-2t}, z = 1 - q, computed without cancellation near 1."""
    d = x - 1.0
    t = np.where(d < 1.0, np.log1p(d + np.sqrt(d * (d + 2.0))),
                 np.log(x) + np.log1p(np.sqrt(np.maximum(1.0 - 1.0 / (x * x), 0.0))))
    q = np.exp(-2.0 * t)
    z = -np.expm1(-2.0 * t)
    return d, t, q, z


def _pow2_renorm(k, mant):
    """Divide ``mant`` by the power of two nearest |mant| (exact), adding the exponent to the
    integer array ``k`` (in place); zeros and non-finite values stay. Integer exponents keep
    the log-scale free of the rounding a running sum of logarithms would accumulate."""
    a = np.abs(mant)
    ok = (a > 0) & np.isfinite(a)
    e = np.frexp(np.where(ok, a, 1.0))[1]
    k += e
    mant *= np.ldexp(1.0, -e)


_LN2 = math.log(2.0)


def _log_product(factor, n, shape):
    """(log_scale, mantissa) of prod_{j<n} factor(j) elementwise, renormalized every 8 steps so
    that products of up to ``MAX_ORDER`` factors of any size neither overflow nor underflow."""
    k = np.zeros(shape, dtype=np.int64)
    mant = np.ones(shape, complex)
    nmax = int(np.max(n)) if np.size(n) else 0
    for j in range(nmax):
        mant = np.where(j < n, mant * factor(j), mant)
        if j % 8 == 7:
            _pow2_renorm(k, mant)
    _pow2_renorm(k, mant)
    return k * _LN2, mant


def _pochhammer_sym(nu, m):
    """Gamma(nu+m+1)/Gamma(nu-m+1) = prod_{j=1-m}^{m} (nu+j) as (log_scale, mantissa); a
    polynomial (no poles), exactly 0 for integers 0 <= nu < m."""
    return _log_product(lambda j: (nu + (j + 1)) * (nu - j), m, nu.shape)


def _rising(a, n):
    """(a)_n for an array a and an integer array n >= 0, as (log_scale, mantissa)."""
    return _log_product(lambda j: a + j, n, np.broadcast(a, n).shape)


def _log_rgamma(z):
    """1/Gamma(z) as (log_scale, mantissa): scipy's rgamma where it cannot overflow, the
    log-gamma function beyond; exactly 0 at the poles z = 0, -1, -2, ..."""
    small = np.abs(z) <= 100.0
    scale = np.zeros(z.shape)
    mant = np.zeros(z.shape, complex)
    mant[small] = sc.rgamma(z[small])
    big = ~small
    if big.any():
        lg = -sc.loggamma(z[big])
        pole = (z[big].imag == 0) & (z[big].real <= 0) & (z[big].real == np.round(z[big].real))
        scale[big] = np.where(pole, 0.0, lg.real)
        mant[big] = np.where(pole, 0.0, np.exp(1j * np.where(pole, 0.0, lg.imag)))
    return scale, mant


def _combine(parts, coeffs):
    """sum_i coeff_i * (s_i, m_i, e_i) on a common scale; coefficients are (log_scale, mantissa)."""
    logs = [s + cs for (s, _, _), (cs, _) in zip(parts, coeffs)]
    top = np.max(np.stack(logs), axis=0)
    top = np.where(np.isfinite(top), top, 0.0)
    mant = np.zeros(top.shape, complex)
    err = np.zeros(top.shape)
    for (s, mt, er), (cs, cm), lg in zip(parts, coeffs, logs):
        with np.errstate(over="ignore", under="ignore", invalid="ignore"):
            f = np.exp(lg - top)
        f = np.where(cm == 0, 0.0, f)
        mant += cm * mt * f
        err += np.abs(cm) * (er + _ROUND * np.abs(mt)) * f
    return top, mant, err


# ----------------------------------------------------------------------------
# a vectorized Gauss hypergeometric series with its own convergence check
# ----------------------------------------------------------------------------

def _hyp_series(a, b, c, z, *, what: str, strict: bool = True):
    """Sum F(a, b; c; z) = sum_n (a)_n (b)_n / ((c)_n n!) z^n elementwise.

    With ``strict=False`` elements that have not converged after ``_NMAX`` terms come back
    as NaN (for a caller that has another method) instead of raising.

    Returns ``(sum, sum of |terms|)``; the second measures the cancellation, hence the
    rounding error ``~ eps * sum|terms|``. Stops an element when the term ratio is below 1 and
    the geometric tail bound ``|t| r/(1-r)`` is below ``_EPS`` relative to the sum (or to
    ``1e-3 sum|terms|`` at a zero of the sum, below the rounding floor anyway).
    """
    n = a.size
    total = np.ones(n, complex)
    absum = np.ones(n)
    if n == 0:
        return total, absum
    act = np.arange(n)
    A, B, C, Z = a.copy(), b.copy(), c.copy(), z.astype(complex)
    term = np.ones(n, complex)
    S = total.copy()
    SA = absum.copy()
    ratio = A * B / C * Z                      # term_{k+1} / term_k at k = 0
    for k in range(_NMAX):
        term = term * ratio
        S += term
        at = np.abs(term)
        SA += at
        k1 = k + 1.0
        ratio = (A + k1) * (B + k1) / ((C + k1) * (k1 + 1.0)) * Z
        if k % 4 != 3:                          # convergence test every 4th term (cheap loop)
            continue
        r = np.abs(ratio)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            tail = at * r / (1.0 - r)
        done = (at == 0) | ((r < 1) & (tail <= _EPS * np.maximum(np.abs(S), 1e-3 * SA)))
        if done.any():
            total[act[done]] = S[done]
            absum[act[done]] = SA[done]
            keep = ~done
            act, A, B, C, Z = act[keep], A[keep], B[keep], C[keep], Z[keep]
            term, S, SA, ratio = term[keep], S[keep], SA[keep], ratio[keep]
            if act.size == 0:
                return total, absum
    if not strict:
        total[act] = np.nan
        absum[act] = np.inf
        return total, absum
    raise ConvergenceError(f"hypergeometric series for {what} did not converge in {_NMAX} terms.")


# ----------------------------------------------------------------------------
# P_nu^m: near region (w-series, Laplace quadrature)
# ----------------------------------------------------------------------------

def _reflect(nu):
    """P_nu^m = P_{-nu-1}^m: use the degree with Re nu >= -1/2."""
    return np.where(nu.real < -0.5, -nu - 1.0, nu)


def _p_near_series(nu, m, x):
    """(log_scale, mantissa, abs_err_mantissa) of P by the w-series; Re nu >= -1/2, x > 1."""
    d = x - 1.0
    w = d / (d + 2.0)
    F, FA = _hyp_series(-nu, m - nu, (m + 1.0).astype(complex), w, what="P_nu^m (w-series)",
                        strict=False)
    ps, poly = _pochhammer_sym(nu, m)
    # log of w^{m/2} ((1+x)/2)^nu / m!
    logs = 0.5 * m * np.log(w) + nu * np.log1p(0.5 * d) - sc.gammaln(m + 1.0) + ps
    scale = logs.real
    mant = np.exp(1j * logs.imag) * poly * F
    # rounding of the sum and of the exponent: its terms (each rounded) reach 1e4 for large m
    # and cancel in part, so count eps times the sum of their sizes
    big = np.abs(0.5 * m * np.log(w)) + sc.gammaln(m + 1.0) + np.abs(ps) + np.abs(nu * np.log1p(0.5 * d))
    err = _ROUND * np.abs(poly) * (FA + big * np.abs(F))
    return scale, mant, err


def _p_near_quad(nu, m, x):
    """(log_scale, mantissa, abs_err) of P by the trapezoidal rule on the Laplace integral."""
    d, t, _, _ = _geom(x)
    s = np.sqrt(d * (d + 2.0))
    nnodes_f = np.ceil(m + 1.5 * np.abs(nu) * t + 40.0)
    # the node count grows like |nu| arccosh(x): refuse before allocating (nu = 1e12 would ask
    # numpy for 22.6 TiB; beyond 1e18 the count does not even fit an integer); a row of nodes holds
    # ~12 float64 temporaries (phi, weights, the complex base, exponent and integrand, cos(m phi))
    top = int(np.argmax(nnodes_f))
    _validate.require_memory(f"P_nu^m at nu = {_nice(nu[top])}, x = {float(x[top]):g} (a Laplace quadrature "
                             f"with {float(nnodes_f[top]):.3g} nodes)", 96.0 * (float(nnodes_f[top]) * 1.2 + 1.0))
    nnodes = nnodes_f.astype(int)
    nnodes += nnodes % 2
    out_scale = np.empty(x.shape)
    out_mant = np.empty(x.shape, complex)
    out_err = np.empty(x.shape)
    # group by node count (rounded up to 2^(k/4)) so that each group is one 2-D array op,
    # in row blocks of at most _QUAD_CELLS points x nodes (bounded memory)
    nn = (2.0 ** (np.ceil(np.log2(nnodes) * 4.0) / 4.0)).astype(int)
    nn += nn % 2
    rs, rm = _rising(nu + 1.0, m)
    for n_here in np.unique(nn):
        phi = np.linspace(0.0, np.pi, n_here + 1)
        wts = np.full(n_here + 1, np.pi / n_here)
        wts[0] *= 0.5
        wts[-1] *= 0.5
        rows = max(1, _QUAD_CELLS // (n_here + 1))
        group = np.nonzero(nn == n_here)[0]
        for b0 in range(0, group.size, rows):
            sel = group[b0:b0 + rows]
            base = x[sel, None] + s[sel, None] * np.cos(phi)[None, :]
            expo = nu[sel, None] * np.log(base)
            # factor out the largest modulus: (x+s)^{Re nu} at phi = 0 for Re nu >= 0, else phi = pi
            sc_row = np.max(expo.real, axis=1)
            f = np.exp(expo - sc_row[:, None]) * np.cos(m[sel, None] * phi[None, :])
            val = f @ wts
            half = f[:, ::2] @ (2.0 * wts[::2])
            absint = np.abs(f) @ wts
            pref = rm[sel] / np.pi
            out_scale[sel] = sc_row + rs[sel]
            out_mant[sel] = pref * val
            # rounding ~ eps * integral of |f|. The trapezoidal rule on a periodic analytic
            # integrand converges geometrically, E(n) ~ C r^n with C >= the integral of |f|,
            # so E(n) ~ E(n/2)^2 / C <= |val - half|^2 / absint (the half-step estimate squared)
            disc = np.abs(val - half)
            with np.errstate(divide="ignore", invalid="ignore"):
                trunc = np.where(absint > 0, disc * disc / absint, 0.0)
            big = np.max(np.abs(expo.imag), axis=1)      # rounding of the phase of base^nu
            out_err[sel] = np.abs(pref) * (_ROUND * absint * (np.sqrt(n_here) + big) + trunc)
    return out_scale, out_mant, out_err


# ----------------------------------------------------------------------------
# P_nu^m: far region (q-series, connection formula)
# ----------------------------------------------------------------------------

def _p_far_terms(nu, m, t, q):
    """P by the connection formula (valid for any nu that is not a half-integer).

    T1 = (-1)^m tan(nu pi)/sqrt(pi) Gamma(nu+m+1)/Gamma(nu+3/2) e^{-(nu+1)t} (1-q)^m F1,
    T2 = -(-1)^m A2 Gamma(nu+1/2)/sqrt(pi) e^{nu t} (1-q)^m F2, with
    A2 = sin(nu pi) Gamma(m-nu)/pi = (1-nu)_{m-1}/Gamma(nu) (m >= 1), -1/Gamma(nu+1) (m = 0),
    the reflection-formula form of tan(nu pi) Gamma(m-nu)/Gamma(1/2-nu) (no poles at integers).
    """
    mf = m.astype(float)
    F1, F1A = _hyp_series(nu + mf + 1.0, (mf + 0.5).astype(complex), nu + 1.5, q,
                          what="P_nu^m (q-series, first term)")
    F2, F2A = _hyp_series(mf - nu, (mf + 0.5).astype(complex), 0.5 - nu, q,
                          what="P_nu^m (q-series, second term)")
    sign = np.where(m % 2 == 0, 1.0, -1.0)
    # tan has period pi: reduce by the (exactly representable) nearest integer first, so that
    # tan(nu pi) is exactly 0 at integer nu (where P_n^m = 0 for n < m must come out as 0)
    tanv = np.tan(np.pi * (nu - np.round(nu.real)))
    g1, g2, g3 = sc.loggamma(nu + mf + 1.0), sc.loggamma(nu + 1.5), sc.loggamma(nu + 0.5)
    lq = mf * np.log1p(-q)
    l1 = g1 - g2 - (nu + 1.0) * t + lq
    # A2 as (log_scale, mantissa): (1-nu)_{m-1} reaches (m-1)! and 1/Gamma(nu) e^{pi |Im nu|/2}
    rs, rm = _rising(1.0 - nu, np.maximum(m - 1, 0))
    gs0, gm0 = _log_rgamma(nu + 1.0)
    gs1, gm1 = _log_rgamma(nu)
    a2s = np.where(m == 0, gs0, rs + gs1)
    a2m = np.where(m == 0, -gm0, rm * gm1)
    l2 = g3 + nu * t + lq + a2s
    # rounding of the exponents, each a sum of logarithms of size up to ~ m ln m: an absolute
    # error eps * (sum of their sizes) in l1, l2 is amplified by the cancellation T1 + T2
    # (measured: 6e-10 at m = 400, x = 100 from 4e-13 in l1)
    big1 = np.abs(g1) + np.abs(g2) + np.abs((nu + 1.0) * t) + np.abs(lq)
    big2 = np.abs(g3) + np.abs(nu * t) + np.abs(lq) + np.abs(a2s)
    scale = np.maximum(l1.real, l2.real)
    c1 = sign * tanv / math.sqrt(math.pi) * np.exp(l1 - scale)
    c2 = -sign * a2m / math.sqrt(math.pi) * np.exp(l2 - scale)
    mant = c1 * F1 + c2 * F2
    err = _ROUND * (np.abs(c1) * (F1A + big1 * np.abs(F1)) + np.abs(c2) * (F2A + big2 * np.abs(F2)))
    return scale, mant, err


def _cauchy(func, nu, centre, radius, *args):
    """Value at nu of an analytic function of nu from its values on a circle around ``centre``.

    ``func(nu, *args)`` returns (log_scale, mantissa, err). Trapezoidal rule for
    f(nu) = (1/2 pi i) oint f(zeta)/(zeta - nu) d zeta; error ~ (|nu-centre|/radius)^M.
    """
    M = _CAUCHY_M
    theta = 2.0 * np.pi * (np.arange(M) + 0.5) / M
    e = np.exp(1j * theta)
    n = nu.size
    zeta = centre[:, None] + radius[:, None] * e[None, :]
    rep = [np.repeat(a, M) for a in args]
    s, mnt, er = func(zeta.ravel(), *rep)
    s = s.reshape(n, M)
    mnt = mnt.reshape(n, M)
    er = er.reshape(n, M)
    smax = np.max(s, axis=1)
    fac = np.exp(s - smax[:, None])
    kern = (radius[:, None] * e[None, :]) / (radius[:, None] * e[None, :] - (nu - centre)[:, None]) / M
    mant = np.sum(mnt * fac * kern, axis=1)
    # errors of the node values, rounding of the sum (the values on the circle may exceed the
    # result by far), and the aliasing error of the trapezoidal rule, ~ max|f| (d/R)^M
    size = np.abs(mnt) * fac
    ratio = np.abs(nu - centre) / radius
    alias = np.max(size, axis=1) * ratio**M / (1.0 - ratio**M)
    err = np.sum((er * fac + _ROUND * size) * np.abs(kern), axis=1) + alias
    return smax, mant, err


def _p_far(nu, m, x):
    _, t, q, _ = _geom(x)
    scale = np.empty(x.shape)
    mant = np.empty(x.shape, complex)
    err = np.empty(x.shape)
    centre = np.floor(nu.real) + 0.5
    radius = np.minimum(0.25, 1.0 / t)
    near_half = np.abs(nu - centre) < 0.25 * radius
    reg = ~near_half
    if reg.any():
        scale[reg], mant[reg], err[reg] = _p_far_terms(nu[reg], m[reg], t[reg], q[reg])
    if near_half.any():
        i = near_half
        scale[i], mant[i], err[i] = _cauchy(_p_far_terms, nu[i], centre[i].astype(complex),
                                            radius[i], m[i], t[i], q[i])
    return scale, mant, err


def _pick(base, alt, idx):
    """Replace entries ``idx`` of ``base`` by ``alt`` where alt's absolute error estimate is smaller.

    Both are (log_scale, mantissa, err) triples; errors are compared on a common scale.
    """
    s0, m0, e0 = base
    s1, m1, e1 = alt
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        e0_on_1 = e0[idx] * np.exp(s0[idx] - s1)
    better = (e1 < e0_on_1) | ~np.isfinite(e0_on_1) | ~np.isfinite(m0[idx])
    better &= np.isfinite(m1) & np.isfinite(e1)
    j = idx[better]
    s0[j], m0[j], e0[j] = s1[better], m1[better], e1[better]


def _p_casoratian(nu, m, x):
    """P for large m from Q and the ratio P^{m+1}/P^m (Re nu >= -1/2, 1 < x <= _X_CF_MAX).

    The ratio r_j = P^{j+1}/P^j solves r_j = b_j/(a_j + r_{j+1}) with a_j = 2(j+1) coth t,
    b_j = (nu-j)(nu+j+1) (the order recurrence DLMF 14.10.6 read downwards); P is the minimal
    solution in increasing j beyond |nu| sinh t (ratio tending to tanh^2(t/2) per step
    against Q), so the continued fraction started at M = max(m, 2 |nu| sinh t) + N with
    N = 40/(-2 ln tanh(t/2)) has converged at j = m (Gautschi; Miller's algorithm). The
    Casoratian P^m Q^{m+1} - Q^m P^{m+1} = -(-1)^m Gamma(nu+m+1)/Gamma(nu-m+1) / sqrt(x^2-1)
    (the Wronskian A&S 8.1.9 of :func:`legendre_wronskian` through the derivative relation
    sqrt(x^2-1) f' = f^{m+1} + m x f^m / sqrt(x^2-1), DLMF 14.10.6) then gives
    P^m = Casoratian / (Q^{m+1} - r_m Q^m) with both Q accurate (upward recurrence).
    This covers large m together with large |nu| at moderate x, where the w-series
    (|nu| sqrt(w) large), the quadrature (cos(m phi) cancels) and the q-series connection
    formula (F ~ e^{m/x}) all cancel. The truncation of the fraction is estimated by a
    second start N steps further out, its rounding by a running error bound.
    """
    n = x.size
    d, t, _, _ = _geom(x)
    sx = np.sqrt(d * (d + 2.0))
    c = x / sx                                              # coth t
    th = np.tanh(0.5 * t)
    nsteps = np.ceil(40.0 / (-2.0 * np.log(th))).astype(np.int64)
    # below j ~ |nu| sinh t the characteristic roots of the recurrence can have equal size
    # (conical nu); from j = 2 |nu| sinh t on their ratio is below (x - 0.87)/(x + 0.87)
    start = np.maximum(m, np.ceil(2.0 * np.abs(nu) * sx).astype(np.int64)) + nsteps + 2
    usable = start - m <= _NMAX
    start = np.where(usable, start, m)
    far_start = np.where(usable, start + nsteps, m)
    r1 = np.zeros(n, complex)                               # fraction started at `start`
    e1 = np.zeros(n)                                        # running rounding-error bound of r1
    r2 = np.zeros(n, complex)                               # ... and at `far_start`
    for j in range(int(far_start.max()) - 1, int(m.min()) - 1, -1):
        a = 2.0 * (j + 1) * c
        b = (nu - j) * (nu + (j + 1.0))
        act2 = (j < far_start) & (j >= m)
        act1 = (j < start) & (j >= m)
        with np.errstate(all="ignore"):
            r2 = np.where(act2, b / (a + r2), r2)
            new = b / (a + r1)
            # d r_j / d r_{j+1} = -r_j / (a + r_{j+1}); three roundings per step
            e1 = np.where(act1, np.abs(new / (a + r1)) * e1 + 3.0 * _ROUND * np.abs(new), e1)
            r1 = np.where(act1, new, r1)
    sq0, q0, eq0 = _log_q_parts(nu, m, x)
    sq1, q1, eq1 = _log_q_parts(nu, m + 1, x)
    top = np.maximum(sq0, sq1)
    f0, f1 = np.exp(sq0 - top), np.exp(sq1 - top)
    q0, eq0, q1, eq1 = q0 * f0, eq0 * f0, q1 * f1, eq1 * f1
    den = q1 - r1 * q0
    ps, pm = _pochhammer_sym(nu, m)
    sign = np.where(m % 2 == 0, -1.0, 1.0)
    scale = ps - np.log(sx) - top
    with np.errstate(all="ignore"):
        mant = sign * pm / den
        cond = (np.abs(q1) + np.abs(r1 * q0)) / np.abs(den)
        rel = ((eq1 + np.abs(r1) * eq0 + (np.abs(r1 - r2) + e1) * np.abs(q0)) / np.abs(den)
               + 4.0 * _ROUND * cond)
    return scale, mant, np.where(usable, rel * np.abs(mant), np.inf)


def _log_p_parts(nu, m, x):
    nu = _reflect(nu)
    scale = np.zeros(x.shape)
    mant = np.zeros(x.shape, complex)
    err = np.zeros(x.shape)
    out = (scale, mant, err)
    at_one = x == 1.0
    mant[at_one] = np.where(m[at_one] == 0, 1.0, 0.0)
    near = (~at_one) & (x <= _X_NEAR_P)
    far = x > _X_NEAR_P
    if near.any():
        i = np.nonzero(near)[0]
        scale[i], mant[i], err[i] = _p_near_series(nu[i], m[i], x[i])
        # sum|terms| / |sum| above _SERIES_LOSS: the series cancels (large |nu| sqrt(w))
        j = i[~(err[i] <= _SERIES_LOSS * _ROUND * np.abs(mant[i]))]
        if j.size:
            _pick(out, _p_near_quad(nu[j], m[j], x[j]), j)
    if far.any():
        i = np.nonzero(far)[0]
        scale[i], mant[i], err[i] = _p_far(nu[i], m[i], x[i])
        # for large m the two terms of the connection formula cancel for x up to about m/3
        # (F1, F2 ~ e^{m/x}; measured: 1e-5 at m = 30, x = 3; 3e-12 at m = 10): the w-series
        # still converges there (slowly) and is the fallback up to x = _X_FAR_FALLBACK. For
        # m < 6 a large error estimate relative to the value only means that P is near one of
        # its zeros (conical oscillation), where the error relative to the envelope is fine,
        # so no fallback is attempted.
        j = i[~(err[i] <= _SERIES_LOSS * _ROUND * np.abs(mant[i]))
              & (x[i] <= _X_FAR_FALLBACK) & (m[i] >= 6)]
        if j.size:
            _pick(out, _p_near_series(nu[j], m[j], x[j]), j)
    # large m with large |nu|: all of the above may cancel; the Casoratian method does not.
    # Only for m > _M_DIRECT_Q: below, a large estimate means a zero of P (measured: the
    # other methods reach 1e-12 there for m <= 30), and root searches evaluate P at its
    # zeros many times (the fallback would cost a Q evaluation each time)
    i = np.nonzero((~at_one) & (m > _M_DIRECT_Q) & (x <= _X_CF_MAX))[0]
    j = i[~(err[i] <= _SERIES_LOSS * _ROUND * np.abs(mant[i]))]
    if j.size:
        _pick(out, _p_casoratian(nu[j], m[j], x[j]), j)
    return out


# ----------------------------------------------------------------------------
# Q_nu^m: near region (log-case series in 1-q), far region (q-series), large m (recurrence)
# ----------------------------------------------------------------------------

def _q_far_terms(nu, m, t, q, strict=True):
    """Q_nu^m = (-1)^m sqrt(pi) Gamma(nu+m+1)/Gamma(nu+3/2) (1-q)^m e^{-(nu+1)t} F(...; q)."""
    mf = m.astype(float)
    F, FA = _hyp_series(nu + mf + 1.0, (mf + 0.5).astype(complex), nu + 1.5, q,
                        what="Q_nu^m (q-series)", strict=strict)
    sign = np.where(m % 2 == 0, 1.0, -1.0)
    logs = (sc.loggamma(nu + mf + 1.0) - sc.loggamma(nu + 1.5) - (nu + 1.0) * t
            + mf * np.log1p(-q) + 0.5 * math.log(math.pi))
    scale = logs.real
    pref = sign * np.exp(1j * logs.imag)
    return scale, pref * F, _ROUND * (FA + np.abs(logs.imag) * np.abs(F))


def _q_far(nu, m, x, strict=True):
    """Q by the q-series; ``strict=False``: NaN where it does not converge (a fallback)."""
    _, t, q, _ = _geom(x)
    scale = np.empty(x.shape)
    mant = np.empty(x.shape, complex)
    err = np.empty(x.shape)
    # nu + 3/2 near a non-positive integer -n: Gamma(nu+3/2) and F have cancelling poles, and
    # at nu = -n-3/2 exactly the leading x^{-nu-1} behaviour drops out, leaving Q ~ x^{nu}
    # smaller than each term by x^{-2n-1}. The reflection (A&S 8.2.2 with integer mu = m)
    #     Q_nu^m = Q_{-nu-1}^m + pi cot(nu pi) P_nu^m,   cot(nu pi) = -tan(delta pi),
    # delta = nu + n + 3/2 (exact in floating point), splits Q into a decaying part and a
    # growing part of size ~ delta without cancellation. (A Cauchy circle around the
    # half-integer was used here before: it cancels by that same factor x^{2n+1} and was
    # 100x off at nu = -3.5, m = 3, x = 50.)
    cpar = nu + 1.5
    centre = np.round(cpar.real)
    bad = (centre <= 0) & (np.abs(cpar - centre) < _Q_CONNECT)
    ok = ~bad
    if ok.any():
        scale[ok], mant[ok], err[ok] = _q_far_terms(nu[ok], m[ok], t[ok], q[ok], strict)
    if bad.any():
        i = np.nonzero(bad)[0]
        delta = nu[i] - (centre[i] - 1.5)
        nu_r = -nu[i] - 1.0                                  # Re nu_r >= n + 1/2 - 1/16
        qr = _log_q_direct(nu_r, m[i], x[i])
        pr = _log_p_parts(nu_r, m[i], x[i])
        cot = -np.tan(np.pi * delta) * np.pi
        one = (np.zeros(i.size), np.ones(i.size, complex))
        scale[i], mant[i], err[i] = _combine([qr, pr], [one, (np.zeros(i.size), cot)])
    return scale, mant, err


def _q_near(nu, m, x):
    """Q by DLMF 15.8.10 (logarithmic case c - a - b = -2m) in z = 1 - q, for x near 1.

    Q = (-1)^m sqrt(pi) z^m e^{-(nu+1)t} [S1 - S2],
    S1 = z^{-2m} Gamma(2m)/Gamma(m+1/2) sum_{k<2m} (nu+1-m)_k (1/2-m)_k / (k! (1-2m)_k) z^k,
    S2 = Pi(nu) / Gamma(1/2-m) sum_k (a)_k (b)_k / (k! (k+2m)!) z^k
         [ln z - psi(k+1) - psi(k+2m+1) + psi(a+k) + psi(b+k)],
    a = nu+m+1, b = m+1/2, Pi(nu) = Gamma(nu+m+1)/Gamma(nu-m+1).
    """
    _, t, _, z = _geom(x)
    mf = m.astype(float)
    n = x.size
    a = nu + mf + 1.0
    b = mf + 0.5
    # S1 (finite, absent for m = 0)
    s1 = np.zeros(n, complex)
    s1a = np.zeros(n)
    mmax = int(m.max()) if n else 0
    term = np.ones(n, complex)
    for k in range(2 * mmax):
        use = k < 2 * m
        s1 = np.where(use, s1 + term, s1)
        s1a = np.where(use, s1a + np.abs(term), s1a)
        denom = (k + 1.0) * (1.0 - 2.0 * mf + k)
        denom = np.where(denom == 0, 1.0, denom)
        term = term * (nu + 1.0 - mf + k) * (0.5 - mf + k) / denom * z
    pref1 = np.where(m > 0, np.exp(sc.gammaln(np.maximum(2.0 * mf, 1.0)) - sc.gammaln(mf + 0.5)), 0.0)
    # S2 (convergent series with logarithm)
    euler = np.euler_gamma
    psi_a = sc.psi(a)
    psi_b = sc.psi(b)
    lnz = np.log(z)
    h1 = np.full(n, -euler)                                       # psi(k+1)
    harm = np.concatenate(([0.0], np.cumsum(1.0 / np.arange(1, 2 * mmax + 1))))
    h2 = -euler + harm[2 * m]                                     # psi(2m+1)
    term = np.exp(-sc.gammaln(2.0 * mf + 1.0)).astype(complex)    # k = 0: 1/(2m)!
    S = np.zeros(n, complex)
    SA = np.zeros(n)
    total = np.zeros(n, complex)
    absum = np.zeros(n)
    act = np.arange(n)
    A, B, Z, LZ, PA, PB, H1, H2, M2 = a, b, z, lnz, psi_a, psi_b, h1, h2, 2.0 * mf
    for k in range(_NMAX):
        br = LZ - H1 - H2 + PA + PB
        tk = term * br
        S = S + tk
        at = np.abs(tk)
        SA = SA + at
        ratio = (A + k) * (B + k) / ((k + 1.0) * (k + M2 + 1.0)) * Z
        r = np.abs(ratio) * 1.05
        tail = np.where(r < 1, (at + np.abs(term)) * r / np.maximum(1.0 - r, 1e-300), np.inf)
        done = (r < 1) & (tail <= _EPS * np.maximum(np.abs(S), 1e-3 * SA)) & (k > 2)
        done |= term == 0
        if done.any():
            total[act[done]] = S[done]
            absum[act[done]] = SA[done]
            keep = ~done
            act, A, B, Z, LZ, PA, PB, H1, H2, M2 = (v[keep] for v in (act, A, B, Z, LZ, PA, PB, H1, H2, M2))
            term, S, SA, ratio = term[keep], S[keep], SA[keep], ratio[keep]
            if act.size == 0:
                break
        # advance to k+1
        PA = PA + 1.0 / (A + k)
        PB = PB + 1.0 / (B + k)
        H1 = H1 + 1.0 / (k + 1.0)
        H2 = H2 + 1.0 / (k + M2 + 1.0)
        term = term * ratio
    else:
        raise ConvergenceError("log-case series for Q_nu^m near x = 1 did not converge.")
    ps, pm = _pochhammer_sym(nu, m)
    poly = pm * np.exp(ps)                          # m <= _M_DIRECT_Q here: no overflow
    rg = sc.rgamma(0.5 - mf)
    c2 = poly * rg
    # assemble with common scale z^{-m} e^{-(Re nu + 1) t}
    logs = -mf * np.log(z) - (nu + 1.0) * t + 0.5 * math.log(math.pi)
    scale = logs.real
    sign = np.where(m % 2 == 0, 1.0, -1.0)
    ph = sign * np.exp(1j * logs.imag)
    zm = np.exp(2.0 * mf * np.log(z))                # z^{2m}: S2 and the scale differ by it
    mant = ph * (pref1 * s1 - c2 * zm * total)
    err = _ROUND * np.abs(ph) * (np.abs(pref1) * s1a + np.abs(c2) * zm * absum
                                 + np.abs(logs.imag) * np.abs(mant))
    return scale, mant, err


def _log_q_direct(nu, m, x):
    """Q for m <= _M_DIRECT_Q by the series in z = 1-q (near 1) or in q (elsewhere)."""
    scale = np.zeros(x.shape)
    mant = np.zeros(x.shape, complex)
    err = np.zeros(x.shape)
    out = (scale, mant, err)
    _, _, _, z = _geom(x)
    near = (z <= _Z_NEAR_Q) | ((m >= 4) & (z <= _Z_NEAR_Q_LARGE_M))
    far = ~near
    if near.any():
        i = np.nonzero(near)[0]
        scale[i], mant[i], err[i] = _q_near(nu[i], m[i], x[i])
        # the log-case series cancels for large |nu| z or large m: the q-series, slow but
        # free of cancellation there, is the fallback (measured: 1e-14 where this gives 1e-6)
        j = i[~(err[i] <= 25.0 * _ROUND * np.abs(mant[i]))]
        if j.size:
            _pick(out, _q_far(nu[j], m[j], x[j], strict=False), j)
    if far.any():
        i = np.nonzero(far)[0]
        scale[i], mant[i], err[i] = _q_far(nu[i], m[i], x[i])
    return out


def _q_recurrence(nu, m, x):
    """Q for m > _M_DIRECT_Q by the upward recurrence in the order (DLMF 14.10.6, x > 1),

        Q^{mu+2} = -2(mu+1) x (x^2-1)^{-1/2} Q^{mu+1} + (nu-mu)(nu+mu+1) Q^mu,

    started from the direct values at mu = _M_DIRECT_Q - 1 and _M_DIRECT_Q. For mu > |nu| the
    characteristic roots are -mu coth(t/2) (Q, dominant) and -mu tanh(t/2) (P), so upward
    recurrence is stable for Q; below |nu| the roots have equal size.

    Error estimate: the recurrence is linear, so y_m = U_m + V_m where U, V are the solutions
    started from (y_0, 0) and (0, y_1). |U_m|/|y_m| and |V_m|/|y_m| are the amplification
    factors of relative errors in the two start values; a rounding error made on the way is
    amplified about as much (at most 3 eps |y| per step, since |a y1| + |b y0| <= 3 |y2| for
    the dominant solution). A worst-case bound |a| e1 + |b| e0 instead grows like 3^steps.
    The values are rescaled by exact powers of two; a running sum of logarithms would lose
    about 1e-11 relative after 1000 steps (measured at m = 1000, x = 1.25).
    """
    n = x.size
    m0 = _M_DIRECT_Q - 1
    s0, y0, e0 = _log_q_direct(nu, np.full(n, m0), x)
    s1, y1, e1 = _log_q_direct(nu, np.full(n, m0 + 1), x)
    scale = np.maximum(s0, s1)
    f0, f1 = np.exp(s0 - scale), np.exp(s1 - scale)
    y0, e0, y1, e1 = y0 * f0, e0 * f0, y1 * f1, e1 * f1
    with np.errstate(divide="ignore", invalid="ignore"):
        r0 = np.where(y0 != 0, e0 / np.abs(y0), 0.0) + _ROUND     # relative start errors
        r1 = np.where(y1 != 0, e1 / np.abs(y1), 0.0) + _ROUND
    u0, u1 = y0.copy(), np.zeros(n, complex)                     # U: started from (y0, 0)
    k = np.zeros(n, dtype=np.int64)
    steps = np.maximum(m - (m0 + 1), 0)
    d = x - 1.0
    c = x / np.sqrt(d * (d + 2.0))                 # coth t, accurate near x = 1
    for mu in range(m0, int(m.max()) - 1):
        act = mu + 2 <= m
        a = -2.0 * (mu + 1) * c
        b = (nu - mu) * (nu + mu + 1.0)
        y2 = a * y1 + b * y0
        u2 = a * u1 + b * u0
        y0, y1 = np.where(act, y1, y0), np.where(act, y2, y1)
        u0, u1 = np.where(act, u1, u0), np.where(act, u2, u1)
        # keep |y1| near 1 (it grows like mu coth(t/2) per step), by exact powers of two
        a1 = np.abs(y1)
        e = np.frexp(np.where((a1 > 0) & np.isfinite(a1), a1, 1.0))[1]
        f = np.ldexp(1.0, -e)
        y0, y1, u0, u1 = y0 * f, y1 * f, u0 * f, u1 * f
        k += e
    au, av = np.abs(u1), np.abs(y1 - u1)
    err = r0 * au + r1 * av + 3.0 * _ROUND * steps * np.maximum(np.maximum(au, av), np.abs(y1))
    return scale + k * _LN2, y1, err


def _log_q_parts(nu, m, x):
    if m.size == 0 or int(m.max()) <= _M_DIRECT_Q:
        return _log_q_direct(nu, m, x)
    scale = np.zeros(x.shape)
    mant = np.zeros(x.shape, complex)
    err = np.zeros(x.shape)
    low = m <= _M_DIRECT_Q
    if low.any():
        scale[low], mant[low], err[low] = _log_q_direct(nu[low], m[low], x[low])
    high = ~low
    scale[high], mant[high], err[high] = _q_recurrence(nu[high], m[high], x[high])
    return scale, mant, err


# ----------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------

def legendre_p_log_parts(nu, m, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Low-level evaluator of :math:`P_\nu^m(x)` on flat, already validated arrays.

    For callers that evaluate many points and check them with :func:`evaluate_checked`
    (``evaluate_checked(legendre_p_log_parts, nu, m, x, warn=False)``); end users call
    :func:`legendre_p` or :func:`legendre_log_p`, which validate their input.

    Parameters
    ----------
    nu : ndarray of complex, shape (n,)
        Degrees.
    m : ndarray of int64, shape (n,)
        Orders from :func:`check_order`.
    x : ndarray of float, shape (n,)
        Arguments :math:`x \ge 1`.

    Returns
    -------
    log_scale, mantissa, abs_err : ndarray, shape (n,)
        :math:`P = \text{mantissa}\cdot e^{\text{log\_scale}}`, with ``abs_err`` the estimated
        absolute error of the mantissa (same scale).

    Raises
    ------
    ValueError
        If the arrays do not broadcast.

    See Also
    --------
    evaluate_checked, legendre_log_p

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.continuum.special import check_order, legendre_p_log_parts
    >>> s, mant, err = legendre_p_log_parts(np.array([0.5 + 0j]), check_order([0]), np.array([2.0]))
    >>> print(f"{(mant * np.exp(s))[0].real:.6f}")
    1.329138
    """
    # validated like legendre_p (flat copies; cheap next to the evaluation itself)
    nu, m, x, _ = _broadcast(nu, m, x)
    return _log_p_parts(nu, m, x)


def _nice(v) -> str:
    v = complex(v)
    return f"{v.real:g}" if v.imag == 0 else f"{v.real:g}{v.imag:+g}j"


def evaluate_checked(func, nu, m, x, *, warn: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Run a low-level evaluator such as :func:`legendre_p_log_parts` and check its result.

    Evaluates in blocks of a few thousand points (bounded working memory), with floating-point
    warnings silenced (intermediate overflow in tail bounds of diverging early terms is
    harmless), then checks that every value is finite and that the estimated relative error
    is below 1e-8; above that it warns with the estimate (which is a true upper estimate, see
    the module docstring).

    The accuracy warning compares the error estimate with the value itself. That is meaningful
    for Q (no zeros on x > 1 in the supported domain) but not for P, which oscillates: near a
    zero of P every method loses relative (not envelope-relative) accuracy, and for P both
    candidate methods are already tried wherever one of them is suspect, so pass
    ``warn=False`` for P.

    Parameters
    ----------
    func : callable
        ``func(nu, m, x) -> (log_scale, mantissa, abs_err)`` on flat arrays.
    nu, m, x : ndarray, shape (n,)
        Complex degrees, int64 orders (validated by :func:`check_order`), float arguments.
    warn : bool, optional
        Issue :class:`~hyperlattice.errors.ConvergenceWarning` for estimated relative errors
        above 1e-8 (default True).

    Returns
    -------
    log_scale, mantissa, abs_err : ndarray, shape (n,)
        As returned by ``func``: the value is ``mantissa * exp(log_scale)``, ``abs_err`` the
        estimated absolute error of the mantissa.

    Raises
    ------
    ValueError
        If ``func`` is not callable, ``warn`` is not True or False, or an order exceeds
        :data:`MAX_ORDER`.
    ConvergenceError
        If a value is not finite (outside the supported domain).

    Warns
    -----
    ConvergenceWarning
        If ``warn`` and an estimated relative error exceeds 1e-8.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.continuum.special import check_order, evaluate_checked, legendre_p_log_parts
    >>> s, mant, err = evaluate_checked(legendre_p_log_parts, np.array([0.5 + 0j]), check_order([0]),
    ...                                 np.array([2.0]), warn=False)
    >>> print(f"{(mant * np.exp(s))[0].real:.6f}")
    1.329138
    """
    func = _validate.function("func", func)
    warn = _validate.flag("warn", warn)
    nu, m, x, _ = _broadcast(nu, m, x)
    return _evaluate_checked(func, nu, m, x, warn=warn)


def _evaluate_checked(func, nu, m, x, *, warn: bool = True):
    """:func:`evaluate_checked` on arrays the caller has validated (flat, same length)."""
    n = x.size
    if n and int(np.max(m)) > MAX_ORDER:
        raise ValueError(f"the order m must be at most {MAX_ORDER:,}, got {int(np.max(m)):,}.")
    s = np.empty(n)
    mt = np.empty(n, complex)
    er = np.empty(n)
    with np.errstate(all="ignore"):
        for b0 in range(0, n, _CHUNK):
            sl = slice(b0, b0 + _CHUNK)
            s[sl], mt[sl], er[sl] = func(nu[sl], m[sl], x[sl])
    # the log-scale itself is rounded (and is a sum of a few logarithms): relative error of
    # the value at least about eps |log_scale|, which the evaluators do not count
    er = er + _ROUND * np.abs(s) * np.abs(mt)
    bad = ~(np.isfinite(s) & np.isfinite(mt))
    bad &= ~((mt == 0) & ~np.isnan(s))
    if bad.any():
        k = int(np.argmax(bad))
        raise ConvergenceError(
            f"Legendre function evaluation failed (non-finite result) at nu = {_nice(nu[k])}, "
            f"m = {m[k]}, x = {float(x[k]):g}; this lies outside the supported domain.")
    with np.errstate(all="ignore"):
        rel = er / np.abs(mt)
    poor = (rel > _WARN_REL) & warn
    if poor.any():
        k = int(np.argmax(np.where(poor, rel, 0)))
        warnings.warn(
            f"Legendre function lost accuracy (estimated relative error {rel[k]:.1e}) at "
            f"nu = {_nice(nu[k])}, m = {m[k]}, x = {float(x[k]):g}, outside the validated domain.",
            ConvergenceWarning, stacklevel=3)
    return s, mt, er


def _check_q_poles(nu, m):
    """Q_nu^m has genuine poles where nu + m + 1 is 0, -1, -2, ... (Gamma(nu+m+1))."""
    a = nu + m + 1.0
    pole = (a.imag == 0) & (a.real <= 0) & (a.real == np.round(a.real))
    if pole.any():
        k = int(np.argmax(pole))
        raise ValueError(f"Q_nu^m has a pole at nu = {_nice(nu[k])}, m = {m[k]} (nu + m + 1 is a "
                         "non-positive integer); it is not defined there.")


def _finish(scale, mant, shape):
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        big = np.exp(scale)
        val = mant * big
    over = np.isinf(big) & (mant != 0)
    if over.any():
        # |value| beyond 1.8e308: say so, and keep the phase (inf * (re + i im) would put NaN in
        # a zero component)
        val[over] = (np.where(mant[over].real != 0, np.copysign(np.inf, mant[over].real), 0.0)
                     + 1j * np.where(mant[over].imag != 0, np.copysign(np.inf, mant[over].imag), 0.0))
        k = int(np.argmax(over))
        warnings.warn(f"the value overflows the float64 range (|value| = e^{float(scale[k]):.6g} > 1.8e308) "
                      "and is returned as inf; the log_* functions (e.g. legendre_log_p) give it as a "
                      "log-scale and a mantissa.", RangeWarning, stacklevel=3)
    val = val.reshape(shape)
    return val[()] if val.ndim == 0 else val



def legendre_p(nu, m, x) -> complex | np.ndarray:
    r"""Associated Legendre function of the first kind :math:`P_\nu^m(x)`, :math:`x \ge 1`.

    DLMF §14.3 (type 3): :math:`P_\nu^m(x) = (x^2-1)^{m/2}\, d^m P_\nu/dx^m`, no
    Condon–Shortley phase. Used by ``eq16``/``eig18``/``eig19`` (radial eigenfunctions with
    :math:`\nu = \tfrac12(-1+\mathrm{i}k)`) and ``spec2`` (Dirichlet condition).

    Parameters
    ----------
    nu : complex or array_like
        Degree (any finite complex value; :math:`P_\nu = P_{-\nu-1}` is used internally).
        Validated: conical :math:`k \le 600`, other complex :math:`|\nu| \lesssim 50`.
    m : int or array_like of int
        Order, :math:`0 \le m \le` :data:`MAX_ORDER` (= 1000); larger orders are refused.
    x : float or array_like
        Argument, :math:`1 \le x \le 10^{12}` is the validated range (larger works).

    Returns
    -------
    complex or ndarray of complex
        Broadcast over ``nu``, ``m`` and ``x`` (at most 2**24 points per call). May overflow
        to ``inf`` for huge real degrees or large orders; use :func:`legendre_log_p` then.

    Raises
    ------
    ValueError
        For ``m < 0``, non-integer ``m``, ``m > MAX_ORDER``, ``x < 1``, NaN, None, bool,
        strings, or shapes that do not broadcast.
    ConvergenceError
        If a series fails to converge (outside the documented domain).

    See Also
    --------
    legendre_q, legendre_log_p, conical_p

    References
    ----------
    DLMF §14.3; Boettcher et al., Phys. Rev. A 102, 032208 (2020), ``eq16`` and Appendix F (``spec2``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.legendre_p(0.5, 0, 2.0).real:.6f}")
    1.329138
    >>> print(f"{hl.legendre_p(-0.5 + 1j, 1, 3.0).real:.6f}")
    -0.520666
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x)
    s, mt, _ = _evaluate_checked(_log_p_parts, nu_f, m_f, x_f, warn=False)
    return _finish(s, mt, shape)


def legendre_q(nu, m, x) -> complex | np.ndarray:
    r"""Associated Legendre function of the second kind :math:`Q_\nu^m(x)`, :math:`x > 1`.

    DLMF §14.3 (type 3) including the phase :math:`e^{\mathrm{i}m\pi} = (-1)^m`:
    :math:`Q_\nu^m = (-1)^m\Gamma(\nu+m+1)\boldsymbol{Q}_\nu^m` (DLMF 14.3.10), equal to
    mpmath's ``legenq(nu, m, x, type=3)``. It is the solution of ``green16`` that decays at
    large :math:`x` for :math:`\operatorname{Re}\nu > -\tfrac12` and is singular at
    :math:`x = 1` (``green17``). Poles at :math:`\nu + m + 1 \in \{0, -1, \dots\}` are
    genuine (ValueError).

    Parameters
    ----------
    nu : complex or array_like
        Degree; validated: conical :math:`k \le 600`, real :math:`\nu \in [-6, 5]` (including
        the half-integers :math:`-\tfrac32, -\tfrac52, \dots`), complex :math:`|\nu| \lesssim 50`.
    m : int or array_like of int
        Order, :math:`0 \le m \le` :data:`MAX_ORDER` (= 1000).
    x : float or array_like
        Argument, :math:`x > 1`; validated up to :math:`10^{12}`.

    Returns
    -------
    complex or ndarray of complex
        Broadcast over ``nu``, ``m`` and ``x``.

    Raises
    ------
    ValueError
        For invalid ``m`` (see :func:`legendre_p`), ``x <= 1``, NaN, None, bool, strings,
        shapes that do not broadcast, or at a pole.
    ConvergenceError
        If a series fails to converge.

    Warns
    -----
    ConvergenceWarning
        Where the estimated relative error exceeds 1e-8 (it states the estimate).

    See Also
    --------
    legendre_p, legendre_log_q, legendre_q_over_p

    References
    ----------
    DLMF §14.3 (14.3.10); Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green16``, ``green17``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> print(f"{hl.legendre_q(0.5, 0, 2.0).real:.6f}")
    0.224014
    >>> print(f"{hl.legendre_q(0.5, 1, 2.0).real:.6f}")
    -0.348896
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x, allow_one=False)
    _check_q_poles(nu_f, m_f)
    s, mt, _ = _evaluate_checked(_log_q_parts, nu_f, m_f, x_f)
    return _finish(s, mt, shape)


def legendre_log_p(nu, m, x) -> tuple[np.ndarray, np.ndarray]:
    r"""Scaled :math:`P_\nu^m(x)` as ``(log_scale, mantissa)``.

    :math:`P = \text{mantissa}\cdot e^{\text{log\_scale}}` (real ``log_scale``), avoiding
    overflow and underflow for large :math:`m`, large real :math:`\nu` or :math:`x \to 1`.

    Parameters
    ----------
    nu : complex or array_like
        Degree, as for :func:`legendre_p`.
    m : int or array_like of int
        Order, :math:`0 \le m \le` :data:`MAX_ORDER`.
    x : float or array_like
        Argument, :math:`x \ge 1`.

    Returns
    -------
    log_scale : ndarray of float
        Real logarithmic scale, with the broadcast shape (0-d arrays for scalar input).
    mantissa : ndarray of complex
        Mantissa of the same shape.

    Raises
    ------
    ValueError
        As for :func:`legendre_p`.
    ConvergenceError
        If a series fails to converge.

    See Also
    --------
    legendre_p, legendre_log_q

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.continuum.special import legendre_log_p
    >>> s, mant = legendre_log_p(0.5, 200, 1e6)
    >>> print(f"{float(s + np.log(abs(mant))):.3f}")  # ln|P|: P itself overflows float64
    860.824
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x)
    s, mt, _ = _evaluate_checked(_log_p_parts, nu_f, m_f, x_f, warn=False)
    return s.reshape(shape), mt.reshape(shape)


def legendre_log_q(nu, m, x) -> tuple[np.ndarray, np.ndarray]:
    r"""Scaled :math:`Q_\nu^m(x)` as ``(log_scale, mantissa)``; see :func:`legendre_log_p`.

    Parameters
    ----------
    nu : complex or array_like
        Degree, as for :func:`legendre_q`.
    m : int or array_like of int
        Order, :math:`0 \le m \le` :data:`MAX_ORDER`.
    x : float or array_like
        Argument, :math:`x > 1`.

    Returns
    -------
    log_scale : ndarray of float
        Real logarithmic scale, with the broadcast shape (0-d arrays for scalar input).
    mantissa : ndarray of complex
        Mantissa; :math:`Q = \text{mantissa}\cdot e^{\text{log\_scale}}`.

    Raises
    ------
    ValueError
        As for :func:`legendre_q` (also at a pole).
    ConvergenceError
        If a series fails to converge.

    Warns
    -----
    ConvergenceWarning
        Where the estimated relative error exceeds 1e-8.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.continuum.special import legendre_log_q
    >>> s, mant = legendre_log_q(0.5, 0, 2.0)
    >>> print(f"{float((mant * np.exp(s)).real):.6f}")
    0.224014
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x, allow_one=False)
    _check_q_poles(nu_f, m_f)
    s, mt, _ = _evaluate_checked(_log_q_parts, nu_f, m_f, x_f)
    return s.reshape(shape), mt.reshape(shape)


def legendre_q_over_p(nu, m, x) -> complex | np.ndarray:
    r"""The ratio :math:`Q_\nu^m(x)/P_\nu^m(x)` evaluated without forming either factor.

    This is the boundary factor :math:`u_m(\rho_L)/v_m(\rho_L)` of ``green31`` (Dirichlet
    correction of the Green function) at :math:`\rho_L = (1+L^2)/(1-L^2)`, which reaches
    :math:`10^{7}` and beyond; both functions are carried as log-scaled pairs so that the
    ratio stays accurate where the factors would overflow.

    Parameters
    ----------
    nu : complex or array_like
        Degree, as for :func:`legendre_q`.
    m : int or array_like of int
        Order, :math:`0 \le m \le` :data:`MAX_ORDER`.
    x : float or array_like
        Argument, :math:`x > 1`.

    Returns
    -------
    complex or ndarray of complex
        :math:`Q_\nu^m(x)/P_\nu^m(x)`, broadcast over the inputs; infinite where :math:`P = 0`.

    Raises
    ------
    ValueError
        As for :func:`legendre_q` (also at a pole).
    ConvergenceError
        If a series fails to converge.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green31``).

    Examples
    --------
    >>> from hyperlattice.continuum.special import legendre_q_over_p
    >>> print(f"{legendre_q_over_p(0.5, 0, 2.0).real:.6f}")
    0.168541
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x, allow_one=False)
    _check_q_poles(nu_f, m_f)
    sp, mp_, _ = _evaluate_checked(_log_p_parts, nu_f, m_f, x_f, warn=False)
    sq, mq, _ = _evaluate_checked(_log_q_parts, nu_f, m_f, x_f)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        val = (mq / mp_) * np.exp(sq - sp)
    val = val.reshape(shape)
    return val[()] if val.ndim == 0 else val


def legendre_wronskian(nu, m, x) -> complex | np.ndarray:
    r"""Exact Wronskian :math:`W\{P_\nu^m, Q_\nu^m\}(x) = P Q' - Q P'` in this convention.

    .. math:: W = \frac{(-1)^m}{1-x^2}\frac{\Gamma(\nu+m+1)}{\Gamma(\nu-m+1)}

    (A&S 8.1.9 with the duplication formula; equals :math:`-\kappa_m/(1-x^2)\cdot(-1)` of
    ``green25`` up to the sign convention of :math:`u_m, v_m`). Used as an identity test.

    Parameters
    ----------
    nu : complex or array_like
        Degree.
    m : int or array_like of int
        Order, :math:`0 \le m \le` :data:`MAX_ORDER`.
    x : float or array_like
        Argument, :math:`x > 1`.

    Returns
    -------
    complex or ndarray of complex
        :math:`W`, broadcast over the inputs.

    Raises
    ------
    ValueError
        If ``m`` or ``x`` is invalid (as for :func:`legendre_q`), or the shapes do not
        broadcast.

    References
    ----------
    Abramowitz & Stegun 8.1.9; Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green25``).

    Examples
    --------
    >>> from hyperlattice.continuum.special import legendre_wronskian
    >>> print(f"{legendre_wronskian(0.5, 1, 2.0).real:.6f}")
    0.250000
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x, allow_one=False)
    sign = np.where(m_f % 2 == 0, 1.0, -1.0)
    ps, pm = _pochhammer_sym(nu_f, m_f)
    with np.errstate(over="ignore"):
        val = sign * pm * np.exp(ps) / ((1.0 - x_f) * (1.0 + x_f))
    val = val.reshape(shape)
    return val[()] if val.ndim == 0 else val


def legendre_cm(nu, m) -> complex | np.ndarray:
    r"""The constant :math:`C_m` of ``green25b`` / ``green26b``.

    .. math:: C_m = \frac{\Gamma(\frac{\nu-m+2}{2})\Gamma(\frac{\nu-m+1}{2})}
                         {4^m\Gamma(\frac{\nu+m+2}{2})\Gamma(\frac{\nu+m+1}{2})}
                  = \frac{\Gamma(\nu-m+1)}{\Gamma(\nu+m+1)}
                  = \frac{(-1)^m}{\prod_{n=0}^{m-1}[(n+\frac12)^2 + \frac14(\lambda-1)]},

    with :math:`\lambda = -4\nu(\nu+1)`; :math:`C_0 = 1`. Computed as the reciprocal of the
    polynomial :math:`\prod_{j=1-m}^{m}(\nu+j)` (no Gamma functions, no poles).

    Parameters
    ----------
    nu : complex or array_like
        Degree.
    m : int or array_like of int
        Order, :math:`0 \le m \le` :data:`MAX_ORDER`; broadcasts against ``nu``.

    Returns
    -------
    complex or ndarray of complex
        :math:`C_m`; infinite where the polynomial vanishes (integer :math:`0 \le \nu < m`).

    Raises
    ------
    ValueError
        If ``nu`` or ``m`` is invalid, the shapes do not broadcast, or they broadcast to too
        many points.

    See Also
    --------
    hyperlattice.continuum.green.coefficient_cm

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green25b``, ``green26b``).

    Examples
    --------
    >>> from hyperlattice.continuum.special import legendre_cm
    >>> [round(complex(c).real, 6) for c in legendre_cm(0.3, [0, 1, 2])]
    [1.0, 2.564103, -1.59261]
    """
    nu_a = _check_nu(nu)
    m_a = check_order(m)
    try:
        nu_b, m_b = np.broadcast_arrays(nu_a, m_a)
    except ValueError:
        raise ValueError(f"nu and m must broadcast to one shape; got shapes {nu_a.shape} and "
                         f"{m_a.shape}.") from None
    if nu_b.size > _MAX_POINTS:
        raise ValueError(f"nu and m broadcast to {nu_b.size:,} points; at most {_MAX_POINTS:,} "
                         "are evaluated in one call.")
    ps, pm = _pochhammer_sym(nu_b.ravel(), m_b.ravel().astype(np.int64))
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        val = np.where(pm == 0, np.inf + 0j, np.exp(-ps) / np.where(pm == 0, 1.0, pm))
    val = val.reshape(nu_b.shape)
    return val[()] if val.ndim == 0 else val


def nu_from_lambda(lam) -> complex | np.ndarray:
    r"""Degree :math:`\nu` for the Helmholtz parameter :math:`\lambda` of ``green16``.

    :math:`\lambda/4 = -\nu(\nu+1)`. The branch :math:`\nu = -\tfrac12 + \tfrac12\sqrt{1-\lambda}`
    with the principal square root has :math:`\operatorname{Re}\nu \ge -\tfrac12` and its cut on
    :math:`\lambda \in [1, \infty)` (the continuous spectrum). It gives :math:`\nu = 0` at
    :math:`\lambda = 0`, makes :math:`Q_\nu^m` the solution decaying as :math:`x\to\infty`, and for
    real :math:`\lambda = 1 + k^2 > 1` gives the paper's :math:`\nu = \tfrac12(-1+\mathrm{i}k)`.

    Parameters
    ----------
    lam : float, complex or array_like
        Helmholtz parameter :math:`\lambda`.

    Returns
    -------
    complex or ndarray of complex
        :math:`\nu`, same shape as ``lam``.

    Raises
    ------
    ValueError
        If ``lam`` is not numeric or not finite.

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix H (``green16``).

    Examples
    --------
    >>> from hyperlattice.continuum.special import nu_from_lambda
    >>> nu = nu_from_lambda(5.0)
    >>> print(f"{nu.real:.6f} {nu.imag:.6f}")
    -0.500000 1.000000
    >>> print(f"{nu_from_lambda(0.0).real:.6f}")
    0.000000
    """
    lam_a = _validate.complex_array("lambda", lam)
    val = -0.5 + 0.5 * np.sqrt(1.0 - lam_a + 0j)
    return val[()] if val.ndim == 0 else val


def conical_p(k, m, x) -> float | np.ndarray:
    r"""Conical function :math:`P^m_{(-1+\mathrm{i}k)/2}(x)` for real :math:`k`, as a real array.

    For :math:`\nu = -\tfrac12 + \mathrm{i}k/2` the function is real for real :math:`x > 1`
    (:math:`P_\nu = P_{-\nu-1} = P_{\bar\nu}`), which is what the Dirichlet condition ``spec2``
    needs. The imaginary part of the complex evaluation (rounding only) is discarded.

    Parameters
    ----------
    k : float or array_like of float
        Real wave number (validated up to 600).
    m : int or array_like of int
        Order, :math:`0 \le m \le` :data:`MAX_ORDER`.
    x : float or array_like
        Argument, :math:`x \ge 1`.

    Returns
    -------
    float or ndarray of float
        The real conical function, broadcast over the inputs.

    Raises
    ------
    ValueError
        If ``k`` is not real and finite, or as for :func:`legendre_p`.
    ConvergenceError
        If a series fails to converge.

    See Also
    --------
    legendre_p, hyperlattice.continuum.spectrum.dirichlet_roots

    References
    ----------
    DLMF §14.20; Boettcher et al., Phys. Rev. A 102, 032208 (2020), Appendix F (``spec2``).

    Examples
    --------
    >>> from hyperlattice.continuum.special import conical_p
    >>> print(f"{conical_p(2.0, 0, 3.0):.6f}")
    0.315500
    """
    k_a = _validate.real_array("the momentum k", k)
    return np.real(legendre_p(-0.5 + 0.5j * k_a, m, x))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
