r"""Monte Carlo statistics shared by every Markov chain of the package: binning, autocorrelation,
jackknife, independent chains.

Conventions
-----------
A chain hands over *bins*: equal-length consecutive blocks of its measurements, each stored as
the block mean. The binning analysis (Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989);
Ambegaokar & Troyer, Am. J. Phys. 78, 150 (2010)) merges neighbouring bins pairwise, level by
level; the naive standard error of the mean of the level-l bins,

.. math::

    \sigma_l = \sqrt{\frac{\sum_k (x_k^{(l)} - \bar x)^2}{N_l (N_l - 1)}},

grows with l until the bins are longer than the autocorrelation time, where it levels off (the
plateau) at the true error. The integrated autocorrelation time, in units of one measurement
(one sweep), follows from :math:`\sigma^2 = 2\tau_{\mathrm{int}}\,\mathrm{var}(x)/n`
(n measurements of variance var(x); :math:`\tau_{\mathrm{int}} = 1/2` without correlation), see
:func:`binning`.

The plateau level keeps 32 to 63 bins, so its bins are only n/63 to n/32 measurements long: for a
short chain they are not long against the autocorrelation time, and the plateau error comes out
low (with :math:`\tau_{\mathrm{int}} \approx 1.6` sweeps and bins of 8 sweeps by about 9 %, for
an AR(1) series :math:`\sigma_B^2/\sigma^2 \approx 1 - 2\rho/(B(1-\rho^2))`). The error of
:func:`binning` is therefore the autocorrelation-function ("Gamma") method with Wolff's automatic
window (U. Wolff, Comput. Phys. Commun. 156, 143 (2004)), :func:`gamma_method`, applied to the
finest bins, whose bias falls as :math:`e^{-W/\tau}` with the window W instead of as
:math:`\tau/B`; the plateau error stands in when it is larger by more than three times its own
statistical uncertainty (a slow mode that the window missed).

Derived quantities (a compressibility :math:`\beta(\langle N^2\rangle - \langle N\rangle^2)`, a
ratio, the largest eigenvalue of a matrix average) get their error from the jackknife over the
plateau-level bins (:func:`jackknife`), which also removes their O(1/n) bias.

This module imports only numpy (layer 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from . import _validate

__all__ = ["Binning", "binning", "gamma_method", "jackknife", "combine_independent", "MIN_BINS"]

#: fewest bins a level may have to count in the plateau search (the error of the error of a
#: level with n bins is about 1/sqrt(2(n-1)): 13 % at 32 bins)
MIN_BINS = 32


@dataclass(frozen=True)
class Binning:
    r"""The binning analysis of one observable.

    Attributes
    ----------
    mean : float
        Mean of all bins.
    error : float
        The error of the mean: the Gamma-method error of the input bins (:func:`gamma_method`),
        or the plateau error (the largest-level error with at least :data:`MIN_BINS` bins) when
        that is larger by more than three times its own statistical uncertainty.
    errors : ndarray
        :math:`\sigma_l` per level l = 0, 1, ... (level l merges :math:`2^l` input bins).
    counts : ndarray of int
        Bins per level.
    tau_int : float
        Integrated autocorrelation time in units of the input bin (a sweep when the input bins are
        single sweeps): :math:`\tau = \tfrac12 (\sigma/\sigma_0)^2` times the
        input bin length ``bin_size`` or from the single-measurement variance (0.5 for
        uncorrelated sweeps: :math:`\sigma^2 = 2\tau\,\mathrm{var}/n`).
    level : int
        The plateau level used.
    converged : bool
        Whether the error stopped growing: the last level's error exceeds the error two levels
        below by less than three times its own statistical uncertainty :math:`1/\sqrt{2(n-1)}`
        (n bins); False also when fewer than three levels qualify.
    """

    mean: float
    error: float
    errors: np.ndarray
    counts: np.ndarray
    tau_int: float
    level: int
    converged: bool


#: Wolff's factor S between the window and the autocorrelation time (his recommended 1.5)
GAMMA_S = 1.5


def gamma_method(x, s_factor: float = GAMMA_S) -> tuple[float, float, int]:
    r"""Error of the mean of a correlated series by its autocorrelation function, Wolff's window.

    The autocorrelation function :math:`\Gamma(t)` of ``x`` is summed up to the window W, the first
    W at which :math:`e^{-W/\tau_W} - \tau_W/\sqrt{W n}` turns negative, where
    :math:`\tau_W = S/\ln((2\tau_{\mathrm{int}}(W) + 1)/(2\tau_{\mathrm{int}}(W) - 1))` (S =
    ``s_factor``): the truncation bias :math:`\propto e^{-W/\tau}` and the statistical error
    :math:`\propto \sqrt{W/n}` of the sum balance (U. Wolff, Comput. Phys. Commun. 156, 143
    (2004), eqs. (31)–(35) and (49) for the bias of the subtracted mean).

    Parameters
    ----------
    x : array_like, shape (n,)
        The series (single measurements or bin means), n >= 2.
    s_factor : float
        Wolff's S (default 1.5).

    Returns
    -------
    (error, tau_int, window) : tuple
        The error of the mean, the integrated autocorrelation time in units of one entry of ``x``
        (1/2 without correlation) and the window; (nan, nan, 0) for fewer than two entries,
        (0, 0.5, 0) for a constant series.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.mcstats import gamma_method
    >>> x = np.random.default_rng(1).normal(size=4096)
    >>> err, tau, w = gamma_method(x)
    >>> round(err * 64, 1), round(tau, 1)
    (1.0, 0.5)
    """
    x = _validate.real_array("x", x).ravel()
    s_factor = _validate.positive_real("s_factor", s_factor)
    n = x.size
    if n < 2:
        return math.nan, math.nan, 0
    y = x - x.mean()
    size = 1 << (2 * n - 1).bit_length()
    f = np.fft.rfft(y, size)
    acf = np.fft.irfft(f * np.conj(f), size)[:n] / (n - np.arange(n))
    g0 = float(acf[0])
    if not g0 > 0.0:
        return 0.0, 0.5, 0
    wmax = max(1, n // 2)
    csum = g0 + 2.0 * np.cumsum(acf[1:wmax + 1])         # C_F(W), W = 1..wmax
    window = wmax
    for w in range(1, wmax + 1):
        tau = 0.5 * csum[w - 1] / g0
        if tau <= 0.5:
            window = w
            break
        tw = s_factor / math.log((2.0 * tau + 1.0) / (2.0 * tau - 1.0))
        if math.exp(-w / tw) - tw / math.sqrt(w * n) < 0.0:
            window = w
            break
    cf = float(csum[window - 1])
    # the subtracted sample mean biases every Gamma(t) by about -C_F/n (Wolff eq. (49))
    cf_corr = cf * (1.0 + (2.0 * window + 1.0) / n)
    g0_corr = g0 + cf_corr / n
    cf_corr = max(cf_corr, 0.0)
    return math.sqrt(cf_corr / n), 0.5 * cf_corr / g0_corr, int(window)


def _levels(x: np.ndarray):
    out = [x]
    while out[-1].shape[0] >= 2 * MIN_BINS:
        y = out[-1]
        k = y.shape[0] // 2
        out.append(0.5 * (y[:2 * k:2] + y[1:2 * k:2]))
    return out


def binning(bins, bin_size: int = 1, variance: float | None = None) -> Binning:
    r"""Binning analysis of the bin means ``bins`` (1-d), each the mean of ``bin_size`` measurements.

    Parameters
    ----------
    bins : array_like, shape (n,)
        Consecutive bin means of one chain.
    bin_size : int
        Measurements (sweeps) per input bin; sets the unit of ``tau_int``.
    variance : float, optional
        The variance of a single measurement (from the chain's running sum of squares). With it
        :math:`\tau_{\mathrm{int}} = n\,\sigma^2/(2\,\mathrm{var})` exactly as defined; without
        it the input bins stand in for single measurements (:math:`\tau = \tfrac12 s
        (\sigma/\sigma_0)^2`, an underestimate when ``bin_size`` is not short against tau).

    Returns
    -------
    Binning

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.mcstats import binning
    >>> x = np.random.default_rng(1).normal(size=4096)
    >>> b = binning(x)
    >>> round(b.error * 64, 1), b.converged, round(b.tau_int, 1)
    (1.0, True, 0.5)
    """
    x = _validate.real_array("bins", bins).ravel()
    n = x.size
    if n < 2:
        return Binning(float(x.mean()) if n else math.nan, math.nan, np.array([math.nan]), np.array([n]),
                       math.nan, 0, False)
    mean = float(x.mean())
    levels = _levels(x)
    errs = np.array([float(np.std(y, ddof=1) / math.sqrt(y.size)) for y in levels])
    counts = np.array([y.size for y in levels])
    level = len(levels) - 1
    plat = err = float(errs[level])
    # the finest bins' autocorrelation function (no finite-bin-length bias); the plateau error
    # when it is larger beyond its own uncertainty (a slow mode outside the window)
    gerr, _, _ = gamma_method(x)
    rel = 1.0 / math.sqrt(2.0 * max(counts[level] - 1, 1))
    if math.isfinite(gerr) and not err > gerr * (1.0 + 3.0 * rel):
        err = gerr
    if variance is not None and variance > 0:
        tau = 0.5 * n * bin_size * err ** 2 / variance
    elif errs[0] > 0:
        tau = 0.5 * (err / errs[0]) ** 2 * bin_size
    else:
        tau = 0.5 * bin_size if err == 0 else math.inf
    # plateau: the error has stopped growing. Neighbouring levels are strongly correlated, so the
    # test compares the last level with the one two below it and flags only a rise beyond three
    # times the statistical uncertainty of the last level's error (a downward fluctuation is noise).
    converged = False
    if level >= 2:
        converged = bool(plat <= errs[level - 2] * (1.0 + 3.0 * rel) or plat == 0.0)
    elif plat == 0.0:
        converged = True
    return Binning(mean, err, errs, counts, float(tau), level, converged)


def plateau_bins(bins, nmin: int = MIN_BINS) -> np.ndarray:
    r"""Merge bins (rows, pairwise) while at least ``2 * nmin`` remain: the bins of the plateau level."""
    y = _validate.real_array("bins", bins)
    if y.ndim not in (1, 2):
        raise ValueError("bins must be a 1-d array of bin values or a 2-d array (bins x observables).")
    nmin = _validate.positive_int("nmin", nmin)
    while y.shape[0] >= 2 * nmin:
        k = y.shape[0] // 2
        y = 0.5 * (y[:2 * k:2] + y[1:2 * k:2])
    return y


def jackknife(func: Callable, *bins) -> tuple[float, float]:
    r"""Jackknife estimate and error of ``func(*means)`` from bins (rows = bins) of each argument.

    Parameters
    ----------
    func : callable
        Takes the means of each argument (arrays of the shape of one row) and returns a float.
    *bins : array_like
        One array per argument, first axis the bins (equal count for all).

    Returns
    -------
    (value, error) : tuple of float
        The bias-corrected estimate :math:`n f(\bar x) - (n-1)\overline{f_{(k)}}` and the jackknife
        error :math:`\sqrt{(n-1)/n \sum_k (f_{(k)} - \overline{f_{(k)}})^2}`.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.mcstats import jackknife
    >>> x = np.arange(10.0)
    >>> v, e = jackknife(lambda m: m, x)
    >>> float(v), round(float(e), 6), round(float(x.std(ddof=1) / np.sqrt(10)), 6)
    (4.5, 0.957427, 0.957427)
    """
    if not callable(func):
        raise ValueError("func must be a function of the observables' means.")
    if not bins:
        raise ValueError("jackknife needs at least one array of bins.")
    arrs = [_validate.real_array("bins", b) for b in bins]
    if any(a.ndim == 0 for a in arrs):
        raise ValueError("bins must be arrays with one entry per bin, not single numbers.")
    n = arrs[0].shape[0]
    if any(a.shape[0] != n for a in arrs):
        raise ValueError("every argument of jackknife needs the same number of bins.")
    total = [a.sum(axis=0) for a in arrs]
    full = float(func(*[s / n for s in total]))
    if n < 2:
        return full, math.nan
    loo = np.array([float(func(*[(s - a[k]) / (n - 1) for s, a in zip(total, arrs)])) for k in range(n)])
    mbar = float(loo.mean())
    err = math.sqrt((n - 1) / n * float(np.sum((loo - mbar) ** 2)))
    return n * full - (n - 1) * mbar, err


def combine_independent(values, errors, weights) -> tuple[float, float]:
    r"""Mean of independent estimates weighted by ``weights`` (e.g. sweeps), with the propagated error.

    :math:`\bar x = \sum_c w_c x_c / W`, :math:`\sigma = \sqrt{\sum_c w_c^2 \sigma_c^2}/W`:
    each chain is an unbiased estimate, the chains are independent.
    """
    v = _validate.real_array("values", values, ndim=1)
    w = _validate.real_array("weights", weights, ndim=1)
    try:        # an error may be NaN (a chain too short for its own error bar), never complex or text
        e = np.asarray(errors, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ValueError("errors must be real numbers, one per estimate.") from None
    if not (v.shape == e.shape == w.shape) or v.size == 0:
        raise ValueError("values, errors and weights must have one entry per estimate, at least one.")
    if np.any(w < 0) or not float(w.sum()) > 0:
        raise ValueError("weights must be non-negative with a positive sum.")
    tot = float(w.sum())
    return float(np.sum(w * v) / tot), float(math.sqrt(float(np.sum((w * e) ** 2))) / tot)
