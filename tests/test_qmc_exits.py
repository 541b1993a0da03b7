"""The directed loops' exit probabilities (least bounce): balance, normalisation, least bounce."""

from __future__ import annotations

import numpy as np
import pytest

from hyperlattice.bosons import _sse_kernels as K


def _probabilities(w):
    """P[le, x] from the cumulative rows of ``_cumulative`` (the bounce on the diagonal)."""
    P = np.zeros((4, 4))
    for le in range(4):
        row = np.array(w, dtype=float)
        K._cumulative(row, le)
        prev = 0.0
        for x in range(4):
            if x == le:
                continue
            P[le, x] = row[x] - prev
            prev = row[x]
        P[le, le] = 1.0 - prev
    return P


def _cases():
    rng = np.random.default_rng(5)
    out = [rng.uniform(0, 1, 4) for _ in range(300)]
    out += [rng.uniform(0, 1, 4) * np.array([6.0, 1, 1, 1]) for _ in range(100)]     # one heavy: bounce
    out += [np.where(rng.uniform(size=4) < 0.4, 0.0, rng.uniform(0.1, 1, 4)) for _ in range(200)]
    out += [np.array([1.0, 1.0, 1.0, 1.0]), np.array([2.0, 1.0, 1.0, 0.0]), np.array([3.0, 1.0, 1.0, 1.0]),
            np.array([8.5, 7.5, 1.4, 1.4]), np.array([1.0, 1.0, 0.0, 0.0]), np.array([0.5, 0.5, 0.5, 0.0])]
    return out


@pytest.mark.parametrize("w", _cases())
def test_exits_balance_normalise_and_bounce_least(w):
    w = np.asarray(w, dtype=float)
    if np.count_nonzero(w) == 0:
        return
    P = _probabilities(w)
    live = w > 0
    # probabilities of the reachable entrances: non-negative and normalised
    assert np.all(P[live] >= -1e-12) and np.allclose(P[live].sum(axis=1), 1.0, atol=1e-12)
    # detailed balance of the directed loops: w_x P(x -> y) = w_y P(y -> x)
    flow = w[:, None] * P
    assert np.allclose(flow[np.ix_(live, live)], flow[np.ix_(live, live)].T, atol=1e-12 * w.sum())
    # an exit of weight zero is never taken
    assert np.all(P[np.ix_(live, ~live)] == 0.0)
    # the least total bounce, max(0, W1 - W2 - W3 - W4), all of it at the heaviest configuration
    order = np.argsort(-w, kind="stable")
    excess = max(0.0, w[order[0]] - w[order[1:]].sum())
    bounce = np.diag(flow)[live]
    assert bounce.sum() == pytest.approx(excess, abs=1e-12 * w.sum())


def test_superfluid_diagonal_vertex_has_no_bounce():
    # a diagonal vertex entered with a change: heavy continue-exit and two hops; Metropolized Gibbs
    # bounced 18 % here
    P = _probabilities(np.array([8.5, 7.5, 1.4, 1.4]))
    assert P[0, 0] == pytest.approx(0.0, abs=1e-12)
    assert P[0, 1] > 0.7
