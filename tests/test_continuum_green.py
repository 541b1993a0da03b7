"""Continuum Green function G(z, z', lambda, L): boundary values, symmetry, closed forms, C_m
convention, the spectral representation green2f, and input validation."""

import mpmath as mp
import numpy as np
import pytest

from hyperlattice.continuum.green import (boundary_constant, coefficient_cm, continuum_green,
                                          fundamental_solution, green_laplace, green_nu)
from hyperlattice.continuum.spectrum import dirichlet_roots, radial_g
from hyperlattice.errors import ConvergenceWarning
from hyperlattice.continuum.special import legendre_cm, legendre_p, legendre_q, legendre_wronskian

# (lambda, L): real below 1 (omega = -2.95 of {7,3}), complex (omega = -2.5+0.1i), real above
# 1 (conical nu), negative (omega < -3) and a small disk
CASES = [(0.8764501345711265, 0.95), (8.764501345711265 + 1.7529002691422533j, 0.95),
         (5.0, 0.9), (-3.0, 0.8), (2.0 + 0.5j, 0.5)]


@pytest.mark.parametrize("lam,L", CASES)
def test_vanishes_on_the_boundary(lam, L):
    phi = np.linspace(0.0, 2 * np.pi, 13)
    zb = L * np.exp(1j * phi)
    for src in (0.0, 0.3 * L * np.exp(0.4j), 0.7 * L * np.exp(2.0j)):
        g_b = continuum_green(zb, src, lam, L)
        g_in = continuum_green(0.5 * L * np.exp(1j * phi) + 0.01, src, lam, L)
        assert np.max(np.abs(g_b)) < 1e-12 * max(1.0, np.max(np.abs(g_in)))


@pytest.mark.parametrize("lam,L", CASES)
def test_symmetric(lam, L):
    rng = np.random.default_rng(1)
    z = 0.9 * L * np.sqrt(rng.random(20)) * np.exp(2j * np.pi * rng.random(20))
    zp = 0.9 * L * np.sqrt(rng.random(20)) * np.exp(2j * np.pi * rng.random(20))
    a = continuum_green(z, zp, lam, L)
    b = continuum_green(zp, z, lam, L)
    assert np.allclose(a, b, rtol=1e-11, atol=1e-13)


def test_cm_matches_wronskian_of_type3_q():
    """C_m = 1/[(1-x^2) W{P, Q}] (jump condition of green22) is (-1)^m legendre_cm: the paper's
    green38 belongs to a Q without the (-1)^m phase."""
    nu = 0.3 - 0.2j
    m = np.arange(8)
    x = 2.7
    from_w = 1.0 / ((1 - x * x) * legendre_wronskian(nu, m, x))
    assert np.allclose(coefficient_cm(nu, m), from_w, rtol=1e-13)
    assert np.allclose(coefficient_cm(nu, m), (-1.0) ** m * legendre_cm(nu, m), rtol=1e-13)
    assert not np.allclose(from_w[1::2], legendre_cm(nu, m)[1::2])


def test_addition_theorem_fixes_the_sign():
    """green27 = green34: (1/2pi) Q_nu(y) = (1/2pi) sum_m eps_m C_m Q^m(rho>) P^m(rho<) cos m dphi."""
    nu = green_nu(2.0 + 1.0j)
    z1, z2 = 0.3 * np.exp(0.4j), 0.6 * np.exp(1.5j)
    r1, r2 = abs(z1), abs(z2)
    x1, x2 = (1 + r1**2) / (1 - r1**2), (1 + r2**2) / (1 - r2**2)
    ms = np.arange(60)
    eps = np.where(ms == 0, 1.0, 2.0)
    dphi = np.angle(z1) - np.angle(z2)
    series = np.sum(eps * coefficient_cm(nu, ms) * legendre_q(nu, ms, x2) * legendre_p(nu, ms, x1)
                    * np.cos(ms * dphi)) / (2 * np.pi)
    assert abs(series - fundamental_solution(z1, z2, 2.0 + 1.0j)) < 1e-13
    wrong = np.sum(eps * legendre_cm(nu, ms) * legendre_q(nu, ms, x2) * legendre_p(nu, ms, x1)
                   * np.cos(ms * dphi)) / (2 * np.pi)
    assert abs(wrong - series) > 1e-2


def test_reduces_to_eq23_as_lambda_to_zero():
    z = np.array([0.1 + 0.2j, -0.5j, 0.6 + 0.3j])
    zp = 0.35 - 0.1j
    g0 = continuum_green(z, zp, 0.0, 0.85)
    assert np.allclose(g0, green_laplace(z, zp, 0.85), rtol=0, atol=0)
    # G is analytic in lambda: the difference is O(lambda), tolerance |lambda| * 10
    for lam in (1e-4, 1e-6j, -1e-8):
        g = continuum_green(z, zp, lam, 0.85)
        assert np.max(np.abs(g - g0)) < 10 * abs(lam)
        assert np.max(np.abs(g - g0)) > 0.01 * abs(lam)


def test_eq23_central_value():
    """green7: G(r, 0, 0, L) = -(1/2pi) ln(r/L)."""
    r = np.array([0.1, 0.4, 0.7])
    assert np.allclose(green_laplace(r, 0.0, 0.8), -np.log(r / 0.8) / (2 * np.pi), rtol=1e-14)


@pytest.mark.parametrize("lam", [0.5, 3.0 + 1.0j, -2.0])
def test_tends_to_infinite_disk_form(lam):
    """L -> 1: G(L) - G(1) = O((1-L)^{2 Re nu + 1}) (the Dirichlet correction's boundary factor)."""
    z = np.array([0.2 + 0.1j, -0.4j])
    zp = 0.3
    g1 = continuum_green(z, zp, lam, 1.0)
    nu = green_nu(lam)
    errs = []
    for eps in (1e-4, 1e-6, 1e-8):
        errs.append(np.max(np.abs(continuum_green(z, zp, lam, 1 - eps) - g1)))
    assert errs[2] < errs[1] < errs[0]
    expo = 2 * nu.real + 1
    slope = np.log(errs[0] / errs[2]) / np.log(1e4)
    assert slope == pytest.approx(expo, rel=0.05)


def test_infinite_disk_closed_form_and_constant():
    """L = 1: (1/2pi) Q_nu(y) with the decaying root equals the paper's Q_{nu_p} - C P_{nu_p};
    lim Q_{nu_p}/P_{nu_p} = pi cot(pi nu_p) for type-3 Q."""
    mp.mp.dps = 30
    for lam in (0.5, -3.0, 0.3 + 0.4j):
        nu_p = -1 - green_nu(lam)
        c_print = boundary_constant(lam)
        c_cot = np.pi / np.tan(np.pi * nu_p)
        y = mp.mpf(1e8)
        c_lim = complex(mp.legenq(nu_p, 0, y, type=3) / mp.legenp(nu_p, 0, y, type=3))
        assert c_cot == pytest.approx(c_lim, rel=1e-6)
        z, zp = 0.3 + 0.2j, -0.1 + 0.4j
        yv = 1 + 2 * abs(z - zp) ** 2 / ((1 - abs(z) ** 2) * (1 - abs(zp) ** 2))
        paper = (complex(mp.legenq(nu_p, 0, yv, type=3)) - c_cot * complex(mp.legenp(nu_p, 0, yv, type=3))) / (2 * np.pi)
        assert continuum_green(z, zp, lam, 1.0) == pytest.approx(paper, rel=1e-12)
        # the printed constant is pi cot(pi nu_p) - i pi/2: it belongs to a Q_nu that is the
        # type-3 one minus (i pi/2) P_nu (the Ferrers-type branch continued to x > 1), and
        # Q^paper - C^paper P = Q^type3 - pi cot(pi nu_p) P is the same Green function
        assert c_print == pytest.approx(c_cot - 0.5j * np.pi, rel=1e-12, abs=1e-12)


@pytest.mark.slow
def test_spectral_representation_green2f():
    """green2f with the Dirichlet roots and radial functions of the continuum module, applied to
    G(lambda) - G(0) (whose terms fall like 1/E^2, so 20 x 20 levels suffice for ~1e-4)."""
    L = 0.8
    nmax = mmax = 20
    k = dirichlet_roots(np.arange(mmax), radius=L, n_roots=nmax)
    xg, wg = np.polynomial.legendre.leggauss(120)
    rq, wq = 0.5 * L * (xg + 1), 0.5 * L * wg
    z = np.array([0.3 * np.exp(0.7j), 0.5j, -0.2 + 0.1j])
    zp = 0.4 + 0.1j
    lam = 3.0 + 1.0j
    rs = np.concatenate([rq, np.abs(z), [abs(zp)]])
    acc = np.zeros(3, complex)
    for m in range(mmax):
        for n in range(nmax):
            kk = k[m, n]
            g = radial_g(kk, m, rs)
            gq, gz, gp = g[: rq.size], g[rq.size: rq.size + 3], g[-1]
            norm2 = 2 * np.pi * np.sum(wq * rq / (1 - rq**2) ** 2 * np.abs(gq) ** 2)
            w = 1 / (kk**2 + 1 - lam) - 1 / (kk**2 + 1)
            dphi = np.angle(z) - np.angle(zp)
            pair = gz * np.conj(gp) / norm2 * w
            acc += pair * np.exp(1j * m * dphi) + (pair * np.exp(-1j * m * dphi) if m else 0)
    ref = continuum_green(z, zp, lam, L) - continuum_green(z, zp, 0, L)
    assert np.max(np.abs(acc - ref) / np.abs(ref)) < 1e-4


def test_truncation_report_and_warning():
    z = 0.99 * np.exp(1j * np.linspace(0, 6, 5))
    g, info = continuum_green(z, 0.2, 0.8, 0.995, tol=1e-10, return_info=True)
    assert info.method == "series" and info.converged and info.tail_estimate <= 1e-10
    assert info.terms > 5
    # both points close to the boundary: the Fourier series needs thousands of orders
    with pytest.warns(ConvergenceWarning):
        _, info = continuum_green(0.99, 0.99 * np.exp(0.01j), 0.8, 0.995, max_terms=50, return_info=True)
    assert not info.converged


def test_tail_estimate_is_honest():
    """A truncated sum agrees with a much longer one to the reported estimate (x10 margin)."""
    z = 0.8 * np.exp(1j * np.linspace(0, 6, 9))
    ref = continuum_green(z, 0.7j, 2.0 + 0.3j, 0.95, tol=1e-15)
    g, info = continuum_green(z, 0.7j, 2.0 + 0.3j, 0.95, tol=1e-6, return_info=True)
    scale = np.abs(fundamental_solution(z, 0.7j, 2.0 + 0.3j)) + np.abs(ref)
    assert np.max(np.abs(g - ref) / scale) < 10 * max(info.tail_estimate, 1e-14)
    assert np.max(np.abs(g - ref) / scale) < 1e-6


def test_coincident_points_infinite():
    g = continuum_green(np.array([0.3j, 0.1]), 0.3j, 0.5, 0.9)
    assert np.isinf(g[0].real) and np.isfinite(g[1])


@pytest.mark.parametrize("kwargs,msg", [
    (dict(z=np.nan, zp=0.1, lam=0.5, radius=0.9), "NaN"),
    (dict(z=0.95, zp=0.1, lam=0.5, radius=0.9), "outside"),
    (dict(z=0.5, zp=0.1, lam=0.5, radius=1.2), "radius"),
    (dict(z=0.5, zp=0.1, lam=0.5, radius=0.0), "radius"),
    (dict(z=0.5, zp=0.1, lam=float("nan"), radius=0.9), "finite"),
    (dict(z=0.5, zp=0.1, lam=2.0, radius=1.0), "continuous spectrum"),
    (dict(z=0.5, zp=0.1, lam=0.5, radius=0.9, tol=0.0), "tol"),
])
def test_bad_input(kwargs, msg):
    with pytest.raises(ValueError, match=msg):
        continuum_green(**kwargs)


def test_dirichlet_eigenvalue_is_an_error():
    L = 0.8
    k = dirichlet_roots(0, radius=L, n_roots=1)[0]
    with pytest.raises(ValueError, match="eigenvalue"):
        continuum_green(0.3, 0.1, 1 + k * k, L)


def test_extend_beyond_L_is_continuous():
    L = 0.9
    r = np.array([L - 1e-7, L, L + 1e-7])
    g = continuum_green(r * np.exp(0.3j), 0.2, 0.8, L, extend=True)
    assert abs(g[1]) < 1e-12
    assert np.sign(g[0].real) == -np.sign(g[2].real)
