"""Regression tests for the defects of issue 10 in continuum/special.py, and its input door.

Each test names the defect it pins down; the references are mpmath's type-3 functions at
30 digits.
"""

from __future__ import annotations

import time
import warnings

import mpmath as mp
import numpy as np
import pytest

import hyperlattice.continuum.special as sp
from hyperlattice.continuum.special import (MAX_ORDER, check_order, conical_p, evaluate_checked, legendre_cm,
                                            legendre_log_p, legendre_log_q, legendre_p, legendre_p_log_parts,
                                            legendre_q, legendre_q_over_p, legendre_wronskian, nu_from_lambda)
from hyperlattice.errors import ConvergenceWarning

mp.mp.dps = 30


def _mpnu(nu):
    nu = complex(nu)
    return mp.mpf(nu.real) if nu.imag == 0 else mp.mpc(nu.real, nu.imag)


def _ref_q(nu, m, x):
    return complex(mp.legenq(_mpnu(nu), m, mp.mpf(x), type=3))


def _ref_p(nu, m, x):
    return complex(mp.legenp(_mpnu(nu), m, mp.mpf(x), type=3))


# ----------------------------------------------------------------------------
# Q near nu = -3/2, -5/2, ...
# ----------------------------------------------------------------------------

def test_q_at_minus_seven_halves_is_right_and_quiet():
    """legendre_q(-3.5, 3, 50.0) was 100x off while its warning claimed 1.5e-7 (the Cauchy circle
    around the half-integer cancelled by x^{2n+1}); now by Q_nu = Q_{-nu-1} + pi cot(nu pi) P_nu."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        got = legendre_q(-3.5, 3, 50.0)
    assert got == pytest.approx(_ref_q(-3.5, 3, 50.0), rel=1e-13)


DELTAS = [0, 1e-12, -1e-8, 1e-4, -1e-4, 0.01, -0.03, 0.05, -0.0624, 0.07, -0.2, 1e-6j, 0.03j, 0.01 + 0.01j]
SCAN_X = [1.07, 1.3, 3.0, 50.0, 1e4]


def test_q_scan_near_negative_half_integers():
    """1,120 points nu = -n-3/2 + delta (n = 0..3, 14 offsets), m in {0, 1, 3, 5}, 5 arguments:
    241 of them had an unwarned relative error above 1e-6 before. Now every point is within
    1e-11 (measured worst 2.6e-14), and wherever a warning would be issued its estimate holds."""
    nus = [-h + d for h in (1.5, 2.5, 3.5, 4.5) for d in DELTAS]
    ms = [0, 1, 3, 5]
    grid = [(nu, m, x) for nu in nus for m in ms for x in SCAN_X]
    assert len(grid) == 1120
    nu_a = np.array([g[0] for g in grid], complex)
    m_a = np.array([g[1] for g in grid])
    x_a = np.array([g[2] for g in grid])
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        got = legendre_q(nu_a, m_a, x_a)
    s, mt, er = evaluate_checked(sp._log_q_parts, nu_a, m_a, x_a, warn=False)
    est = er / np.abs(mt)
    worst = 0.0
    for (nu, m, x), g, e in zip(grid, got, est):
        ref = _ref_q(nu, m, x)
        err = abs(g - ref) / abs(ref)
        worst = max(worst, err)
        assert err <= 1e-11, (nu, m, x, err)
        assert err <= 3 * e + 1e-13, (nu, m, x, err, e)       # the estimate is an upper estimate
    assert worst > 0


# ----------------------------------------------------------------------------
# P: at the switch x = 3, large orders, refusal of huge orders
# ----------------------------------------------------------------------------

@pytest.mark.parametrize("x", [np.nextafter(3.0, 0.0), 3.0, np.nextafter(3.0, 4.0), 2.999999999999])
def test_p_at_the_x3_switch(x):
    """legendre_p(11.3765j, 5, 3.0) was 3.6e-10 off: the quadrature's half-step error estimate
    (1e-3 |val - half|) was 1e4 too large, so the w-series (off by 1.6e-10) won the pick."""
    assert legendre_p(11.3765j, 5, x) == pytest.approx(_ref_p(11.3765j, 5, x), rel=1e-14)


def test_p_order_100_is_finite():
    """legendre_p(0.5, 100, 2.0) raised 'at a pole in nu' (Gamma(nu+m+1)/Gamma(nu-m+1) overflowed
    in double); the value is -4.18e131."""
    got = legendre_p(0.5, 100, 2.0)
    assert got.real == pytest.approx(-4.1845899541177284e131, rel=1e-12)
    assert got == pytest.approx(complex(mp.legenp(0.5, 100, 2, type=3)), rel=1e-12)


@pytest.mark.parametrize("m", [10**7, MAX_ORDER + 1, 1e300, 10**30])
def test_huge_orders_are_refused_at_once(m):
    """legendre_p(0.5, 10**7, 2.0) took 32 s before failing; orders beyond MAX_ORDER are refused
    before any work, with a plain sentence."""
    for func in (legendre_p, legendre_q, legendre_log_p, legendre_log_q, legendre_q_over_p):
        t0 = time.perf_counter()
        with pytest.raises(ValueError, match=f"at most {MAX_ORDER:,}"):
            func(0.5, m, 2.0)
        assert time.perf_counter() - t0 < 0.1
    with pytest.raises(ValueError, match=f"at most {MAX_ORDER:,}"):
        evaluate_checked(legendre_p_log_parts, np.array([0.5 + 0j]), np.array([10**7]), np.array([2.0]))


def test_max_order_itself_works():
    """m = MAX_ORDER is inside the supported domain for both kinds (P ~ 1e2564, Q ~ 1e3041)."""
    s, mt = legendre_log_p(-0.5 + 3j, MAX_ORDER, 3.0)
    assert np.isfinite(s) and abs(mt) > 0
    s, mt = legendre_log_q(-0.5 + 3j, MAX_ORDER, 1.25)
    ref = mp.legenq(_mpnu(-0.5 + 3j), MAX_ORDER, mp.mpf(1.25), type=3)
    got = mp.mpc(complex(mt)) * mp.exp(mp.mpf(float(s)))
    assert abs(got - ref) <= 1e-10 * abs(ref)


def test_q_poles_are_value_errors():
    """Q_nu^m has genuine poles where nu + m + 1 = 0, -1, ...: a ValueError that says so."""
    with pytest.raises(ValueError, match="pole"):
        legendre_q(-2.0, 1, 2.0)
    with pytest.raises(ValueError, match="pole"):
        legendre_log_q(np.array([0.5, -4.0]), 2, 3.0)


# ----------------------------------------------------------------------------
# the input door: ValueError with a plain sentence for every public function
# ----------------------------------------------------------------------------

class _Opaque:
    """A plain object of no numeric kind, with a fixed repr: the test ids must be the same in
    every process (pytest-xdist's workers compare their collections; object()'s repr holds
    its address)."""

    def __repr__(self):
        return "object()"


BAD_VALUES = [None, np.nan, np.inf, True, "a", ["a", "b"], [[1, 2], [1, 2, 3]], [1, None], {"a": 1}, _Opaque()]
BAD_ORDERS = BAD_VALUES + [-1, 1.5, 10**30]
BAD_X = BAD_VALUES + [0.5, 2 + 1j]

GOOD = (0.5 + 0.2j, 1, 2.0)


def _calls():
    three = [legendre_p, legendre_q, legendre_log_p, legendre_log_q, legendre_q_over_p, legendre_wronskian]
    for func in three:
        for bad in BAD_VALUES:
            yield func, (bad, GOOD[1], GOOD[2])
        for bad in BAD_ORDERS:
            yield func, (GOOD[0], bad, GOOD[2])
        for bad in BAD_X:
            yield func, (GOOD[0], GOOD[1], bad)
    for bad in BAD_VALUES:
        yield legendre_cm, (bad, 1)
        yield nu_from_lambda, (bad,)
        yield conical_p, (bad, 1, 2.0)
        yield conical_p, (1.0, 1, bad)
    for bad in BAD_ORDERS:
        yield legendre_cm, (0.5, bad)
        yield conical_p, (1.0, bad, 2.0)
        yield check_order, (bad,)


@pytest.mark.parametrize("func,args", list(_calls()),
                         ids=lambda v: v.__name__ if callable(v) else repr(v)[:30])
def test_bad_input_is_a_value_error(func, args):
    with pytest.raises(ValueError) as info:
        func(*args)
    text = str(info.value)
    assert text.endswith(".") and "\n" not in text and "Traceback" not in text


def test_shapes_that_do_not_broadcast_and_oversized_requests():
    with pytest.raises(ValueError, match="broadcast"):
        legendre_p(np.zeros(3), 1, np.full(4, 2.0))
    with pytest.raises(ValueError, match="broadcast"):
        legendre_cm(np.zeros(3), np.arange(4))
    with pytest.raises(ValueError, match="at most 16,777,216"):     # refused before allocating
        legendre_p(np.zeros((5000, 1)), 1, np.full((1, 5000), 2.0))


def test_x_below_one_and_q_at_one():
    with pytest.raises(ValueError, match="x >= 1"):
        legendre_p(0.5, 0, 0.999)
    with pytest.raises(ValueError, match="singular"):
        legendre_log_q(0.5, 0, 1.0)
    assert legendre_p(0.5, 0, 2.0 + 0j) == legendre_p(0.5, 0, 2.0)   # complex x with zero imag part


# ----------------------------------------------------------------------------
# public names for the continuum package (no private helpers across modules)
# ----------------------------------------------------------------------------

def test_public_helpers_replace_the_private_ones():
    for name in ("check_order", "legendre_p_log_parts", "evaluate_checked", "MAX_ORDER"):
        assert name in sp.__all__
    assert not hasattr(sp, "_check_m") and not hasattr(sp, "_guarded")  # no private names across modules
    m = check_order([0, 3.0, 7])
    assert m.dtype == np.int64 and list(m) == [0, 3, 7]
    nu = np.array([-0.5 + 2j, 0.3])
    x = np.array([1.5, 40.0])
    s, mt, er = evaluate_checked(legendre_p_log_parts, nu, check_order([2, 2]), x, warn=False)
    assert np.allclose(mt * np.exp(s), legendre_p(nu, 2, x), rtol=1e-15)
    assert np.all(er >= 0) and np.all(er < 1e-12 * np.abs(mt))
