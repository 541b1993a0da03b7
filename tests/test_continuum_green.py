"""Continuum Green function G(z, z', lambda, L): boundary values, symmetry, closed forms, C_m
convention, the spectral representation green2f, and input validation."""

import warnings

import mpmath as mp
import numpy as np
import pytest

from hyperlattice.continuum.green import (boundary_constant, coefficient_cm, continuum_green,
                                          fundamental_solution, green_infinite_disk, green_laplace, green_nu)
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


# ----------------------------------------------------------------------------
# issue 10: defects found with unusual input, each with its regression test
# ----------------------------------------------------------------------------

def _mp_green(z, zp, lam, L, M, dps=30):
    """Reference green33 = green34 - green36 in mpmath (30 digits), summed over m = 0..M.

    P~^m = P^m Gamma(nu-m+1)/Gamma(nu+m+1) = w^(m/2)/m! ((1+x)/2)^nu F(-nu, m-nu; m+1; w) (DLMF 14.3.1
    with 15.8.1, w = r^2 exactly: entire in nu, so integer nu needs no care); Q^m(x_L) from
    mpmath.legenq(type=3) at m = 0, 1 and the upward recurrence DLMF 14.10.6 (stable for Q); C_m with
    the (-1)^m of type-3 Q. Checked against a sum with mpmath.legenp for P^m (same 16 digits, 300x
    slower). Returns (G, |last term|).
    """
    mp.mp.dps = dps
    z, zp, L = mp.mpc(z), mp.mpc(zp), mp.mpf(L)
    lam = mp.mpf(complex(lam).real) if complex(lam).imag == 0 else mp.mpc(lam)
    nu = -mp.mpf(1) / 2 + mp.sqrt(1 - lam) / 2
    r, rp = abs(z), abs(zp)

    def x(s):
        return (1 + s**2) / (1 - s**2)

    def ptilde(m, s):
        return (s**m / mp.factorial(m) * ((1 + x(s)) / 2) ** nu
                * mp.hyp2f1(-nu, m - nu, m + 1, s**2))

    y = 1 + 2 * abs(z - zp) ** 2 / ((1 - r**2) * (1 - rp**2))
    total = mp.legenq(nu, 0, y, type=3) / (2 * mp.pi)
    xl = x(L)
    c = xl / mp.sqrt(xl**2 - 1)
    q = [mp.legenq(nu, 0, xl, type=3), mp.legenq(nu, 1, xl, type=3)]
    for j in range(M - 1):
        q.append(-2 * (j + 1) * c * q[-1] + (nu - j) * (nu + j + 1) * q[-2])
    dphi = mp.arg(z) - mp.arg(zp)
    term = 0
    for m in range(M + 1):
        term = (q[m] * ptilde(m, r) * ptilde(m, rp) / ptilde(m, L) * (1 if m == 0 else 2) * (-1) ** m
                * mp.cos(m * dphi) / (2 * mp.pi))
        total -= term
    return complex(total), abs(complex(term))


# (z, z', lambda, L, orders M of the reference sum): the defects of issue 10 and the integer-nu path
MP_CASES = [
    (0.1, 0.2, 1e-13, 0.3, 40),                              # tiny lambda (was 6.4 % off at 1e-16)
    (0.1, 0.2, 3e-16, 0.3, 40),
    (0.3 * np.exp(0.4j), 0.5, -8.0, 0.8, 80),                # nu = 1: Miller throughout
    (0.2 + 0.1j, -0.35j, -24.0, 0.7, 80),                    # nu = 2 (principal root)
    (0.2 + 0.1j, -0.35j, -24.0 + 1e-7, 0.7, 80),             # just off nu = 2
    (0.75 * 0.8, 0.6 * np.exp(2.0j), -8.0 + 0j, 0.8, 200),   # nu = 1, near the circle
    # small disk, both near the circle (2,600 terms of the mpmath reference: seconds each, so
    # three of the four are in the slow tier)
    pytest.param(0.99 * 0.3, 0.99 * 0.3 * np.exp(0.3j), 0.5, 0.3, 2600, marks=pytest.mark.slow),
    (0.99 * 0.1, 0.99 * 0.1 * np.exp(0.3j), 3.0, 0.1, 2600),          # (raised ConvergenceError)
    pytest.param(0.99 * 0.01, 0.99 * 0.01 * np.exp(0.3j), 100.0, 0.01, 2600, marks=pytest.mark.slow),
    pytest.param(0.99 * 0.2, 0.99 * 0.2 * np.exp(0.3j), 2.0 + 0.5j, 0.2, 2600, marks=pytest.mark.slow),
]


@pytest.mark.parametrize("z,zp,lam,L,M", MP_CASES)
def test_against_mpmath_series(z, zp, lam, L, M):
    """|G - G_ref| within 1e-13 of the scale |G_0| + |delta G| of the cancelling terms (near the circle
    G itself is 1000x smaller than G_0, and tol is relative to that scale by design), and within ten
    times the reported truncation estimate."""
    ref, last = _mp_green(z, zp, lam, L, M)
    g, info = continuum_green(z, zp, lam, L, return_info=True)
    g0 = fundamental_solution(z, zp, lam)
    scale = abs(g0) + abs(g0 - g)                        # |G_0| + |delta G|, the scale of tol
    assert last < 1e-20 * scale                          # the reference sum has converged
    # rounding: the terms of green36 may exceed delta G itself (they alternate), hence 1e-13
    assert abs(g - ref) <= max(10 * info.tail_estimate, 1e-13) * scale


@pytest.mark.slow
def test_against_mpmath_series_at_0999():
    """Both points at 0.999 L: 4000 orders (accelerated) against a 26000-order reference."""
    z, zp, lam, L = 0.999 * 0.3, 0.999 * 0.3 * np.exp(0.3j), 0.5, 0.3
    ref, _ = _mp_green(z, zp, lam, L, 26000)
    g, info = continuum_green(z, zp, lam, L, return_info=True)
    assert info.converged and abs(g - ref) <= 1e-14 * abs(fundamental_solution(z, zp, lam))


@pytest.mark.parametrize("zp", [0.2, 0.15 - 0.1j])
def test_tiny_lambda_is_continuous_with_eq23(zp):
    """lambda between 1e-16 and 1e-11 was up to 6.4 % off without a warning: G(lambda) must be
    G(0) (eq23, closed form) + lambda dG/dlambda to rounding."""
    L, z = 0.3, 0.1
    g0 = green_laplace(z, zp, L)
    slope = (continuum_green(z, zp, 1e-5, L) - continuum_green(z, zp, -1e-5, L)) / 2e-5
    for lam in (1e-18, 1e-17, 1e-16, 3e-16, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11, -1e-16, 1e-16j):
        g = continuum_green(z, zp, lam, L)
        assert abs(g - (g0 + lam * slope)) <= 1e-14 * abs(g0), lam


@pytest.mark.parametrize("L", [0.3, 0.2, 0.1, 0.01])
@pytest.mark.parametrize("f", [0.9, 0.99])
def test_small_disk_with_both_points_near_the_circle(L, f):
    """L <= 0.3 with both points near |z| = L raised ConvergenceError (Q^m at m >= 73 failed in the
    Legendre module); Q^m(rho_L) now comes from its stable upward recurrence and the slow series
    is accelerated by subtracting its lambda = 0 part."""
    z, zp = f * L, f * L * np.exp(0.3j)
    g, info = continuum_green(z, zp, 0.5, L, return_info=True)
    assert info.converged and np.isfinite(g)
    assert continuum_green(zp, z, 0.5, L) == pytest.approx(g, rel=1e-11, abs=1e-15)
    # the lambda -> 0 limit is eq23 exactly: G(1e-9) - G_laplace = O(lambda L^2)
    g_small = continuum_green(z, zp, 1e-9, L)
    assert abs(g_small - green_laplace(z, zp, L)) <= 1e-9 * L * L + 1e-14


def test_near_circle_satisfies_the_helmholtz_equation():
    """(lambda + Delta_g) G = 0 away from the source, by a Richardson-extrapolated five-point
    Laplacian (Delta_g = (1-|z|^2)^2 (d_x^2 + d_y^2)); together with the boundary values and the
    symmetry this fixes G (uniqueness of the Dirichlet problem)."""
    for L, lam in ((0.3, 0.5), (0.1, 3.0)):
        zp = 0.99 * L * np.exp(0.3j)
        z0 = 0.99 * L * 0.998
        h = 1e-3 * L

        def g(z):
            return continuum_green(z, zp, lam, L)

        def lap(hh):
            return (g(z0 + hh) + g(z0 - hh) + g(z0 + 1j * hh) + g(z0 - 1j * hh) - 4 * g(z0)) / hh**2

        dg = (1 - abs(z0) ** 2) ** 2 * (4 * lap(h) - lap(2 * h)) / 3
        assert abs(dg + lam * g(z0)) <= 1e-3 * (abs(dg) + abs(lam * g(z0)))


def test_points_on_the_circle_give_zero():
    L = 0.6
    zb = L * np.exp(1j * np.array([0.0, 1.0, 2.5]))
    zb = zb * (L / np.abs(zb))
    assert np.all(continuum_green(zb, 0.3j, 2.0, L) == 0)
    # both points on the circle (distinct): 0, not "the series diverges"
    assert continuum_green(L, L * np.exp(0.5j), 2.0, L) == 0


def test_tiny_disk_radius():
    """continuum_green(0, 1e-301, lam=.5, radius=1e-300) raised ZeroDivisionError."""
    g, info = continuum_green(0, 1e-301, lam=0.5, radius=1e-300, return_info=True)
    assert info.method == "laplace" and g == pytest.approx(-np.log(0.1) / (2 * np.pi), rel=1e-15)
    # eq23 is scale invariant in z/L: the same value for every tiny disk
    assert green_laplace(0.3e-200, -0.2e-200j, 1e-200) == pytest.approx(green_laplace(0.3, -0.2j, 1.0), rel=1e-14)
    # small disk, lambda L^2 not negligible: the series while x_L - 1 = 2L^2 keeps 16 ulps
    with pytest.raises(ValueError, match="too small"):
        continuum_green(0.3e-8, 0.1e-8, 1e9, 1e-8)


@pytest.mark.parametrize("L", [0.01, 1e-3, 1e-5, 1e-7])
def test_small_disks_keep_full_accuracy(L):
    """The Legendre module takes x = (1+r^2)/(1-r^2), whose x - 1 is only eps/r^2 accurate: a disk
    of radius 1e-4 was accurate to 1e-8 (1e-11 at 1e-3). Measured against eq23 at |lambda| L^2 =
    1e-14, where G and eq23 agree to 1e-14 relative."""
    lam = 1e-14 / L**2
    for f in (1e-9, 0.1, 0.5, 0.99):
        z, zp = f * L, 0.5 * L * np.exp(0.3j)
        g = continuum_green(z, zp, lam, L)
        scale = abs(fundamental_solution(z, zp, lam)) + abs(fundamental_solution(z, zp, lam) - g)
        assert abs(g - green_laplace(z, zp, L)) <= 2e-14 * scale


def test_integer_nu_slow_path():
    """nu = 1 (lambda = -8) and nu = 2 (lambda = -24, principal root): Miller's recurrence is used
    for every radius, since the upward recurrence of P^m cancels there. Boundary, symmetry and
    continuity in lambda across the integer."""
    for lam, L in ((-8.0, 0.8), (-24.0, 0.7)):
        assert green_nu(lam) == pytest.approx(-0.5 + 0.5 * np.sqrt(1 - lam))
        phi = np.linspace(0.0, 2 * np.pi, 9)
        for src in (0.0, 0.3 * L * np.exp(0.4j), 0.93 * L * np.exp(2.0j)):
            assert np.max(np.abs(continuum_green(L * np.exp(1j * phi), src, lam, L))) < 1e-12
        rng = np.random.default_rng(3)
        z = 0.95 * L * np.sqrt(rng.random(12)) * np.exp(2j * np.pi * rng.random(12))
        zp = 0.95 * L * np.sqrt(rng.random(12)) * np.exp(2j * np.pi * rng.random(12))
        a = continuum_green(z, zp, lam, L)
        assert np.allclose(a, continuum_green(zp, z, lam, L), rtol=1e-11, atol=1e-14)
        # analytic in lambda: the values at lam +- eps bracket the one at lam to O(eps^2)
        eps = 1e-6
        up, down = continuum_green(z, zp, lam + eps, L), continuum_green(z, zp, lam - eps, L)
        assert np.max(np.abs(a - (up + down) / 2)) < 1e-9 * np.max(np.abs(a))
        assert np.max(np.abs(up - down)) > 0


@pytest.mark.parametrize("name,call,ok", [
    ("z", lambda v: continuum_green(v, 0.1, 0.5, 0.9), {"complex"}),
    ("zp", lambda v: continuum_green(0.1, v, 0.5, 0.9), {"complex"}),
    ("lam", lambda v: continuum_green(0.1, 0.2, v, 0.9), {"complex"}),
    ("radius", lambda v: continuum_green(0.1, 0.2, 0.5, v), set()),
    ("tol", lambda v: continuum_green(0.1, 0.2, 0.5, 0.9, tol=v), set()),
    ("extend", lambda v: continuum_green(0.1, 0.2, 0.5, 0.9, extend=v), {"bool"}),
    ("max_terms", lambda v: continuum_green(0.1, 0.2, 0.5, 0.9, max_terms=v), set()),
    ("return_info", lambda v: continuum_green(0.1, 0.2, 0.5, 0.9, return_info=v), {"bool"}),
    ("laplace z", lambda v: green_laplace(v, 0.2, 0.9), {"complex"}),
    ("laplace radius", lambda v: green_laplace(0.1, 0.2, v), set()),
    ("fundamental", lambda v: fundamental_solution(0.1, 0.2, v), {"complex"}),
    ("infinite disk", lambda v: green_infinite_disk(v, 0.2, 0.5), {"complex"}),
    ("green_nu", lambda v: green_nu(v), {"complex"}),
    ("cm nu", lambda v: coefficient_cm(v, 2), {"complex"}),
    ("cm m", lambda v: coefficient_cm(0.5, v), set()),
    ("boundary_constant", lambda v: boundary_constant(v), {"complex"}),
])
def test_bad_values_give_valueerror(name, call, ok):
    """None/NaN/inf/bool/str/ragged/complex/object: ValueError everywhere (max_terms=None leaked
    TypeError)."""
    bad = {"none": None, "nan": float("nan"), "inf": float("inf"), "bool": True, "str": "seven",
           "ragged": [[1, 2], [3]], "complex": 1 + 2j, "object": object()}
    for tag, v in bad.items():
        if tag in ok:
            continue
        with pytest.raises(ValueError):
            call(v)


def test_too_many_pairs_refused_before_allocating():
    import tracemalloc

    z = np.zeros(2**13, complex) + 0.1
    zp = np.zeros((2**13, 1), complex) + 0.2j
    tracemalloc.start()
    try:
        with pytest.raises(ValueError, match="pairs"):
            continuum_green(z, zp, 0.5, 0.9)
        assert tracemalloc.get_traced_memory()[1] < 5e6
    finally:
        tracemalloc.stop()


def test_chunked_tables_give_the_same_values(monkeypatch):
    """Pairs are split whenever the (M+1) x radii tables would exceed _TABLE_BYTES."""
    import hyperlattice.continuum.green as kg

    rng = np.random.default_rng(5)
    z = 0.9 * 0.95 * np.sqrt(rng.random(40)) * np.exp(2j * np.pi * rng.random(40))
    full, info = continuum_green(z, 0.6j, 2.0 + 0.3j, 0.95, return_info=True)
    monkeypatch.setattr(kg, "_TABLE_BYTES", 20_000)
    split, info2 = continuum_green(z, 0.6j, 2.0 + 0.3j, 0.95, return_info=True)
    assert np.allclose(split, full, rtol=1e-13, atol=1e-16) and info2.converged


def test_accelerated_series_agrees_with_the_plain_one(monkeypatch):
    """Near the circle the lambda = 0 series is subtracted; with the switch moved beyond reach the
    plain sum (many more orders) gives the same value."""
    import hyperlattice.continuum.green as kg

    L = 0.5
    z, zp = 0.985 * L, 0.985 * L * np.exp(0.2j)
    acc, info = continuum_green(z, zp, 3.0 + 1.0j, L, return_info=True)
    assert info.method == "series-accelerated" and info.converged
    monkeypatch.setattr(kg, "_PLAIN_TERMS", 10**6)
    plain, info2 = continuum_green(z, zp, 3.0 + 1.0j, L, return_info=True)
    assert info2.method == "series" and info2.terms > info.terms
    assert abs(acc - plain) <= 1e-12 * abs(fundamental_solution(z, zp, 3.0 + 1.0j))


@pytest.mark.parametrize("lam", [1000.0, 3000.0, pytest.param(1e4, marks=pytest.mark.slow),
                                 pytest.param(1e5 + 0j, marks=pytest.mark.slow)])
def test_large_lambda_is_right_or_says_how_wrong(lam):
    """Real lambda >~ 1000 was silently wrong (1e-8 at 1000, 5e-6 at 3000, O(1) at 1e4, all with
    tail estimates ~1e-18): Miller's start depth ignored the oscillatory range m < |nu| sinh t of the
    recurrence. The start now follows the recurrence's own decay factors, and where P~^m(rho_L) sits
    near a zero (lambda close to a Dirichlet eigenvalue of order m, ubiquitous at large lambda) the
    amplified rounding is estimated and warned about."""
    z, zp, L = 0.5, 0.3j, 0.8
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        g, info = continuum_green(z, zp, lam, L, return_info=True)
    ref, last = _mp_green(z, zp, lam, L, 500 if abs(lam) < 5e4 else 1500, dps=40)
    g0 = fundamental_solution(z, zp, lam)
    scale = abs(g0) + abs(g0 - g)
    assert abs(g - ref) <= max(10 * (info.tail_estimate + info.rounding_estimate), 1e-12) * scale
    assert abs(g.imag) <= 1e-12 * scale or not info.converged          # real lambda > 1, L < 1: G real


def test_lambda_beyond_the_legendre_range_is_refused():
    from hyperlattice.continuum.green import MAX_LAMBDA

    for call in (lambda: continuum_green(0.1, 0.2, 2 * MAX_LAMBDA, 0.9),
                 lambda: fundamental_solution(0.1, 0.2, -2 * MAX_LAMBDA),
                 lambda: green_infinite_disk(0.1, 0.2, 2j * MAX_LAMBDA)):
        with pytest.raises(ValueError, match="beyond the range"):
            call()


@pytest.mark.slow
def test_overflowing_series_raises_instead_of_returning_nan():
    """Regression: points near the circle of the l = 7 disk with max_terms = 1e5 overflowed the
    green36 series; the result was NaN with a NaN error estimate and no warning."""
    from hyperlattice.dictionary import disk_radius_for_rings, lambda_from_energy
    from hyperlattice.errors import ConvergenceError

    L = disk_radius_for_rings(7, 7, 3)[0]
    r = np.tanh(np.arctanh(L) - 0.19)
    z = np.full(4, r + 0j)
    zp = r * np.exp(1j * np.linspace(0.5, np.pi, 4))
    with pytest.raises(ConvergenceError, match="overflows"):
        continuum_green(z, zp, complex(lambda_from_energy(-3.2, 7, 3)), L, tol=1e-10, max_terms=100_000)
