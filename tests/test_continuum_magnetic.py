"""Continuum side of issue 11: magnetic Dirichlet levels on the hyperbolic disk, Landau limit."""

import math

import mpmath as mp
import numpy as np
import pytest

from hyperlattice.continuum.magnetic import (MagneticSpectrum, dirichlet_function, hyp2f1_real_interval,
                                             hypergeometric_parameters, landau_levels, magnetic_levels,
                                             magnetic_roots, radial_function)
from hyperlattice.continuum.spectrum import continuum_levels
from hyperlattice.dictionary import field_from_flux, flux_from_field
from hyperlattice.results import Result

# (m, B, kappa, r): below and above the threshold 1 + B^2/4, both signs, up to r = 0.999
RADIAL_CASES = [(0, 0.0, 5.0, 0.5), (2, 3.0, 20.0, 0.9), (-1, -2.0, 40.0, 0.99), (1, 10.0, 11.3, 0.999),
                (3, 5.0, 7.3, 0.3), (-2, 7.5, 3.1, 0.95), (0, 1.5, 150.0, 0.97), (5, -4.0, 60.0, 0.7)]


def _mp_radial(m, B, kappa, r):
    a, b, c, d = (complex(v) for v in hypergeometric_parameters(m, B, kappa))
    with mp.workdps(30):
        u = mp.mpf(r) ** 2
        val = mp.mpf(r) ** abs(m) * (1 - u) ** ((1 - mp.mpc(d)) / 2) * mp.hyp2f1(mp.mpc(a), mp.mpc(b),
                                                                               mp.mpc(c), u)
        scale = mp.mpf(r) ** abs(m) * abs((1 - u) ** ((1 - mp.mpc(d)) / 2))  # size of each part
        return complex(val), float(scale)


@pytest.mark.parametrize("m,B,kappa,r", RADIAL_CASES)
def test_radial_function_against_mpmath_hyp2f1(m, B, kappa, r):
    ref, scale = _mp_radial(m, B, kappa, r)
    assert abs(ref.imag) < 1e-25 * max(1.0, abs(ref.real))       # R is real
    got = radial_function(r, m, B, kappa)
    # relative to the size of the solution's terms (the value itself may be a cancellation)
    assert abs(got - ref.real) <= 1e-12 * max(abs(ref.real), scale)


def test_hyp2f1_against_mpmath_complex_parameters():
    a = np.array([0.5 - 3j, 2.0 + 1j, -1.5 + 0.5j])
    b = np.array([0.5 + 3j, -0.3 + 2j, 4.0 - 1j])
    c = np.array([1.0, 3.0, 2.5 + 1j])
    u = np.array([0.0, 0.3, 0.8, 0.99])
    got = hyp2f1_real_interval(a, b, c, u)
    with mp.workdps(30):
        for i, uv in enumerate(u):
            for j in range(3):
                ref = complex(mp.hyp2f1(mp.mpc(a[j]), mp.mpc(b[j]), mp.mpc(c[j]), mp.mpf(uv)))
                assert abs(got[i, j] - ref) <= 1e-12 * max(1.0, abs(ref))


def test_radial_function_satisfies_the_radial_ode():
    m, B, kappa = 2, 6.0, 17.0
    r = np.linspace(0.2, 0.9, 8)
    hstep = 1e-4
    R0 = radial_function(r, m, B, kappa)
    Rp = radial_function(r + hstep, m, B, kappa)
    Rm = radial_function(r - hstep, m, B, kappa)
    d1 = (Rp - Rm) / (2 * hstep)
    d2 = (Rp - 2 * R0 + Rm) / hstep**2
    A = B * r**2 / (2 * (1 - r**2))
    lhs = (1 - r**2) ** 2 * (d2 + d1 / r - (m - A) ** 2 / r**2 * R0) + kappa * R0
    assert np.max(np.abs(lhs)) < 1e-5 * np.max(np.abs(kappa * R0))


@pytest.mark.parametrize("kw", [dict(radius=0.5), dict(radius=0.9), dict(rings=3), dict(rings=5)])
def test_zero_flux_equals_continuum_levels(kw):
    a = magnetic_levels(levels=8, flux=0.0, **kw)
    b = continuum_levels(levels=8, **kw)
    assert np.max(np.abs(a.energies - b.energies)) < 1e-12
    assert list(a.m) == list(b.m) and list(a.n) == list(b.n)
    assert np.all(a.errors < 1e-12)
    assert list(a.degeneracy) == list(b.degeneracy)
    s = a.summary()
    assert set(s) == set(b.summary()) | {"flux"}
    assert np.allclose(s["k"], b.k, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("m,B", [(0, 2.5), (1, 4.0), (3, -6.0), (-2, 1.0)])
def test_sign_symmetry(m, B):
    # a and b' swap under (m, B) -> (-m, -B): equal up to rounding
    assert np.allclose(magnetic_roots(m, B, 0.8, 3), magnetic_roots(-m, -B, 0.8, 3), rtol=1e-13, atol=0)


def test_levels_sign_symmetry_and_nondegenerate():
    a = magnetic_levels(rings=4, levels=6, flux=0.2)
    b = magnetic_levels(rings=4, levels=6, flux=-0.2)
    assert np.allclose(a.energies, b.energies, rtol=0, atol=1e-13)
    assert list(a.m) == [-v for v in b.m]
    assert np.all(a.degeneracy == 1) and np.all(np.diff(a.energies) >= 0)
    assert a.summary()["flux"] == 0.2 and a.field == pytest.approx(field_from_flux(0.2))


def test_dirichlet_roots_are_roots():
    k = magnetic_roots(1, 3.0, 0.7, 3)
    f = dirichlet_function(k, 1, 3.0, 0.7)
    fs = dirichlet_function(k + 1e-6, 1, 3.0, 0.7)
    assert np.all(np.abs(f) < 1e-6 * np.abs(fs))
    assert np.all(np.diff(k) > 0)


def test_landau_levels_formula():
    out = landau_levels(10.0)
    assert np.array_equal(out["kappa"], [10.0, 22.0]) and out["threshold"] == 26.0
    assert landau_levels(2.0)["kappa"].size == 0          # needs B > 2
    assert np.array_equal(landau_levels(-14.0)["kappa"], landau_levels(14.0)["kappa"])
    # kappa_N = (2N+1)B - 4N(N+1) lies below the threshold for every discrete level
    for B in (3.0, 7.0, 20.0):
        o = landau_levels(B)
        assert np.all(o["kappa"] < o["threshold"]) and o["kappa"].size == math.ceil(B / 4 - 0.5)


def test_dirichlet_levels_approach_landau_levels():
    B, L = 10.0, 0.99999
    kN = landau_levels(B)["kappa"]
    # B > 0: (n, m) -> N = n - 1 + max(0, -m)
    for m in (0, 1, 2):
        k = magnetic_roots(m, B, L, 3)
        assert abs(k[0] - kN[0]) < 1e-8 and abs(k[1] - kN[1]) < 1e-6
        assert k[2] > landau_levels(B)["threshold"]
    k = magnetic_roots(-1, B, L, 2)
    assert abs(k[0] - kN[1]) < 1e-6 and k[1] > landau_levels(B)["threshold"]
    assert magnetic_roots(-2, B, L, 1)[0] > landau_levels(B)["threshold"]
    # mirrored for B < 0
    assert abs(magnetic_roots(1, -B, L, 1)[0] - kN[1]) < 1e-6


def test_flux_field_dictionary():
    assert field_from_flux(1.0, 7, 3) == pytest.approx(24.0)          # face area pi/12
    assert flux_from_field(field_from_flux(0.37, 8, 3), 8, 3) == pytest.approx(0.37, rel=1e-14)
    assert np.allclose(field_from_flux(np.array([0.0, 0.5]), 7, 3), [0.0, 12.0])


def test_result_round_trip():
    a = magnetic_levels(radius=0.8, levels=3, flux=0.1)
    b = Result.from_dict(a.as_dict())
    assert isinstance(b, MagneticSpectrum) and np.array_equal(b.energies, a.energies) and b.flux == 0.1


@pytest.mark.parametrize("call", [
    lambda: magnetic_levels(levels=0),
    lambda: magnetic_levels(radius=1.5),
    lambda: magnetic_levels(radius=0.5, flux="x"),
    lambda: magnetic_levels(radius=0.5, flux=float("nan")),
    lambda: magnetic_levels(p=4, q=4, radius=0.5),
    lambda: magnetic_levels(radius=0.5, rings=3),
    lambda: radial_function(1.0, 0, 1.0, 2.0),
    lambda: radial_function(0.5, 0.5, 1.0, 2.0),
    lambda: magnetic_roots(0, 1e9, 0.5),
    lambda: landau_levels(None),
    lambda: hyp2f1_real_interval(1, 1, -2, 0.5),
    lambda: field_from_flux(1j),
    lambda: flux_from_field("B"),
])
def test_bad_input(call):
    with pytest.raises(ValueError):
        call()


# regression: before the step rule t <= u0/|c|, orders m ~ 100 on large disks gave random signs
@pytest.mark.parametrize("m,B,kappa,r", [(120, 0.0, 1.25, math.sqrt(1 - 3.9e-5)), (80, 0.3, 1.5, 0.9999),
                                         (-3, 40.0, 150.0, 0.999), (60, -20.0, 90.0, 0.99)])
def test_radial_function_large_orders_and_fields(m, B, kappa, r):
    ref, scale = _mp_radial(m, B, kappa, r)
    got = radial_function(r, m, B, kappa)
    assert abs(got - ref.real) <= 1e-11 * max(abs(ref.real), scale)


def test_zero_flux_equals_continuum_levels_large_disk():
    a = magnetic_levels(rings=12, levels=4, flux=0.0)
    b = continuum_levels(rings=12, levels=4)
    assert np.max(np.abs(a.energies - b.energies)) < 1e-12 and list(a.m) == list(b.m)


def test_landau_approach_rate_is_s_to_the_delta():
    # kappa(L) - kappa_N ~ C (1 - L^2)^delta with delta = B/2 - 2N - 1 (the decaying exponent
    # beta_+ - beta_- of the Landau state): one decade of 1 - L gives a factor ~ 10^delta
    B = 10.0
    d3 = magnetic_roots(0, B, 0.999, 2) - landau_levels(B)["kappa"]
    d4 = magnetic_roots(0, B, 0.9999, 2) - landau_levels(B)["kappa"]
    assert np.all(d3 > 0) and np.all(d4 > 0)                      # Dirichlet levels lie above
    for ratio, delta in zip(d3 / d4, (4.0, 2.0)):
        assert 10 ** (delta - 0.1) < ratio < 10 ** (delta + 0.1)


def test_error_bounds_hold_against_mpmath_roots():
    from hyperlattice.dictionary import hopping_scale

    spec = magnetic_levels(radius=0.8, levels=4, flux=0.2)
    B = spec.field
    with mp.workdps(30):
        u = mp.mpf(spec.radius) ** 2
        for kap, m, err in zip(spec.kappa, spec.m, spec.errors):
            def R(k, m=int(m)):
                d = mp.sqrt(1 - k + mp.mpf(B) ** 2 / 4)
                beta = (1 - d) / 2
                a = beta + (abs(m) + m + mp.mpf(B) / 2) / 2
                b = beta + (abs(m) - m - mp.mpf(B) / 2) / 2
                return mp.re((1 - u) ** beta * mp.hyp2f1(a, b, 1 + abs(m), u))
            ref = mp.findroot(R, mp.mpf(kap))
            assert abs(float(ref) - kap) * hopping_scale(7, 3) <= err
            assert err < 1e-13


# ---------------------------------------------------------------------------------------------
# the scan along the field stops at the first order whose lowest root is not below the K-th level
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("p,q,rings,flux", [
    (7, 3, 3, 0.05), (7, 3, 4, 0.3), (7, 3, 5, 0.1), (8, 3, 3, 0.6), (8, 3, 4, -0.3),
    (4, 5, 3, 0.3), (3, 7, 3, 0.1), (5, 4, 4, 0.3), (3, 7, 3, 1.0),
])
def test_truncated_scan_equals_exhaustive_scan(p, q, rings, flux):
    """The K lowest levels equal the K smallest roots of EVERY order up to beyond A_phi(L) (one
    vectorised bracketing of all orders, as before the scan was truncated), and the lowest root
    grows with m along the field, the property the truncated scan relies on."""
    from hyperlattice.continuum.magnetic import _refine, _roots_below

    K = 4
    got = magnetic_levels(p, q, rings=rings, levels=K, flux=flux)
    B, x = got.field, got.x
    s, t = 2.0 / (x + 1.0), math.acosh(x)
    a_edge = abs(B) * (1.0 - s) / (2.0 * s)
    sign = 1 if B > 0 else -1
    along = sign * np.arange(0, math.floor(a_edge) + 3)
    orders = np.concatenate([along, -sign * np.arange(1, K + 1)]).astype(float)
    kcut = 1.1 * math.sqrt(got.kappa[-1] - 1.0) + 0.05
    cells, grid = _roots_below(orders, B, s, t, kcut)
    lo = np.concatenate([1.0 + grid[c] ** 2 for c in cells])
    hi = np.concatenate([1.0 + grid[c + 1] ** 2 for c in cells])
    mm = np.concatenate([np.full(c.size, m) for m, c in zip(orders, cells)])
    every, _ = _refine(lo, hi, mm, B, s)
    np.testing.assert_allclose(got.kappa, np.sort(every)[:K], rtol=1e-12)
    # the lowest root of each order along the field, up to the first order without one below kcut
    first = [c.size > 0 for c in cells[: along.size]]
    upto = first.index(False) if False in first else along.size
    lowest = np.array([every[np.flatnonzero(mm == m)[0]] for m in along[:upto]])
    assert upto >= 2 and np.all(np.diff(lowest) >= -8 * np.finfo(float).eps * lowest[1:])


def test_large_disks_reach_the_landau_levels():
    """l = 12 holds ~1e5 flux quanta at f = 0.3; the lowest states are Landau-like, kappa_0 = B."""
    for flux, tol in ((0.3, 1e-9), (0.2, 1e-5)):
        got = magnetic_levels(7, 3, rings=12, levels=3, flux=flux)
        kappa0 = landau_levels(got.field)["kappa"][0]
        assert np.all(got.kappa >= kappa0 * (1 - 1e-14))
        assert np.all(got.kappa - kappa0 <= tol * kappa0)
        assert got.m.tolist() == [0, 1, 2] and got.n.tolist() == [1, 1, 1]


def test_threshold_kappa_in_a_forbidden_region_is_finite():
    """Regression: kappa exactly at 1 + B^2/4 with a large order gave a zero local wavenumber and
    a ZeroDivisionError in the step rule."""
    value = dirichlet_function(10.0, 100, 6.0, 0.9)
    assert np.isfinite(value)

