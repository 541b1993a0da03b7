"""Legendre functions of complex degree (type 3, x >= 1) against mpmath at 30 digits.

Each region has its own tolerance (see docs/continuum.md). For conical degrees, which
oscillate, the error is measured relative to the envelope
|tan(nu pi)|/pi (|Q_nu^m| + |Q_{-nu-1}^m|) >= |P_nu^m| (A&S 8.2.3), so that zeros of P
are judged by absolute accuracy relative to the local amplitude.
"""

import itertools
import warnings

import mpmath as mp
import numpy as np
import pytest

from hyperlattice.errors import ConvergenceWarning
from hyperlattice.continuum.special import (conical_p, legendre_cm, legendre_log_p, legendre_p, legendre_q,
                                  legendre_q_over_p, legendre_wronskian, nu_from_lambda)

mp.mp.dps = 30

X_NEAR = [1.0, 1.0 + 1e-9, 1.001, 1.05, 1.5, 2.9]
X_FAR = [3.1, 10.0, 1e3, 1e7, 1e10, 1e12]
M_SET = [0, 1, 3, 10, 30]


def _mpnu(nu):
    nu = complex(nu)
    return mp.mpf(nu.real) if nu.imag == 0 else mp.mpc(nu.real, nu.imag)


def _ref_p(nu, m, x):
    if x == 1.0:
        return 1.0 + 0j if m == 0 else 0j     # P_nu^m(1) = delta_{m0} (mpmath cannot take x = 1)
    nu = complex(nu)
    if nu.imag == 0 and nu.real == int(nu.real) and 0 <= nu.real < m:
        return 0j                               # P_n^m = 0 for integers 0 <= n < m
    if x < 1.01 and m > 3:
        return _ref_p_series(nu, m, x)
    return complex(mp.legenp(_mpnu(nu), m, mp.mpf(x), type=3))


def _ref_p_series(nu, m, x):
    """DLMF 14.3.1 with the c = 1 - m limit taken analytically, at 30 digits:
    P = (x^2-1)^{m/2} / (2^m m!) Gamma(nu+m+1)/Gamma(nu-m+1) F(nu+m+1, m-nu; m+1; (1-x)/2).
    (A different series from the package's Pfaff form; used where mpmath.legenp gives up,
    i.e. for tiny values at x -> 1 and large m.)"""
    n, x = _mpnu(nu), mp.mpf(x)
    poly = mp.fprod([n + j for j in range(1 - m, m + 1)]) if m else 1
    return complex((x * x - 1) ** (mp.mpf(m) / 2) / (2**m * mp.factorial(m)) * poly
                   * mp.hyp2f1(n + m + 1, m - n, m + 1, (1 - x) / 2))


def _ref_q(nu, m, x):
    return complex(mp.legenq(_mpnu(nu), m, mp.mpf(x), type=3))


def _envelope(nu, m, x):
    """Amplitude bound for conical P (|P| <= this), from the connection formula."""
    nu = complex(nu)
    if x == 1.0 or nu.imag < 0.1:
        # k < 0.2: no oscillation below x ~ 1e10 and tan(nu pi) ~ 1/k overestimates; use |P|
        return 0.0
    t = abs(complex(mp.tan(mp.pi * _mpnu(nu))))
    return t / np.pi * (abs(_ref_q(nu, m, x)) + abs(_ref_q(-nu - 1, m, x)))


# (label, degrees, x values, rtol, conical?)
P_REGIONS = [
    ("conical k<=40, x<=3", [-0.5 + 0j, -0.5 + 0.005j, -0.5 + 0.25j, -0.5 + 1.5j, -0.5 + 20j], X_NEAR, 1e-12, True),
    ("conical k<=40, x>3", [-0.5 + 0j, -0.5 + 0.005j, -0.5 + 0.25j, -0.5 + 1.5j, -0.5 + 20j], X_FAR, 1e-12, True),
    ("conical k=300 (small disks)", [-0.5 + 150j], X_NEAR + [10.0, 1e3], 1e-12, True),
    ("conical k=300, x>=1e7", [-0.5 + 150j], [1e7, 1e10], 3e-12, True),
    ("real nu (lambda<1)", [0.0, 0.3, 1.0, 2.5, 4.2, -0.9, -2.5], X_NEAR + X_FAR, 1e-12, False),
    ("complex nu (complex lambda)", [0.7 + 1.3j, 3 - 2j, -0.2 + 5j, 2 + 0.5j], X_NEAR + X_FAR, 1e-12, False),
]


@pytest.mark.parametrize("label,nus,xs,rtol,conical", P_REGIONS, ids=[r[0] for r in P_REGIONS])
def test_legendre_p_against_mpmath(label, nus, xs, rtol, conical):
    worst = 0.0
    for nu, m in itertools.product(nus, M_SET):
        got = legendre_p(nu, m, np.array(xs))
        for x, g in zip(xs, got):
            ref = _ref_p(nu, m, x)
            scale = max(abs(ref), _envelope(nu, m, x)) if conical else abs(ref)
            if scale == 0.0:
                assert abs(g) <= 1e-14 * max(1.0, x ** abs(complex(nu).real)), (nu, m, x, g)
                continue
            err = abs(g - ref) / scale
            worst = max(worst, err)
            assert err <= rtol, (label, nu, m, x, g, ref, err)
    assert worst > 0.0  # the comparison really ran


Q_REGIONS = [
    ("conical", [-0.5 + 0j, -0.5 + 0.25j, -0.5 + 1.5j, -0.5 + 20j, -0.5 + 150j], 1e-12),
    ("real nu", [0.0, 0.3, 1.0, 2.5, -0.9, -1.3], 1e-12),
    ("complex nu", [0.7 + 1.3j, 3 - 2j, -0.2 + 5j, 2 + 0.5j], 1e-12),
]


@pytest.mark.parametrize("label,nus,rtol", Q_REGIONS, ids=[r[0] for r in Q_REGIONS])
def test_legendre_q_against_mpmath(label, nus, rtol):
    xs = X_NEAR[1:] + [1.2, 1.3] + X_FAR
    for nu, m in itertools.product(nus, M_SET):
        got = legendre_q(nu, m, np.array(xs))
        for x, g in zip(xs, got):
            ref = _ref_q(nu, m, x)
            err = abs(g - ref) / abs(ref)
            assert err <= rtol, (label, nu, m, x, g, ref, err)


def test_q_convention_is_dlmf_type3():
    """Q_nu^m = (-1)^m Gamma(nu+m+1) * Olver's bold Q (DLMF 14.3.10)."""
    nu, m, x = 0.3 + 0.8j, 3, 4.0
    bold = (mp.sqrt(mp.pi) * (x * x - 1) ** (m / 2) / (2 ** (_mpnu(nu) + 1) * mp.mpf(x) ** (_mpnu(nu) + m + 1))
            * mp.hyp2f1((_mpnu(nu) + m) / 2 + 1, (_mpnu(nu) + m + 1) / 2, _mpnu(nu) + 1.5, 1 / mp.mpf(x) ** 2)
            / mp.gamma(_mpnu(nu) + 1.5))
    ref = complex((-1) ** m * mp.gamma(_mpnu(nu) + m + 1) * bold)
    assert legendre_q(nu, m, x) == pytest.approx(ref, rel=1e-13)


@pytest.mark.parametrize("nu", [-0.5 + 0.3j, -0.5 + 7j, 0.4, 1.7 + 0.6j])
@pytest.mark.parametrize("m", [0, 2, 7])
def test_wronskian_identity(nu, m):
    """P Q' - Q P' with derivatives from the m-recurrence (DLMF 14.10.5 for x > 1):
    sqrt(x^2-1) f' = f^{m+1} + m x f^m / sqrt(x^2-1), equals the closed form."""
    x = np.array([1.0 + 1e-6, 1.01, 1.3, 2.0, 3.5, 50.0, 1e6])
    s = np.sqrt((x - 1) * (x + 1))
    p0, p1 = legendre_p(nu, m, x), legendre_p(nu, m + 1, x)
    q0, q1 = legendre_q(nu, m, x), legendre_q(nu, m + 1, x)
    w = (p0 * q1 - q0 * p1) / s
    expect = legendre_wronskian(nu, m, x)
    scale = (np.abs(p0 * q1) + np.abs(q0 * p1)) / s
    assert np.all(np.abs(w - expect) <= 1e-12 * scale)
    assert np.all(np.abs(w - expect) <= 1e-10 * np.abs(expect))


def test_derivative_relation_matches_mpmath():
    nu, m, x = -0.5 + 2j, 2, 1.7
    s = np.sqrt(x * x - 1)
    dp = (legendre_p(nu, m + 1, x) + m * x / s * legendre_p(nu, m, x)) / s
    ref = complex(mp.diff(lambda y: mp.legenp(_mpnu(nu), m, y, type=3), mp.mpf(x)))
    assert dp == pytest.approx(ref, rel=1e-12)


@pytest.mark.parametrize("nu,m", [(-0.5 + 3j, 0), (-0.5 + 3j, 4), (0.8 - 0.4j, 2), (2.0, 1)])
def test_legendre_ode_residual(nu, m):
    """(1-x^2) f'' - 2x f' + [nu(nu+1) - m^2/(1-x^2)] f = 0 by a 5-point stencil."""
    for func in (legendre_p, legendre_q):
        for x0 in (1.2, 2.5, 7.0, 40.0):
            h = 1e-3 * (x0 - 1.0)
            xs = x0 + h * np.arange(-2, 3)
            f = func(nu, m, xs)
            d1 = (f[0] - 8 * f[1] + 8 * f[3] - f[4]) / (12 * h)
            d2 = (-f[0] + 16 * f[1] - 30 * f[2] + 16 * f[3] - f[4]) / (12 * h * h)
            terms = [(1 - x0 * x0) * d2, -2 * x0 * d1, (nu * (nu + 1) - m * m / (1 - x0 * x0)) * f[2]]
            res = sum(terms)
            assert abs(res) <= 1e-6 * max(abs(t) for t in terms), (func.__name__, x0)


def test_special_values():
    x = np.array([1.0, 1.5, 10.0, 1e9])
    assert np.allclose(legendre_p(0.0, 0, x), 1.0, rtol=0, atol=4e-15)
    assert np.allclose(legendre_p(1.0, 0, x), x, rtol=1e-14)
    assert np.allclose(legendre_p(2.0, 1, x), 3 * x * np.sqrt(x * x - 1), rtol=1e-14)
    assert np.all(np.abs(legendre_p(1.0, 2, x)) <= 1e-15 * x)   # P_n^m = 0 for integer n < m
    assert legendre_p(-0.5 + 0.7j, 3, 1.0) == 0
    # P_nu = P_{-nu-1}
    assert legendre_p(-1.8 + 0.3j, 2, 5.0) == pytest.approx(legendre_p(0.8 - 0.3j, 2, 5.0), rel=1e-14)
    # Q_0 = artanh(1/x)
    assert legendre_q(0.0, 0, 3.0).real == pytest.approx(np.arctanh(1 / 3), rel=1e-14)


def test_conical_is_real_and_broadcasts():
    k = np.linspace(0.0, 5.0, 11)[:, None]
    x = np.array([1.1, 4.0, 1e8])[None, :]
    v = conical_p(k, 1, x)
    assert v.shape == (11, 3) and v.dtype == float
    full = legendre_p(-0.5 + 0.5j * k, 1, x)
    assert np.all(np.abs(full.imag) <= 1e-12 * (1 + np.abs(full.real)))
    mm = legendre_p(-0.5 + 1j, np.arange(4)[:, None], np.array([1.5, 9.0]))
    assert mm.shape == (4, 2)
    assert mm[2, 1] == pytest.approx(legendre_p(-0.5 + 1j, 2, 9.0), rel=1e-15)


@pytest.mark.parametrize("nu", [-0.5 + 1.1j, 0.9 + 2.3j, 0.25])
@pytest.mark.parametrize("m", [0, 5, 30])
def test_q_over_p_at_large_boundary_argument(nu, m):
    """u_m/v_m at rho_L ~ 1e7 (green31), also for m = 30."""
    x = 2.5e7
    ref = complex(mp.legenq(_mpnu(nu), m, x, type=3) / mp.legenp(_mpnu(nu), m, x, type=3))
    assert legendre_q_over_p(nu, m, x) == pytest.approx(ref, rel=1e-11)


def test_log_scaled_values_extend_the_range():
    s, mant = legendre_log_p(-0.5 + 2j, 30, 1.0 + 2**-50)    # P ~ 1e-260: near underflow
    ref = mp.mpc(_ref_p_series(-0.5 + 2j, 30, mp.mpf(1) + mp.mpf(2) ** -50))
    got = mp.mpc(complex(mant)) * mp.e ** mp.mpf(float(s))
    assert abs(got - ref) <= 1e-12 * abs(ref)


def test_cm_matches_green25b_and_green26b():
    for nu, m in [(-0.5 + 1.3j, 3), (0.4 + 0.2j, 5), (2.2, 1), (0.3, 0)]:
        n = _mpnu(nu)
        ref = (mp.gamma((n - m + 2) / 2) * mp.gamma((n - m + 1) / 2)
               / (4**m * mp.gamma((n + m + 2) / 2) * mp.gamma((n + m + 1) / 2)))
        assert legendre_cm(nu, m) == pytest.approx(complex(ref), rel=1e-13)
        lam = -4 * nu * (nu + 1)
        alt = (-1) ** m / np.prod([(j + 0.5) ** 2 + 0.25 * (lam - 1) for j in range(m)]) if m else 1.0
        assert legendre_cm(nu, m) == pytest.approx(alt, rel=1e-12)


def test_nu_from_lambda_branch():
    assert nu_from_lambda(0.0) == 0
    assert nu_from_lambda(1.0 + 4.0) == pytest.approx(-0.5 + 1j)
    lam = np.array([-3.0, 0.5, 2.0 + 0.3j, 50 - 1j])
    nu = nu_from_lambda(lam)
    assert np.all(nu.real >= -0.5)
    assert np.allclose(-4 * nu * (nu + 1), lam)


@pytest.mark.parametrize("bad", [
    dict(nu=0.5, m=-1, x=2.0), dict(nu=0.5, m=1.5, x=2.0), dict(nu=0.5, m=1, x=0.9),
    dict(nu=0.5, m=1, x=np.nan), dict(nu=np.nan, m=1, x=2.0), dict(nu=0.5, m=1, x=np.inf),
])
def test_bad_input_raises_value_error(bad):
    with pytest.raises(ValueError):
        legendre_p(**bad)
    with pytest.raises(ValueError):
        legendre_q(**bad)


def test_q_singular_at_one():
    with pytest.raises(ValueError, match="singular"):
        legendre_q(0.3, 0, 1.0)


def test_no_warnings_in_validated_domain():
    x = np.geomspace(1 + 1e-8, 1e12, 200)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        for m in (0, 4, 30):
            legendre_q(-0.5 + 3j, m, x)
            legendre_p(-0.5 + 3j, m, x)
