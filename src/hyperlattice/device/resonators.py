r"""Resonator lattices with ports: the device a circuit-QED group fabricates and measures.

A device is a set of resonators on the sites of a graph of the package (a flake, a periodic
cluster, a user's adjacency matrix) or of its line graph (the coplanar-waveguide layout: resonator
k is the flake edge (i, j)), with the Hamiltonian (the package's sign, :math:`H = -tA`)

.. math::

    H = \sum_k \omega_k a_k^\dagger a_k - \sum_{\langle kl\rangle} J_{kl}(a_k^\dagger a_l + h.c.),

a uniform internal loss rate :math:`\kappa_{int}` on every resonator and ports p coupled to
resonators :math:`r_p` at rates :math:`\kappa_p` (energy decay rates into the line, full widths at
half maximum, in the units of :math:`\omega`: MHz, GHz, whatever the user works in; nothing here
assumes t = 1).

Resonators are named, not numbered: ``"i-j"`` is the line-graph resonator on the flake edge (i, j),
i < j in the paper's site order; ``"i"`` is the resonator on site i of a site graph. A coupling is
named by its two resonators, ``"i-j|k-l"`` or ``"i|j"`` (either order).

Fabrication disorder is drawn (Gaussian :math:`\sigma_\omega`, relative :math:`\sigma_J`, seeded)
and/or given explicitly by name; explicit values replace drawn ones.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..results import Result

__all__ = ["Device", "resonator_device", "graph_edges", "flat_band_degeneracy"]

#: largest device the package builds (resonators); the frequency sweeps have their own limits
MAX_RESONATORS = 5_000_000


def _source_adjacency(graph) -> tuple[sp.csr_matrix, np.ndarray | None, str]:
    """(A, parent edges of a line-graph Lattice or None, a description) of any graph of the package."""
    if getattr(type(graph), "__hyperlattice_lattice__", False) is True:
        from ..graph.operators import adjacency

        desc = f"{{{graph.p},{graph.q}}} flake of {graph.rings} rings"
        if graph.kind == "line_graph":
            return adjacency(graph), np.asarray(graph.parent_edges, np.int64), "line graph of the " + desc
        return adjacency(graph), None, desc
    if hasattr(graph, "genus") and hasattr(graph, "adjacency") and callable(graph.adjacency):
        return sp.csr_matrix(graph.adjacency(), dtype=float), None, f"{{{graph.p},{graph.q}}} cluster {graph.name}"
    if sp.issparse(graph) or isinstance(graph, np.ndarray):
        mat = sp.csr_matrix(graph)
        if mat.ndim != 2 or mat.shape[0] != mat.shape[1] or mat.shape[0] == 0:
            raise ValueError(f"an adjacency matrix must be square and non-empty, got shape {mat.shape}.")
        if mat.dtype.kind not in "biuf":
            raise ValueError(f"an adjacency matrix must hold real numbers, got {mat.dtype}.")
        mat = mat.astype(float)
        if mat.nnz and not np.all(np.isfinite(mat.data)):
            raise ValueError("the adjacency matrix holds NaN or infinite entries.")
        if mat.nnz and abs(mat - mat.T).max() > 0:
            raise ValueError("the adjacency matrix must be symmetric.")
        if mat.diagonal().any():
            raise ValueError("the adjacency matrix must have a zero diagonal (on-site frequencies are set "
                             "by omega0 and the disorder).")
        return mat, None, f"graph of {mat.shape[0]} sites"
    raise ValueError("the graph must be a Lattice (ring_lattice, line_graph), a Cluster (pbc_cluster) or a "
                     f"square adjacency matrix, got {type(graph).__name__}.")


def graph_edges(adjacency) -> np.ndarray:
    """The edges (i, j), i < j, of a symmetric adjacency matrix, sorted by i, then j.

    Parameters
    ----------
    adjacency : sparse matrix or ndarray
        A symmetric N x N adjacency matrix.

    Returns
    -------
    ndarray, shape (E, 2)
        int64 pairs with i < j.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import graph_edges
    >>> graph_edges(np.array([[0, 1, 1], [1, 0, 0], [1, 0, 0]])).tolist()
    [[0, 1], [0, 2]]
    """
    up = sp.coo_matrix(sp.triu(sp.csr_matrix(adjacency), k=1))
    keep = up.data != 0
    pairs = np.column_stack([up.row[keep], up.col[keep]]).astype(np.int64)
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))] if len(pairs) else pairs.reshape(0, 2)


def flat_band_degeneracy(edges, n_sites: int) -> int:
    r"""Multiplicity of the eigenvalue −2 of the line graph's adjacency :math:`A_L`.

    :math:`A_L = B^T B - 2` with B the unsigned site–edge incidence matrix, so the eigenvalue −2
    has multiplicity dim ker B: per connected component, edges − sites, plus one when the component
    is bipartite (Cvetković, Rowlinson, Simić, *Spectral generalizations of line graphs*, Thm 2.2.4).

    Parameters
    ----------
    edges : array_like, shape (E, 2)
        The edges (i, j) of the parent graph.
    n_sites : int
        Sites of the parent graph.

    Returns
    -------
    int
        The multiplicity of −2 in the spectrum of :math:`A_L`.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import flat_band_degeneracy
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> flat_band_degeneracy(lat.edges, lat.sites)      # 140 edges - 112 sites, not bipartite
    28
    """
    from scipy.sparse.csgraph import connected_components

    n = _validate.positive_int("n_sites", n_sites)
    e = np.asarray(edges)
    if e.ndim != 2 or e.shape[1] != 2 or e.dtype.kind not in "iu":
        raise ValueError(f"edges must be an integer array of shape (E, 2), got {_validate._shown(edges)}.")
    if e.size and (e.min() < 0 or e.max() >= n):
        raise ValueError(f"edges name sites outside 0..{n - 1}.")
    e = e.astype(np.int64)
    a = sp.coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n)).tocsr()
    ncomp, label = connected_components(a, directed=False)
    # bipartite test: 2-colour by BFS order, then check every edge
    colour = np.full(n, -1, np.int64)
    sym = (a + a.T).tocsr()
    from scipy.sparse.csgraph import breadth_first_order

    for c in range(ncomp):
        root = int(np.flatnonzero(label == c)[0])
        order, pred = breadth_first_order(sym, root, directed=False, return_predecessors=True)
        colour[root] = 0
        for v in order[1:]:
            colour[v] = 1 - colour[pred[v]]
    bad = colour[e[:, 0]] == colour[e[:, 1]]
    edges_c = np.bincount(label[e[:, 0]], minlength=ncomp)
    sites_c = np.bincount(label, minlength=ncomp)
    odd = np.bincount(label[e[:, 0]][bad], minlength=ncomp) > 0
    return int(np.sum(edges_c - sites_c + (~odd)))


@dataclass(frozen=True, eq=False, kw_only=True)
class Device(Result):
    r"""A resonator lattice with ports, as fabricated (ideal or disordered).

    Attributes
    ----------
    resonators : tuple of str
        Resonator names in the order of the matrices (``"i-j"`` line graph, ``"i"`` sites).
    omega : ndarray
        Resonator frequencies :math:`\omega_k` (the user's units).
    bonds : ndarray, shape (B, 2)
        Coupled resonator pairs (k, l), k < l, by position in ``resonators``.
    couplings : ndarray, shape (B,)
        :math:`J_{kl}` of each bond (:math:`H_{kl} = -J_{kl}`).
    kappa_int : float
        Internal loss rate of every resonator (FWHM).
    ports : tuple of str
        The resonator each port couples to, by name, in port order.
    port_index : ndarray
        Those resonators by position.
    port_kappa : ndarray
        :math:`\kappa_p` of each port (FWHM).
    line_graph : bool
        True when the resonators are the edges of a parent graph.
    flat_band : int or None
        With ``line_graph``: the multiplicity of the eigenvalue −2 of the line graph's adjacency.
    seed : int or None
        Seed of the drawn disorder (None: none drawn).
    description : str
        What the device is.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import resonator_device
    >>> dev = resonator_device(hl.ring_lattice(7, 3, 3), line_graph=True, omega0=7000.0, J=-66.0,
    ...                        kappa_int=0.7, ports={"0-1": 1.0, "110-111": 1.0})
    >>> dev.size, dev.flat_band, dev.ports
    (140, 28, ('0-1', '110-111'))
    """

    NOT_TABULAR: ClassVar[str] = "a device is a graph with couplings, not a table"

    resonators: tuple
    omega: np.ndarray
    bonds: np.ndarray
    couplings: np.ndarray
    kappa_int: float
    ports: tuple
    port_index: np.ndarray
    port_kappa: np.ndarray
    line_graph: bool = False
    flat_band: int | None = None
    seed: int | None = None
    description: str = ""

    @property
    def size(self) -> int:
        """Number of resonators."""
        return len(self.resonators)

    def hamiltonian(self) -> sp.csr_matrix:
        r"""H = diag(ω_k) − Σ J_kl (``|k⟩⟨l|`` + ``|l⟩⟨k|``), sparse, real symmetric (the user's units)."""
        n = self.size
        b = np.asarray(self.bonds, np.int64).reshape(-1, 2)
        j = np.asarray(self.couplings, float)
        rows = np.concatenate([b[:, 0], b[:, 1], np.arange(n)])
        cols = np.concatenate([b[:, 1], b[:, 0], np.arange(n)])
        vals = np.concatenate([-j, -j, np.asarray(self.omega, float)])
        return sp.csr_matrix((vals, (rows, cols)), shape=(n, n))



def _name_table(names) -> dict:
    return {nm: k for k, nm in enumerate(names)}


def _resonator(table: dict, key, what: str, line: bool) -> int:
    if isinstance(key, (bool, np.bool_)):
        raise ValueError(f"{what} must name a resonator, got {key!r}.")
    if isinstance(key, (int, np.integer)) and not line:
        key = str(int(key))
    if not isinstance(key, str):
        example = "'0-1'" if line else "'0'"
        raise ValueError(f"{what} must name a resonator (a string like {example}), got {_validate._shown(key)}.")
    k = key.strip()
    if line and "-" in k:
        a, _, b = k.partition("-")
        try:
            i, j = sorted((int(a), int(b)))
            k = f"{i}-{j}"
        except ValueError:
            pass
    if k not in table:
        form = "an edge 'i-j' of the parent graph" if line else "a site 'i'"
        raise ValueError(f"{what} {key!r} names no resonator of this device (a resonator is {form}).")
    return table[k]


def _ports(ports, table: dict, all_names: list, line: bool, shared: bool) -> tuple[list, np.ndarray, np.ndarray]:
    if isinstance(ports, dict):
        items = list(ports.items())
    elif isinstance(ports, (list, tuple)):
        items = []
        for p in ports:
            if not isinstance(p, (list, tuple)) or len(p) != 2:
                raise ValueError(f"each port must be a pair (resonator, kappa), got {_validate._shown(p)}.")
            items.append(tuple(p))
    else:
        raise ValueError(f"ports must map resonator names to kappa (a dict or a list of pairs), got "
                         f"{_validate._shown(ports)}.")
    if not items:
        raise ValueError("a device needs at least one port.")
    names, idx, kap = [], [], []
    for key, kappa in items:
        k = _resonator(table, key, "the port", line)
        kv = _validate.real(f"the kappa of port {key!r}", kappa)
        if not kv > 0:
            raise ValueError(f"the kappa of port {key!r} must be positive, got {kv:g}.")
        if k in idx and not shared:
            raise ValueError(f"two ports couple to resonator {key!r}; give each port its own resonator (or "
                             "shared_ports=True for one resonator with two lines).")
        names.append(all_names[k])
        idx.append(k)
        kap.append(kv)
    return names, np.asarray(idx, np.int64), np.asarray(kap, float)


def _coupling_key(table: dict, key, line: bool) -> tuple[int, int]:
    if not isinstance(key, str) or key.count("|") != 1:
        form = "'i-j|k-l'" if line else "'i|j'"
        raise ValueError(f"a coupling is named by its two resonators, {form}, got {_validate._shown(key)}.")
    a, b = key.split("|")
    ka = _resonator(table, a, "the coupling end", line)
    kb = _resonator(table, b, "the coupling end", line)
    return (ka, kb) if ka < kb else (kb, ka)


def _values(name: str, mapping) -> dict:
    if mapping is None:
        return {}
    if not isinstance(mapping, dict):
        raise ValueError(f"{name} must map resonator names to values (a dict), got {_validate._shown(mapping)}.")
    return mapping


def _layout(graph, line: bool, what: str = "a device") -> tuple:
    """(names, bonds (B, 2) k < l sorted, weights, flat-band count or None, description, line) of the nodes:
    the sites of ``graph``, or with ``line`` the edges of it (a line-graph Lattice is named by its parent edges)."""
    adj, parent, desc = _source_adjacency(graph)
    if line and parent is not None:
        raise ValueError("line_graph=True takes the parent graph; this Lattice is already a line graph.")
    if line:
        edges = graph_edges(adj)
        if adj.nnz and np.any(adj.data != 1):
            raise ValueError("a line graph needs a simple graph (adjacency entries 0 or 1).")
        n = len(edges)
        if n == 0:
            raise ValueError("the graph has no edges, so its line graph has no resonators.")
        if n > MAX_RESONATORS:
            raise ValueError(f"the line graph has {n:,} resonators, more than the {MAX_RESONATORS:,} {what} takes.")
        inc = sp.csr_matrix((np.ones(2 * n), (edges.ravel(), np.repeat(np.arange(n), 2))), shape=(adj.shape[0], n))
        al = sp.triu((inc.T @ inc).tocsr(), k=1).tocoo()
        bonds = np.column_stack([al.row, al.col]).astype(np.int64)
        weights = np.ones(len(bonds))
        names = [f"{i}-{j}" for i, j in edges]
        flat = flat_band_degeneracy(edges, adj.shape[0])
        desc = "line graph of the " + desc
    else:
        n = adj.shape[0]
        if n > MAX_RESONATORS:
            raise ValueError(f"the graph has {n:,} sites, more than the {MAX_RESONATORS:,} {what} takes.")
        up = sp.triu(adj, k=1).tocoo()
        bonds = np.column_stack([up.row, up.col]).astype(np.int64)
        weights = up.data.astype(float)
        if parent is not None:
            names = [f"{min(i, j)}-{max(i, j)}" for i, j in parent]
            line = True
            flat = flat_band_degeneracy(parent, int(parent.max()) + 1)
        else:
            names = [str(k) for k in range(n)]
            flat = None
    order = np.lexsort((bonds[:, 1], bonds[:, 0])) if len(bonds) else np.zeros(0, np.int64)
    bonds, weights = bonds[order].reshape(-1, 2), weights[order]
    return names, bonds, weights, flat, desc, line


def resonator_device(graph, *, line_graph: bool = False, omega0: float = 0.0, J: float = 1.0,
                     kappa_int: float = 0.0, ports=None, frequencies: dict | None = None,
                     hoppings: dict | None = None, sigma_omega: float = 0.0, sigma_J: float = 0.0,
                     seed: int | None = None, shared_ports: bool = False) -> Device:
    r"""Build a device: resonators on a graph (or its line graph), couplings, ports, disorder.

    Parameters
    ----------
    graph : Lattice, Cluster or adjacency matrix
        The sites (``line_graph=False``) or the parent graph whose edges are the resonators. A
        line-graph Lattice (:func:`hyperlattice.line_graph`) is taken as it is, named by its
        ``parent_edges``. Entries :math:`A_{kl}` of a matrix multiply J.
    line_graph : bool, optional
        Resonators on the edges of ``graph`` (the coplanar-waveguide layout); default False.
    omega0 : float, optional
        Bare resonator frequency; default 0 (user's units).
    J : float, optional
        Coupling; :math:`H_{kl} = -J` on every bond (J < 0 for capacitively coupled CPW resonators,
        whose band is then :math:`\omega_0 + |J| \cdot \mathrm{spec}(A)` flipped); default 1.
    kappa_int : float, optional
        Internal loss rate of every resonator (≥ 0, FWHM); default 0 (lossless).
    ports : dict or list of (name, kappa)
        Resonator name → port coupling rate κ_p > 0 (FWHM), in port order.
    frequencies : dict, optional
        Explicit ω_k by resonator name (replace drawn values).
    hoppings : dict, optional
        Explicit J_kl by coupling name ``"a|b"`` (the two resonators must be coupled).
    sigma_omega : float, optional
        Standard deviation of Gaussian frequency disorder (user's units); default 0.
    sigma_J : float, optional
        Relative standard deviation of the couplings (J_kl = J (1 + σ_J ξ)); default 0.
    seed : int, optional
        Seed of the drawn disorder (needed when a σ is non-zero).
    shared_ports : bool, optional
        Allow two ports on one resonator (input and output lines of a single resonator); default
        False, when ports overlapping on a resonator are taken for a mistake and refused.

    Returns
    -------
    Device

    Raises
    ------
    ValueError
        A port naming no resonator, κ ≤ 0 or NaN, two ports on one resonator, a key naming no
        resonator or coupling, a negative σ, a drawn disorder without seed.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import resonator_device
    >>> dev = resonator_device(hl.ring_lattice(7, 3, 1), omega0=5.0, J=0.1, kappa_int=0.01,
    ...                        ports=[("0", 0.05), ("3", 0.05)], frequencies={"2": 5.02})
    >>> dev.size, [round(float(w), 3) for w in dev.omega[:3]]
    (7, [5.0, 5.0, 5.02])
    >>> resonator_device(hl.ring_lattice(7, 3, 1), ports={"9": 1.0})
    Traceback (most recent call last):
    ...
    ValueError: the port '9' names no resonator of this device (a resonator is a site 'i').
    """
    line = _validate.flag("line_graph", line_graph)
    shared = _validate.flag("shared_ports", shared_ports)
    omega0 = _validate.real("omega0", omega0)
    J = _validate.real("J", J)
    kappa_int = _validate.real("kappa_int", kappa_int, minimum=0.0)
    sigma_omega = _validate.real("sigma_omega", sigma_omega, minimum=0.0)
    sigma_J = _validate.real("sigma_J", sigma_J, minimum=0.0)
    if seed is not None:
        seed = _validate.integer("seed", seed, minimum=0, maximum=2**63 - 1)
    if (sigma_omega > 0 or sigma_J > 0) and seed is None:
        raise ValueError("drawn disorder (sigma_omega or sigma_J > 0) needs a seed, so that the device can be "
                         "drawn again.")
    freq = _values("frequencies", frequencies)
    hop = _values("hoppings", hoppings)
    if ports is None:
        raise ValueError("a device needs at least one port (ports={name: kappa}).")

    names, bonds, weights, flat, desc, line = _layout(graph, line)
    n = len(names)
    table = _name_table(names)
    port_names, port_idx, port_kap = _ports(ports, table, names, line, shared)

    omega = np.full(n, omega0)
    coup = J * weights
    if seed is not None:
        rng = np.random.default_rng(seed)
        d_omega = rng.standard_normal(n)
        d_j = rng.standard_normal(len(bonds))
        omega = omega + sigma_omega * d_omega
        coup = coup * (1.0 + sigma_J * d_j)
    for key, val in freq.items():
        omega[_resonator(table, key, "the frequency key", line)] = _validate.real(f"the frequency of {key!r}", val)
    if hop:
        bond_pos = {(int(a), int(b)): k for k, (a, b) in enumerate(bonds)}
        for key, val in hop.items():
            pair = _coupling_key(table, key, line)
            if pair not in bond_pos:
                raise ValueError(f"the coupling key {key!r} names two resonators that are not coupled.")
            coup[bond_pos[pair]] = _validate.real(f"the coupling {key!r}", val)
    return Device(resonators=tuple(names), omega=omega, bonds=bonds, couplings=coup, kappa_int=kappa_int,
                  ports=tuple(port_names), port_index=port_idx, port_kappa=port_kap, line_graph=line,
                  flat_band=flat, seed=seed, description=desc)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
