"""The shared Monte Carlo statistics: error bars of correlated series that hold at short runs."""

import math

import numpy as np
import pytest

from hyperlattice import mcstats


def _ar1(rng, rho, n, count):
    """``count`` independent stationary AR(1) series x_k = rho x_{k-1} + e_k of length n."""
    x = np.empty((count, n))
    x[:, 0] = rng.normal(size=count) / math.sqrt(1.0 - rho * rho)
    e = rng.normal(size=(count, n))
    for k in range(1, n):
        x[:, k] = rho * x[:, k - 1] + e[:, k]
    return x


def test_short_correlated_series_get_their_true_error():
    """AR(1) with rho = 0.8 (tau_int = 4.5) in 1024 steps: the plateau level keeps 32-63 bins of 16
    steps, too short against tau, and its error^2 is about 14 % low; the reported error (Gamma method)
    has the exact one, sqrt(2 tau var / n), on average over 200 series."""
    rho, n = 0.8, 1024
    x = _ar1(np.random.default_rng(7), rho, n, 200)
    tau = (1 + rho) / (2 * (1 - rho))
    exact2 = 2 * tau / (1 - rho * rho) / n
    bs = [mcstats.binning(s) for s in x]
    rep2 = np.mean([b.error ** 2 for b in bs])
    plat2 = np.mean([b.errors[b.level] ** 2 for b in bs])
    # each error^2 carries ~10 % noise: the mean of 200 about 1 %
    assert 0.9 < rep2 / exact2 < 1.1
    assert plat2 / exact2 < 0.9
    assert np.mean([b.tau_int for b in bs]) == pytest.approx(tau, rel=0.1)


def test_gamma_method_of_white_noise_and_constants():
    x = np.random.default_rng(1).normal(size=4096)
    err, tau, w = mcstats.gamma_method(x)
    assert err * 64 == pytest.approx(1.0, abs=0.05) and tau == pytest.approx(0.5, abs=0.05) and w >= 1
    assert mcstats.gamma_method(np.ones(10)) == (0.0, 0.5, 0)
    assert all(math.isnan(v) for v in mcstats.gamma_method([1.0])[:2])
    with pytest.raises(ValueError):
        mcstats.gamma_method(np.ones(10), s_factor=0.0)


def test_a_slow_mode_outside_the_window_keeps_the_plateau_error():
    """A slow square wave (period 512) under white noise: the window closes on the fast part, the
    plateau error is far larger, and binning reports the larger one."""
    rng = np.random.default_rng(3)
    n = 8192
    x = rng.normal(size=n) + 0.3 * np.sign(np.sin(2 * np.pi * np.arange(n) / 512 + rng.uniform(0, 6)))
    b = mcstats.binning(x)
    g, _, _ = mcstats.gamma_method(x)
    assert b.error >= g
