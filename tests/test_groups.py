"""Coset enumeration and PSL(2, r) arithmetic, checked against brute force."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from hyperlattice.errors import HyperlatticeError
from hyperlattice.graph import groups
from hyperlattice.graph.clusters import _map_from_darts

P = groups.parse_word


def _perms(table):
    """The permutations of the cosets by each generator (columns 0, 2, ...)."""
    return [table[:, 2 * i] for i in range(table.shape[1] // 2)]


def _satisfies(table, word) -> bool:
    c = np.arange(len(table))
    for g in word:
        c = table[c, g]
    return bool(np.all(c == np.arange(len(table))))


def _psl2_closure(gens, r):
    """Brute-force closure of matrices in PSL(2, r) (as canonical tuples): the group order."""
    def canon(m):
        m = tuple(v % r for v in m)
        neg = tuple((-v) % r for v in m)
        return min(m, neg)

    one = canon((1, 0, 0, 1))
    seen = {one}
    frontier = [one]
    while frontier:
        nxt = []
        for a in frontier:
            for g in gens:
                b = canon(groups._mul(a, g, r))
                if b not in seen:
                    seen.add(b)
                    nxt.append(b)
        frontier = nxt
    return len(seen)


def test_parse_word():
    assert P("x y X Y") == (0, 2, 1, 3)
    assert P("(x y)^3") == (0, 2) * 3
    assert P("x^2 (x Y)^2") == (0, 0, 0, 3, 0, 3)
    for bad in ("x z", "(x y", "x)", "x^", "x^0"):
        with pytest.raises(ValueError):
            P(bad)


# (name, relators, brute-force generators as permutations of range(n), order): the triangle
# groups (2,3,n) for n = 2..5 are S3, A4, S4, A5 (Coxeter & Moser, ch. 6)
_S4_X = [1, 0, 2, 3]               # (0 1)
_S4_Y = [0, 2, 3, 1]               # (1 2 3)
_A5_X = [1, 0, 3, 2, 4]            # (0 1)(2 3)
_A5_Y = [0, 2, 4, 3, 1]            # (1 2 4)
CASES = [
    ("S3", ["x^2", "y^3", "(x y)^2"], [[1, 0, 2], [1, 2, 0]], 6),
    ("A4", ["x^2", "y^3", "(x y)^3"], [[1, 0, 3, 2], [0, 2, 3, 1]], 12),
    ("S4", ["x^2", "y^3", "(x y)^4"], [_S4_X, _S4_Y], 24),
    ("A5", ["x^2", "y^3", "(x y)^5"], [_A5_X, _A5_Y], 60),
]


@pytest.mark.parametrize("name,rels,gens,order", CASES, ids=[c[0] for c in CASES])
def test_coset_enumeration_against_brute_force(name, rels, gens, order):
    words = [P(w) for w in rels]
    # the concrete generators satisfy the relators, so they generate a quotient of the group
    for w in words:
        perm = np.arange(len(gens[0]))
        for g in w:
            perm = np.asarray(gens[g // 2])[perm] if g % 2 == 0 else np.argsort(gens[g // 2])[perm]
        assert np.array_equal(perm, np.arange(len(gens[0])))
    assert groups.permutation_group_order(gens) == order
    table = groups.coset_table(2, words)
    assert len(table) == order
    assert all(_satisfies(table, w) for w in words)
    assert groups.permutation_group_order(_perms(table)) == order  # the regular representation
    # columns are permutations, inverse columns their inverses
    for g in range(4):
        assert sorted(table[:, g]) == list(range(order))
        assert np.array_equal(table[table[:, g], g ^ 1], np.arange(order))


def test_klein_presentation_is_psl27_by_brute_force():
    rels = [P(w) for w in ("x^2", "y^3", "(x y)^7", "(x Y x y)^4")]
    table = groups.coset_table(2, rels)
    x, y = groups.psl2_triple(7, 3, 7)
    assert len(table) == _psl2_closure([x, y], 7) == groups.psl2_order(7) == 168


def test_subgroup_index():
    rels = [P(w) for w in ("x^2", "y^3", "(x y)^7", "(x Y x y)^4")]
    assert len(groups.coset_table(2, rels, [P("y")])) == 168 // 3   # the 56 vertices of the Klein map
    assert len(groups.coset_table(2, rels, [P("x")])) == 168 // 2
    assert len(groups.coset_table(2, rels, [P("x y")])) == 168 // 7


def test_standard_form_does_not_depend_on_relator_order():
    rels = [P(w) for w in ("x^2", "y^3", "(x y)^4")]
    tables = [groups.coset_table(2, list(perm)) for perm in itertools.permutations(rels)]
    assert all(np.array_equal(tables[0], t) for t in tables[1:])


@pytest.mark.parametrize("rels,order", [
    (["y^3", "x^2", "x y x X x y"], 6),          # freely equal to (x y)^2
    (["y^3", "x^2", "(x X x y)^2"], 6),
    (["x^2", "y^3", "(x X x y)^4"], 24),
    (["x^2", "y^7", "(x y)^3", "(x Y X x x y)^4"], 168),
])
def test_unreduced_relators_regression(rels, order):
    # regression: a scan whose forward part ran past a shortened backward part compared with
    # the start coset instead of the backward one, and collapsed these groups to order 2 or 1
    assert len(groups.coset_table(2, [P(w) for w in rels])) == order


def test_infinite_index_gives_up():
    with pytest.raises(HyperlatticeError):
        groups.coset_table(2, groups.triangle_relators(7, 3), max_cosets=5000)


@pytest.mark.parametrize("r", [7, 13, 29])
def test_psl2_triple_orders_and_generation(r):
    x, y = groups.psl2_triple(7, 3, r)
    assert groups.psl2_element_order(x, r) == 2
    assert groups.psl2_element_order(y, r) == 3
    assert groups.psl2_element_order(groups._mul(x, y, r), r) == 7
    if r <= 13:
        assert _psl2_closure([x, y], r) == groups.psl2_order(r)


def test_psl2_no_triple():
    assert groups.psl2_triple(7, 3, 11) is None   # 7 divides none of 11, 5, 6
    assert groups.psl2_triple(8, 3, 13) is None


@pytest.mark.parametrize("r", [7, 13])
def test_psl2_dart_tables_are_matrix_products(r):
    x, y = groups.psl2_triple(7, 3, r)
    X, Y = groups.psl2_dart_tables(x, y, r)
    n = groups.psl2_order(r)
    # decode every index by brute force: enumerate PSL(2, r) in the documented index order
    elements = {}
    half = (r - 1) // 2
    for a in range(1, half + 1):
        for c in range(r):
            for b in range(r):
                d = (1 + b * c) * pow(a, -1, r) % r
                elements[((a - 1) * r + c) * r + b] = (a, b, c, d)
    for c in range(1, half + 1):
        for d in range(r):
            elements[half * r * r + (c - 1) * r + d] = (0, (-pow(c, -1, r)) % r, c, d)
    assert len(elements) == n
    index = {}
    for i, m in elements.items():
        index[m] = i
        index[tuple((-v) % r for v in m)] = i
    for i in range(0, n, max(1, n // 300)):
        assert X[i] == index[groups._mul(elements[i], x, r)]
        assert Y[i] == index[groups._mul(elements[i], y, r)]


@pytest.mark.parametrize("p,q,r", [(7, 3, 13), (7, 3, 29), (8, 3, 17), (3, 7, 13)])
def test_psl2_map_equals_dart_table_route(p, q, r):
    x, y = groups.psl2_triple(p, q, r)
    X, Y = groups.psl2_dart_tables(x, y, r)
    assert np.array_equal(groups.psl2_map(x, y, r, q), _map_from_darts(X, Y, p, q))
