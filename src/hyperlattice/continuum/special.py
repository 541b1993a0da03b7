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
  (the trapezoidal rule on the circle converges like :math:`(|\nu-\nu_0|/R)^{M}`).
* :math:`Q`, :math:`x` near 1 (:math:`1-q \le z_*`): the same :math:`q`-series continued to
  :math:`q\to 1` by the logarithmic-case formula DLMF 15.8.10 (here
  :math:`c-a-b = -2m`), which is a convergent series in :math:`1-q` containing
  :math:`\ln(1-q)` and digamma functions and is free of degenerate cases; elsewhere the
  :math:`q`-series above. Near :math:`-\tfrac32, -\tfrac52, \dots` (where :math:`\nu+\tfrac32`
  is a pole of :math:`\Gamma`) the Cauchy formula is used as for :math:`P`.

Every series checks its own truncation (tail bound from the term ratio) and raises
:class:`~hyperlattice.errors.ConvergenceError` if it does not converge. Values are carried as
``(log_scale, mantissa)`` pairs internally so that large orders (:math:`m \le 30`) and
arguments up to :math:`10^{12}` neither overflow nor underflow; :func:`legendre_q_over_p` and
:func:`legendre_log_p` / :func:`legendre_log_q` expose that.

Accuracy (measured against mpmath at 30 digits, see ``docs/continuum.md`` and
``tests/test_special.py``): relative error below :math:`10^{-13}` away from zeros for
:math:`x \in [1, 10^{12}]`, :math:`m \le 30`, conical :math:`k \le 600` and complex
:math:`|\nu| \lesssim 50`; near zeros the error is at that level relative to the local envelope.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy import special as sc

from ..errors import ConvergenceError, ConvergenceWarning

__all__ = [
    "legendre_p",
    "legendre_q",
    "legendre_log_p",
    "legendre_log_q",
    "legendre_q_over_p",
    "legendre_wronskian",
    "legendre_cm",
    "conical_p",
    "nu_from_lambda",
]

_EPS = 2.0**-54          # target relative size of the neglected tail of every series
_NMAX = 20000            # hard cap on series terms (never reached in the documented domain)
_X_NEAR_P = 3.0          # P: w-series for x <= 3 (w <= 1/2), q-series beyond (q < 0.03)
_Z_NEAR_Q = 0.5          # Q: log-case series in z = 1-q for z <= _Z_NEAR_Q (x <= 1.0607) ...
_Z_NEAR_Q_LARGE_M = 0.75  # ... and up to z = 0.75 (x <= 1.25) for m >= 4, where the q-series is slow
_CAUCHY_M = 32           # nodes on the Cauchy circle around half-integer degrees
_SERIES_LOSS = 1e2       # if sum|terms|/|sum| exceeds this, try the Laplace quadrature too


# ----------------------------------------------------------------------------
# input handling
# ----------------------------------------------------------------------------

def _check_m(m) -> np.ndarray:
    m_arr = np.asarray(m)
    if m_arr.dtype.kind == "f":
        if not np.all(np.isfinite(m_arr)) or np.any(m_arr != np.round(m_arr)):
            raise ValueError("the order m must be a non-negative integer.")
        m_arr = m_arr.astype(np.int64)
    elif m_arr.dtype.kind not in "iu":
        raise ValueError("the order m must be a non-negative integer.")
    if np.any(m_arr < 0):
        raise ValueError("the order m must be non-negative; use P^m = P^{|m|} up to the "
                         "documented factors for negative m.")
    return m_arr.astype(np.int64)


def _check_x(x, *, allow_one: bool = True) -> np.ndarray:
    x_arr = np.asarray(x)
    if np.iscomplexobj(x_arr):
        if np.any(x_arr.imag != 0):
            raise ValueError("the argument x must be real (x >= 1); complex x is not supported.")
        x_arr = x_arr.real
    x_arr = x_arr.astype(float)
    if np.any(np.isnan(x_arr)):
        raise ValueError("the argument x contains NaN.")
    if np.any(~np.isfinite(x_arr)):
        raise ValueError("the argument x must be finite.")
    if np.any(x_arr < 1.0):
        raise ValueError("the argument x must satisfy x >= 1 (the functions are of type 3, x > 1).")
    if not allow_one and np.any(x_arr == 1.0):
        raise ValueError("Q_nu^m(x) is singular at x = 1; pass x > 1.")
    return x_arr


def _check_nu(nu) -> np.ndarray:
    nu_arr = np.asarray(nu).astype(complex)
    if np.any(~np.isfinite(nu_arr)):
        raise ValueError("the degree nu must be finite (no NaN or inf).")
    return nu_arr


def _broadcast(nu, m, x, *, allow_one=True):
    nu_a = _check_nu(nu)
    m_a = _check_m(m)
    x_a = _check_x(x, allow_one=allow_one)
    nu_b, m_b, x_b = np.broadcast_arrays(nu_a, m_a, x_a)
    shape = nu_b.shape
    return (nu_b.ravel().copy(), m_b.ravel().astype(np.int64), x_b.ravel().copy(), shape)


def _geom(x):
    """t = arccosh x, d = x - 1, q = e^{-2t}, z = 1 - q, computed without cancellation near 1."""
    d = x - 1.0
    t = np.where(d < 1.0, np.log1p(d + np.sqrt(d * (d + 2.0))),
                 np.log(x) + np.log1p(np.sqrt(np.maximum(1.0 - 1.0 / (x * x), 0.0))))
    q = np.exp(-2.0 * t)
    z = -np.expm1(-2.0 * t)
    return d, t, q, z


def _pochhammer_sym(nu, m):
    """Gamma(nu+m+1)/Gamma(nu-m+1) = prod_{j=1-m}^{m} (nu+j), as a polynomial (no poles)."""
    out = np.ones(nu.shape, complex)
    mmax = int(m.max()) if m.size else 0
    for j in range(1, mmax + 1):
        use = j <= m
        out = np.where(use, out * (nu + j) * (nu - j + 1), out)
    return out


def _rising(a, n):
    """(a)_n for an array a and an integer array n >= 0 (elementwise)."""
    out = np.ones(np.broadcast(a, n).shape, complex)
    nmax = int(np.max(n)) if np.size(n) else 0
    for j in range(nmax):
        out = np.where(j < n, out * (a + j), out)
    return out


# ----------------------------------------------------------------------------
# a vectorized Gauss hypergeometric series with its own convergence check
# ----------------------------------------------------------------------------

def _hyp_series(a, b, c, z, *, what: str):
    """Sum F(a, b; c; z) = sum_n (a)_n (b)_n / ((c)_n n!) z^n elementwise.

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
    raise ConvergenceError(f"hypergeometric series for {what} did not converge in {_NMAX} terms.")


# ----------------------------------------------------------------------------
# P_nu^m: near region (w-series, Laplace quadrature) and far region (q-series)
# ----------------------------------------------------------------------------

def _reflect(nu):
    """P_nu^m = P_{-nu-1}^m: use the degree with Re nu >= -1/2."""
    return np.where(nu.real < -0.5, -nu - 1.0, nu)


def _p_near_series(nu, m, x):
    """(log_scale, mantissa, abs_err_mantissa) of P by the w-series; Re nu >= -1/2, 1 < x <= 3."""
    d = x - 1.0
    w = d / (d + 2.0)
    F, FA = _hyp_series(-nu, m - nu, (m + 1.0).astype(complex), w, what="P_nu^m (w-series)")
    poly = _pochhammer_sym(nu, m)
    # log of w^{m/2} ((1+x)/2)^nu / m!
    logs = 0.5 * m * np.log(w) + nu * np.log1p(0.5 * d) - sc.gammaln(m + 1.0)
    scale = logs.real
    mant = np.exp(1j * logs.imag) * poly * F
    err = np.abs(poly) * FA * 4e-16
    return scale, mant, err


def _p_near_quad(nu, m, x):
    """(log_scale, mantissa, abs_err) of P by the trapezoidal rule on the Laplace integral."""
    d, t, _, _ = _geom(x)
    s = np.sqrt(d * (d + 2.0))
    nnodes = np.ceil(m + 1.5 * np.abs(nu) * t + 40.0).astype(int)
    nnodes += nnodes % 2
    out_scale = np.empty(x.shape)
    out_mant = np.empty(x.shape, complex)
    out_err = np.empty(x.shape)
    # group by node count (rounded up to a multiple of 16) so that each group is one 2-D array op
    nn = (2.0 ** (np.ceil(np.log2(nnodes) * 4.0) / 4.0)).astype(int)
    nn += nn % 2
    for n_here in np.unique(nn):
        sel = np.nonzero(nn == n_here)[0]
        phi = np.linspace(0.0, np.pi, n_here + 1)
        wts = np.full(n_here + 1, np.pi / n_here)
        wts[0] *= 0.5
        wts[-1] *= 0.5
        base = x[sel, None] + s[sel, None] * np.cos(phi)[None, :]
        lg = np.log(base)
        expo = nu[sel, None] * lg
        # factor out the largest modulus: (x+s)^{Re nu} at phi = 0 for Re nu >= 0, else phi = pi
        sc_row = np.max(expo.real, axis=1)
        f = np.exp(expo - sc_row[:, None]) * np.cos(m[sel, None] * phi[None, :])
        val = f @ wts
        half = f[:, ::2] @ (2.0 * wts[::2]) if n_here % 2 == 0 else val
        absint = np.abs(f) @ wts
        pref = _rising(nu[sel] + 1.0, m[sel]) / np.pi
        out_scale[sel] = sc_row
        out_mant[sel] = pref * val
        # rounding ~ eps * integral of |f|; discretisation judged by the half-step rule
        disc = np.abs(val - half)
        out_err[sel] = np.abs(pref) * (4e-16 * absint * np.sqrt(n_here) + 1e-3 * disc)
    return out_scale, out_mant, out_err


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
    l1 = sc.loggamma(nu + mf + 1.0) - sc.loggamma(nu + 1.5) - (nu + 1.0) * t + mf * np.log1p(-q)
    a2 = np.where(m == 0, -sc.rgamma(nu + 1.0), _rising(1.0 - nu, np.maximum(m - 1, 0)) * sc.rgamma(nu))
    l2 = sc.loggamma(nu + 0.5) + nu * t + mf * np.log1p(-q)
    scale = np.maximum(l1.real, l2.real)
    c1 = sign * tanv / math.sqrt(math.pi) * np.exp(l1 - scale)
    c2 = -sign * a2 / math.sqrt(math.pi) * np.exp(l2 - scale)
    mant = c1 * F1 + c2 * F2
    err = 4e-16 * (np.abs(c1) * F1A + np.abs(c2) * F2A)
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
    err = np.sum(er * fac * np.abs(kern), axis=1)
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
    better = e1 < e0_on_1
    j = idx[better]
    s0[j], m0[j], e0[j] = s1[better], m1[better], e1[better]


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
        j = i[err[i] > _SERIES_LOSS * 4e-16 * np.abs(mant[i])]
        if j.size:
            _pick(out, _p_near_quad(nu[j], m[j], x[j]), j)
    if far.any():
        i = np.nonzero(far)[0]
        scale[i], mant[i], err[i] = _p_far(nu[i], m[i], x[i])
        # for large m the two terms of the connection formula cancel for moderate x (measured:
        # 1e-5 at m = 30, x = 3; 3e-12 at m = 10): the w-series still converges there (slowly)
        # and is the fallback up to x = 100. For m < 6 a large error estimate relative to the
        # value only means that P is near one of its zeros (conical oscillation), where the
        # error relative to the envelope is fine, so no fallback is attempted.
        j = i[(err[i] > _SERIES_LOSS * 4e-16 * np.abs(mant[i])) & (x[i] <= 100.0) & (m[i] >= 6)]
        if j.size:
            _pick(out, _p_near_series(nu[j], m[j], x[j]), j)
    return out


# ----------------------------------------------------------------------------
# Q_nu^m: near region (log-case series in 1-q) and far region (q-series)
# ----------------------------------------------------------------------------

def _q_far_terms(nu, m, t, q):
    """Q_nu^m = (-1)^m sqrt(pi) Gamma(nu+m+1)/Gamma(nu+3/2) (1-q)^m e^{-(nu+1)t} F(...; q)."""
    mf = m.astype(float)
    F, FA = _hyp_series(nu + mf + 1.0, (mf + 0.5).astype(complex), nu + 1.5, q,
                        what="Q_nu^m (q-series)")
    sign = np.where(m % 2 == 0, 1.0, -1.0)
    logs = (sc.loggamma(nu + mf + 1.0) - sc.loggamma(nu + 1.5) - (nu + 1.0) * t
            + mf * np.log1p(-q) + 0.5 * math.log(math.pi))
    scale = logs.real
    pref = sign * np.exp(1j * logs.imag)
    return scale, pref * F, 4e-16 * FA


def _q_far(nu, m, x):
    _, t, q, _ = _geom(x)
    scale = np.empty(x.shape)
    mant = np.empty(x.shape, complex)
    err = np.empty(x.shape)
    # nu + 3/2 near a non-positive integer: Gamma(nu+3/2) and F have cancelling poles
    cpar = nu + 1.5
    centre = np.round(cpar.real)
    radius = np.full(x.shape, 0.25)
    bad = (centre <= 0) & (np.abs(cpar - centre) < 0.25 * radius)
    ok = ~bad
    if ok.any():
        scale[ok], mant[ok], err[ok] = _q_far_terms(nu[ok], m[ok], t[ok], q[ok])
    if bad.any():
        i = bad
        scale[i], mant[i], err[i] = _cauchy(_q_far_terms, nu[i], (centre[i] - 1.5).astype(complex),
                                            radius[i], m[i], t[i], q[i])
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
    poly = _pochhammer_sym(nu, m)
    rg = sc.rgamma(0.5 - mf)
    c2 = poly * rg
    # assemble with common scale z^{-m} e^{-(Re nu + 1) t}
    logs = -mf * np.log(z) - (nu + 1.0) * t + 0.5 * math.log(math.pi)
    scale = logs.real
    sign = np.where(m % 2 == 0, 1.0, -1.0)
    ph = sign * np.exp(1j * logs.imag)
    zm = np.exp(2.0 * mf * np.log(z))                # z^{2m}: S2 and the scale differ by it
    mant = ph * (pref1 * s1 - c2 * zm * total)
    err = 4e-16 * np.abs(ph) * (np.abs(pref1) * s1a + np.abs(c2) * zm * absum)
    return scale, mant, err


def _log_q_parts(nu, m, x):
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
        j = i[err[i] > 25.0 * 4e-16 * np.abs(mant[i])]
        if j.size:
            _pick(out, _q_far(nu[j], m[j], x[j]), j)
    if far.any():
        i = np.nonzero(far)[0]
        scale[i], mant[i], err[i] = _q_far(nu[i], m[i], x[i])
    return out


# ----------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------

def _guarded(func, nu, m, x, *, warn=True):
    """Run an evaluator with floating-point warnings silenced (intermediate overflow in tail
    bounds of diverging early terms is harmless) and check the result and its error estimate.

    The accuracy warning compares the error estimate with the value itself. That is meaningful
    for Q (no zeros on x > 1 in the supported domain) but not for P, which oscillates: near a
    zero of P every method loses relative (not envelope-relative) accuracy, and for P both
    candidate methods are already tried wherever one of them is suspect, so ``warn=False``.
    """
    with np.errstate(all="ignore"):
        s, mt, er = func(nu, m, x)
    bad = ~(np.isfinite(s) & np.isfinite(mt))
    bad &= ~((mt == 0) & ~np.isnan(s))
    if bad.any():
        k = int(np.argmax(bad))
        raise ConvergenceError(
            f"Legendre function evaluation failed (non-finite result) at nu={nu[k]!r}, m={m[k]}, "
            f"x={x[k]!r}; this is at a pole in nu or outside the supported domain.")
    with np.errstate(all="ignore"):
        rel = er / np.abs(mt)
    poor = (rel > 1e-8) & warn
    if poor.any():
        k = int(np.argmax(np.where(poor, rel, 0)))
        warnings.warn(
            f"Legendre function lost accuracy (estimated relative error {rel[k]:.1e}) at "
            f"nu={nu[k]!r}, m={m[k]}, x={x[k]!r}, outside the validated domain.",
            ConvergenceWarning, stacklevel=3)
    return s, mt, er


def _finish(scale, mant, shape):
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        val = mant * np.exp(scale)
    val = val.reshape(shape)
    return val[()] if val.ndim == 0 else val


def legendre_p(nu, m, x):
    r"""Associated Legendre function of the first kind :math:`P_\nu^m(x)`, :math:`x \ge 1`.

    DLMF §14.3 (type 3): :math:`P_\nu^m(x) = (x^2-1)^{m/2}\, d^m P_\nu/dx^m`, no
    Condon–Shortley phase. Used by ``eq16``/``eig18``/``eig19`` (radial eigenfunctions with
    :math:`\nu = \tfrac12(-1+\mathrm{i}k)`) and ``spec2`` (Dirichlet condition).

    Parameters
    ----------
    nu : complex or array_like
        Degree (any complex value; :math:`P_\nu = P_{-\nu-1}` is used internally).
    m : int or array_like of int
        Order, :math:`m \ge 0`.
    x : float or array_like
        Argument, :math:`1 \le x \le 10^{12}` is the validated range (larger works).

    Returns
    -------
    complex or ndarray of complex
        Broadcast over ``nu``, ``m`` and ``x``. May overflow to ``inf`` for huge real degrees;
        use :func:`legendre_log_p` then.

    Raises
    ------
    ValueError
        For ``m < 0``, non-integer ``m``, ``x < 1`` or NaN input.
    ConvergenceError
        If a series fails to converge (outside the documented domain).
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x)
    s, mt, _ = _guarded(_log_p_parts, nu_f, m_f, x_f, warn=False)
    return _finish(s, mt, shape)


def legendre_q(nu, m, x):
    r"""Associated Legendre function of the second kind :math:`Q_\nu^m(x)`, :math:`x > 1`.

    DLMF §14.3 (type 3) including the phase :math:`e^{\mathrm{i}m\pi} = (-1)^m`:
    :math:`Q_\nu^m = (-1)^m\Gamma(\nu+m+1)\boldsymbol{Q}_\nu^m` (DLMF 14.3.10), equal to
    mpmath's ``legenq(nu, m, x, type=3)``. It is the solution of ``green16`` that decays at
    large :math:`x` for :math:`\operatorname{Re}\nu > -\tfrac12` and is singular at
    :math:`x = 1` (``green17``). Poles at :math:`\nu + m + 1 \in \{0, -1, \dots\}` are
    genuine.

    Parameters
    ----------
    nu : complex or array_like
    m : int or array_like of int, ``m >= 0``
    x : float or array_like, ``x > 1``

    Returns
    -------
    complex or ndarray of complex

    Raises
    ------
    ValueError
        For ``m < 0``, ``x <= 1`` or NaN input.
    ConvergenceError
        If a series fails to converge.
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x, allow_one=False)
    s, mt, _ = _guarded(_log_q_parts, nu_f, m_f, x_f)
    return _finish(s, mt, shape)


def legendre_log_p(nu, m, x):
    r"""Scaled :math:`P_\nu^m(x)`: returns ``(log_scale, mantissa)`` with
    :math:`P = \text{mantissa}\cdot e^{\text{log\_scale}}` (real ``log_scale``), avoiding
    overflow and underflow for large :math:`m`, large real :math:`\nu` or :math:`x \to 1`."""
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x)
    s, mt, _ = _guarded(_log_p_parts, nu_f, m_f, x_f, warn=False)
    return s.reshape(shape), mt.reshape(shape)


def legendre_log_q(nu, m, x):
    r"""Scaled :math:`Q_\nu^m(x)` as ``(log_scale, mantissa)``; see :func:`legendre_log_p`."""
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x, allow_one=False)
    s, mt, _ = _guarded(_log_q_parts, nu_f, m_f, x_f)
    return s.reshape(shape), mt.reshape(shape)


def legendre_q_over_p(nu, m, x):
    r"""The ratio :math:`Q_\nu^m(x)/P_\nu^m(x)` evaluated without forming either factor.

    This is the boundary factor :math:`u_m(\rho_L)/v_m(\rho_L)` of ``green31`` (Dirichlet
    correction of the Green function) at :math:`\rho_L = (1+L^2)/(1-L^2)`, which reaches
    :math:`10^{7}` and beyond; both functions are carried as log-scaled pairs so that the
    ratio stays accurate where the factors would overflow. Infinite where :math:`P = 0`.
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x, allow_one=False)
    sp, mp_, _ = _guarded(_log_p_parts, nu_f, m_f, x_f, warn=False)
    sq, mq, _ = _guarded(_log_q_parts, nu_f, m_f, x_f)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        val = (mq / mp_) * np.exp(sq - sp)
    val = val.reshape(shape)
    return val[()] if val.ndim == 0 else val


def legendre_wronskian(nu, m, x):
    r"""Exact Wronskian :math:`W\{P_\nu^m, Q_\nu^m\}(x) = P Q' - Q P'` in this convention.

    .. math:: W = \frac{(-1)^m}{1-x^2}\frac{\Gamma(\nu+m+1)}{\Gamma(\nu-m+1)}

    (A&S 8.1.9 with the duplication formula; equals :math:`-\kappa_m/(1-x^2)\cdot(-1)` of
    ``green25`` up to the sign convention of :math:`u_m, v_m`). Used as an identity test.
    """
    nu_f, m_f, x_f, shape = _broadcast(nu, m, x, allow_one=False)
    sign = np.where(m_f % 2 == 0, 1.0, -1.0)
    val = sign * _pochhammer_sym(nu_f, m_f) / ((1.0 - x_f) * (1.0 + x_f))
    val = val.reshape(shape)
    return val[()] if val.ndim == 0 else val


def legendre_cm(nu, m):
    r"""The constant :math:`C_m` of ``green25b`` / ``green26b``.

    .. math:: C_m = \frac{\Gamma(\frac{\nu-m+2}{2})\Gamma(\frac{\nu-m+1}{2})}
                         {4^m\Gamma(\frac{\nu+m+2}{2})\Gamma(\frac{\nu+m+1}{2})}
                  = \frac{\Gamma(\nu-m+1)}{\Gamma(\nu+m+1)}
                  = \frac{(-1)^m}{\prod_{n=0}^{m-1}[(n+\frac12)^2 + \frac14(\lambda-1)]},

    with :math:`\lambda = -4\nu(\nu+1)`; :math:`C_0 = 1`. Computed as the reciprocal of the
    polynomial :math:`\prod_{j=1-m}^{m}(\nu+j)` (no Gamma functions, no poles).
    """
    nu_a = _check_nu(nu)
    m_a = _check_m(m)
    nu_b, m_b = np.broadcast_arrays(nu_a, m_a)
    val = 1.0 / _pochhammer_sym(nu_b.ravel(), m_b.ravel().astype(np.int64))
    val = val.reshape(nu_b.shape)
    return val[()] if val.ndim == 0 else val


def nu_from_lambda(lam):
    r"""Degree :math:`\nu` for the Helmholtz parameter :math:`\lambda` of ``green16``.

    :math:`\lambda/4 = -\nu(\nu+1)`. The branch :math:`\nu = -\tfrac12 + \tfrac12\sqrt{1-\lambda}`
    with the principal square root has :math:`\operatorname{Re}\nu \ge -\tfrac12` and its cut on
    :math:`\lambda \in [1, \infty)` (the continuous spectrum). It gives :math:`\nu = 0` at
    :math:`\lambda = 0`, makes :math:`Q_\nu^m` the solution decaying as :math:`x\to\infty`, and for
    real :math:`\lambda = 1 + k^2 > 1` gives the paper's :math:`\nu = \tfrac12(-1+\mathrm{i}k)`.
    """
    lam_a = np.asarray(lam, dtype=complex)
    if np.any(~np.isfinite(lam_a)):
        raise ValueError("lambda must be finite.")
    val = -0.5 + 0.5 * np.sqrt(1.0 - lam_a + 0j)
    return val[()] if val.ndim == 0 else val


def conical_p(k, m, x):
    r"""Conical function :math:`P^m_{(-1+\mathrm{i}k)/2}(x)` for real :math:`k`, as a real array.

    For :math:`\nu = -\tfrac12 + \mathrm{i}k/2` the function is real for real :math:`x > 1`
    (:math:`P_\nu = P_{-\nu-1} = P_{\bar\nu}`), which is what the Dirichlet condition ``spec2``
    needs. The imaginary part of the complex evaluation (rounding only) is discarded.
    """
    k_a = np.asarray(k, dtype=float)
    if np.any(~np.isfinite(k_a)):
        raise ValueError("the momentum k must be finite real numbers.")
    return np.real(legendre_p(-0.5 + 0.5j * k_a, m, x))
