r"""Dirichlet levels of the magnetic Laplacian on a hyperbolic disk (the continuum side of the flux dictionary).

Conventions
-----------
Metric ``ds^2 = |dz|^2/(1-|z|^2)^2`` on the Poincaré disk (curvature :math:`-4`, the paper's), area
element :math:`dV = r\,dr\,d\phi/(1-r^2)^2`; the disk :math:`|z|<r` has area
:math:`\int_0^r 2\pi s\,ds/(1-s^2)^2 = \pi r^2/(1-r^2)`. A uniform field B (flux B per unit
hyperbolic area, :math:`\hbar = e = 1`, one flux quantum is :math:`2\pi`) in the symmetric gauge

.. math:: A = \frac{B r^2}{2(1-r^2)}\,d\phi,\qquad
          dA = \frac{B r}{(1-r^2)^2}\,dr\wedge d\phi = B\,dV,

so the flux through :math:`|z|<r` is :math:`2\pi A_\phi(r) = B\cdot\pi r^2/(1-r^2)`. Positive B
points out of the disk (counterclockwise circulation of A); :math:`\psi = e^{\mathrm im\phi}R`
with :math:`m>0` circulates counterclockwise. The magnetic Laplacian is
:math:`\Delta_B = (1-|z|^2)^2(\nabla - \mathrm iA)^2` (the 2-d conformal factor cancels in
:math:`\sqrt g\,g^{ij}`). The lattice flux f (quanta per p-gon face) maps to B by
:func:`hyperlattice.dictionary.field_from_flux`.

Radial equation
---------------
With :math:`\psi = e^{\mathrm im\phi}R(r)` and :math:`(\partial_\phi - \mathrm iA_\phi)^2 \to
-(m - A_\phi)^2`, :math:`-\Delta_B\psi = \kappa\psi` reads

.. math:: (1-r^2)^2\Bigl[R'' + \frac{R'}{r} - \frac{(m - A_\phi)^2}{r^2}R\Bigr] + \kappa R = 0 .

In :math:`u = r^2` (:math:`s = 1-u`, :math:`b = B/2`):
:math:`4u s^2 R_{uu} + 4 s^2 R_u + [\kappa - (m s - b u)^2/u]R = 0`, a Fuchsian equation with
singular points :math:`0, 1, \infty` and exponents :math:`\pm|m|/2` (at 0),
:math:`\beta_\pm = \frac12(1\pm\delta)`, :math:`\delta = \sqrt{1 - \kappa + B^2/4}` (at 1),
:math:`\pm(m+b)/2` (at :math:`\infty`); they sum to 1 (Fuchs). Hence (Riemann P-symbol,
DLMF 15.11) the solution regular at :math:`r=0`, normalised to :math:`R\sim r^{|m|}`, is

.. math:: R(r) = u^{|m|/2}(1-u)^{\beta_-}\,F(a, b'; c; u),\qquad
          a = \beta_- + \tfrac12(|m| + m + b),\quad b' = \beta_- + \tfrac12(|m| - m - b),\quad
          c = 1 + |m|,

with :math:`F` the Gauss function (DLMF 15.2.1) solving DLMF 15.10.1; :math:`c - a - b' = \delta`.
R is real (a real equation, real exponent at 0). For :math:`\kappa > 1 + B^2/4`, :math:`\delta`
is imaginary and a, b' are complex; at B = 0, :math:`\delta = \mathrm ik` and R is the conical
function of ``spec2`` (checked in the tests: the levels agree with
:func:`hyperlattice.continuum.spectrum.continuum_levels`).

Evaluation of F for :math:`0\le u<1`
------------------------------------
scipy's ``hyp2f1`` refuses complex a, b, c, so F is evaluated here, vectorised over the
parameters: the Maclaurin series (DLMF 15.2.1) up to :math:`u_a \le \min(1/2, 1/|ab'|)`, then
analytic continuation by Taylor re-expansion of DLMF 15.10.1 about successive points
:math:`u_0` (the Taylor-series method of DLMF §3.7(ii)): with :math:`g_n = f_n t^n`,

.. math:: g_{n+2} = -\frac{[(1-2u_0)n + c - (a+b'+1)u_0](n+1)\,t\,g_{n+1}
                    - (n+a)(n+b')\,t^2 g_n}{u_0(1-u_0)(n+2)(n+1)} .

Each step has :math:`t \le \frac12\min(u_0, 1-u_0)` (geometric convergence, ratio 1/2),
:math:`t \le u_0/|c|` (the recurrence also carries the solution :math:`u^{1-c}`, whose Taylor
terms sum to :math:`(1-t/u_0)^{1-c}`: this bounds their amplification of rounding by e) and
:math:`t\,k_u \le 1` with the local WKB wavenumber :math:`k_u` (no cancellation between terms);
near :math:`u=1` the steps shrink with :math:`1-u`, so a disk with :math:`1-L^2 = 10^{-9}` needs a
few dozen steps. Unlike the :math:`1-z` connection formula (DLMF 15.8.4) this has no trouble when
:math:`c-a-b'` is (near) an integer, which happens at every Landau level. A series stops when two
consecutive terms are below :math:`10^{-17}` of the largest term (after the hump); more than
:data:`_MAX_TERMS` terms raise :class:`~hyperlattice.errors.ConvergenceError`. The evaluation
error is estimated by a second, independent continuation path (other step sizes).

Dirichlet levels and error bounds
---------------------------------
:math:`\kappa(n, m; B, L)` is the n-th root in :math:`\kappa` of :math:`R(L) = 0` at fixed m.
Since :math:`\kappa > 1` (diamagnetic inequality and the bottom 1 of the spectrum of
:math:`-\Delta_g`), roots are searched in :math:`k=\sqrt{\kappa-1}` on the zero-field grid of
:mod:`hyperlattice.continuum.spectrum`; the grid is halved until a grid and its half agree on the
number of sign changes, then roots are refined by Chandrupatla
(:func:`scipy.optimize.elementwise.find_root`). Each root gets a verified enclosure
:math:`[\kappa-\delta,\kappa+\delta]` (sign change with both values above ten times the estimated
evaluation error); :math:`E = -q + \frac q4 h^2\kappa` is linear in :math:`\kappa`, so
:math:`\frac q4 h^2\delta` (plus rounding) is the energy error bound.
The rounding of L itself is not included (the zero-field module includes it).

Which orders are scanned
------------------------
Against the field (:math:`mB < 0`) and beyond :math:`m = A_\phi(L)` along it, the lowest root
grows with :math:`|m|` (the centrifugal term :math:`(m - A_\phi)^2/r^2` does at every r). Between
0 and :math:`A_\phi(L)` along the field the state of order m sits near the radius where
:math:`A_\phi(r) \approx m` and moves out towards the Dirichlet edge as m grows; that its lowest
root grows with m there too is observed, not proven, and checked against an exhaustive scan of
every order (``test_truncated_scan_equals_exhaustive_scan``). The scan along the field therefore
stops at the first order whose lowest root is not below the K-th level found so far. A disk
holding :math:`10^5` flux quanta (l = 12, f = 0.3) needs the orders 0..K only.

Limits: :math:`|B| \le` :data:`MAX_FIELD`, at most :data:`MAX_LEVELS` levels, and orders up to
:data:`~hyperlattice.continuum.spectrum.MAX_ORDER` (ValueError if the lowest levels would need
more). Measured cost (``benchmarks/bench_magnetic.py``): 4-6 ms per level (idle machine) at l = 5..12 and
f = 0.05..0.3, the search over orders included, like the zero-field module (6-8 ms per level
in the same run); the compiled continuation (:func:`_kernel`) made it 20-30x faster than the
NumPy version it replaced.

L -> 1: hyperbolic Landau levels
--------------------------------
Comtet (Ann. Phys. 173, 185 (1987)) gives, for curvature :math:`-1` and field :math:`b_1`, the
discrete eigenvalues :math:`(2N+1)b_1 - N(N+1)` of :math:`-\Delta_{B}`, :math:`N < b_1 - \frac12`,
and the continuum above :math:`\frac14 + b_1^2`. The paper's metric is :math:`g = g_{-1}/4`
(distances are half), so :math:`\Delta_{g} = 4\Delta_{-1}`, :math:`dV = dV_{-1}/4` and
:math:`b_1 = B/4`:

.. math:: \kappa_N = (2N+1)B - 4N(N+1),\quad 0 \le N < \frac B4 - \frac12,\qquad
          \kappa_{\rm th} = 1 + \frac{B^2}4 .

Derived here directly as well: F is a polynomial of degree N when
:math:`\beta_+ + \frac12(|m| - m - b) = -N'` (for :math:`B>0`), normalisable iff
:math:`\delta > 0`, i.e. :math:`\delta = B/2 - 2N - 1` with :math:`N = N' + \max(0,-m)`; the
Dirichlet level (n, m) tends to :math:`\kappa_N` with :math:`N = n - 1 + \max(0, -m)` for
:math:`B>0` (mirror for :math:`B<0`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import elementwise as _elementwise

from .. import _validate
from .._ties import stable_order
from ..dictionary import energy_from_lambda, field_from_flux, hopping_scale
from ..errors import ConvergenceError
from ..geometry import lattice_h
from ..results import Levels
from .spectrum import MAX_ORDER, _check_disk_x, _grid_step, asymptotic_energies, disk_argument

__all__ = [
    "hypergeometric_parameters",
    "hyp2f1_real_interval",
    "radial_function",
    "dirichlet_function",
    "magnetic_roots",
    "landau_levels",
    "magnetic_levels",
    "MagneticSpectrum",
    "MAX_FIELD",
    "MAX_LEVELS",
]

#: largest number of terms of one series before ConvergenceError
_MAX_TERMS = 4000
#: largest number of continuation steps
_MAX_STEPS = 100_000
_TOL = 1e-17
_TOLERANCES = {"xatol": 1e-15, "xrtol": 4.0 * np.finfo(float).eps, "fatol": 0.0, "frtol": 0.0}
#: largest ``|field|`` accepted (the series and step counts grow like ``|B|``)
MAX_FIELD = 1e4
#: largest number of levels accepted (about half a minute on one core at 16 ms per level)
MAX_LEVELS = 2_000
#: largest kappa magnitude dirichlet_function takes (checked to 1e6 of both signs; -1e9 and 1e12 fail to converge)
MAX_KAPPA = 1e6


def hypergeometric_parameters(m, B, kappa) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    r"""The parameters ``(a, b', c, delta)`` of the regular radial solution, broadcast.

    :math:`\delta = \sqrt{1-\kappa+B^2/4}` (principal root; imaginary above the threshold),
    :math:`\beta_- = \frac12(1-\delta)`, :math:`a = \beta_- + \frac12(|m| + m + B/2)`,
    :math:`b' = \beta_- + \frac12(|m| - m - B/2)`, :math:`c = 1 + |m|` (module docstring).

    Parameters
    ----------
    m : int or array_like
        Angular momentum (order) of :math:`\psi = e^{\mathrm im\phi}R(r)`.
    B : float or array_like
        Uniform field per unit area of the paper's metric (:math:`\hbar = e = 1`).
    kappa : float or array_like
        Eigenvalue :math:`\kappa` of :math:`-\Delta_B`.

    Returns
    -------
    a, b', c, delta : ndarray of complex
        The Gauss-function parameters and :math:`\delta`, with the broadcast shape.

    Raises
    ------
    ValueError
        If an argument is not real and finite, or the shapes do not broadcast.

    References
    ----------
    DLMF 15.10-15.11 (Riemann P-symbol).

    Examples
    --------
    >>> from hyperlattice.continuum.magnetic import hypergeometric_parameters
    >>> a, b, c, delta = hypergeometric_parameters(1, 2.0, 3.0)
    >>> print(complex(a), complex(b), complex(c), complex(delta))
    (2-0.5j) -0.5j (2+0j) 1j
    """
    m = _validate.real_array("m", m)
    B = _validate.real_array("the field B", B)
    kappa = _validate.real_array("kappa", kappa)
    delta = np.sqrt((1.0 - kappa + 0.25 * B * B).astype(complex))
    beta = 0.5 * (1.0 - delta)
    am = np.abs(m)
    a = beta + 0.5 * (am + m + 0.5 * B)
    b = beta + 0.5 * (am - m - 0.5 * B)
    c = 1.0 + am + 0.0j
    return np.broadcast_arrays(a, b, c, delta)


def _hyp2f1(a, b, c, s_target: float, *, safety: float = 1.0, wave=None):
    r"""F(a, b; c; 1 - s_target) for arrays of parameters (module docstring): the Maclaurin
    series, then Taylor steps of at most ``safety`` times min(u, 1-u)/2 and 1/(local wavenumber).

    ``wave = (kappa, m, b, delta)`` of the radial problem gives that wavenumber; without it
    (general parameters) a bound from :math:`|ab|` and :math:`|c-a-b|` is used. Each parameter set
    takes its own steps, in the compiled kernel of :func:`_kernel`.
    """
    a, b, c = (np.ascontiguousarray(v, dtype=complex).ravel() for v in (a, b, c))
    if a.size == 0:
        return np.empty(a.shape, complex)
    if wave is None:  # F'' ~ -ab/(us) F and the s^(c-a-b) behaviour at u = 1
        wk, wm, wb, wd = 4.0 * np.abs(a * b), np.zeros(a.size), np.zeros(a.size), np.abs(c - a - b)
    else:
        kappa, m, bh, delta = wave
        wk, wm, wd = (np.broadcast_to(np.asarray(v, float), a.shape).astype(float)
                      for v in (kappa, m, np.abs(delta)))
        wb = np.full(a.size, float(bh))
    out = np.empty(a.size, complex)
    status = np.zeros(a.size, np.int64)
    _kernel()(a, b, c, float(s_target), float(safety), wk, wm, wb, wd, _TOL, _MAX_TERMS, _MAX_STEPS,
              out, status)
    bad = int(status.max())
    if bad == 1:
        raise ConvergenceError(f"the 2F1 Maclaurin series did not converge in {_MAX_TERMS} terms.")
    if bad == 2:
        raise ConvergenceError(f"a 2F1 Taylor continuation step did not converge in {_MAX_TERMS} terms.")
    if bad == 3:
        raise ConvergenceError("the 2F1 continuation needed too many steps.")
    return out


@functools.cache
def _kernel():
    """The compiled continuation (numba, compiled on first use and cached on disk, never at import).

    Written by hand because no library evaluates 2F1 with complex a, b, c on [0, 1) (scipy's
    ``hyp2f1`` refuses complex parameters; mpmath is slower per value). The NumPy version it
    replaced ran the whole batch with the steps of its worst member and spent most of its time in
    interpreter overhead on small arrays (130-230 ms per level on a loaded machine, 6-11 ms now under the same load).
    """
    import numba

    @numba.njit(cache=True)
    def series(a, b, c, u, tol, max_terms):
        term = 1.0 + 0.0j
        f = 1.0 + 0.0j
        df = 0.0 + 0.0j
        if u == 0.0:
            return f, a * b / c, True
        big = 1.0
        quiet = 0
        for n in range(max_terms):
            term = term * (a + n) * (b + n) / ((c + n) * (n + 1)) * u
            f += term
            df += (n + 1) * term / u
            at = abs(term)
            big = max(big, at)
            if at <= tol * big and abs((a + n) * (b + n) * u) < abs((c + n) * (n + 1)):
                quiet += 1
                if quiet >= 2:
                    return f, df, True
            else:
                quiet = 0
        return f, df, False

    @numba.njit(cache=True)
    def step(a, b, c, f0, d0, u0, s0, t, tol, max_terms):
        g0 = f0
        g1 = d0 * t
        f = g0 + g1
        dsum = g1
        big = max(abs(g0), abs(g1))
        apb = a + b
        ab = a * b
        lin = c - (apb + 1.0) * u0
        slope = 2.0 * s0 - 1.0
        den0 = u0 * s0
        quiet = 0
        for n in range(max_terms):
            c1 = t / (den0 * (n + 2))
            c2 = c1 * t / (n + 1)
            g2 = ((n * n + n * apb + ab) * g0) * c2 - ((lin + slope * n) * g1) * c1
            f += g2
            dsum += (n + 2) * g2
            ag = abs(g2)
            big = max(big, ag)
            if n > 2:
                if ag <= tol * big and abs(g1) <= 1e-8 * big:
                    quiet += 1
                    if quiet >= 2:
                        return f, dsum / t, True
                else:
                    quiet = 0
            g0 = g1
            g1 = g2
        return f, dsum / t, False

    @numba.njit(cache=True)
    def run(a, b, c, s_target, safety, wk, wm, wb, wd, tol, max_terms, max_steps, out, status):
        u_target = 1.0 - s_target
        for i in range(a.size):
            ai, bi, ci = a[i], b[i], c[i]
            ab = abs(ai * bi) / abs(ci)
            cmax = max(1.0, abs(ci))
            ua = min(u_target, 0.5 * safety, safety / max(ab, 1e-300))
            f, d, ok = series(ai, bi, ci, ua, tol, max_terms)
            if not ok:
                status[i] = 1
                continue
            if ua >= u_target:
                out[i] = f
                continue
            u0 = ua
            s0 = 1.0 - ua
            done = False
            for _ in range(max_steps):
                w = wk[i] * u0 - (wm[i] * s0 - wb[i] * u0) ** 2
                k = np.sqrt(max(w, 0.0)) / (2.0 * u0 * s0) + wd[i] / (2.0 * s0)
                # a zero wavenumber (kappa at the threshold in a forbidden region): no oscillation
                k = max(k, 1e-300)
                t = safety * min(0.5 * s0, 0.5 * u0, u0 / cmax, 1.0 / k)
                last = s0 - t <= s_target * (1.0 + 1e-12)
                if last:
                    t = s0 - s_target
                f, d, ok = step(ai, bi, ci, f, d, u0, s0, t, tol, max_terms)
                if not ok:
                    status[i] = 2
                    break
                if last:
                    out[i] = f
                    done = True
                    break
                s0 = s0 - t
                u0 = 1.0 - s0
            if not done and status[i] == 0:
                status[i] = 3

    return run


def hyp2f1_real_interval(a, b, c, u) -> np.ndarray:
    r"""Gauss :math:`F(a, b; c; u)` (DLMF 15.2.1) for complex a, b, c and real :math:`0\le u<1`.

    Vectorised over a, b, c (broadcast); u a scalar or an array (one continuation per distinct
    u). See the module docstring for the method.

    Parameters
    ----------
    a, b : complex or array_like
        Numerator parameters.
    c : complex or array_like
        Denominator parameter, not a non-positive integer.
    u : float or array_like of float
        Argument(s), :math:`0 \le u < 1`.

    Returns
    -------
    ndarray of complex
        :math:`F(a, b; c; u)`.

    Raises
    ------
    ValueError
        If c is a non-positive integer, u is outside [0, 1), or an argument is not finite.
    ConvergenceError
        If the continuation does not converge.

    References
    ----------
    DLMF 15.2.1.

    Examples
    --------
    >>> from hyperlattice.continuum.magnetic import hyp2f1_real_interval
    >>> import math
    >>> print(f"{complex(hyp2f1_real_interval(1.0, 1.0, 2.0, 0.5)).real:.6f}", f"{math.log(4):.6f}")
    1.386294 1.386294
    """
    a, b, c = (np.asarray(_validate.complex_array(name, v)) for name, v in (("a", a), ("b", b), ("c", c)))
    a, b, c = np.broadcast_arrays(a, b, c)
    if np.any((c.imag == 0) & (c.real <= 0) & (c.real == np.round(c.real))):
        raise ValueError("c must not be a non-positive integer.")
    u = _validate.real_array("u", u)
    if np.any(u < 0) or np.any(u >= 1):
        raise ValueError("u must satisfy 0 <= u < 1.")
    out = np.empty(u.shape + a.shape, complex)
    for idx, uv in np.ndenumerate(u):
        out[idx] = _hyp2f1(a.ravel(), b.ravel(), c.ravel(), 1.0 - float(uv)).reshape(a.shape)
    return out


def _field(B) -> float:
    return _validate.real("the field B", B, minimum=-MAX_FIELD, maximum=MAX_FIELD)


#: the largest ``|kappa|`` radial_function accepts (the 2F1 continuation takes ~sqrt(kappa) steps)
KAPPA_MAX = 1e10


def radial_function(r, m, B, kappa) -> np.ndarray:
    r"""Regular radial solution :math:`R(r) = r^{|m|}(1-r^2)^{\beta_-}F(a,b';c;r^2)` of the magnetic problem.

    The real solution (module docstring) of
    :math:`-\Delta_B(e^{\mathrm im\phi}R) = \kappa e^{\mathrm im\phi}R`, normalised to
    :math:`R \sim r^{|m|}` at the origin.

    Parameters
    ----------
    r : float or array_like of float
        Radii, :math:`0\le r<1`.
    m : int
        Angular momentum, :math:`|m| \le` ``MAX_ORDER``.
    B : float
        Uniform field, flux per unit area of the paper's metric (:math:`\hbar = e = 1`, one
        quantum is :math:`2\pi`; positive out of the disk), :math:`|B| \le` :data:`MAX_FIELD`.
    kappa : float
        Eigenvalue :math:`\kappa` of :math:`-\Delta_B`, :math:`|\kappa| \le` ``KAPPA_MAX``.

    Returns
    -------
    ndarray of float
        :math:`R(r)`, same shape as ``r``.

    Raises
    ------
    ValueError
        If a radius is outside [0, 1), or ``m``, ``B`` or ``kappa`` is invalid or too large.
    ConvergenceError
        If the hypergeometric continuation does not converge.

    Examples
    --------
    >>> from hyperlattice.continuum.magnetic import radial_function
    >>> print(f"{float(radial_function(0.5, 0, 0.0, 2.0)):.6f}")
    0.861409
    >>> [round(float(v), 6) for v in radial_function([0.0, 0.5], 1, 2.0, 3.0)]
    [0.0, 0.416095]
    """
    r = _validate.real_array("the radius r", r)
    if np.any(r < 0) or np.any(r >= 1):
        raise ValueError("the radius r must satisfy 0 <= r < 1.")
    m = _validate.integer("m", m, minimum=-MAX_ORDER, maximum=MAX_ORDER)
    B = _field(B)
    # beyond 1e10 the continuation's step count runs out (ConvergenceError), and near 1e140 the
    # local wavenumber overflows the step-size arithmetic: refuse at the door instead
    kappa = _validate.real("kappa", kappa, minimum=-KAPPA_MAX, maximum=KAPPA_MAX)
    a, b, c, delta = (np.atleast_1d(v) for v in hypergeometric_parameters(m, B, kappa))
    out = np.empty(r.shape)
    for idx, rv in np.ndenumerate(r):
        s = (1.0 - rv) * (1.0 + rv)
        F = _hyp2f1(a, b, c, s, wave=(kappa, m, 0.5 * B, delta))[0]
        out[idx] = (rv ** abs(m) * np.exp(0.5 * (1.0 - delta[0]) * math.log(s)) * F).real
    return out[()] if r.ndim == 0 else out


def _dfunc(kappa, m, B: float, s: float, *, safety: float = 1.0) -> np.ndarray:
    r"""Sign-carrying Dirichlet function: R(L) divided by the positive factor
    :math:`L^{|m|}s^{(1-\operatorname{Re}\delta)/2}` (keeps it finite for every field)."""
    kappa, m = np.broadcast_arrays(np.asarray(kappa, float), np.asarray(m, float))
    shape = kappa.shape
    a, b, c, delta = hypergeometric_parameters(m.ravel(), B, kappa.ravel())
    F = _hyp2f1(a, b, c, s, safety=safety, wave=(kappa.ravel(), m.ravel(), 0.5 * B, delta))
    return (np.exp(-0.5j * delta.imag * math.log(s)) * F).real.reshape(shape)


def dirichlet_function(kappa, m, B, radius) -> np.ndarray:
    r"""The function whose roots in :math:`\kappa` are the magnetic Dirichlet levels.

    :math:`R(L)` up to a positive factor, broadcast over ``kappa`` and ``m``.

    Parameters
    ----------
    kappa : float or array_like of float
        Eigenvalue(s) :math:`\kappa` of :math:`-\Delta_B`.
    m : int or array_like of int
        Angular momenta, :math:`|m| \le` ``MAX_ORDER``.
    B : float
        Uniform field, flux per unit area of the paper's metric (:math:`\hbar = e = 1`, one
        quantum is :math:`2\pi`; positive out of the disk), :math:`|B| \le` :data:`MAX_FIELD`.
    radius : float
        Disk radius :math:`L \in (0, 1)`.

    Returns
    -------
    ndarray of float
        Values with the sign of :math:`R(L)`, broadcast over ``kappa`` and ``m``.

    Raises
    ------
    ValueError
        If ``m`` is not integral or too large, or another argument is invalid.

    See Also
    --------
    magnetic_roots

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.continuum.magnetic import dirichlet_function
    >>> v = dirichlet_function(np.array([2.0, 30.0]), 0, 0.0, 0.5)
    >>> np.sign(v).tolist()
    [1.0, -1.0]
    """
    kappa = _validate.real_array("kappa", kappa)
    if np.any(np.abs(kappa) > MAX_KAPPA):
        # -1e300 divided by zero inside the 2F1 continuation, 1e300 ran on: refused before work
        raise ValueError(f"kappa must lie within +-{MAX_KAPPA:g} (the range in which the 2F1 continuation is "
                         f"checked), got {float(np.max(np.abs(kappa))):g} in magnitude.")
    m = np.asarray(_validate.real_array("m", m))
    if np.any(m != np.round(m)) or np.any(np.abs(m) > MAX_ORDER):
        raise ValueError(f"m must be integers with |m| <= {MAX_ORDER}.")
    L = _validate.radius("the disk radius L", radius)
    return _dfunc(kappa, m, _field(B), (1.0 - L) * (1.0 + L))


def _refine(lo, hi, m, B, s):
    res = _elementwise.find_root(lambda kk, mm: _dfunc(kk, mm, B, s), (lo, hi), args=(m,),
                                 tolerances=_TOLERANCES)
    if not np.all(res.success):
        raise ConvergenceError("the magnetic Dirichlet root refinement did not converge.")
    width = np.abs(np.asarray(res.bracket[1]) - np.asarray(res.bracket[0]))
    return np.asarray(res.x, float), width


def _enclosure(kappa, m, B, s, width):
    """Half-width of a verified sign-change enclosure of each root (module docstring)."""
    delta = np.maximum(width, 4.0 * np.spacing(kappa))
    out = np.full(kappa.size, np.nan)
    todo = np.arange(kappa.size)
    for _ in range(25):
        kk = np.concatenate([kappa[todo] - delta[todo], kappa[todo] + delta[todo]])
        mm = np.concatenate([m[todo], m[todo]])
        f1 = _dfunc(kk, mm, B, s)
        f2 = _dfunc(kk, mm, B, s, safety=0.6)
        err = np.abs(f1 - f2) + 1e-15 * np.maximum(np.abs(f1), np.abs(f2))
        ok = np.abs(f1) > 10.0 * err
        nt = todo.size
        good = ok[:nt] & ok[nt:] & (np.sign(f1[:nt]) * np.sign(f1[nt:]) < 0)
        out[todo[good]] = delta[todo[good]]
        todo = todo[~good]
        if todo.size == 0:
            return out
        delta[todo] *= 4.0
    raise ConvergenceError("no verified enclosure for a magnetic Dirichlet root.")


def _roots_below(ms: np.ndarray, B: float, s: float, t: float, kcut: float):
    """Sign-change cells of every order below k = kcut (k = sqrt(kappa - 1)), grid halved until
    a grid and its half agree on the number of sign changes. Returns (list of k-grid cell
    arrays per order, grid)."""
    dk = _grid_step(t)
    for _ in range(8):
        npts = math.ceil(kcut / dk) + 1
        fine = np.arange(2 * npts - 1) * (dk / 2.0)
        vals = _dfunc(1.0 + fine[None, :] ** 2, ms[:, None], B, s)
        sg = np.sign(vals)
        coarse = sg[:, ::2]
        nf = np.sum((sg[:, :-1] * sg[:, 1:] < 0) | (sg[:, :-1] == 0), axis=1)
        nc = np.sum((coarse[:, :-1] * coarse[:, 1:] < 0) | (coarse[:, :-1] == 0), axis=1)
        if np.array_equal(nf, nc):
            hit = (sg[:, :-1] * sg[:, 1:] < 0) | (sg[:, :-1] == 0)
            return [np.flatnonzero(row) for row in hit], fine
        dk /= 2.0
    raise ConvergenceError("the magnetic root scan did not stabilise under grid refinement.")


def magnetic_roots(m, B, radius, n_roots: int = 1) -> np.ndarray:
    r"""The ``n_roots`` lowest Dirichlet eigenvalues :math:`\kappa(n, m; B, L)` of :math:`-\Delta_B` for one order m.

    n = 1, 2, ... on the disk of radius L. At B = 0, :math:`\kappa = 1 + k^2` with the roots k of
    :func:`hyperlattice.continuum.spectrum.dirichlet_roots`.

    Parameters
    ----------
    m : int
        Angular momentum, :math:`|m| \le` ``MAX_ORDER``.
    B : float
        Uniform field, flux per unit area of the paper's metric (:math:`\hbar = e = 1`, one
        quantum is :math:`2\pi`; positive out of the disk), :math:`|B| \le` :data:`MAX_FIELD`.
    radius : float
        Disk radius :math:`L \in (0, 1)`.
    n_roots : int, optional
        Number of eigenvalues (default 1, at most :data:`MAX_LEVELS`).

    Returns
    -------
    ndarray of float
        Shape ``(n_roots,)``, increasing.

    Raises
    ------
    ValueError
        If an argument is invalid or the disk is too small for double precision.
    ConvergenceError
        If bracketing or refinement of a root fails.

    See Also
    --------
    magnetic_levels

    Examples
    --------
    >>> from hyperlattice.continuum.magnetic import magnetic_roots
    >>> [round(float(k), 6) for k in magnetic_roots(0, 0.0, 0.5, 2)]
    [20.483218, 102.296698]
    >>> [round(float(k), 6) for k in magnetic_roots(0, 2.0, 0.5, 2)]
    [20.54454, 102.381474]
    """
    m = _validate.integer("m", m, minimum=-MAX_ORDER, maximum=MAX_ORDER)
    B = _field(B)
    L = _validate.radius("the disk radius L", radius)
    n_roots = _validate.positive_int("n_roots", n_roots, maximum=MAX_LEVELS)
    x = (1.0 + L * L) / ((1.0 - L) * (1.0 + L))
    _check_disk_x(x, L)
    s = (1.0 - L) * (1.0 + L)
    t = math.acosh(x)
    kcut = 4.0 * _grid_step(t) * 6
    ms = np.array([float(m)])
    while True:
        cells, grid = _roots_below(ms, B, s, t, kcut)
        if cells[0].size >= n_roots:
            break
        kcut *= 1.6
    idx = cells[0][:n_roots]
    k, _ = _refine(1.0 + grid[idx] ** 2, 1.0 + grid[idx + 1] ** 2, np.full(idx.size, float(m)), B, s)
    return k


# ----------------------------------------------------------------------------
# L -> 1
# ----------------------------------------------------------------------------

def landau_levels(B) -> dict:
    r"""Discrete hyperbolic Landau levels of :math:`-\Delta_B` on the whole disk.

    In the paper's metric, with the threshold of the continuous spectrum (module docstring, from
    Comtet's curvature :math:`-1` formulas with :math:`b_1 = B/4`, :math:`\Delta_g = 4\Delta_{-1}`):
    :math:`\kappa_N = (2N+1)|B| - 4N(N+1)` for :math:`0 \le N < |B|/4 - 1/2`.

    Parameters
    ----------
    B : float
        Uniform field, flux per unit area of the paper's metric (:math:`\hbar = e = 1`, one
        quantum is :math:`2\pi`; positive out of the disk), :math:`|B| \le` :data:`MAX_FIELD`.

    Returns
    -------
    dict
        ``{"kappa": ndarray of the kappa_N (empty for |B| <= 2), "threshold": 1 + B^2/4}``.

    Raises
    ------
    ValueError
        If ``B`` is not a finite real number with :math:`|B| \le` :data:`MAX_FIELD`.

    See Also
    --------
    hyperlattice.dictionary.field_from_flux

    References
    ----------
    A. Comtet, Ann. Phys. 173, 185 (1987).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> d = hl.landau_levels(24.0)
    >>> d["kappa"].tolist(), d["threshold"]
    ([24.0, 64.0, 96.0, 120.0, 136.0, 144.0], 145.0)
    >>> hl.landau_levels(1.0)["kappa"].tolist()
    []
    """
    B = abs(_field(B))
    nmax = math.ceil(B / 4.0 - 0.5)  # N < B/4 - 1/2
    N = np.arange(max(0, nmax))
    return {"kappa": (2 * N + 1) * B - 4.0 * N * (N + 1), "threshold": 1.0 + 0.25 * B * B}


# ----------------------------------------------------------------------------
# levels
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class MagneticSpectrum(Levels):
    r"""The lowest levels of :math:`-q - \frac q4 h^2\Delta_B` on a Dirichlet disk (a :class:`Levels`).

    Like :class:`~hyperlattice.continuum.spectrum.ContinuumSpectrum`, with ``kappa`` (the
    eigenvalues of :math:`-\Delta_B`) instead of k, plus ``flux`` (quanta per p-gon face) and
    ``field`` (B). With flux, +m and -m are separate levels (degeneracy 1). The attributes below
    come in addition to those of :class:`~hyperlattice.results.Levels` (energies and errors in
    units of t).

    Attributes
    ----------
    error_kind : str
        ``"energy error bound"``.
    method : str
        ``"magnetic-dirichlet-roots"``.
    description : str
        One sentence on the root search.
    rings : int or None
        Ring count the disk was derived from, or None for a given radius.
    radius, x : float
        The Euclidean disk radius L in the paper's Poincaré disk and :math:`x_L = (1+L^2)/(1-L^2)`.
    h : float
        :math:`\tanh d_0`.
    kappa : ndarray, shape (K,)
        Eigenvalues of :math:`-\Delta_B` (the level energies are :math:`-q + \frac q4 h^2\kappa`
        in the paper's dictionary).
    flux : float
        Flux quanta per p-gon face.
    field : float
        :math:`B = 2\pi f/\mathcal A_p` per unit area of the paper's metric (:math:`\hbar = e = 1`;
        positive B points out of the disk).
    asymptotic : dict
        ``{"E0", "E1", "E_inf"}`` of the field-free disk
        (:func:`~hyperlattice.continuum.spectrum.asymptotic_energies`).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> s = hl.magnetic_levels(7, 3, rings=2, levels=4, flux=0.1)
    >>> [round(float(e), 4) for e in s.energies], s.m.tolist()
    ([-2.5567, -2.1686, -1.9609, -1.7085], [0, 1, -1, 2])
    >>> round(s.field, 6), s.degeneracy.tolist()          # f = 0.1 through each heptagon
    (2.4, [1, 1, 1, 1])
    """

    error_kind: str = "energy error bound"
    method: str = "magnetic-dirichlet-roots"
    description: str = ("roots of r^|m| (1-r^2)^beta 2F1(a,b;c;r^2) at r = L: grid bracketing + "
                        "Chandrupatla, 2F1 by series and Taylor continuation")
    rings: int | None
    radius: float
    x: float
    h: float
    kappa: np.ndarray
    flux: float
    field: float
    asymptotic: dict

    @property
    def degeneracy(self) -> np.ndarray:
        """1 per state with flux; the +-m pairs count 2 at zero flux, as without field."""
        if self.field == 0.0:
            return np.where(self.m == 0, 1, 2)
        return np.ones(len(self), dtype=int)

    def summary(self) -> dict:
        """The CLI contract: the keys of ContinuumSpectrum.summary() (k = sqrt(kappa - 1)) plus flux
        (the field B stays on the result as ``field``)."""
        return {"p": self.p, "q": self.q, "rings": self.rings, "radius": self.radius,
                "h": self.h, "energies": self.energies.tolist(), "n": self.n.tolist(),
                "m": self.m.tolist(), "k": np.sqrt(np.maximum(self.kappa - 1.0, 0.0)).tolist(),
                "asymptotic": dict(self.asymptotic), "flux": self.flux}


def _corotating_done(found: list, lowest: dict, K: int, B: float, s: float) -> bool:
    r"""Whether the scan along the field (orders m with :math:`mB > 0`) may stop after the order
    just scanned: its lowest root is not below the K-th lowest root found so far.

    This relies on the lowest root :math:`\kappa(1, m)` growing with m on the field's side. Beyond
    :math:`m = A_\phi(L)` that is proven (the centrifugal term :math:`(m - A_\phi)^2/r^2` grows with
    m at every r); inside, where the Landau-like state of order m sits at the radius with
    :math:`A_\phi(r)\approx m` and moves towards the Dirichlet edge as m grows, it is an observed
    property, checked against the exhaustive scan over every order up to :math:`A_\phi(L)` for
    {7,3}, {8,3}, {4,5}, {3,7}, {5,4}, l = 1..5 and f up to 2 (``tests/test_continuum_magnetic.py``).
    Lowest roots are refined (and cached in ``lowest``); other roots count with the upper end of
    their grid cell, so the K-th value used is an upper bound of the true K-th level. Ties within
    rounding (deep Landau levels are degenerate to :math:`10^{-16}`) stop the scan: either state
    is then a correct K-th level within its error bound.
    """
    todo = [mm for mm, c0, _ in found if c0.size and mm not in lowest]
    if todo:
        lo = np.array([1.0 + g[c0[0]] ** 2 for mm, c0, g in found if mm in todo])
        hi = np.array([1.0 + g[c0[0] + 1] ** 2 for mm, c0, g in found if mm in todo])
        kap, _ = _refine(lo, hi, np.array(todo, float), B, s)
        lowest.update(zip(todo, kap.tolist()))
    uppers = []
    for mm, c0, g in found:
        ub = 1.0 + g[c0 + 1] ** 2
        ub[0] = lowest[mm]
        uppers.extend(ub.tolist())
    if len(uppers) < K:
        return False
    kth = sorted(uppers)[K - 1]
    last = found[-1][0]
    return lowest[last] >= kth * (1.0 - 8.0 * np.finfo(float).eps)


def magnetic_levels(p=7, q=3, radius=None, rings=None, levels: int = 4, flux=0.0) -> MagneticSpectrum:
    r"""The ``levels`` lowest states of :math:`H = -q - \frac q4 h^2\Delta_B` on a Dirichlet disk.

    The field is :math:`B` = :func:`~hyperlattice.dictionary.field_from_flux` (``flux`` quanta
    per p-gon). Every order m with a root below a cutoff is scanned (for :math:`B>0`, the lowest
    root grows with m beyond :math:`m_* = A_\phi(L)` and with :math:`|m|` for m < 0; mirrored for
    B < 0), the cutoff growing until there are at least ``levels`` states; along the field the
    scan stops at the first order whose lowest root is not below the K-th level found (module
    docstring, "Which orders are scanned").

    Parameters
    ----------
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    radius : float, optional
        Disk radius :math:`L \in (0, 1)`; give exactly one of ``radius`` and ``rings``.
    rings : int, optional
        Number of rings of the {p,q} lattice; L from Eq. (10) with its exact site count.
    levels : int, optional
        Number of states (default 4, at most :data:`MAX_LEVELS`).
    flux : float, optional
        Flux f in quanta through one p-gon face (default 0; f > 0 counterclockwise).

    Returns
    -------
    MagneticSpectrum
        A :class:`~hyperlattice.results.Levels` with ``energies`` (ascending, units of t),
        labels ``n`` and signed ``m``, ``errors`` (energy error bounds), ``kappa`` (eigenvalues
        of :math:`-\Delta_B`), ``flux``, ``field`` (B), ``radius``, ``x``, ``h``.

    Raises
    ------
    ValueError
        If an argument is invalid, the field exceeds :data:`MAX_FIELD`, or the levels need
        orders beyond :data:`~hyperlattice.continuum.spectrum.MAX_ORDER`.
    ConvergenceError
        If bracketing or refinement of a root fails.

    See Also
    --------
    hyperlattice.continuum.spectrum.continuum_levels : the same at zero flux.
    landau_levels

    Examples
    --------
    >>> import hyperlattice as hl
    >>> s = hl.magnetic_levels(7, 3, rings=2, levels=4, flux=0.1)
    >>> [round(float(e), 6) for e in s.energies]
    [-2.556742, -2.168578, -1.960907, -1.708488]
    >>> s.m.tolist(), round(s.field, 6)
    ([0, 1, -1, 2], 2.4)
    """
    p, q = _validate.pq(p, q)
    K = _validate.positive_int("levels", levels, maximum=MAX_LEVELS)
    flux = _validate.real("flux", flux, minimum=-1e6, maximum=1e6)
    B = float(field_from_flux(flux, p, q))
    if abs(B) > MAX_FIELD:
        raise ValueError(f"the flux {flux:g} gives a field |B| = {abs(B):g} beyond {MAX_FIELD:g}.")
    L, x = disk_argument(radius, p=p, q=q, rings=rings)
    _check_disk_x(x, L)
    s = 2.0 / (x + 1.0)               # 1 - L^2, exact from x for ring disks
    t = math.acosh(x)
    a_edge = abs(B) * (1.0 - s) / (2.0 * s)   # A_phi(L): beyond this order the roots grow with |m|
    sign = 1 if B >= 0 else -1
    # orders that can hold one of the K lowest states: on the field's side the scan stops at the
    # first order whose lowest root is not below the K-th level found so far (the lowest root
    # grows with m there, see _corotating_done), beyond m0 = A_phi(L) it provably grows, so
    # (1, m0 + j) has j states below it; on the other side (1, -j) has j below it; at B = 0 the
    # +-m pairs make |m| <= K/2 (as without field)
    if B == 0:
        caps = {True: K // 2, False: K // 2}
    else:
        caps = {True: min(math.floor(a_edge) + K, MAX_ORDER), False: min(K - 1, MAX_ORDER)}
    kcut = 12.0 * _grid_step(t)
    lowest: dict[int, float] = {}     # refined lowest root per co-rotating order (cache over kcut)
    while True:
        found = []
        count = 0
        for direction in ((1,) if B == 0 else (1, -1)):
            m0, nb, done = (0 if direction == 1 else -1), 2, False
            corotating = B != 0 and direction * sign > 0
            cap = caps[direction * sign > 0]
            while not done:
                block = m0 + direction * np.arange(nb)
                block = block[np.abs(block) <= cap]
                if block.size == 0:
                    if corotating and cap == MAX_ORDER:
                        raise ValueError(f"the lowest levels need orders beyond |m| = {MAX_ORDER} "
                                         f"(the disk holds {a_edge:.3g} flux quanta).")
                    break
                cells, grid = _roots_below(block.astype(float), B, s, t, kcut)
                for mm, c0 in zip(block.tolist(), cells):
                    if c0.size:
                        found.append((mm, c0, grid))
                        count += c0.size * (2 if (B == 0 and mm != 0) else 1)
                    # the lowest root grows with |m| on both sides (proven against the field
                    # and beyond A_phi(L) along it, checked inside; see _corotating_done):
                    # the first order without a root below kcut ends the scan
                    if c0.size == 0:
                        done = True
                        break
                if corotating and not done and count >= K:
                    done = _corotating_done(found, lowest, K, B, s)
                m0 += direction * block.size
                nb = min(2 * nb, 64)
        if count >= K:
            break
        kcut *= 1.5
    ms = np.concatenate([np.full(c.size, float(mm)) for mm, c, _ in found])
    ns = np.concatenate([np.arange(1, c.size + 1) for _, c, _ in found])
    lo = np.concatenate([1.0 + g[c] ** 2 for _, c, g in found])
    hi = np.concatenate([1.0 + g[c + 1] ** 2 for _, c, g in found])
    kap, width = _refine(lo, hi, ms, B, s)
    delta = _enclosure(kap, ms, B, s, width)
    if B == 0:  # +-m degenerate: list +m then -m as the zero-field levels do
        pos = ms > 0
        kap, ns, delta = (np.concatenate([v, v[pos]]) for v in (kap, ns, delta))
        ms = np.concatenate([ms, -ms[pos]])
    # levels within their enclosures of each other (the +-m pairs at B = 0, crossings of
    # different m at special fields) are ordered by (|m|, +m first, n), not by rounding
    order = stable_order(kap, delta, np.abs(ms).astype(np.int64), (ms < 0).astype(np.int64), ns)[:K]
    kap, ns, ms, delta = kap[order], ns[order], ms[order].astype(int), delta[order]
    scale = hopping_scale(p, q)
    energies = np.asarray(energy_from_lambda(kap, p, q), float)
    errors = scale * delta + 4.0 * np.finfo(float).eps * (q + scale * kap)
    return MagneticSpectrum(p=p, q=q, rings=None if rings is None else int(rings), radius=L, x=x,
                            h=lattice_h(p, q), energies=energies, n=ns, m=ms, errors=errors, kappa=kap,
                            flux=flux, field=B,
                            asymptotic=asymptotic_energies(p, q, radius=None if rings is not None else radius,
                                                           rings=rings))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
