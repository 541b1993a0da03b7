r"""Finite groups for periodic {p,q} clusters: coset enumeration and :math:`PSL(2, \mathbb F_r)`.

A periodic {p,q} cluster is the quotient of the {p,q} lattice by a torsion-free normal subgroup
N of the orientation-preserving triangle group

.. math:: \Delta(2, q, p) = \langle x, y \mid x^2 = y^q = (xy)^p = 1 \rangle ,

so it is described by the finite group :math:`G = \Delta / N` together with the images of x
and y. The *darts* (directed edges) of the cluster are the elements of G: y turns a dart
counterclockwise about its vertex, x reverses it, and xy walks around a face. This module
produces, for a finite quotient, the two permutations of the darts :math:`d \mapsto d x` and
:math:`d \mapsto d y` (the right-regular representation), by two independent routes:

* :func:`coset_table`: Todd–Coxeter coset enumeration (the HLT strategy with coincidence
  processing, following the textbook description in Holt, Eick & O'Brien, *Handbook of
  Computational Group Theory*, ch. 5) from a presentation with extra relators;
* :func:`psl2_dart_tables`: explicit matrices in :math:`PSL(2, \mathbb F_r)`, r an odd prime,
  for generating triples found from traces (Macbeath, *Generators of the linear fractional
  groups*, Proc. Symp. Pure Math. 12 (1969)); vectorised in numba, millions of darts per second.

Words are tuples of integers: generator i is ``2*i``, its inverse ``2*i + 1``; the triangle
group uses generator 0 = x, 1 = y (:func:`parse_word` reads ``"x y X Y"`` style strings,
capital = inverse).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .. import _validate
from ..errors import HyperlatticeError

__all__ = [
    "parse_word",
    "coset_table",
    "permutation_group_order",
    "triangle_relators",
    "psl2_order",
    "psl2_element_order",
    "psl2_triple",
    "psl2_dart_tables",
    "psl2_map",
    "is_prime",
]

#: coset enumeration refuses to define more cosets than this (a Python list per coset)
MAX_COSETS = 2_000_000
#: the most generators coset_table takes (the table has two columns per generator)
MAX_GENERATORS = 1000
#: the largest n is_prime tests (trial division: up to 10**6 divisions)
MAX_PRIME_TEST = 10**12


# ----------------------------------------------------------------------------
# words
# ----------------------------------------------------------------------------

def parse_word(text: str, letters: str = "xy") -> tuple[int, ...]:
    """A word such as ``"x y X Y"`` or ``"(x y)^7"`` as a tuple of generator codes.

    Lower-case letters are generators, upper-case their inverses; ``( ... )^n`` repeats a group
    (n >= 1). Spaces (and ``*``) are ignored. Generator i has code ``2*i``, its inverse
    ``2*i + 1``.

    Parameters
    ----------
    text : str
        The word.
    letters : str, optional
        The generator letters in order; default ``"xy"``.

    Returns
    -------
    tuple of int
        The generator codes.

    Raises
    ------
    ValueError
        For an unknown letter, unbalanced parentheses or a bad exponent.

    See Also
    --------
    coset_table

    Examples
    --------
    >>> from hyperlattice.graph.groups import parse_word
    >>> parse_word("x y X Y"), parse_word("(x y)^3")
    ((0, 2, 1, 3), (0, 2, 0, 2, 0, 2))
    """
    if not isinstance(text, str):
        raise ValueError(f"a word must be a string such as 'x y X Y', got {type(text).__name__}.")
    s = text.replace(" ", "").replace("*", "")
    pos = 0

    def group() -> list[int]:
        nonlocal pos
        out: list[int] = []
        while pos < len(s) and s[pos] != ")":
            ch = s[pos]
            if ch == "(":
                pos += 1
                inner = group()
                if pos >= len(s) or s[pos] != ")":
                    raise ValueError(f"unbalanced parentheses in the word {text!r}.")
                pos += 1
                out.extend(inner * _exponent())
            elif ch.lower() in letters:
                pos += 1
                code = 2 * letters.index(ch.lower()) + (1 if ch.isupper() else 0)
                out.extend([code] * _exponent())
            else:
                raise ValueError(f"unknown letter {ch!r} in the word {text!r} (use {letters} and capitals).")
        return out

    def _exponent() -> int:
        nonlocal pos
        if pos < len(s) and s[pos] == "^":
            pos += 1
            start = pos
            while pos < len(s) and s[pos].isdigit():
                pos += 1
            if start == pos:
                raise ValueError(f"an exponent ^ needs a positive integer in the word {text!r}.")
            n = int(s[start:pos])
            if n < 1:
                raise ValueError(f"exponents must be positive in the word {text!r}.")
            return n
        return 1

    word = group()
    if pos != len(s):
        raise ValueError(f"unbalanced parentheses in the word {text!r}.")
    return tuple(word)


def triangle_relators(p: int, q: int) -> list[tuple[int, ...]]:
    """The relators :math:`x^2, y^q, (xy)^p` of the triangle group Δ(2, q, p).

    p and q are at most :data:`MAX_COSETS`: a relator longer than the coset limit can never
    close a scan of :func:`coset_table` (and 10**140 letters do not fit in memory).

    Parameters
    ----------
    p, q : int
        Orders of xy and y, 2 to 2,000,000.

    Returns
    -------
    list of tuple of int
        The three relators as words (x = 0, y = 2).

    Raises
    ------
    ValueError
        If p or q is out of range.

    See Also
    --------
    coset_table

    Examples
    --------
    >>> from hyperlattice.graph.groups import triangle_relators
    >>> triangle_relators(4, 3)
    [(0, 0), (2, 2, 2), (0, 2, 0, 2, 0, 2, 0, 2)]
    """
    p = _validate.integer("p", p, minimum=2, maximum=MAX_COSETS)
    q = _validate.integer("q", q, minimum=2, maximum=MAX_COSETS)
    return [(0, 0), (2,) * q, (0, 2) * p]


# ----------------------------------------------------------------------------
# Todd–Coxeter
# ----------------------------------------------------------------------------

def coset_table(n_generators: int, relators, subgroup=(), *, max_cosets: int = MAX_COSETS) -> np.ndarray:
    r"""Coset table of the subgroup H generated by ``subgroup`` in the finitely presented group.

    HLT strategy: each live coset in turn is scanned under every relator (and coset 0 under
    the subgroup generators), defining new cosets to complete each scan; a scan that closes
    with two different cosets records a coincidence, processed with a union-find queue.

    Parameters
    ----------
    n_generators : int
        Number of generators of the group (at most 1000).
    relators : sequence of words
        Words (tuples of generator codes, see the module docstring) equal to the identity.
    subgroup : sequence of words, optional
        Generators of H (empty, the default: the trivial subgroup, so the table is the regular
        representation of the group).
    max_cosets : int, optional
        Give up (:class:`~hyperlattice.errors.HyperlatticeError`) when more cosets than this
        are alive at once; the index may be infinite, or merely large. Default 2,000,000.

    Returns
    -------
    numpy.ndarray of int64, shape (index, 2 * n_generators)
        ``table[c, 2*i]`` is the coset :math:`c\, g_i`, ``table[c, 2*i+1]`` the coset
        :math:`c\, g_i^{-1}`; coset 0 is H itself and cosets are numbered in the order a
        breadth-first walk over the columns first meets them (a standard form, so two
        enumerations of the same action give identical tables).

    Raises
    ------
    ValueError
        For invalid words or arguments.
    HyperlatticeError
        When more than ``max_cosets`` cosets are alive at once.

    See Also
    --------
    parse_word, triangle_relators, hyperlattice.graph.clusters.cluster_from_relators

    References
    ----------
    .. [1] D. F. Holt, B. Eick and E. A. O'Brien, *Handbook of Computational Group Theory*
       (Chapman & Hall/CRC, 2005), ch. 5.

    Examples
    --------
    >>> from hyperlattice.graph.groups import coset_table, parse_word, triangle_relators
    >>> coset_table(2, triangle_relators(3, 3)).shape      # the tetrahedral group A4
    (12, 4)
    >>> coset_table(2, triangle_relators(7, 3) + [parse_word("(x y x Y)^4")]).shape   # Klein quartic
    (168, 4)
    """
    ngen = _validate.positive_int("n_generators", n_generators, maximum=MAX_GENERATORS)
    max_cosets = _validate.positive_int("max_cosets", max_cosets)
    ncol = 2 * ngen
    rels = [_checked_word("relator", w, ncol) for w in _sequence("relators", relators)]
    subs = [_checked_word("subgroup generator", w, ncol) for w in _sequence("subgroup", subgroup)]
    # free cancellation does not change the group; empty relators are dropped
    rels = [w for w in rels if w]
    table: list[list[int]] = [[-1] * ncol]
    parent = [0]
    live = [1]
    state = {"alive": 1}

    def rep(c: int) -> int:
        root = c
        while parent[root] != root:
            root = parent[root]
        while parent[c] != root:  # path compression
            parent[c], c = root, parent[c]
        return root

    def define(c: int, g: int) -> None:
        if state["alive"] >= max_cosets:
            raise HyperlatticeError(f"coset enumeration gave up after {max_cosets:,} live cosets "
                                    "(the index is infinite or larger than max_cosets).")
        n = len(table)
        table.append([-1] * ncol)
        parent.append(n)
        live.append(1)
        state["alive"] += 1
        table[c][g] = n
        table[n][g ^ 1] = c

    def merge(a: int, b: int, queue: list) -> None:
        a, b = rep(a), rep(b)
        if a != b:
            lo, hi = min(a, b), max(a, b)
            parent[hi] = lo
            queue.append(hi)

    def coincidence(a: int, b: int) -> None:
        queue: list[int] = []
        merge(a, b, queue)
        i = 0
        while i < len(queue):
            dead = queue[i]
            i += 1
            live[dead] = 0
            state["alive"] -= 1
            row = table[dead]
            for g in range(ncol):
                d = row[g]
                if d < 0:
                    continue
                table[d][g ^ 1] = -1
                mu, nu = rep(dead), rep(d)
                if table[mu][g] >= 0:
                    merge(nu, table[mu][g], queue)
                elif table[nu][g ^ 1] >= 0:
                    merge(mu, table[nu][g ^ 1], queue)
                else:
                    table[mu][g] = nu
                    table[nu][g ^ 1] = mu

    def scan_and_fill(c: int, word) -> None:
        n = len(word)
        f, i = c, 0
        b, j = c, n - 1
        while True:
            while i <= j and table[f][word[i]] >= 0:
                f = table[f][word[i]]
                i += 1
            if i > j:  # the scans met: f and b (= c until a backward scan ran) must agree
                if f != b:
                    coincidence(f, b)
                return
            while j >= i and table[b][word[j] ^ 1] >= 0:
                b = table[b][word[j] ^ 1]
                j -= 1
            if j < i:
                coincidence(f, b)
                return
            if i == j:  # a deduction closes the scan
                table[f][word[i]] = b
                table[b][word[i] ^ 1] = f
                return
            define(f, word[i])

    for w in subs:
        scan_and_fill(0, w)
    c = 0
    while c < len(table):
        if live[c]:
            for w in rels:
                scan_and_fill(c, w)
                if not live[c]:
                    break
            if live[c]:
                for g in range(ncol):
                    if table[c][g] < 0:
                        define(c, g)
        c += 1
    return _standardize([i for i in range(len(table)) if live[i]], table, rep, ncol)


def _sequence(name: str, value) -> list:
    if isinstance(value, str):
        return [value]
    try:
        return list(value)
    except TypeError:
        raise ValueError(f"{name} must be a list of words, got {type(value).__name__}.") from None


def _checked_word(what: str, w, ncol: int) -> tuple[int, ...]:
    if isinstance(w, str):
        w = parse_word(w)
    try:
        t = tuple(_validate.integer(what, g) for g in w)
    except (TypeError, ValueError):
        raise ValueError(f"a {what} must be a word (a sequence of generator codes).") from None
    if any(g < 0 or g >= ncol for g in t):
        raise ValueError(f"a {what} uses a generator code outside 0..{ncol - 1}.")
    return t


def _standardize(alive: list[int], table, rep, ncol: int) -> np.ndarray:
    """Renumber live cosets in breadth-first order from coset 0 (a canonical form)."""
    order = {0: 0}
    queue = [0]
    k = 0
    while k < len(queue):
        c = queue[k]
        k += 1
        for g in range(ncol):
            d = rep(table[c][g])
            if d not in order:
                order[d] = len(queue)
                queue.append(d)
    if len(order) != len(alive):  # pragma: no cover - a complete table is connected
        raise HyperlatticeError("coset enumeration ended with an incomplete table.")
    out = np.empty((len(queue), ncol), dtype=np.int64)
    for c in queue:
        out[order[c]] = [order[rep(table[c][g])] for g in range(ncol)]
    return out


def permutation_group_order(generators) -> int:
    """Order of the group generated by permutations (arrays of images), by brute-force closure.

    Used to check coset enumeration; costs memory proportional to the order times the degree.

    Parameters
    ----------
    generators : sequence of sequence of int
        Permutations of ``range(n)`` as arrays of images, all of the same n.

    Returns
    -------
    int
        The order of the generated group.

    Raises
    ------
    ValueError
        If the generators are not permutations of one ``range(n)``.

    See Also
    --------
    coset_table

    Examples
    --------
    >>> from hyperlattice.graph.groups import permutation_group_order
    >>> permutation_group_order([[1, 0, 2], [0, 2, 1]])   # S3
    6
    """
    try:
        gens = [tuple(_validate.integer("a permutation entry", i, minimum=0) for i in g) for g in generators]
    except TypeError:
        raise ValueError("generators must be a list of permutations (sequences of images).") from None
    if not gens or any(sorted(g) != list(range(len(gens[0]))) for g in gens):
        raise ValueError("generators must be permutations of range(n), all of the same n.")
    n = len(gens[0])
    identity = tuple(range(n))
    seen = {identity}
    frontier = [identity]
    while frontier:
        nxt = []
        for a in frontier:
            for g in gens:
                b = tuple(g[i] for i in a)  # a then g
                if b not in seen:
                    seen.add(b)
                    nxt.append(b)
        frontier = nxt
    return len(seen)


# ----------------------------------------------------------------------------
# PSL(2, F_r), r an odd prime
# ----------------------------------------------------------------------------

def is_prime(n: int) -> bool:
    """Trial division (n is at most a few thousand here; at most :data:`MAX_PRIME_TEST`).

    Parameters
    ----------
    n : int
        The number, at most 10**12.

    Returns
    -------
    bool
        Whether n is a prime (False for n < 2).

    Raises
    ------
    ValueError
        If n is not an integer or exceeds 10**12.

    Examples
    --------
    >>> from hyperlattice.graph.groups import is_prime
    >>> is_prime(97), is_prime(91)
    (True, False)
    """
    # an integer at the door: inf or NaN would loop forever in the trial division below
    n = _validate.integer("n", n, maximum=MAX_PRIME_TEST)
    if n < 2:
        return False
    if n % 2 == 0:
        return n == 2
    k = 3
    while k * k <= n:
        if n % k == 0:
            return False
        k += 2
    return True


def psl2_order(r: int) -> int:
    r""":math:`|PSL(2, \mathbb F_r)| = r(r^2 - 1)/2` for an odd prime r.

    Parameters
    ----------
    r : int
        An odd prime (any integer >= 2 is accepted and put into the formula).

    Returns
    -------
    int
        The group order.

    Raises
    ------
    ValueError
        If r is not an integer >= 2.

    Examples
    --------
    >>> from hyperlattice.graph.groups import psl2_order
    >>> psl2_order(7)
    168
    """
    r = _validate.integer("r", r, minimum=2)
    return r * (r * r - 1) // 2


def _mul(a, b, r):
    return ((a[0] * b[0] + a[1] * b[2]) % r, (a[0] * b[1] + a[1] * b[3]) % r,
            (a[2] * b[0] + a[3] * b[2]) % r, (a[2] * b[1] + a[3] * b[3]) % r)


def psl2_element_order(m, r: int) -> int:
    r"""Order in PSL(2, r) of the matrix ``m = (a, b, c, d)`` (of determinant 1): m^k = ±1.

    Parameters
    ----------
    m : sequence of 4 int
        The matrix :math:`\begin{pmatrix} a & b\\ c & d\end{pmatrix}` with
        :math:`ad - bc = 1 \bmod r`.
    r : int
        An odd prime.

    Returns
    -------
    int
        The smallest k >= 1 with :math:`m^k = \pm 1`.

    Raises
    ------
    ValueError
        If r is not an odd prime or m is not a determinant-1 matrix of integers.
    HyperlatticeError
        If no order up to r + 1 is found (not expected for a matrix of SL(2)).

    Examples
    --------
    >>> from hyperlattice.graph.groups import psl2_element_order
    >>> psl2_element_order((0, 1, 6, 0), 7)
    2
    """
    r = _psl2_check_prime(r)
    try:
        m = tuple(_validate.integer("a matrix entry", v) % r for v in m)
    except TypeError:
        raise ValueError("m must be a matrix (a, b, c, d) of integers.") from None
    if len(m) != 4 or (m[0] * m[3] - m[1] * m[2]) % r != 1:
        raise ValueError(f"m must be (a, b, c, d) with ad - bc = 1 mod {r}.")
    one, minus = (1, 0, 0, 1), (r - 1, 0, 0, r - 1)
    acc = m
    for k in range(1, r + 2):
        if acc == one or acc == minus:
            return k
        acc = _mul(acc, m, r)
    raise HyperlatticeError(f"no element of PSL(2,{r}) has order above {r + 1}; the matrix is not in SL(2).")


def _power(m, k: int, r: int):
    out = (1, 0, 0, 1)
    while k:
        if k & 1:
            out = _mul(out, m, r)
        m = _mul(m, m, r)
        k >>= 1
    return out


def _is_pm_one(m, r: int) -> bool:
    return m[1] == 0 and m[2] == 0 and (m[0] == m[3] == 1 or m[0] == m[3] == r - 1)


def _has_order(m, n: int, r: int) -> bool:
    """Whether m has order exactly n in PSL(2, r) (m^n = ±1, m^(n/l) != ±1 for primes l | n)."""
    if not _is_pm_one(_power(m, n, r), r):
        return False
    primes = [l for l in range(2, n + 1) if n % l == 0 and is_prime(l)]
    return not any(_is_pm_one(_power(m, n // l, r), r) for l in primes)


def _traces_of_order(n: int, r: int) -> list[int]:
    """Traces t in 0..r-1 of the elements of order n in PSL(2, r) (companion matrices).

    The order of a non-identity element of SL(2, r) depends only on its trace, except for
    t = ±2, where the companion matrix is unipotent (order r).
    """
    return [t for t in range(r) if _has_order((0, r - 1, 1, t), n, r)]


def psl2_triple(p: int, q: int, r: int):
    r"""Matrices x, y in SL(2, r) whose images in PSL(2, r) have orders 2, q, and p for xy.

    The trace of x is 0 (order 2), the trace of y the smallest t in 0..r-1 whose elements
    have order q, the trace of xy the smallest one of order p. Such a triple exists for any
    traces (Macbeath 1969); it generates PSL(2, r) unless it lies in a Borel subgroup
    (:math:`\mathrm{tr}[x, y] = 2`, refused here) or in one of the small exceptional subgroups
    A4, S4, A5 (only possible when p, q <= 5; the caller checks that the cluster is connected).

    Parameters
    ----------
    p, q : int
        Orders of xy and y, 2 to 10,000.
    r : int
        An odd prime.

    Returns
    -------
    tuple of two tuples (a, b, c, d), or None
        (x, y), or None when PSL(2, r) has no elements of order p or q (or only a reducible
        pair).

    Raises
    ------
    ValueError
        If p, q are out of range or r is not an odd prime.

    See Also
    --------
    psl2_map, hyperlattice.graph.clusters.psl2_cluster

    References
    ----------
    .. [1] A. M. Macbeath, "Generators of the linear fractional groups", Proc. Symp. Pure
       Math. 12 (1969).

    Examples
    --------
    >>> from hyperlattice.graph.groups import psl2_triple
    >>> psl2_triple(7, 3, 7)
    ((0, 1, 6, 0), (0, 6, 1, 1))
    """
    p = _validate.integer("p", p, minimum=2, maximum=10_000)
    q = _validate.integer("q", q, minimum=2, maximum=10_000)
    r = _psl2_check_prime(r)
    ty = _traces_of_order(q, r)
    tz = _traces_of_order(p, r)
    if not ty or not tz:
        return None
    ty, tz = ty[0], tz[0]
    # tr[x, y] = tr(x)^2 + tr(y)^2 + tr(xy)^2 - tr x tr y tr xy - 2 (Fricke); = 2 means reducible
    if (ty * ty + tz * tz - 2) % r == 2 % r:
        return None
    # x = [[0, 1], [-1, 0]]; y = [[a, b], [c, d]] with a + d = ty, det 1 and tr(xy) = c - b = tz
    x = (0, 1, r - 1, 0)
    for a in range(r):
        d = (ty - a) % r
        # b (b + tz) = a d - 1: a quadratic in b with discriminant tz^2 + 4 (a d - 1)
        disc = (tz * tz + 4 * (a * d - 1)) % r
        root = _sqrt_mod(disc, r)
        if root is None:
            continue
        b = ((-tz + root) * pow(2, -1, r)) % r
        c = (b + tz) % r
        y = (a, b, c, d)
        if (a * d - b * c) % r != 1:  # pragma: no cover - guaranteed by construction
            continue
        if _has_order(y, q, r) and _has_order(_mul(x, y, r), p, r):
            return x, y
    return None


def _sqrt_mod(a: int, r: int) -> int | None:
    a %= r
    if a == 0:
        return 0
    if pow(a, (r - 1) // 2, r) != 1:
        return None
    for s in range(1, r):  # r is at most a few thousand; a table would be no faster to write
        if s * s % r == a:
            return s
    return None  # pragma: no cover


def _inverses(r: int) -> np.ndarray:
    inv = np.zeros(r, dtype=np.int64)
    for a in range(1, r):
        inv[a] = pow(a, -1, r)
    return inv


def psl2_dart_tables(x, y, r: int) -> tuple[np.ndarray, np.ndarray]:
    r"""Right multiplication by x and by y on all of :math:`PSL(2, \mathbb F_r)` (darts).

    Elements are indexed by a bijection with ``range(r (r^2-1)/2)``: the sign of
    :math:`\pm\begin{pmatrix} a & b\\ c & d\end{pmatrix}` is fixed by making the first non-zero
    entry of the first column at most (r-1)/2; then the index is
    :math:`((a-1) r + c) r + b` when a != 0 (d follows from the determinant) and
    :math:`\tfrac{r-1}{2} r^2 + (c-1) r + d` when a = 0 (then b = -1/c).

    Parameters
    ----------
    x, y : sequence of 4 int
        Matrices (a, b, c, d) of SL(2, r), e.g. from :func:`psl2_triple`.
    r : int
        An odd prime.

    Returns
    -------
    X, Y : numpy.ndarray of int32, shape (r (r^2 - 1)/2,)
        ``X[i]`` the index of element i times x, ``Y[i]`` of element i times y.

    Raises
    ------
    ValueError
        If r is not an odd prime or x, y are not determinant-1 matrices.

    See Also
    --------
    psl2_map

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.graph.groups import psl2_dart_tables, psl2_triple
    >>> x, y = psl2_triple(7, 3, 7)
    >>> X, Y = psl2_dart_tables(x, y, 7)
    >>> X.shape, bool(np.array_equal(X[X], np.arange(168)))     # x has order 2
    ((168,), True)
    """
    r = _psl2_check_prime(r)
    x, y = _matrix("x", x, r), _matrix("y", y, r)
    n = _dart_count(r)
    X = np.empty(n, dtype=np.int32)
    Y = np.empty(n, dtype=np.int32)
    _kernels()["psl2_tables"](np.int64(r), _inverses(r), _mul_tables(r, x, y, _mul(x, y, r)), X, Y)
    return X, Y


def psl2_map(x, y, r: int, q: int) -> np.ndarray:
    r"""Neighbour table (rotation system) of the map of :math:`PSL(2, \mathbb F_r)` directly.

    The same table, numbered the same way, as the dart tables of :func:`psl2_dart_tables` fed
    to the generic builder (a vertex is numbered by the rank of its smallest dart), but without
    the dart tables: the smallest dart of a vertex is found by multiplying matrices, so the
    only scattered memory access is one look-up of a vertex number per neighbour. Runs in
    parallel (numba threads).

    Parameters
    ----------
    x, y : sequence of 4 int
        Matrices (a, b, c, d) of SL(2, r), e.g. from :func:`psl2_triple`.
    r : int
        An odd prime.
    q : int
        Order of y (the coordination number), 2 to 10,000.

    Returns
    -------
    numpy.ndarray of int32, shape (r (r^2 - 1)/(2q), q)
        ``nb[v, j]`` is the head of the dart :math:`d_v y^j`, :math:`d_v` the smallest dart of
        vertex v.

    Raises
    ------
    ValueError
        If r is not an odd prime, x, y are not determinant-1 matrices, or q is out of range.

    See Also
    --------
    psl2_dart_tables, hyperlattice.graph.clusters.psl2_cluster

    Examples
    --------
    >>> from hyperlattice.graph.groups import psl2_map, psl2_triple
    >>> x, y = psl2_triple(7, 3, 7)
    >>> psl2_map(x, y, 7, 3).shape     # the Klein quartic's 56 sites
    (56, 3)
    """
    r = _psl2_check_prime(r)
    x, y = _matrix("x", x, r), _matrix("y", y, r)
    q = _validate.integer("q", q, minimum=2, maximum=10_000)
    n = _dart_count(r)
    k = _kernels()
    inv = _inverses(r)
    T = _mul_tables(r, x, y, _mul(x, y, r))
    vmask = np.empty(n, dtype=np.uint8)
    k["psl2_mask"](np.int64(r), inv, T, q, vmask)
    vreps = np.flatnonzero(vmask).astype(np.int64)
    # the number of a vertex is the rank of its smallest dart among all smallest darts: a bit
    # array with a running count per 64-bit word (n/8 + n/16 bytes) instead of an int32 table
    # (4 n bytes), so that the look-ups, scattered all over, mostly hit the cache
    bits = np.packbits(vmask, bitorder="little")
    del vmask
    words = np.zeros((len(bits) + 7) // 8, dtype=np.uint64)
    words.view(np.uint8)[: len(bits)] = bits
    del bits
    before = np.zeros(len(words), dtype=np.int64)
    np.cumsum(np.bitwise_count(words)[:-1], out=before[1:])
    nb = np.empty((len(vreps), q), dtype=np.int32)
    k["psl2_fill"](np.int64(r), inv, T, q, vreps, words, before, nb)
    return nb


def _mul_tables(r: int, *mats) -> np.ndarray:
    """``T[g, k, a] = a * mats[g][k] mod r``: a product by a fixed matrix becomes table look-ups
    and conditional subtractions (integer division is the slowest instruction in the loop)."""
    a = np.arange(r, dtype=np.int64)
    return np.array([[a * int(m[k]) % r for k in range(4)] for m in mats], dtype=np.int32)


@functools.lru_cache(maxsize=None)
def _kernels() -> dict:
    """numba kernels, compiled on first use (never at import) and cached on disk.

    The small helpers become module globals (not closure variables), so that numba can cache
    the kernels that call them.
    """
    import numba

    global _k_neg, _k_encode, _k_decode, _k_addmod, _k_mul, _k_vertex_min, _k_is_orbit_min, _k_rank

    @numba.njit(cache=True, inline="always")
    def _k_neg(v, r):
        return r - v if v else 0

    @numba.njit(cache=True, inline="always")
    def _k_encode(a, b, c, d, r, half, base):
        if a != 0:
            if a > half:
                a, b, c = r - a, _k_neg(b, r), _k_neg(c, r)
            return ((a - 1) * r + c) * r + b
        if c > half:
            c, d = r - c, _k_neg(d, r)
        return base + (c - 1) * r + d

    @numba.njit(cache=True, inline="always")
    def _k_decode(i, r, half, base, inv):
        rr = r * r
        if i < base:
            a = i // rr + 1
            rem = i - (a - 1) * rr
            c = rem // r
            b = rem - c * r
            d = ((1 + b * c) % r) * inv[a] % r
        else:
            j = i - base
            c = j // r + 1
            d = j - (c - 1) * r
            a = 0
            b = _k_neg(inv[c], r)
        return a, b, c, d

    @numba.njit(cache=True, inline="always")
    def _k_addmod(u, v, r):
        s = u + v
        return s - r if s >= r else s

    @numba.njit(cache=True, inline="always")
    def _k_mul(a, b, c, d, T, g, r):
        # (a b; c d) times the generator g, whose entries' multiples are tabulated in T[g]
        return (_k_addmod(T[g, 0, a], T[g, 2, b], r), _k_addmod(T[g, 1, a], T[g, 3, b], r),
                _k_addmod(T[g, 0, c], T[g, 2, d], r), _k_addmod(T[g, 1, c], T[g, 3, d], r))

    @numba.njit(cache=True, parallel=True)
    def psl2_tables(r, inv, T, X, Y):
        half = (r - 1) // 2
        base = half * r * r
        for i in numba.prange(X.shape[0]):
            a, b, c, d = _k_decode(i, r, half, base, inv)
            a1, b1, c1, d1 = _k_mul(a, b, c, d, T, 0, r)
            X[i] = _k_encode(a1, b1, c1, d1, r, half, base)
            a1, b1, c1, d1 = _k_mul(a, b, c, d, T, 1, r)
            Y[i] = _k_encode(a1, b1, c1, d1, r, half, base)

    @numba.njit(cache=True, inline="always")
    def _k_vertex_min(a, b, c, d, T, q, r, half, base):
        m = _k_encode(a, b, c, d, r, half, base)
        for _ in range(q - 1):
            a, b, c, d = _k_mul(a, b, c, d, T, 1, r)
            e = _k_encode(a, b, c, d, r, half, base)
            if e < m:
                m = e
        return m

    @numba.njit(cache=True, inline="always")
    def _k_is_orbit_min(i, a, b, c, d, T, g, length, r, half, base):
        # stop at the first smaller dart of the orbit
        for _ in range(length - 1):
            a, b, c, d = _k_mul(a, b, c, d, T, g, r)
            if _k_encode(a, b, c, d, r, half, base) < i:
                return 0
        return 1

    @numba.njit(cache=True, parallel=True)
    def psl2_mask(r, inv, T, q, vmask):
        half = (r - 1) // 2
        base = half * r * r
        for i in numba.prange(vmask.shape[0]):
            a, b, c, d = _k_decode(i, r, half, base, inv)
            vmask[i] = _k_is_orbit_min(i, a, b, c, d, T, 1, q, r, half, base)

    @numba.njit(cache=True, inline="always")
    def _k_rank(m, words, before):
        w = words[m >> 6]
        x = w & ((np.uint64(1) << np.uint64(m & 63)) - np.uint64(1))
        # population count of x (the set bits below m in its word)
        x = x - ((x >> np.uint64(1)) & np.uint64(0x5555555555555555))
        x = (x & np.uint64(0x3333333333333333)) + ((x >> np.uint64(2)) & np.uint64(0x3333333333333333))
        x = (x + (x >> np.uint64(4))) & np.uint64(0x0F0F0F0F0F0F0F0F)
        x = (x * np.uint64(0x0101010101010101)) >> np.uint64(56)
        return before[m >> 6] + np.int64(x)

    @numba.njit(cache=True, parallel=True)
    def psl2_fill(r, inv, T, q, vreps, words, before, nb):
        half = (r - 1) // 2
        base = half * r * r
        for v in numba.prange(vreps.shape[0]):
            a, b, c, d = _k_decode(vreps[v], r, half, base, inv)
            for j in range(q):
                a1, b1, c1, d1 = _k_mul(a, b, c, d, T, 0, r)
                nb[v, j] = _k_rank(_k_vertex_min(a1, b1, c1, d1, T, q, r, half, base), words, before)
                a, b, c, d = _k_mul(a, b, c, d, T, 1, r)

    return {"psl2_tables": psl2_tables, "psl2_mask": psl2_mask, "psl2_fill": psl2_fill}


def _dart_count(r: int) -> int:
    n = psl2_order(r)
    if n >= 2**31:  # darts are numbered with int32 (and memory is checked by the callers)
        raise ValueError(f"PSL(2,{r}) has {n:,} elements; at most 2**31 - 1 darts are supported.")
    return n


def _matrix(name: str, m, r: int) -> tuple[int, int, int, int]:
    try:
        t = tuple(_validate.integer(f"an entry of {name}", v) % r for v in m)
    except TypeError:
        raise ValueError(f"{name} must be a matrix (a, b, c, d) of integers.") from None
    if len(t) != 4 or (t[0] * t[3] - t[1] * t[2]) % r != 1:
        raise ValueError(f"{name} must be (a, b, c, d) with ad - bc = 1 mod {r}.")
    return t


def _psl2_check_prime(r) -> int:
    r = _validate.integer("r", r, minimum=3, maximum=100_000)
    if not is_prime(r):
        raise ValueError(f"r must be an odd prime, got {r}.")
    if math.prod((r, r, r)) > 2**62:  # pragma: no cover - far beyond memory anyway
        raise ValueError(f"r = {r} is too large.")
    return r


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
