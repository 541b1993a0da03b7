r"""Frames of the two-orbital (QWZ) model on closed surfaces, and which Chern invariants depend on them.

The QWZ hop :math:`T(\theta) = \tfrac12[\sigma_z + i(\cos\theta\,\sigma_x + \sin\theta\,\sigma_y)] =
U(\theta)\,T_0\,U(\theta)^\dagger`, :math:`U(\theta) = e^{-i\theta\sigma_z/2}`, :math:`T_0 = T(0)`, needs the
angle of every bond in one frame. On a curved closed surface no global frame exists (a vector
field has zeros, Poincaré–Hopf), so a frame is a choice, and two are offered here.

* ``"lift"``: the bond angles of :func:`~hyperlattice.topology.models.cluster_angles` (chord
  angles of a breadth-first lift of the cluster into the Poincaré disk, the frame of
  :func:`~hyperlattice.topology.surfaces.cluster_chern`). The edges off the spanning tree take the
  angle seen from one end; the result depends on the labelling of the sites (the root and the
  tree), i.e. it is not invariant under the cluster's automorphisms.
* ``"covariant"``: the rotation system gives every site its own tangent frame (slot s of site i
  points at angle :math:`a_{is} = 2\pi s/q`, the geodesic tangent towards that neighbour in a
  frame rotated with the site), and the hop carries the spin connection,

  .. math:: T_{ij} = \sigma_e\, U(a_{ij})\, T_0\, U(a_{ji} - \pi)^\dagger \quad (i < j), \qquad T_{ji} = T_{ij}^\dagger,

  which reduces to :math:`T(\theta)` in the plane (:math:`a_{ji} = a_{ij} + \pi`). Around a face
  the :math:`\sigma_z` rotations multiply to the Levi-Civita holonomy, angle
  :math:`A = (p-2)\pi - 2\pi p/q` (the face's area at curvature -1); the signs
  :math:`\sigma_e = \pm1` are fixed (a linear system over :math:`\mathbb Z_2`) so that the spinor
  holonomy is the continuous lift :math:`U(A)`, not :math:`-U(A)`. The two orbitals then see
  :math:`\pm A/2` flux per face, :math:`\pm(g-1)` quanta in all (a spin structure: the square
  root of the canonical bundle). A rotation of the frame at one site is the unitary
  :math:`U(\alpha_i)` on that site, so the whole Chern matrix is exactly frame independent; the
  remaining freedom in :math:`\sigma_e` is a gauge transformation (a sign on a site) or a spin
  structure (a shift of k by pi along a cycle), neither of which changes the Chern numbers of the
  torus.

Under a relabelling of the sites the windings' basis changes by :math:`A \in GL(2g, \mathbb Z)`,
:math:`C \to A^T C A`: the gcd of the entries and :math:`|\mathrm{Pf}\, C|` are the invariants to
compare (:func:`frame_invariants`).
"""

from __future__ import annotations

import math

import numpy as np

from .. import _validate
from .models import ModelTerms

__all__ = ["qwz_frame_terms", "frame_invariants", "relabel_cluster", "spin_connection_signs", "covariant_critical_mass"]

_SX = np.array([[0, 1], [1, 0]], dtype=np.complex128)
_SY = np.array([[0, -1j], [1j, 0]], dtype=np.complex128)
_SZ = np.array([[1, 0], [0, -1]], dtype=np.complex128)
_T0 = 0.5 * (_SZ + 1j * _SX)


def _u(theta):
    theta = np.asarray(theta, dtype=float)
    out = np.zeros(theta.shape + (2, 2), dtype=np.complex128)
    out[..., 0, 0] = np.exp(-0.5j * theta)
    out[..., 1, 1] = np.exp(0.5j * theta)
    return out


def _cluster(value):
    from ..graph.clusters import Cluster

    if not isinstance(value, Cluster):
        raise ValueError(f"expected a Cluster (from pbc_cluster), got {type(value).__name__}.")
    return value


def _back_slots(nb: np.ndarray) -> np.ndarray:
    n, q = nb.shape
    back = np.full((n, q), -1, dtype=np.int64)
    for r in range(q):
        back = np.where(nb[nb, r] == np.arange(n)[:, None], r, back)
    return back


def _gf2_solve(A: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """One solution x of A x = b over GF(2) (Gaussian elimination), None if inconsistent."""
    A = A.astype(bool).copy()
    b = b.astype(bool).copy()
    rows, cols = A.shape
    pivots = []
    r = 0
    for c in range(cols):
        hit = np.flatnonzero(A[r:, c])
        if len(hit) == 0:
            continue
        k = r + hit[0]
        A[[r, k]], b[[r, k]] = A[[k, r]], b[[k, r]]
        others = np.flatnonzero(A[:, c])
        others = others[others != r]
        A[others] ^= A[r]
        b[others] ^= b[r]
        pivots.append(c)
        r += 1
        if r == rows:
            break
    if np.any(b[r:]):
        return None
    x = np.zeros(cols, dtype=bool)
    for i, c in enumerate(pivots):
        x[c] = b[i]
    return x


def spin_connection_signs(cluster) -> np.ndarray:
    r"""The edge signs :math:`\sigma_e` of the covariant frame (module docstring), one per edge of ``cluster.edges``.

    Parameters
    ----------
    cluster : Cluster
        A periodic cluster with its rotation system.

    Returns
    -------
    numpy.ndarray of int64, shape (E,)
        +1 or -1; with them every face's spinor holonomy is :math:`U(A)` (checked).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.frames import spin_connection_signs
    >>> s = spin_connection_signs(hl.pbc_cluster(8, 3, "bolza"))
    >>> s.shape, set(s.tolist()) <= {-1, 1}
    ((24,), True)
    """
    c = _cluster(cluster)
    phi_e, faces_e, faces_s = _edge_connection(c)
    area = (c.p - 2) * math.pi - 2 * math.pi * c.p / c.q
    total = (phi_e[faces_e] * faces_s).sum(axis=1)               # (F,) = A + 2 pi m_f
    m = np.rint((total - area) / (2 * math.pi)).astype(np.int64)
    if np.max(np.abs(total - area - 2 * math.pi * m)) > 1e-9:  # pragma: no cover - geometry of the map
        raise ValueError("the face holonomies of the rotation-system frame are not the face angle.")
    nf, ne = faces_e.shape[0], len(phi_e)
    inc = np.zeros((nf, ne), dtype=np.int64)
    np.add.at(inc, (np.repeat(np.arange(nf), c.p), faces_e.ravel()), 1)
    x = _gf2_solve(inc % 2, np.mod(m, 2))
    if x is None:  # pragma: no cover - a spin structure exists on every orientable surface
        raise ValueError("no spin structure solves the face signs.")
    return np.where(x, -1, 1).astype(np.int64)


def _edge_connection(c):
    """Connection angle phi_e = a_ij - a_ji + pi of each edge (i < j) and the faces' edges and signs."""
    nb = np.asarray(c.neighbours, dtype=np.int64)
    n, q = nb.shape
    back = _back_slots(nb)
    edges = np.asarray(c.edges, dtype=np.int64)
    keys = edges[:, 0] * n + edges[:, 1]
    slot_of = {}
    v = np.repeat(np.arange(n), q)
    s = np.tile(np.arange(q), n)
    lower = v < nb.ravel()
    eidx = np.searchsorted(keys, v[lower] * n + nb.ravel()[lower])
    a_ij = 2 * math.pi * s[lower] / q
    a_ji = 2 * math.pi * back.ravel()[lower] / q
    phi = np.zeros(len(edges))
    phi[eidx] = a_ij - a_ji + math.pi
    del slot_of
    faces = np.asarray(c.faces, dtype=np.int64)
    a, b = faces, np.roll(faces, -1, axis=1)
    fe = np.searchsorted(keys, np.minimum(a, b) * n + np.maximum(a, b))
    # the hop H[a, b] of a face step carries U(phi) for a < b (its T_ab), U(-phi) for a > b (T_ba^dagger)
    return phi, fe, np.where(a < b, 1, -1)


def qwz_frame_terms(cluster, *, M: float = 1.0, frame: str = "covariant", alpha=None) -> ModelTerms:
    r"""The QWZ model on a cluster in a chosen frame (see the module docstring).

    Parameters
    ----------
    cluster : Cluster
        A periodic cluster with its rotation system (simple graph).
    M : float, optional
        The mass :math:`M\sigma_z` (default 1).
    frame : {"covariant", "lift"}, optional
        The rotation-system frame with the spin connection (default), or the disk lift of
        :func:`~hyperlattice.topology.models.cluster_angles` (no connection).
    alpha : array_like of float, shape (sites,), optional
        ``"covariant"`` only: a rotation of the frame at every site (radians); the model changes by
        the unitary :math:`\oplus_i U(\alpha_i)`.

    Returns
    -------
    ModelTerms

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.frames import qwz_frame_terms
    >>> t = qwz_frame_terms(hl.pbc_cluster(8, 3, "bolza"), M=1.0)
    >>> t.orbitals, t.blocks.shape
    (2, (48, 2, 2))
    """
    from ..graph.bands import edge_windings
    from .models import model_terms

    c = _cluster(cluster)
    M = _validate.real("M", M, minimum=-1e6, maximum=1e6)
    frame = _validate.choice("frame", frame, ("covariant", "lift"))
    if frame == "lift":
        if alpha is not None:
            raise ValueError("alpha rotates the covariant frame only.")
        return model_terms(c, "qwz", M=M)
    n, q = c.sites, c.q
    al = np.zeros(n) if alpha is None else _validate.real_array("alpha", alpha)
    if al.shape != (n,):
        raise ValueError(f"alpha must have one angle per site ({n}), got shape {al.shape}.")
    nb = np.asarray(c.neighbours, dtype=np.int64)
    back = _back_slots(nb)
    edges = np.asarray(c.edges, dtype=np.int64)
    keys = edges[:, 0] * n + edges[:, 1]
    sign = spin_connection_signs(c)
    v = np.repeat(np.arange(n), q)
    s = np.tile(np.arange(q), n)
    u = nb.ravel()
    lower = v < u
    i, j = v[lower], u[lower]
    eidx = np.searchsorted(keys, i * n + j)
    a_ij = 2 * math.pi * s[lower] / q + al[i]
    a_ji = 2 * math.pi * back.ravel()[lower] / q + al[j]
    T = sign[eidx][:, None, None] * (_u(a_ij) @ _T0[None] @ np.conj(np.swapaxes(_u(a_ji - math.pi), 1, 2)))
    W = edge_windings(c).windings[eidx]                        # winding of i -> j
    tail = np.concatenate([i, j])
    head = np.concatenate([j, i])
    blocks = np.concatenate([T, np.conj(np.swapaxes(T, 1, 2))])
    wind = np.concatenate([W, -W]).astype(np.int64)
    onsite = np.broadcast_to(M * _SZ, (n, 2, 2)).astype(np.complex128)
    return ModelTerms(model="qwz", orbitals=2, onsite=onsite, tail=tail, head=head, blocks=blocks,
                      windings=wind, parameters={"M": M, "frame": frame})


def relabel_cluster(cluster, seed: int = 0, *, rotate_slots: bool = True):
    r"""The same map with its sites renumbered (and, optionally, each rotation started at a random slot).

    An isomorphic cluster: every frame-independent invariant must come out the same.

    Parameters
    ----------
    cluster : Cluster
        A periodic cluster.
    seed : int, optional
        Seed of the permutation (default 0).
    rotate_slots : bool, optional
        Also start every site's counterclockwise neighbour list at a random slot (default True).

    Returns
    -------
    Cluster

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.frames import relabel_cluster
    >>> relabel_cluster(hl.pbc_cluster(8, 3, "bolza"), 1).genus
    2
    """
    from dataclasses import replace

    c = _cluster(cluster)
    seed = _validate.integer("seed", seed, minimum=0, maximum=2**63 - 1)
    rng = np.random.default_rng(seed)
    nb = np.asarray(c.neighbours, dtype=np.int64)
    n, q = nb.shape
    perm = rng.permutation(n)                  # new site k is old site perm[k]
    inv = np.argsort(perm)
    new = inv[nb[perm]]
    if rotate_slots:
        shift = rng.integers(0, q, size=n)
        new = new[np.arange(n)[:, None], (np.arange(q)[None] + shift[:, None]) % q]
    return replace(c, name=f"{c.name} (relabelled {seed})", neighbours=new.astype(np.int32))


def frame_invariants(terms: ModelTerms, *, grid: int = 12, max_grid: int = 48) -> dict:
    r"""The first Chern matrix of a model's half-filled Abelian bands and its basis-independent invariants.

    Parameters
    ----------
    terms : ModelTerms
        On a cluster (windings in :math:`\mathbb Z^{2g}`).
    grid, max_grid : int, optional
        The 2-subtorus grids (:func:`~hyperlattice.topology.surfaces.cluster_chern`'s method).

    Returns
    -------
    dict
        ``chern`` (2g x 2g list), ``gcd``, ``pfaffian``, ``abs_pfaffian``, ``gap`` (smallest on the
        grids), ``grid`` (the largest grid used).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.frames import qwz_frame_terms, frame_invariants
    >>> inv = frame_invariants(qwz_frame_terms(hl.pbc_cluster(8, 3, "bolza"), M=1.0))
    >>> sorted(inv)
    ['abs_pfaffian', 'chern', 'gap', 'gcd', 'grid', 'pfaffian']
    """
    from ..graph.solvers import single_threaded_blas
    from .surfaces import _all_subtori, _pf

    if not isinstance(terms, ModelTerms) or terms.windings.shape[1] < 2:
        raise ValueError("frame_invariants needs ModelTerms on a closed surface.")
    grid = _validate.integer("grid", grid, minimum=4, maximum=256)
    max_grid = _validate.integer("max_grid", max_grid, minimum=grid, maximum=256)
    g2 = terms.windings.shape[1]
    raw = np.zeros((g2, g2))
    gaps: list = []
    with single_threaded_blas():
        n = _all_subtori(terms, g2, terms.sites * terms.orbitals // 2, grid, max_grid, raw, gaps, [])
    C = np.rint(raw).astype(np.int64)
    vals = [abs(int(x)) for x in C[np.triu_indices(g2, 1)]]
    pf = int(round(_pf(C.astype(float))))
    return {"chern": C.tolist(), "gcd": math.gcd(*vals), "pfaffian": pf, "abs_pfaffian": abs(pf),
            "gap": float(min(gaps)), "grid": int(n)}


def covariant_critical_mass(p: int = 8, q: int = 3) -> float:
    r"""The continuum estimate of the mass where the covariant QWZ model's gap closes on a {p,q} lattice.

    In the covariant frame the :math:`\sigma_z` part of the bonds, :math:`\tfrac12\sigma_z` with the
    spin connection, is half of a magnetic adjacency whose two orbitals see :math:`\pm A/2` flux per
    face: in the paper's metric (face area :math:`A/4`) a field :math:`B = 2 = |K|/2`, the spin-1/2
    coupling to curvature :math:`K = -4`. At B = 2 the magnetic Laplacian has no discrete Landau
    level (Comtet: :math:`N < B/4 - 1/2 = 0`) and its spectrum starts at :math:`\kappa = 1 + B^2/4 = 2`;
    the mass band's edge, through the paper's dictionary :math:`E = -q + \frac q4 h^2 \kappa`, closes
    the gap of :math:`H \approx m\sigma_z + v\,\sigma\cdot p` at

    .. math:: M_c = -\tfrac12 E(\kappa = 2) = \frac q2 - \frac q4 h^2,

    below the flat value q/2; near it the gap is :math:`2|M - M_c|` (the Dirac operator on the disk
    has no curvature gap: Camporesi and Higuchi, J. Geom. Phys. 20, 1 (1996)).

    Parameters
    ----------
    p, q : int, optional
        The {p,q} lattice (default {8,3}).

    Returns
    -------
    float
        :math:`M_c` in units of the hop (the gap closes at :math:`\pm M_c`).

    Examples
    --------
    >>> from hyperlattice.topology.frames import covariant_critical_mass
    >>> round(covariant_critical_mass(8, 3), 3)
    1.409
    """
    from .. import dictionary

    p, q = _validate.pq(p, q)
    return float(-0.5 * dictionary.energy_from_lambda(2.0, p, q))


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
