r"""Quantum Monte Carlo of the Bose–Hubbard model on any graph: stochastic series expansion (SSE)
with directed loops.

.. math::

    H = -\sum_{\langle ij\rangle} t_{ij} (a_i^\dagger a_j + \mathrm{h.c.})
        + \frac{U}{2} \sum_i n_i (n_i - 1) - \mu \sum_i n_i ,
    \qquad t_{ij} = t A_{ij} \ge 0 ,

grand canonical at inverse temperature β, with the occupation cutoff :math:`n_i \le n_{\max}`
(:math:`n_{\max} = 1`: hard-core bosons, the spin-1/2 XY model). :math:`A` is the adjacency
of a flake, of a periodic cluster, or any symmetric matrix of couplings.

Algorithm
---------
Sandvik's SSE (Sandvik, PRB 59, R14157 (1999)) with the directed-loop update of Syljuåsen and
Sandvik, PRE 66, 046701 (2002), for soft-core bosons as in Syljuåsen, PRE 67, 046701 (2003).
The Hamiltonian is written as :math:`H = -\sum_b H_b + \sum_b C_b` over the bonds b = (i, j);
the bond operator carries the hopping and the on-site energy split over the bonds of each site
(:math:`z_i` = number of bonds of site i):

.. math::

    \langle n_i n_j | H_b | n_i n_j\rangle = C_b - \frac{\epsilon(n_i)}{z_i} - \frac{\epsilon(n_j)}{z_j},
    \qquad \epsilon(n) = \frac U2 n(n-1) - \mu n,

    \langle n_i \pm 1, n_j \mp 1 | H_b | n_i n_j\rangle = t_b \sqrt{\max(n_i, n_i \pm 1)\,\max(n_j, n_j \mp 1)},

with :math:`C_b = \max \epsilon_i/z_i + \max \epsilon_j/z_j + c\,t_b` (:data:`OFFSET` c keeps
every diagonal vertex away from weight zero, which would trap the loops). Every vertex weight is
non-negative: there is no sign problem for :math:`t_{ij} \ge 0`. A sweep is one diagonal update
(insertion/removal of diagonal operators at every slot of the string of length M) and a fixed
number of directed loops (about 3n vertex legs per sweep; 8n on measured sweeps when G is
measured, the worm estimator's own budget); a loop's head leaves each vertex with the exit
probabilities of least bounce (:func:`._sse_kernels._cumulative`): the symmetric solution of the
directed-loop equations (Syljuåsen & Sandvik, PRE 66, 046701 (2002)) whose only bounce is
:math:`\max(0, W_1 - W_2 - W_3 - W_4)` at the heaviest of the four configurations. In the
superfluid, where most diagonal vertices can be left without a bounce, it halves the energy's
autocorrelation time against the Metropolized-Gibbs rule (:math:`P(i\to k) = \min[w_k/(Z-w_i),
w_k/(Z-w_k)]`, Liu, Statist. Comput. 6, 113 (1996)) used up to version 0.5.0.

Estimators (per sweep; n = number of operators, N = number of bosons, conserved along τ):

* energy :math:`\langle H\rangle = \big\langle \tfrac1M \sum_{p=0}^{M-1} \sum_i \epsilon(n_i(p))\big\rangle
  - \langle n_{\mathrm{offd}}\rangle/\beta`: the diagonal (site) energy averaged over the M time
  slices of each configuration (a diagonal observable, Sandvik, AIP Conf. Proc. 1297, 135 (2010))
  plus the kinetic energy from the number of off-diagonal operators. It is unbiased like the
  textbook :math:`-\langle n\rangle/\beta + \sum_b C_b`, whose variance carries
  :math:`\langle n\rangle/\beta^2` from the constant :math:`C_b` (which must cover every occupation
  up to :math:`n_{\max}`: n is large in a Mott insulator); the slice average has none of it;
* density :math:`\langle N\rangle / M`; compressibility
  :math:`\kappa = \beta(\langle N^2\rangle - \langle N\rangle^2)/M` (jackknife over bins);
* site density :math:`\langle n_i\rangle` averaged over the M time slices of each configuration;
* bond kinetic energy :math:`\langle a_i^\dagger a_j + a_j^\dagger a_i\rangle = \langle n_b\rangle/(\beta t_b)`
  (:math:`n_b` the off-diagonal operators on b).

Sign structure
--------------
Negative couplings are accepted when a gauge :math:`a_i \to s_i a_i`, :math:`s_i = \pm 1`, makes
every :math:`t_{ij} s_i s_j` non-negative (e.g. t < 0 on a bipartite graph); the chain runs on the
transformed model and the off-diagonal correlations are transformed back
(:math:`G_{ij} \to s_i s_j G_{ij}`). Otherwise, and for complex hopping (a flux), the weights
cannot all be positive and :func:`qmc` refuses.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import time
import warnings
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from .. import _validate, mcstats
from .._progress import progress_bar
from ..errors import HyperlatticeError
from ..results import Column, Result, to_jsonable

__all__ = ["QMCResult", "qmc", "qmc_memory", "qmc_seconds", "merge_chains", "QMCWarning", "OFFSET"]

#: diagonal-vertex offset c in units of the bond hopping (see the module docstring)
OFFSET = 0.5
#: scalar bins kept per chain (binning analysis resolution) and bins of the site-resolved arrays
_SCALAR_BINS = 2048
_VECTOR_BINS = 32
#: per-sweep scalars accumulated by the kernel: n, n^2, N, N^2, N^4, E, E^2
_SCALARS = 7
#: vertex legs visited by the loops per sweep, in units of the string's n operators (the update's
#: budget). With the least-bounce exits, energy efficiencies 1/(sigma_E^2 x CPU s) of 2n / 3n / 4n
#: / 8n (four seeds of 5000 sweeps each, benchmarks/qmc_legs_scan.py, with another job on the
#: machine): l = 3 superfluid at beta = 2 4.7 / 5.4 / 5.0 / -, at beta = 8 3.5 / 5.8 / 4.6 / -,
#: l = 4 superfluid 0.71 / 0.62 / 0.56 / 0.40, Klein superfluid 10.5 / 17 / 9.4 / 7.5; Mott points
#: equal within errors from 3n to 4n. 3n is the best choice over the superfluid points.
_TARGET_LEGS = 3.0
#: the rule for the loop's exit probabilities (part of a checkpoint's fingerprint)
_EXIT_RULE = "least-bounce"
#: the Green-function estimator's own budget: a measured sweep with ``measure_green`` runs the
#: loops of this many legs per operator (each of the 4n legs about twice), so that G is averaged
#: over enough head positions even on small graphs (the update's 3n is one or two loops per
#: sweep on a 6-site ring)
_GREEN_LEGS = 8.0
#: the kernels' vertex positions, links and leg states are int32: 4 legs per slot must stay below
_INT32_MAX = 2**31 - 1
#: the checkpoint file and the lock file in a checkpoint directory
_CHECKPOINT_FILE = "qmc_chain.npz"
_LOCK_FILE = ".qmc_chain.lock"
#: seconds of work between checkpoint writes
_CHECKPOINT_SECONDS = 60.0
#: most winding components whose moments are measured (D (D + 1) / 2 + 1 scalar columns)
MAX_WINDINGS = 64
#: bytes per operator slot (ops int64 with the 4/3 headroom; int32 vertex positions, links and leg states)
_BYTES_PER_OP = 8 * (4 / 3) + 4 + 16 + 16


class QMCWarning(UserWarning):
    """A Monte Carlo chain returned, but thermalisation or the binning plateau is in doubt."""


# ----------------------------------------------------------------------------
# the model: bonds, gauge, isolated sites
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Model:
    sites: int
    bi: np.ndarray
    bj: np.ndarray
    tb: np.ndarray          # gauged hopping, all > 0
    gauge: np.ndarray       # s_i = +-1
    degree: np.ndarray
    z: np.ndarray | None    # Poincaré-disk coordinates (flakes) or None
    d0: float | None        # edge length of the {p,q} lattice (flakes and clusters)
    label: str
    kind: str               # "flake", "cluster" or "graph"
    # sites without bonds, left out of the chain and added exactly (indices of the graph given, which
    # has ``full_sites`` sites); empty for every flake and cluster
    dropped: tuple = ()
    full_sites: int = 0


def _matrix(system):
    if sp.issparse(system) or isinstance(system, np.ndarray):
        mat = sp.csr_matrix(system)
        if mat.ndim != 2 or mat.shape[0] != mat.shape[1] or mat.shape[0] == 0:
            raise ValueError(f"the adjacency matrix must be square and non-empty, got shape {mat.shape}.")
        if np.iscomplexobj(mat.data):
            if np.any(mat.data.imag != 0):
                raise ValueError("complex hopping (a magnetic flux) gives the quantum Monte Carlo a sign problem; "
                                 "use exact diagonalisation or mean field instead.")
            mat = sp.csr_matrix(mat.real)
        mat = sp.csr_matrix(mat, dtype=np.float64)
        if not np.all(np.isfinite(mat.data)):
            raise ValueError("the adjacency matrix must have finite entries.")
        if mat.nnz and abs(mat - mat.T).max() > 0:
            raise ValueError("the adjacency matrix must be symmetric.")
        loops = np.flatnonzero(mat.diagonal())
        if loops.size:
            raise ValueError(f"the adjacency matrix has {loops.size} self-loop(s) (A_ii != 0, e.g. site {int(loops[0])}); "
                             "a bond joins two sites: put an on-site energy into mu, or remove the diagonal.")
        return mat, None, None, "graph", f"graph of {mat.shape[0]} sites"
    if hasattr(system, "neighbours") and hasattr(system, "genus"):                  # a Cluster
        from .. import geometry

        return (sp.csr_matrix(system.adjacency(), dtype=np.float64), None, float(geometry.d0(system.p, system.q)),
                "cluster",
                f"{{{system.p},{system.q}}} cluster {system.name}")
    if hasattr(system, "ring_offsets") and hasattr(system, "neighbours"):           # a Lattice
        from ..graph.operators import adjacency

        from .. import geometry

        lat = _validate.lattice(system, kind="sites")
        return (sp.csr_matrix(adjacency(lat), dtype=np.float64), np.asarray(lat.z, dtype=complex),
                float(geometry.d0(lat.p, lat.q)), "flake",
                f"{{{lat.p},{lat.q}}} flake, l = {lat.rings}")
    raise ValueError(f"system must be a flake, a periodic cluster or an adjacency matrix, got "
                     f"{_validate._shown(system)}.")


def _model(system, t: float, isolated: bool = False) -> _Model:
    mat, z, d0, kind, label = _matrix(system)
    n = mat.shape[0]
    up = sp.triu(mat, k=1).tocoo()
    keep = up.data != 0
    bi = up.row[keep].astype(np.int64)
    bj = up.col[keep].astype(np.int64)
    hop = t * up.data[keep]
    gauge = np.ones(n)
    if np.any(hop < 0):
        # a Z2 gauge s_i with s_i s_j t_ij >= 0 on every bond, by breadth-first search
        sgn = sp.csr_matrix((np.sign(hop), (bi, bj)), shape=(n, n))
        sgn = (sgn + sgn.T).tocsr()
        seen = np.zeros(n, dtype=bool)
        for root in range(n):
            if seen[root]:
                continue
            seen[root] = True
            queue = deque([root])
            while queue:
                u = queue.popleft()
                for k in range(sgn.indptr[u], sgn.indptr[u + 1]):
                    w = sgn.indices[k]
                    want = gauge[u] * sgn.data[k]
                    if not seen[w]:
                        seen[w] = True
                        gauge[w] = want
                        queue.append(w)
        if np.any(gauge[bi] * gauge[bj] * hop < 0):
            why = ("t < 0 on a graph that is not bipartite" if np.all(hop <= 0) else
                   "couplings of mixed sign that no gauge a_i -> -a_i makes all non-negative")
            raise ValueError(f"{why} gives the quantum Monte Carlo a sign problem (frustrated hopping); "
                             "use exact diagonalisation or mean field instead.")
    tb = np.abs(hop).astype(float)
    degree = np.bincount(np.concatenate([bi, bj]), minlength=n).astype(np.int64)
    if bi.size and np.any(degree == 0) and not isolated:
        # the directed loops draw the occupation of a site that no operator touches uniformly from
        # 0..nmax (right for a bonded site, whose on-site energy lives in its bond vertices; wrong
        # for a site without bonds, whose energy has no vertex at all): see _drop_isolated
        raise ValueError(f"{int(np.sum(degree == 0))} site(s) have no bond (e.g. site {int(np.argmax(degree == 0))}); "
                         "remove them and add their single-site thermal averages (exact_thermal of one site).")
    return _Model(n, bi, bj, tb, gauge, degree, z, d0, label, kind)


def _drop_isolated(model: _Model) -> _Model:
    """The model of the bonded sites alone (renumbered in order), recording the sites without bonds.

    The directed loops draw the occupation of a site that no operator touches uniformly from
    0..nmax: the right weight for a bonded site (its on-site energy lives in its bond vertices),
    the wrong one for a site without bonds, whose energy has no vertex at all. Such a site is an
    independent single-site problem: it is left out of the chain and its exact thermal average is
    added to the results (:func:`_add_isolated`). A model without such sites is returned as it is.
    """
    iso = model.degree == 0
    if not iso.any() or model.bi.size == 0:
        return model
    keep = np.flatnonzero(~iso)
    new = np.full(model.sites, -1, dtype=np.int64)
    new[keep] = np.arange(keep.size)
    # the renumbering is monotone: the bonds keep their order (and their windings, row by row)
    return _Model(int(keep.size), new[model.bi], new[model.bj], model.tb, model.gauge[keep], model.degree[keep],
                  None if model.z is None else model.z[keep], model.d0, model.label, model.kind,
                  tuple(int(i) for i in np.flatnonzero(iso)), model.sites)


def _bond_windings(system, model: _Model, windings) -> tuple[np.ndarray, str]:
    r"""Integer windings of the model's bonds (B, D) and, when there are none, the reason.

    ``windings``: None (automatic: a Cluster's :func:`~hyperlattice.graph.bands.edge_windings`,
    nothing otherwise), False (off), a :class:`~hyperlattice.graph.bands.Windings`, or a pair
    ``(edges, w)``: edges (E, 2) and the integer winding w (E, D) of each directed edge
    ``edges[k, 0] -> edges[k, 1]``, every bond of the graph exactly once.
    """
    nb = model.bi.size
    none = np.zeros((nb, 0), dtype=np.int64)
    if windings is False:
        return none, "not asked for (windings=False)."
    if windings is None:
        if model.kind == "cluster":
            from ..graph.bands import edge_windings

            windings = edge_windings(system)
        elif model.kind == "flake":
            return none, ("an open flake has no non-contractible cycles, so no winding number: use the "
                          "condensate fraction.")
        else:
            return none, ("an adjacency matrix carries no windings: pass windings= (e.g. "
                          "compare.qmc_lobe.square_lattice_windings(L) for the L x L torus; on the command "
                          "line --windings FILE.npy).")
    if hasattr(windings, "edges") and hasattr(windings, "windings"):
        edges, w = windings.edges, windings.windings
    elif isinstance(windings, (tuple, list)) and len(windings) == 2:
        edges, w = windings
    else:
        raise ValueError("windings must be None, False, a Windings (graph.bands.edge_windings) or a pair "
                         "(edges, windings) of arrays of shapes (E, 2) and (E, D).")
    try:
        edges = np.asarray(edges)
        w = np.asarray(w)
    except (TypeError, ValueError):
        raise ValueError("windings must be a pair of integer arrays (edges (E, 2), windings (E, D)).") from None
    if (edges.ndim != 2 or edges.shape[1:] != (2,) or w.ndim != 2 or w.shape[0] != edges.shape[0]
            or w.shape[1] < 1 or edges.dtype.kind not in "iu" or w.dtype.kind not in "iu"):
        raise ValueError(f"windings must be integer arrays of shapes (E, 2) and (E, D) with D >= 1, got "
                         f"{edges.shape} and {w.shape}.")
    skipped = ""
    if w.shape[1] > MAX_WINDINGS:
        # an optional observable: measure the components that fit, say which were left out
        skipped = (f"the stiffness is measured for the first {MAX_WINDINGS} of the {w.shape[1]} winding components "
                   f"(components {MAX_WINDINGS + 1}-{w.shape[1]} skipped: the chain bins the moments W_a W_b of at "
                   f"most {MAX_WINDINGS} components, {MAX_WINDINGS * (MAX_WINDINGS + 1) // 2:,} columns); rho_s and "
                   "stiffness_geometric refer to the measured "
                   f"{MAX_WINDINGS} x {MAX_WINDINGS} block.")
        warnings.warn(skipped, QMCWarning, stacklevel=3)
        w = w[:, :MAX_WINDINGS]
    n = model.sites
    if edges.size and (edges.min() < 0 or edges.max() >= n):
        raise ValueError(f"the edges of windings must be sites 0..{n - 1}.")
    lo = np.minimum(edges[:, 0], edges[:, 1]).astype(np.int64)
    hi = np.maximum(edges[:, 0], edges[:, 1]).astype(np.int64)
    sign = np.where(edges[:, 0] < edges[:, 1], 1, -1).astype(np.int64)
    keys = lo * n + hi
    order = np.argsort(keys, kind="stable")
    bond_keys = model.bi * n + model.bj
    if keys.size != nb or np.any(np.diff(keys[order]) == 0) or np.any(keys[order] != np.sort(bond_keys)):
        raise ValueError(f"windings must give every bond of the graph exactly once ({nb} bonds, "
                         f"{keys.size} edges given).")
    pos = np.searchsorted(keys[order], bond_keys)
    out = (w.astype(np.int64) * sign[:, None])[order[pos]]
    return np.ascontiguousarray(out), skipped


# ----------------------------------------------------------------------------
# the result
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class QMCResult(Result):
    r"""Thermal averages of the Bose–Hubbard model from one SSE chain (or several merged).

    Attributes
    ----------
    system : str
        What was simulated (``"{7,3} flake, l = 3"``, a cluster name, or ``"graph of M sites"``).
    sites : int
        Number of sites M.
    U, mu, t, beta : float
        Interaction, chemical potential, hopping scale and inverse temperature (energies in the
        unit of t; β in its inverse).
    nmax : int
        Occupation cutoff.
    sweeps, thermalization : int
        Measured and thermalisation sweeps (summed over chains after :func:`merge_chains`).
    seed : int or None
        The seed of the chain (None for merged chains: see ``seeds``).
    seeds : tuple of int
        Seeds of every chain in the result.
    chains : int
        Number of independent chains merged.
    energy, energy_err : float
        :math:`\langle H\rangle` (total, the :math:`-\mu N` term included) and its error.
    density, density_err : float
        :math:`\langle N\rangle/M` and its error.
    compressibility, compressibility_err : float
        :math:`\kappa = \beta(\langle N^2\rangle - \langle N\rangle^2)/M` (jackknife).
    tau_int : dict
        Integrated autocorrelation time in sweeps per observable (``energy``, ``density``,
        ``compressibility``): :math:`\sigma^2 = 2\tau\,\mathrm{var}/n_{\mathrm{sweeps}}`.
    bins, bin_size : int
        Number of plateau-level bins of the scalar observables and their length in sweeps.
    converged : bool
        True when the binning errors of all scalar observables reached a plateau and the first and
        second half of the measurements agree (see :func:`qmc`, Notes).
    notes : tuple of str
        What was noticed (the same sentences are issued as :class:`QMCWarning`).
    site_density, site_density_err : ndarray, shape (M,)
        :math:`\langle n_i\rangle` and its error.
    bonds : ndarray of int, shape (B, 2)
        The bonds (i < j).
    bond_kinetic, bond_kinetic_err : ndarray, shape (B,)
        :math:`\langle a_i^\dagger a_j + a_j^\dagger a_i\rangle` per bond (the nearest-neighbour
        one-body density matrix, twice its real part).
    green_distance, green, green_err : ndarray or None
        The equal-time one-body density matrix :math:`G(i,j) = \langle a_i^\dagger a_j\rangle`
        (i != j) averaged over the site pairs of each distance class: their mean distance, the
        average and its error (None when not measured). Classes: hyperbolic distance in bins of
        :math:`d_0/2` on flakes, graph distance on clusters (times :math:`d_0`) and adjacencies
        (hops); pairs in different components form a last class at distance inf.
    green_pairs : ndarray of int or None
        Ordered site pairs per class.
    distance_kind : str
        ``"hyperbolic"``, ``"graph x d0"``, ``"graph (hops)"`` or ``""`` (not measured).
    green_matrix : ndarray, shape (M, M), or None
        The full G (diagonal: :math:`\langle n_i\rangle`), stored up to :data:`G_FULL_MAX` sites.
    condensate_fraction, condensate_fraction_err : float
        Largest eigenvalue of G over :math:`\langle N\rangle` (Penrose–Onsager), jackknife error
        over blocks of the chain; nan when G is not stored.
    mean_operators : float
        Mean length n of the operator string.
    string_length : int
        The string length M_L fixed after thermalisation.
    loops_per_sweep : int
        Directed loops per sweep (fixed after thermalisation).
    seconds : float
        Wall-clock seconds of the run (summed over chains).
    stiffness, stiffness_err : ndarray, shape (D, D), or None
        The superfluid stiffness tensor :math:`\Upsilon_{ab} = \langle W_a W_b\rangle/\beta` from
        the winding numbers :math:`W \in \mathbb Z^D` of the world lines around the D
        non-contractible cycles (D = 2 on a torus, 2g on a genus-g cluster; see :func:`qmc`,
        Notes), in the energy unit of U, mu and t, and its error (binning). None when the graph
        carries no windings (``stiffness_note`` says why).
    rho_s, rho_s_err : float
        :math:`\operatorname{tr}\Upsilon/D = \langle W\cdot W\rangle/(D\beta)`: on the L x L
        square torus the usual :math:`\rho_s = \langle W_x^2 + W_y^2\rangle/(2\beta)`; its
        autocorrelation time is ``tau_int["stiffness"]``. nan without windings.
    stiffness_geometric, stiffness_geometric_err : float
        :math:`(\det\Upsilon)^{1/D}` (jackknife), unchanged by a change of the integer homology
        basis (``rho_s`` of a genus-g cluster depends on the basis); equal to :math:`\rho_s` for an
        isotropic torus. nan without windings.
    stiffness_note : str
        Why ``stiffness`` is None ("" when measured), or which winding components were skipped.
    bond_hopping : ndarray, shape (B,), or None
        The coupling :math:`t_{ij} = t A_{ij}` of each bond (None when read back from a sweep's
        table, whose rows do not store it); :func:`merge_chains` refuses chains whose couplings differ.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons import qmc
    >>> r = qmc(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=1.0, nmax=2, sweeps=2000, seed=1, progress=False)
    >>> r.sites, r.nmax, sorted(r.tau_int)[:2]
    (7, 2, ['compressibility', 'density'])
    """

    COLUMNS = (Column("site_density", "site_density", "bosons"),
               Column("site_density_err", "site_density_err", "bosons"))

    system: str
    sites: int
    U: float
    mu: float
    t: float
    beta: float
    nmax: int
    sweeps: int
    thermalization: int
    seed: int | None
    seeds: tuple
    chains: int
    energy: float
    energy_err: float
    density: float
    density_err: float
    compressibility: float
    compressibility_err: float
    tau_int: dict
    bins: int
    bin_size: int
    converged: bool
    notes: tuple
    site_density: np.ndarray
    site_density_err: np.ndarray
    bonds: np.ndarray
    bond_kinetic: np.ndarray
    bond_kinetic_err: np.ndarray
    green_distance: np.ndarray | None
    green: np.ndarray | None
    green_err: np.ndarray | None
    green_pairs: np.ndarray | None
    distance_kind: str
    green_matrix: np.ndarray | None
    condensate_fraction: float
    condensate_fraction_err: float
    mean_operators: float
    string_length: int
    loops_per_sweep: int
    seconds: float
    stiffness: np.ndarray | None = None
    stiffness_err: np.ndarray | None = None
    rho_s: float = math.nan
    rho_s_err: float = math.nan
    stiffness_geometric: float = math.nan
    stiffness_geometric_err: float = math.nan
    stiffness_note: str = "not measured."
    bond_hopping: np.ndarray | None = None

    def summary(self) -> dict:
        """The JSON view: the scalar observables with errors, tau_int, the run's size and flags."""
        keys = ("system", "sites", "U", "mu", "t", "beta", "nmax", "sweeps", "thermalization", "seed", "chains",
                "energy", "energy_err", "density", "density_err", "compressibility", "compressibility_err",
                "bins", "bin_size", "converged", "mean_operators", "seconds", "rho_s", "rho_s_err",
                "stiffness_geometric", "stiffness_geometric_err")
        out = {"type": self.TYPE}
        for k in keys:
            out[k] = to_jsonable(getattr(self, k))
        out["stiffness"] = to_jsonable(self.stiffness.tolist() if self.stiffness is not None else None)
        out["stiffness_err"] = to_jsonable(self.stiffness_err.tolist() if self.stiffness_err is not None else None)
        out["stiffness_note"] = self.stiffness_note
        out["tau_int"] = to_jsonable(dict(self.tau_int))
        out["notes"] = to_jsonable(list(self.notes))
        return out

    def table(self) -> list[dict]:
        """One row per scalar observable: ``observable, value, error, tau_int``."""
        rows = []
        for name in ("energy", "density", "compressibility"):
            rows.append({"observable": name, "value": float(getattr(self, name)),
                         "error": float(getattr(self, name + "_err")), "tau_int": float(self.tau_int.get(name, math.nan))})
        if self.stiffness is not None:
            rows.append({"observable": "rho_s", "value": float(self.rho_s), "error": float(self.rho_s_err),
                         "tau_int": float(self.tau_int.get("stiffness", math.nan))})
        return rows

    def __str__(self) -> str:
        lines = [f"SSE QMC, {self.system}: U = {self.U:g}, mu = {self.mu:g}, t = {self.t:g}, beta = {self.beta:g}, "
                 f"nmax = {self.nmax}, {self.sweeps} sweeps, {self.chains} chain(s)"]
        for r in self.table():
            lines.append(f"  {r['observable']:<16} {r['value']: .6f} +- {r['error']:.6f}   tau_int = {r['tau_int']:.2f}")
        if not self.converged:
            lines.append("  not converged: " + " ".join(self.notes))
        return "\n".join(lines)


# ----------------------------------------------------------------------------
# the chain
# ----------------------------------------------------------------------------

def _weights(model: _Model, U: float, mu: float, nmax: int):
    n = np.arange(nmax + 1, dtype=float)
    eps = 0.5 * U * n * (n - 1) - mu * n
    z = np.maximum(model.degree, 1).astype(float)
    esite = eps[None, :] / z[:, None]
    cb = esite[model.bi].max(axis=1) + esite[model.bj].max(axis=1) + OFFSET * model.tb
    return eps, np.ascontiguousarray(esite), cb


#: largest exit-probability table (bytes); beyond it the exits are computed at each vertex
_TABLE_BYTES = 64 * 2**20


def _exit_tables(model: _Model, esite: np.ndarray, cb: np.ndarray, nmax: int, sq: np.ndarray):
    """Bond classes (equal vertex weights) and their exit tables, or an empty table when too big."""
    from . import _sse_kernels as K

    key = np.concatenate([model.tb[:, None], esite[model.bi], esite[model.bj], cb[:, None]], axis=1)
    _, rep, cls = np.unique(key, axis=0, return_index=True, return_inverse=True)
    size = rep.size * (nmax + 1) ** 4 * 32 * 8
    if size > _TABLE_BYTES:
        return np.zeros((0, 1, 4, 2, 4)), np.zeros(model.bi.size, dtype=np.int64)
    tab = K.exit_table(rep.astype(np.int64), model.bi, model.bj, model.tb, cb, esite, sq, nmax)
    return tab, cls.astype(np.int64).ravel()


def _isolated(model: _Model, eps: np.ndarray, beta: float) -> tuple[float, float, float, np.ndarray]:
    """Exact (energy, <N>, var N, site density) of the sites without bonds (independent sites)."""
    iso = model.degree == 0
    k = int(iso.sum())
    dens = np.zeros(model.sites)
    if k == 0:
        return 0.0, 0.0, 0.0, dens
    n = np.arange(eps.size, dtype=float)
    w = np.exp(-beta * (eps - eps.min()))
    w /= w.sum()
    e1, n1, n2 = float(w @ eps), float(w @ n), float(w @ n ** 2)
    dens[iso] = n1
    return k * e1, k * n1, k * (n2 - n1 * n1), dens


#: largest system whose full one-body density matrix G(i, j) is accumulated (condensate fraction)
G_FULL_MAX = 2000


@dataclass(frozen=True)
class _Green:
    mode: int               # 0: off, 1: class table, 2: classes from the disk coordinates
    gclass: np.ndarray
    zr: np.ndarray
    zi: np.ndarray
    omz: np.ndarray
    hbin: float
    ncls: int
    pairs: np.ndarray       # ordered pairs per class
    distance: np.ndarray    # mean pair distance per class
    kind: str               # "hyperbolic", "graph x d0", "graph (hops)" or ""
    blocks: int             # blocks of the full G (0: not stored)
    note: str


def _green_setup(model: _Model, measure: bool) -> _Green:
    from .. import geometry

    empty_i = np.zeros((1, 1), dtype=np.int64)
    one = np.ones(1)
    off = _Green(0, empty_i, one, one, one, 1.0, 1, np.zeros(1, dtype=np.int64), np.zeros(1), "", 0, "")
    if not measure:
        return off
    n = model.sites
    if n <= G_FULL_MAX:
        blocks = 8 if n <= 1000 else 4
        if model.z is not None:
            hbin = model.d0 / 2
            dist = np.asarray(geometry.distance(model.z[:, None], model.z[None, :], check=False), dtype=float)
            kind = "hyperbolic"
        else:
            from scipy.sparse.csgraph import shortest_path

            adj = sp.csr_matrix((np.ones(model.bi.size), (model.bi, model.bj)), shape=(n, n))
            dist = shortest_path(adj, directed=False, unweighted=True)
            if model.d0 is not None:
                dist = dist * model.d0
                hbin = model.d0
                kind = "graph x d0"
            else:
                hbin = 1.0
                kind = "graph (hops)"
        finite = np.isfinite(dist)
        cls = np.zeros((n, n), dtype=np.int64)
        cls[finite] = np.rint(dist[finite] / hbin).astype(np.int64)
        top = int(cls.max()) + 1
        cls[~finite] = top                     # pairs in different components
        ncls = top + 1
        off_diag = ~np.eye(n, dtype=bool)
        pairs = np.bincount(cls[off_diag], minlength=ncls)
        dsum = np.bincount(cls[off_diag & finite], weights=dist[off_diag & finite], minlength=ncls)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = np.where(pairs > 0, dsum / np.maximum(pairs, 1), np.nan)
        mean[top] = np.inf if pairs[top] else np.nan
        return _Green(1, cls, one, one, one, hbin, ncls, pairs, mean, kind, blocks, "")
    if model.z is not None:
        from . import _sse_kernels as K

        z = model.z
        omz = np.asarray(geometry.one_minus_abs2(z), dtype=float)
        hbin = model.d0 / 2
        rmax = float(np.max(np.arctanh(np.minimum(np.abs(z), 1 - 1e-16))))
        ncls = int(2 * rmax / hbin) + 3
        pairs, dsum = K.pair_counts(z.real.copy(), z.imag.copy(), omz, hbin, ncls)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = np.where(pairs > 0, dsum / np.maximum(pairs, 1), np.nan)
        return _Green(2, empty_i, z.real.copy(), z.imag.copy(), omz, hbin, ncls, pairs, mean, "hyperbolic", 0,
                      f"the full G(i, j) is not stored above {G_FULL_MAX} sites: no condensate fraction.")
    return off.__class__(**{**off.__dict__, "note": f"G(i, j) is not measured on a graph without coordinates of more "
                                                   f"than {G_FULL_MAX} sites."})


def _fingerprint(model: _Model, U, mu, t, beta, nmax, seed, wind=None) -> str:
    """The chain's identity in a checkpoint: the physics, the seed and the algorithm's constants
    (not the thermalisation, whose length the checkpoint records; nor the sweeps, which may grow)."""
    h = hashlib.sha256()
    for a in (model.bi, model.bj, model.tb, model.gauge):
        h.update(np.ascontiguousarray(a).tobytes())
    if wind is not None and wind.shape[1]:
        h.update(b"windings" + np.ascontiguousarray(wind).tobytes())
    if model.dropped:           # sites without bonds (added exactly): part of the graph, not of the chain
        h.update(b"isolated" + np.asarray(model.dropped + (model.full_sites,), dtype=np.int64).tobytes())
    h.update(json.dumps([model.sites, U, mu, t, beta, nmax, seed, OFFSET, _TARGET_LEGS,
                         _EXIT_RULE, _GREEN_LEGS, _SCALAR_BINS, _VECTOR_BINS, _SCALARS]).encode())
    return h.hexdigest()


class _Chain:
    """The full state of one Markov chain (what a checkpoint stores)."""

    FIELDS = ("ops", "state", "rng", "sbins", "scur", "sinfo", "vbins", "vcur", "vinfo", "loopstat", "counters",
              "gbins", "gcur", "ginfo")

    def __init__(self, model: _Model, seed: int, green: _Green, length: int = 16, windings: int = 0):
        from . import _sse_kernels as K

        nv = model.sites + model.bi.size + green.ncls
        g = model.sites if green.blocks else 1
        self.gbins = np.zeros((max(green.blocks, 1), g, g))
        self.gcur = np.zeros((g, g))
        self.ginfo = np.array([0, 1, 0], dtype=np.int64)
        # the first string length: a quarter of the expected bound, so that the growth per
        # thermalisation sweep (4/3, or 2 when the string is full) reaches a large string in a few
        # sweeps, not in dozens
        self.ops = np.full(max(16, int(length)), -1, dtype=np.int64)
        self.state = np.zeros(model.sites, dtype=np.int64)
        self.rng = K.seed_state(seed)
        # n, n^2, N, N^2, N^4, E, E^2 (_SCALARS), then with D windings: W_a W_b (a <= b) and (W.W)^2
        ncol = _SCALARS + (windings * (windings + 1) // 2 + 1 if windings else 0)
        self.sbins = np.zeros((_SCALAR_BINS, ncol))
        self.scur = np.zeros(ncol)
        self.sinfo = np.array([0, 1, 0], dtype=np.int64)      # bins filled, bin size, sweeps in current bin
        self.vbins = np.zeros((_VECTOR_BINS, nv))
        self.vcur = np.zeros(nv)
        self.vinfo = np.array([0, 1, 0], dtype=np.int64)
        # decayed legs visited, decayed loops, undone loop updates, loops of a measured sweep with G
        self.loopstat = np.zeros(4)
        # nops, nloops, thermalisation sweeps done, measurement sweeps done
        self.counters = np.array([0, 1, 0, 0], dtype=np.int64)

    def arrays(self) -> dict:
        """The arrays a checkpoint stores."""
        return {k: getattr(self, k) for k in self.FIELDS}

    def save(self, path: Path, meta: dict) -> None:
        """Write the chain to ``path`` atomically, every array under the file's SHA-256 checksum."""
        from . import _checkpoint

        _checkpoint.write(path, meta, self.arrays())

    def restore(self, arrays: dict, model: _Model, nmax: int, where: str) -> None:
        """Take the arrays of a checkpoint (checksum verified by the reader) after checking their
        names, dtypes, shapes and ranges, so that no edited file can reach a kernel with an index
        out of bounds or a configuration that is not a valid world-line picture."""
        def bad(what):
            return ValueError(f"the checkpoint {where} is inconsistent ({what}); delete it to start the chain afresh.")

        if set(arrays) != set(self.FIELDS):
            raise bad("its arrays are not those of a chain")
        for k in self.FIELDS:
            want, got = getattr(self, k), arrays[k]
            if got.dtype != want.dtype or got.ndim != want.ndim or (k != "ops" and got.shape != want.shape):
                raise bad(f"field {k} has dtype {got.dtype} and shape {got.shape}, expected {want.dtype} and "
                          f"{'(M,)' if k == 'ops' else want.shape}")
        ops, state, counters = arrays["ops"], arrays["state"], arrays["counters"]
        m = ops.size
        if m < 16 or 4 * m >= _INT32_MAX:
            raise bad(f"an operator string of length {m}")
        nb = model.bi.size
        kind = ops & 3
        bond = ops >> 2
        if np.any((ops < -1) | ((ops >= 0) & ((bond >= nb) | (kind == 3)))):
            raise bad("an operator that is not -1 or 4 b + k with a bond b and k = 0, 1, 2")
        if np.any((state < 0) | (state > nmax)) or np.any(state[model.degree == 0] != 0):
            raise bad(f"an occupation outside 0..{nmax}")
        # the world lines: every off-diagonal operator moves one boson along its bond; the
        # occupations stay within 0..nmax and come back to the first slice's (periodic in tau)
        offd = (ops >= 0) & (kind != 0)
        sb, sk = bond[offd], kind[offd]
        step = np.where(sk == 1, 1, -1)
        site = np.concatenate([model.bi[sb], model.bj[sb]])
        delta = np.concatenate([step, -step])
        when = np.concatenate([np.flatnonzero(offd)] * 2)
        order = np.lexsort((when, site))
        site, delta = site[order], delta[order]
        run = np.cumsum(delta)
        starts = np.flatnonzero(np.r_[True, site[1:] != site[:-1]]) if site.size else np.zeros(0, dtype=np.int64)
        base = np.repeat(run[starts] - delta[starts], np.diff(np.r_[starts, site.size]))
        occ = state[site] + run - base
        if np.any((occ < 0) | (occ > nmax)):
            raise bad(f"its world lines leave the occupations 0..{nmax}")
        ends = np.r_[starts[1:], site.size][: starts.size] - 1
        if site.size and np.any(occ[ends] != state[site[ends]]):
            raise bad("its world lines are not periodic in imaginary time")
        nops = int(np.count_nonzero(ops >= 0))
        if counters[0] != nops or not 1 <= counters[1] <= 4 * (nops + 16) or np.any(counters[2:] < 0):
            raise bad("its operator and loop counters")
        if not np.any(arrays["rng"]):
            raise bad("a generator state of zeros")
        for k in ("sbins", "scur", "vbins", "vcur", "gbins", "gcur", "loopstat"):
            if not np.all(np.isfinite(arrays[k])):
                raise bad(f"non-finite numbers in {k}")
        loopstat = arrays["loopstat"]
        if np.any(loopstat < 0) or loopstat[3] > 4 * (nops + 16):
            raise bad("its loop statistics")
        sweeps = int(counters[3])
        for info, bins in (("sinfo", "sbins"), ("vinfo", "vbins"), ("ginfo", "gbins")):
            filled, size, cur = (int(x) for x in arrays[info])
            nbins = arrays[bins].shape[0]
            if not (0 <= filled < nbins and size >= 1 and size & (size - 1) == 0 and 0 <= cur < size):
                raise bad(f"its bin counters {info}")
            if (info != "ginfo" or self.gbins.shape[1] > 1) and filled * size + cur != sweeps and model.sites > 1:
                raise bad(f"its bin counters {info} disagree with its {sweeps} measured sweeps")
        # every closed bin holds sums of a quantity and of its square over size sweeps (n, N, E) and
        # of N^2, N^4: sum x^2 >= (sum x)^2 / size, and n, N within the string and the cutoff
        filled, size = int(arrays["sinfo"][0]), int(arrays["sinfo"][1])
        sb = arrays["sbins"][:filled]
        top = float(model.sites) * nmax
        cap = np.array([float(m), float(m) ** 2, top, top ** 2, top ** 4])
        if np.any(sb[:, :5] < 0) or np.any(sb[:, :5] > size * cap * (1 + 1e-12)) or np.any(sb[:, 6] < 0):
            raise bad("its scalar bins lie outside what the chain can produce")
        for a, b in ((0, 1), (2, 3), (3, 4), (5, 6)):
            if np.any(sb[:, b] * size < sb[:, a] ** 2 * (1 - 1e-9)):
                raise bad("its scalar bins are not sums of a quantity and of its square")
        for k in self.FIELDS:
            setattr(self, k, np.array(arrays[k]))

    def green_loops(self) -> int:
        """Loops of a measured sweep with the Green function (the G estimator's budget, set in
        thermalisation for :data:`_GREEN_LEGS`)."""
        return max(int(self.counters[1]), int(self.loopstat[3]))

    def advance(self, K, n: int, thermalize: bool, beta, model, tb, cb, esite, sq, nmax, g: _Green,
                tables, eps, wind) -> None:
        ops, nops, nloops = K.run(n, thermalize, _TARGET_LEGS, self.ops, self.state, int(self.counters[0]),
                                  int(self.counters[1]), beta, model.bi, model.bj, tb, cb, esite, sq, nmax,
                                  self.rng, self.sbins, self.scur, self.sinfo, self.vbins, self.vcur, self.vinfo,
                                  self.loopstat, g.mode, g.gclass, g.zr, g.zi, g.omz, g.hbin, g.ncls,
                                  self.gbins, self.gcur, self.ginfo, model.gauge, tables[0], tables[1],
                                  eps, _GREEN_LEGS, wind)
        self.ops = ops
        self.counters[0] = nops
        self.counters[1] = nloops
        self.counters[2 if thermalize else 3] += n


#: the string's bytes over _BYTES_PER_OP x the bound: the string's growth (old and new arrays at
#: once), the kernel's work arrays, and a mean operator count that can pass the bound (by 9 % on the
#: 847-site flake at beta = 8); the peak RSS of string-dominated chains grew by 83-103 bytes per
#: bound operator (l = 5, 6; benchmarks/qmc_memory_check.py), and 2.5 gives 117
_STRING_MARGIN = 2.5


def _green_bytes(sites: int, measure: bool) -> float:
    """Bytes of the full G(i, j): its bins and running sum (blocks + 1 matrices of M x M floats), and
    12 more: the set-up's class table and the analysis's temporaries (the peak RSS of a chain on
    the 847-site flake grew by about 19.5 M x M floats, benchmarks/qmc_memory_check.py)."""
    if not measure or sites > G_FULL_MAX:
        return 0.0
    blocks = 8 if sites <= 1000 else 4
    return 8.0 * sites * sites * (blocks + 1 + 12)


def _memory_need(model: _Model, beta: float, cb: np.ndarray, nmax: int, U: float, mu: float,
                 measure_green: bool = True) -> tuple[float, float]:
    """(string length bound beta * sum_b max vertex weight, bytes expected for the chain)."""
    n = np.arange(nmax + 1, dtype=float)
    eps = 0.5 * U * n * (n - 1) - mu * n
    z = np.maximum(model.degree, 1).astype(float)
    emin = eps.min() / z
    wmax = np.maximum(cb - emin[model.bi] - emin[model.bj], model.tb * nmax)
    bound = beta * float(wmax.sum()) + 16
    need = (_BYTES_PER_OP * bound * _STRING_MARGIN + 8.0 * (model.sites + model.bi.size) * (_VECTOR_BINS + 8)
            + _green_bytes(model.sites, measure_green))
    return bound, need


#: address space a chain needs besides :func:`qmc_memory`'s count, once numba is loaded: the
#: kernels' machine code and LLVM's JIT engine (about 20 MB on first use) and OpenBLAS's work buffer
#: (32 MB on its first matrix product), measured with /proc/self/status VmSize on Linux x86-64
_RUNTIME_BYTES = 64 * 2**20


def _load_kernels():
    """The numba kernels, imported before the memory check (numba and LLVM map about 170 MB of
    address space), a failure under an address-space limit said in one sentence."""
    try:
        from . import _sse_kernels as K
    except (OSError, MemoryError, ImportError) as exc:
        _, address = _validate.memory_limits()
        if address is None and not isinstance(exc, MemoryError):
            raise
        raise MemoryError(f"loading the quantum Monte Carlo's compiled kernels (numba, LLVM: about 200 MB of "
                          f"address space) failed with {_validate._bytes(_validate.available_memory())} left to "
                          "this process; raise its memory limit (ulimit -v).") from None
    return K


def _check_memory(model: _Model, beta: float, cb: np.ndarray, nmax: int, U: float, mu: float,
                  measure_green: bool = True) -> float:
    """The expected string length bound beta * sum_b max vertex weight; refuse when it won't fit."""
    bound, need = _memory_need(model, beta, cb, nmax, U, mu, measure_green)
    _validate.require_memory(f"the SSE chain (an operator string of up to {bound:,.0f} operators at beta = {beta:g}, "
                             f"its bins and G(i, j), and {_RUNTIME_BYTES // 2**20} MiB for the compiled kernels and BLAS)",
                             need + _RUNTIME_BYTES)
    return bound


def _check_int32(bound: float, beta: float) -> None:
    """Refuse a string whose leg indices could pass the kernels' int32 arrays, before allocating: the
    string holds up to 4/3 of the largest operator count, which may pass the bound (by 9 % seen; 25 %
    allowed), and 4 legs per slot."""
    slots = 4 / 3 * 1.25 * bound + 8
    if 4 * slots >= _INT32_MAX:
        raise ValueError(f"the operator string may reach {slots:,.0f} slots at beta = {beta:g} (4 legs each), beyond "
                         f"the kernels' 32-bit indices ({_INT32_MAX:,}); lower beta, the couplings or the size.")


def _physical_inputs(U, mu, t, beta, nmax) -> tuple:
    """The model's numbers checked at the door, as :func:`qmc` and :func:`qmc_memory` take them."""
    U = _validate.real("U", U)
    mu = _validate.real("mu", mu)
    if isinstance(t, complex) or np.iscomplexobj(t):
        if complex(t).imag != 0:
            raise ValueError("complex hopping (a magnetic flux) gives the quantum Monte Carlo a sign problem; "
                             "use exact diagonalisation or mean field instead.")
        t = complex(t).real
    t = _validate.real("t", t)
    beta = _validate.real("beta", beta)
    if not beta > 0:
        raise ValueError(f"beta must be positive, got {beta!r}.")
    nmax = _validate.integer("nmax", nmax, minimum=1, maximum=1000)
    if t == 0:
        raise ValueError("t = 0 leaves no bond term; the sites are independent (use exact_thermal).")
    return U, mu, t, beta, nmax


def _bonded_model(system, t: float, whole: bool = False) -> "_Model":
    """:func:`_model` of the bonded sites (:func:`_drop_isolated`; ``whole``: of every site), refusing a graph
    without bonds (its sites are independent)."""
    model = _model(system, t, isolated=True)
    if model.bi.size == 0:
        raise ValueError("the graph has no bonds: the sites are independent (use exact_thermal).")
    return model if whole else _drop_isolated(model)


def qmc_memory(system, *, U: float, mu: float, beta: float, nmax: int, t: float = 1.0,
               measure_green: bool = True) -> int:
    r"""Bytes a :func:`qmc` chain is expected to need, as its refusal computes them (nothing is allocated).

    The operator string of the SSE holds about :math:`\beta \sum_b W_b^{\max}` operators at most
    (:math:`W_b^{\max}` the largest vertex weight of bond b, energy unit of t, β its inverse); each
    slot costs the string, vertex, link and leg arrays, with a margin of 2.5 for the string's
    growth, plus the site- and bond-resolved bins and, with ``measure_green`` up to
    :data:`G_FULL_MAX` sites, the bins of the full one-body density matrix and the temporaries of
    its set-up and analysis (21 M x M floats up to 1000 sites, 17 above). :func:`qmc` refuses (MemoryError, one sentence,
    before allocating) when this plus 64 MiB (the compiled kernels' code and LLVM's JIT engine,
    OpenBLAS's work buffer) exceeds the memory the process may still allocate once numba is
    loaded, the address-space limit (``ulimit -v``) included; the sweep task ``qmc`` refuses a
    grid point with this number before the grid runs.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        As in :func:`qmc`.
    U, mu : float
        On-site interaction and chemical potential (units of the hopping).
    beta : float
        Inverse temperature, > 0.
    nmax : int
        Occupation cutoff, >= 1.
    t : float, optional
        Hopping scale (default 1).
    measure_green : bool, optional
        As in :func:`qmc` (default True).

    Returns
    -------
    int
        Bytes, as :func:`qmc`'s refusal counts them (without its fixed 64 MiB).

    Raises
    ------
    ValueError
        On bad input or a sign problem (as :func:`qmc`).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons import qmc_memory
    >>> qmc_memory(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=2.0, nmax=2) < 2**20
    True
    """
    U, mu, t, beta, nmax = _physical_inputs(U, mu, t, beta, nmax)
    measure_green = _validate.flag("measure_green", measure_green)
    model = _bonded_model(system, t)
    _, _, cb = _weights(model, U, mu, nmax)
    _, need = _memory_need(model, beta, cb, nmax, U, mu, measure_green)
    return int(math.ceil(need))


#: CPU seconds per sweep and per operator of the string's bound: 0.2-1.1 us measured on the {7,3}
#: heptagon and the l = 3, 4 flakes (112 and 315 sites, beta = 4-8, nmax = 2-20; 600 sweeps each,
#: the machine loaded to 13 on 2 cores), up to 7.6 us for short runs of 847 sites; 1 us is the
#: estimate's scale, not a bound
SECONDS_PER_OPERATOR = 1e-6


def qmc_seconds(system, *, U: float, mu: float, beta: float, nmax: int, t: float = 1.0, sweeps: int = 20000,
                thermalization: int | None = None) -> float:
    r"""CPU seconds a :func:`qmc` chain is expected to take, estimated before anything runs.

    (thermalization + sweeps) x the string's bound :math:`eta\sum_b W_b^{\max}` (the operators
    of a sweep, see :func:`qmc_memory`) x :data:`SECONDS_PER_OPERATOR`: the scale of a run, right
    within a factor of a few (superfluid strings pass the bound by up to 50 %, large graphs cost
    more per operator). The command line announces a run estimated above 30 s and refuses one
    above ``--max-seconds`` with this number.

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        As in :func:`qmc`.
    U, mu : float
        On-site interaction and chemical potential (units of the hopping).
    beta : float
        Inverse temperature, > 0.
    nmax : int
        Occupation cutoff, >= 1.
    t : float, optional
        Hopping scale (default 1).
    sweeps : int, optional
        Measurement sweeps (default 20000).
    thermalization : int, optional
        Thermalisation sweeps (default ``max(200, sweeps // 5)``, as :func:`qmc`).

    Returns
    -------
    float
        Seconds.

    Raises
    ------
    ValueError
        On bad input (as :func:`qmc`).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons import qmc_seconds
    >>> qmc_seconds(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=2.0, nmax=2, sweeps=4000) < 5
    True
    """
    U, mu, t, beta, nmax = _physical_inputs(U, mu, t, beta, nmax)
    sweeps = _validate.integer("sweeps", sweeps, minimum=1)
    if thermalization is None:
        thermalization = max(200, sweeps // 5)
    thermalization = _validate.integer("thermalization", thermalization, minimum=0)
    model = _bonded_model(system, t)
    _, _, cb = _weights(model, U, mu, nmax)
    bound, _ = _memory_need(model, beta, cb, nmax, U, mu, False)
    return float((thermalization + sweeps) * bound * SECONDS_PER_OPERATOR)


def qmc(system, *, U: float, mu: float, beta: float, nmax: int, t: float = 1.0, sweeps: int = 20000,
        thermalization: int | None = None, seed: int | None = None, checkpoint=None,
        measure_green: bool = True, windings=None, progress=None) -> QMCResult:
    r"""Grand-canonical SSE quantum Monte Carlo of the Bose–Hubbard model (one Markov chain).

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        A flake (:func:`~hyperlattice.ring_lattice`), a periodic cluster
        (:func:`~hyperlattice.graph.clusters.pbc_cluster`) or a symmetric adjacency matrix (bond
        hopping :math:`t_{ij} = t A_{ij}`; negative entries only when a gauge removes the signs).
    U, mu : float
        On-site interaction and chemical potential (units of the hopping).
    beta : float
        Inverse temperature, > 0.
    nmax : int
        Occupation cutoff, >= 1 (1: hard-core bosons).
    t : float, optional
        Hopping scale (default 1). t < 0 is accepted on bipartite graphs only.
    sweeps : int, optional
        Measurement sweeps (default 20000).
    thermalization : int, optional
        Thermalisation sweeps (default ``max(200, sweeps // 5)``), during which the string
        length and the loops per sweep adapt; they are frozen afterwards. 0 is refused (the
        estimates would be biased) unless resuming a thermalised checkpoint; a resumed chain that
        has begun measuring keeps the thermalisation it did (another explicit value is refused).
    seed : int, optional
        Seed of the chain's generator; None draws one (stored in the result, and in the
        checkpoint, from which a rerun without a seed reads it back).
    checkpoint : str or path, optional
        A directory, locked for the run: the chain state is saved there at the start, every
        minute, at the end and on SIGINT/SIGTERM (then ``KeyboardInterrupt`` is raised, saying
        so), under a SHA-256 of every array, written atomically. A rerun with the same physics
        and seed (``sweeps`` may grow) resumes from it, bit-identically to an uninterrupted run;
        a checkpoint of other parameters, damaged, or edited is refused in one sentence.
    measure_green : bool, optional
        Measure the equal-time one-body density matrix :math:`G(i,j)` with the worm estimator of
        the directed loops (default True; see Notes), by distance class, and the full matrix and
        the condensate fraction up to :data:`G_FULL_MAX` sites.
    windings : Windings or (edges, windings) or False, optional
        Integer windings :math:`w_b \in \mathbb Z^D` of the bonds for the superfluid stiffness
        (see Notes): by default those of a periodic cluster
        (:func:`~hyperlattice.graph.bands.edge_windings`) and none for a flake or a matrix; for an
        adjacency matrix give a :class:`~hyperlattice.graph.bands.Windings` or a pair of integer
        arrays ``(edges (E, 2), w (E, D))``, w the winding of the directed edge
        ``edges[k, 0] -> edges[k, 1]``, every bond once (the L x L torus:
        :func:`hyperlattice.compare.qmc_lobe.square_lattice_windings`). False: not measured.
    progress : bool, optional
        Progress bar on stderr (default: when a terminal watches, see :mod:`hyperlattice._progress`).

    Returns
    -------
    QMCResult

    Raises
    ------
    ValueError
        On bad input, a sign problem, a string beyond the kernels' 32-bit indices, or a
        checkpoint of another run, damaged, inconsistent or in use.
    KeyboardInterrupt
        On SIGINT or SIGTERM (in the main thread), after the checkpoint was saved.
    MemoryError
        When the operator string (about :math:`\beta \sum_b W_b^{\max}` operators) will not fit.

    Warns
    -----
    QMCWarning
        When a binning error has not reached its plateau or the two halves of the measurements
        disagree by more than 4σ (thermalisation in doubt).

    Notes
    -----
    Errors come from a binning analysis (:mod:`hyperlattice.mcstats`) of up to 2048 bins per
    chain; κ and other derived quantities from the jackknife of the plateau-level bins. Sweeps
    beyond the last complete bin (fewer than ``bin_size``) are not counted in the averages.

    **Superfluid stiffness.** A flat U(1) connection on the graph, a phase :math:`\theta\cdot w_b`
    on the hopping :math:`a_j^\dagger a_i` along each directed bond (:math:`\theta \in \mathbb R^D`),
    is a twist :math:`\theta_a` around the a-th non-contractible cycle when :math:`w_b \in \mathbb Z^D`
    is an integer 1-cocycle whose sum along a closed walk is the walk's homology class (its
    coordinates in a basis of :math:`H_1(\Sigma;\mathbb Z) = \mathbb Z^D`; D = 2 on a torus,
    D = 2g on a closed orientable surface of genus g; the cluster windings come from a
    tree-cotree decomposition, :func:`~hyperlattice.graph.bands.edge_windings`). In the expansion
    every off-diagonal operator then carries :math:`e^{\pm i\theta\cdot w_b}`, a configuration
    the phase :math:`e^{i\theta\cdot W}` with W the total winding of its world lines (an
    integer vector), so :math:`Z(\theta)/Z(0) = \langle e^{i\theta\cdot W}\rangle` exactly and,
    with :math:`\langle W\rangle = 0` (time reversal),

    .. math::

        F(\theta) - F(0) = \tfrac12 \theta^{\mathsf T}\Upsilon\theta + O(\theta^4), \qquad
        \Upsilon_{ab} = \frac{\langle W_a W_b\rangle}{\beta}.

    On the d-dimensional torus this is Pollock and Ceperley's winding-number formula (PRB 36,
    8343 (1987)), :math:`\rho_s = \langle W^2\rangle L^{2-d}/(d\beta)`; for the L x L square
    torus (d = 2) the twist free energy of a uniform phase gradient :math:`\theta/L` is
    :math:`\tfrac12\rho_s\theta^2` per direction, so :math:`\Upsilon = \rho_s` and
    ``rho_s`` = :math:`\langle W_x^2 + W_y^2\rangle/(2\beta)`. On a genus-g surface the same
    expansion defines :math:`\Upsilon` as the response to twists around the 2g cycles of the
    homology basis (no length factors: a cluster has no uniform phase gradient); it is a
    bilinear form on :math:`H^1(\Sigma;\mathbb R)`, so its matrix depends on the basis, and
    ``stiffness_geometric`` :math:`= (\det\Upsilon)^{1/D}` does not (an integer change of basis
    has determinant ±1). It is exact at every β on the finite graph (the thermal response, not
    only the ground state's). An open flake has no non-contractible cycle (W = 0 always): there
    the condensate fraction is the superfluid indicator; an adjacency matrix carries no windings
    unless they are given.

    Sites without bonds (an adjacency with empty rows) are independent single-site problems: the
    chain runs on the bonded sites, and each site without bonds adds its exact thermal averages
    (those of :func:`exact_thermal` on one site) to the energy, the density, the compressibility
    (the variances of independent parts add), the site densities and G(i, i), with G(i, j) = 0 to
    every other site; a note says so. (The loops could not sample such a site: they draw the
    occupation of a site that no operator touches uniformly, the right weight for a bonded site,
    whose on-site energy lives in its bond vertices, and the wrong one for a site without bonds.)
    A graph without any bond is refused (use :func:`exact_thermal`). A self-loop (a diagonal entry
    of the adjacency) is refused: an on-site energy belongs in μ.

    The one-body density matrix comes from the loop construction (Dorneich & Troyer, PRE 64,
    066701 (2001); in the directed-loop form of Syljuåsen & Sandvik, PRE 66, 046701 (2002) and
    Syljuåsen, PRE 67, 046701 (2003)). At each position of the head (after every exit from a
    vertex), when head and tail lie on segments of two different sites, the kernel adds

    .. math::

        X_{kl} = N_{\mathrm{gap}} \sqrt{n_k^>\, n_l^>}

    to :math:`G_{kl}` (k the site whose segment jumps up by one, :math:`a_k^\dagger`; :math:`n^>`
    the larger occupation on each discontinuous segment; :math:`N_{\mathrm{gap}}` the number of
    gaps between consecutive operators that both segments span), and the estimator is

    .. math::

        \langle a_k^\dagger a_l\rangle = \frac{2}{N_{\mathrm{loops}}}\Big\langle\sum_{\text{head positions}}
        X_{kl}\Big\rangle ,

    :math:`N_{\mathrm{loops}}` every loop started, aborted starts included. The factor 2 follows
    from the loop's weights:

    1. *Open configurations.* A loop in progress is a string with two unit discontinuities, the
       tail (where it started) and the head, each on a segment (a piece of one site's worldline
       between two consecutive vertices). Its weight is :math:`W(Y) = \prod_v W_v`, every vertex
       with its own leg states (times the factor :math:`\beta^n (M_L - n)!/M_L!` that every
       configuration of n operators in a string of length :math:`M_L` shares). The directed-loop equations
       :math:`W_v(s) P(e \to x\,|\,s) = W_v(s') P(x \to e\,|\,s')` balance each step of the head
       against the reversed step (the head on the same segment, moving the other way), so the
       stationary measure of an open state is :math:`c\,W(Y)` for either direction of the head,
       with one constant c.
    2. *The constant.* A loop starts from a closed configuration C at one of the 4n legs with one
       of the two changes ±1 (probability :math:`1/(8n)`) and makes its first exit; the reverse is
       the last exit of a loop that heals the tail at that leg. Balancing the two with the vertex
       equation gives :math:`c = \pi(C)/(8n\,W(C))`: per closed configuration visited, i.e. per loop
       started, a directed open state is visited :math:`W(Y)/(8nZ)` times on average,
       :math:`Z = \sum_C W(C)`. The start leg is not part of the state: the same Y follows from a
       start at either end of the tail's segment (from two different C), and nothing after the
       start depends on which.
    3. *Counting.* One physical configuration with :math:`a_k^\dagger` on a segment of site k and
       :math:`a_l` on a segment of site :math:`l \ne k` is four directed states: either
       discontinuity can be the head, and the head can move up or down its segment. Per loop the
       estimator's sum therefore has mean :math:`\sum_Y 4\,W(Y) X_{kl}(Y)/(8nZ)`.
    4. *The observable.* :math:`\mathrm{Tr}(a_k^\dagger a_l e^{-\beta H}) = \sum_n \frac{\beta^n}{n!}
       \mathrm{Tr}(a_k^\dagger a_l H^n)`; by the cyclic trace the pair can sit in any of the n gaps
       of the string, each with weight 1/n, and its matrix elements are
       :math:`\sqrt{n_k^>}\sqrt{n_l^>}`, so :math:`\langle a_k^\dagger a_l\rangle = \sum_Y W(Y)
       X_{kl}(Y)/(nZ)`.

    Comparing 3 and 4, the sum per loop has mean :math:`\langle a_k^\dagger a_l\rangle/2`: the
    factor is 2 = 8/4. (An earlier count took the start leg as part of the state, eight directed
    states per configuration, and predicted 1.) Nothing in it depends on whether k and l are
    neighbours, on the cutoff (the loop moves one boson at a time, so each discontinuity is one
    :math:`a^\dagger` or :math:`a` with matrix element :math:`\sqrt{n^>}`) or on the graph; the tests
    compare G(i, j) with :func:`exact_thermal` for neighbours and farther pairs at nmax = 1, 2, 3
    (``tests/test_qmc_green.py``, ``tests/test_qmc_sse.py``), and the nearest-neighbour value with
    the independent estimator ``bond_kinetic`` from the operator counts.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons import qmc
    >>> r = qmc(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=2.0, nmax=2, sweeps=4000, seed=1, progress=False)
    >>> r.sites, abs(r.density - 0.97273) < 4 * r.density_err   # exact_thermal: 0.97273
    (7, True)
    """
    U, mu, t, beta, nmax = _physical_inputs(U, mu, t, beta, nmax)
    sweeps = _validate.integer("sweeps", sweeps, minimum=1)
    if thermalization is not None:
        thermalization = _validate.integer("thermalization", thermalization, minimum=0)
    if seed is not None:
        seed = _validate.integer("seed", seed, minimum=0)
    measure_green = _validate.flag("measure_green", measure_green)
    whole = _bonded_model(system, t, whole=True)
    wind, wind_note = _bond_windings(system, whole, windings)
    model = _drop_isolated(whole)           # the chain runs on the bonded sites (the bonds keep their order)
    eps, esite, cb = _weights(model, U, mu, nmax)
    K = _load_kernels()          # before the check: the available memory is then what the chain has
    bound = _check_memory(model, beta, cb, nmax, U, mu, measure_green)
    _check_int32(bound, beta)
    ckdir = None if checkpoint is None else _validate.directory("checkpoint", checkpoint)
    with contextlib.ExitStack() as stack:
        if ckdir is not None:
            from . import _checkpoint

            stack.enter_context(_checkpoint.locked(ckdir, _LOCK_FILE))
        stop = stack.enter_context(_stop_signals())
        result = _run_chain(K, model, wind, wind_note, eps, esite, cb, bound, stop, ckdir, system_args=dict(
            U=U, mu=mu, t=t, beta=beta, nmax=nmax, sweeps=sweeps, thermalization=thermalization, seed=seed,
            measure_green=measure_green, progress=progress))
    return _add_isolated(result, whole, eps, beta) if model.dropped else result


def _add_isolated(r: QMCResult, whole: _Model, eps: np.ndarray, beta: float) -> QMCResult:
    """The result on the whole graph from the chain of its bonded sites (:func:`_drop_isolated`).

    A site without bonds is an independent single-site problem with the exact thermal averages of
    :func:`_isolated`: they are added to the energy, to N and to var N (the sites are independent
    of the rest, so the variances add), the site densities and G(i, i) = <n_i>; G(i, j) = 0 between
    it and any other site (the pairs of the distance class inf). The chain's error bars carry over
    (an exact term has none); the condensate fraction max(lambda_max(G_b), <n_i>) / Tr G is
    propagated to first order, linearly (conservatively) in the chain's fraction and trace.
    """
    e_iso, n_iso, var_iso, dens = _isolated(whole, eps, beta)
    n, mb = whole.sites, r.sites
    keep = np.flatnonzero(whole.degree > 0)
    iso = np.flatnonzero(whole.degree == 0)
    sd_err = np.zeros(n)
    sd = dens.copy()
    sd[keep], sd_err[keep] = r.site_density, r.site_density_err
    out = {"sites": n, "energy": r.energy + e_iso, "density": (r.density * mb + n_iso) / n,
           "density_err": r.density_err * mb / n,
           "compressibility": (r.compressibility * mb + beta * var_iso) / n,
           "compressibility_err": r.compressibility_err * mb / n, "site_density": sd, "site_density_err": sd_err,
           "bonds": keep[r.bonds],
           "notes": r.notes + (f"{iso.size} site(s) without bonds (e.g. site {int(iso[0])}) are independent: their "
                               "exact single-site thermal averages are added (energy, density, compressibility, "
                               "site densities, G(i, i)).",)}
    if r.green is not None:
        extra = n * (n - 1) - mb * (mb - 1)          # ordered pairs with a site without bonds: G = 0
        dist, g, g_err, pairs = (np.asarray(a, float) for a in (r.green_distance, r.green, r.green_err,
                                                                r.green_pairs))
        if dist.size and np.isinf(dist[-1]):
            tot = pairs[-1] + extra
            g, g_err = g.copy(), g_err.copy()
            g[-1], g_err[-1] = g[-1] * pairs[-1] / tot, g_err[-1] * pairs[-1] / tot
            pairs = np.concatenate([pairs[:-1], [tot]])
        else:
            dist, g, g_err = (np.append(a, v) for a, v in ((dist, np.inf), (g, 0.0), (g_err, 0.0)))
            pairs = np.append(pairs, extra)
        out.update(green_distance=dist, green=g, green_err=g_err,
                   green_pairs=pairs.astype(np.asarray(r.green_pairs).dtype))
    n1 = n_iso / iso.size
    if r.green_matrix is not None:
        gm = np.zeros((n, n))
        gm[np.ix_(keep, keep)] = r.green_matrix
        gm[iso, iso] = n1
        out["green_matrix"] = gm
        tr = float(np.trace(r.green_matrix))
    else:
        tr = r.density * mb
    cf, cf_err = r.condensate_fraction, r.condensate_fraction_err
    if math.isfinite(cf):
        s_tr = r.density_err * mb
        den = tr + n_iso
        lam = cf * tr
        bonded = (cf * tr / den, cf_err * tr / den + cf * n_iso / den ** 2 * s_tr)     # lambda_max from G_b
        single = (n1 / den, n1 / den ** 2 * s_tr)                                       # lambda_max = <n_i>
        tie = abs(lam - n1) <= 2 * (cf_err * tr + cf * s_tr) if math.isfinite(cf_err) else False
        best = bonded if lam >= n1 else single
        out["condensate_fraction"] = best[0]
        out["condensate_fraction_err"] = max(bonded[1], single[1]) if tie else best[1]
    import dataclasses

    return dataclasses.replace(r, **out)


def _stop_signals():
    from ._checkpoint import StopSignals

    return StopSignals()


def _draw_seed() -> int:
    return int(np.random.SeedSequence().entropy % (2**63))


def _run_chain(K, model, wind, wind_note, eps, esite, cb, bound, stop, ckdir, system_args) -> QMCResult:
    """The chain of :func:`qmc` from its checkpoint (if any) to the end, stopping cleanly on a signal."""
    a = system_args
    U, mu, t, beta, nmax, sweeps = a["U"], a["mu"], a["t"], a["beta"], a["nmax"], a["sweeps"]
    thermalization, seed, measure_green = a["thermalization"], a["seed"], a["measure_green"]
    ckpt = None if ckdir is None else ckdir / _CHECKPOINT_FILE
    stored = None
    if ckpt is not None and ckpt.exists():
        from . import _checkpoint

        stored = _checkpoint.read(ckpt)
        if seed is None:      # the seed drawn by the first run of this directory
            seed = stored[0].get("seed")
            if not isinstance(seed, int) or isinstance(seed, bool) or seed < 0:
                raise ValueError(f"the checkpoint {str(ckpt)!r} is inconsistent (no seed); delete it to start the "
                                 "chain afresh.")
    if seed is None:
        seed = _draw_seed()
    sq = np.sqrt(np.arange(nmax + 2, dtype=float))
    green = _green_setup(model, measure_green)
    tables = _exit_tables(model, esite, cb, nmax, sq)
    chain = _Chain(model, seed, green, length=min(bound / 4, 1e8), windings=wind.shape[1])
    fp = _fingerprint(model, U, mu, t, beta, nmax, seed, wind) + f"-green{int(measure_green)}"
    params = {"system": model.label, "sites": model.sites, "U": U, "mu": mu, "t": t, "beta": beta, "nmax": nmax,
              "seed": seed, "measure_green": measure_green, "windings": int(wind.shape[1])}
    if stored is not None:
        meta, arrays = stored
        if meta.get("fingerprint") != fp:
            old = meta.get("parameters", {}) if isinstance(meta.get("parameters"), dict) else {}
            diff = [f"{k} = {old[k]!r} there, {v!r} here" for k, v in params.items() if k in old and old[k] != v]
            raise ValueError(f"the checkpoint {str(ckpt)!r} belongs to a run with other parameters "
                             f"({'; '.join(diff) if diff else 'another graph, couplings or windings'}); use another "
                             "directory, or delete it to start afresh.")
        chain.restore(arrays, model, nmax, repr(str(ckpt)))
        if chain.counters[3] > sweeps:
            raise ValueError(f"the checkpoint already holds {int(chain.counters[3])} measured sweeps, more than "
                             f"the {sweeps} asked for.")
    done_therm, measuring = int(chain.counters[2]), bool(chain.counters[3] > 0)
    if measuring:
        # thermalisation ended when the measurements began: more sweeps continue the same chain
        if thermalization not in (None, 0, done_therm):
            raise ValueError(f"the checkpoint's chain was thermalised for {done_therm} sweeps before it began "
                             f"measuring, not {thermalization}; rerun with thermalization {done_therm} or without it.")
        thermalization = done_therm
    else:
        if thermalization is None:
            thermalization = max(200, sweeps // 5)
        if thermalization == 0 and done_therm == 0:
            raise ValueError("thermalization 0 measures the starting configuration: the string length and the "
                             "loops per sweep adapt only while thermalising, so every estimate would be biased; "
                             "give thermalization >= 1 (default max(200, sweeps/5)) or resume a thermalised "
                             "checkpoint.")
        thermalization = max(thermalization, done_therm)

    def meta():
        return {"fingerprint": fp, "seed": seed, "thermalization": thermalization, "parameters": params}

    def stop_now():
        done = int(chain.counters[2] + chain.counters[3])
        if ckpt is not None:
            chain.save(ckpt, meta())
            kept = f"the chain is saved in {str(ckdir)!r}: rerun the same command to resume"
        else:
            kept = "nothing kept (a checkpoint directory, --checkpoint DIR, keeps the chain for a rerun)"
        stop.reraise(f"stopped after {done:,} of {thermalization + sweeps:,} sweeps; {kept}")

    if ckpt is not None and stored is None:
        chain.save(ckpt, meta())          # the directory belongs to this run from now on
    if stop.signum is not None:
        stop_now()
    start = time.perf_counter()
    last_save = start
    total = thermalization + sweeps
    with progress_bar(total, "qmc", unit="sweep", progress=a["progress"]) as bar:
        bar.update(int(chain.counters[2] + chain.counters[3]))
        chunk = 1         # the first sweeps of a long string may be slow: answer a signal soon
        while chain.counters[2] < thermalization or chain.counters[3] < sweeps:
            therm = bool(chain.counters[2] < thermalization)
            left = (thermalization - chain.counters[2]) if therm else (sweeps - chain.counters[3])
            n = int(min(chunk, left))
            t0 = time.perf_counter()
            chain.advance(K, n, therm, beta, model, model.tb, cb, esite, sq, nmax, green, tables, eps, wind)
            dt = time.perf_counter() - t0
            bar.update(n)
            if 4 * chain.ops.size >= _INT32_MAX:
                raise HyperlatticeError(f"the operator string grew to {chain.ops.size:,} slots, beyond the kernels' "
                                        "32-bit leg indices; lower beta or the couplings.")
            if stop.signum is not None:
                stop_now()
            # chunks of about half a second (the split never changes the chain)
            chunk = int(max(1, min(4 * chunk, n * 0.5 / max(dt, 1e-6))))
            if ckpt is not None and time.perf_counter() - last_save > _CHECKPOINT_SECONDS:
                chain.save(ckpt, meta())
                last_save = time.perf_counter()
    if ckpt is not None:
        chain.save(ckpt, meta())
    seconds = time.perf_counter() - start
    return _analyse(chain, model, U=U, mu=mu, t=t, beta=beta, nmax=nmax, sweeps=sweeps,
                    thermalization=int(chain.counters[2]), seed=seed, cb=cb, eps=eps, seconds=seconds, green=green,
                    ndim=int(wind.shape[1]), wind_note=wind_note)


def _stiffness(raw: np.ndarray, bs: int, beta: float, d: int, notes: list) -> dict:
    """Stiffness tensor, tr/D and det^(1/D) with errors from the winding moments in ``raw[:, _SCALARS:]``."""
    iu = np.triu_indices(d)
    ncol = iu[0].size
    mom = raw[:, _SCALARS:_SCALARS + ncol] / beta                       # bin means of W_a W_b / beta
    Y = np.zeros((d, d))
    Yerr = np.zeros((d, d))
    for k, (a, b) in enumerate(zip(*iu)):
        bb = mcstats.binning(mom[:, k], bs)
        Y[a, b] = Y[b, a] = bb.mean
        Yerr[a, b] = Yerr[b, a] = bb.error
    diag = np.flatnonzero(iu[0] == iu[1])
    ww = raw[:, _SCALARS + diag].sum(axis=1)                     # bin means of W.W
    var = max(float(raw[:, _SCALARS + ncol].mean()) - float(ww.mean()) ** 2, 0.0)
    rs = mcstats.binning(ww / (d * beta), bs, variance=var / (d * beta) ** 2)
    if not rs.converged:
        notes.append(f"the binning error of the stiffness has not reached a plateau ({raw.shape[0] * bs} sweeps, "
                     f"tau_int = {rs.tau_int:.3g} sweeps): run longer.")
    plateau = mcstats.plateau_bins(mom)

    def geometric(m):
        y = np.zeros((d, d))
        y[iu] = m
        y = y + np.triu(y, 1).T
        return float(max(np.linalg.det(y), 0.0) ** (1.0 / d))

    geo, geo_err = mcstats.jackknife(geometric, plateau)
    return dict(stiffness=Y, stiffness_err=Yerr, rho_s=float(rs.mean), rho_s_err=float(rs.error),
                stiffness_geometric=float(geo), stiffness_geometric_err=float(geo_err), stiffness_note="",
                tau=float(rs.tau_int), converged=bool(rs.converged))


def _analyse(chain: _Chain, model: _Model, *, U, mu, t, beta, nmax, sweeps, thermalization, seed, cb, eps,
             seconds, green: _Green, ndim: int = 0, wind_note: str = "") -> QMCResult:
    nb, bs = int(chain.sinfo[0]), int(chain.sinfo[1])
    notes = []
    if nb < 2:
        raise HyperlatticeError("too few sweeps for an error estimate (fewer than two complete bins).")
    raw = chain.sbins[:nb] / bs                    # bin means of n, n^2, N, N^2, N^4, E, E^2
    e_iso, n_iso, var_iso, dens_iso = _isolated(model, eps, beta)
    M = model.sites
    nsw = nb * bs
    mean = raw.mean(axis=0)
    var_N = max(mean[3] - mean[2] ** 2, 0.0)
    var_N2 = max(mean[4] - mean[3] ** 2, 0.0)
    var_E = max(mean[6] - mean[5] ** 2, 0.0)
    en = mcstats.binning(raw[:, 5] + e_iso, bs, variance=var_E)
    de = mcstats.binning((raw[:, 2] + n_iso) / M, bs, variance=var_N / M ** 2)
    n2 = mcstats.binning(raw[:, 3], bs, variance=var_N2)
    plateau = mcstats.plateau_bins(raw[:, 2:4])
    kap, _ = mcstats.jackknife(lambda a, b: beta * (b - a * a) / M, plateau[:, 0], plateau[:, 1])
    kap += beta * var_iso / M
    # its error: the Gamma method on the linearised bins beta (N^2 - 2 <N> N) / M (the jackknife over
    # the 32-63 plateau bins shares their finite-length bias, see hyperlattice.mcstats)
    kap_err = mcstats.binning(beta * (raw[:, 3] - 2.0 * mean[2] * raw[:, 2]) / M, bs).error
    tau = {"energy": en.tau_int, "density": de.tau_int, "compressibility": n2.tau_int}
    converged = True
    stiff = {"stiffness_note": wind_note}
    if ndim:
        stiff = _stiffness(raw, bs, beta, ndim, notes)
        stiff["stiffness_note"] = wind_note        # "" or which components were skipped
        tau["stiffness"] = stiff.pop("tau")
        converged = stiff.pop("converged")
    for name, b in (("energy", en), ("density", de), ("N^2", n2)):
        if not b.converged:
            converged = False
            notes.append(f"the binning error of {name} has not reached a plateau ({nsw} sweeps, tau_int = "
                         f"{b.tau_int:.3g} sweeps): run longer.")
    # thermalisation check: the halves of the measurement phase agree
    pl = mcstats.plateau_bins(np.stack([raw[:, 5], raw[:, 2] / M], axis=1))
    h = pl.shape[0] // 2
    if h >= 2:
        for k, name in ((0, "energy"), (1, "density")):
            a, b = pl[:h, k], pl[h:2 * h, k]
            sa = a.std(ddof=1) / math.sqrt(h)
            sb = b.std(ddof=1) / math.sqrt(h)
            diff = abs(a.mean() - b.mean())
            if diff > 4 * math.hypot(sa, sb) and diff > 1e-12 * (1 + abs(a.mean())):
                converged = False
                notes.append(f"the {name} of the first and second half of the measurements differ by "
                             f"{diff / math.hypot(sa, sb):.1f} sigma: thermalisation ({thermalization} sweeps) "
                             "was too short.")
    # the string length M is frozen after thermalisation: a string that was still filling up (bins
    # whose mean n comes within 10 % of M) truncated the expansion, and every estimate is biased
    length = int(chain.ops.shape[0])
    if chain.loopstat[2] > 0:
        converged = False
        notes.append(f"{int(chain.loopstat[2])} sweep(s) had a directed loop longer than the cap (200 x the "
                     "number of vertex legs) and their loop update was undone: the configuration was far from "
                     "equilibrium; run with more thermalization sweeps.")
    if nb and float(raw[:, 0].max()) > 0.9 * length:
        converged = False
        notes.append(f"the operator string (length {length}) was nearly full during the measurements "
                     f"(up to {float(raw[:, 0].max()):.0f} operators): thermalisation ({thermalization} sweeps) was "
                     "too short for it to grow; the results are biased, run with more thermalization sweeps.")
    vnb, vbs = int(chain.vinfo[0]), int(chain.vinfo[1])
    vb = chain.vbins[:vnb] / vbs
    sd = vb[:, :M].mean(axis=0) + dens_iso
    sd_err = vb[:, :M].std(axis=0, ddof=1) / math.sqrt(vnb) if vnb > 1 else np.full(M, np.nan)
    nbd = model.bi.size
    kin_scale = model.gauge[model.bi] * model.gauge[model.bj] / (beta * model.tb)
    kin = vb[:, M:M + nbd].mean(axis=0) * kin_scale
    kin_err = (vb[:, M:M + nbd].std(axis=0, ddof=1) / math.sqrt(vnb) if vnb > 1 else np.nan) * np.abs(kin_scale)
    nloops = float(chain.green_loops())     # loops of a measured sweep with G
    g_dist = g_val = g_err = g_pairs = None
    g_mat = None
    cf = cf_err = math.nan
    if green.mode:
        keep = green.pairs > 0
        per = vb[:, M + nbd:][:, keep] / (nloops * green.pairs[keep])
        g_dist, g_pairs = green.distance[keep], green.pairs[keep]
        g_val = per.mean(axis=0)
        g_err = per.std(axis=0, ddof=1) / math.sqrt(vnb) if vnb > 1 else np.full(g_val.shape, np.nan)
    if green.note:
        notes.append(green.note)
    if green.blocks:
        gnb, gbs = int(chain.ginfo[0]), int(chain.ginfo[1])
        blocks = chain.gbins[:gnb] / gbs
        eye = np.eye(M, dtype=bool)
        sgn = np.outer(model.gauge, model.gauge)

        def physical(gsum):
            g = np.where(eye, gsum, gsum / nloops)
            return 0.5 * (g + g.T) * sgn

        def fraction(gmean):
            g = physical(gmean)
            return float(np.linalg.eigvalsh(g)[-1] / np.trace(g))

        g_mat = physical(blocks.mean(axis=0)) + np.diag(dens_iso)
        if gnb >= 2:
            cf, cf_err = mcstats.jackknife(fraction, blocks)
        else:
            cf = fraction(blocks.mean(axis=0))
    for note in notes:
        if note != green.note:
            warnings.warn(note, QMCWarning, stacklevel=3)
    return QMCResult(
        system=model.label, sites=M, U=U, mu=mu, t=t, beta=beta, nmax=nmax, sweeps=sweeps,
        thermalization=thermalization, seed=seed, seeds=(seed,), chains=1,
        energy=en.mean, energy_err=en.error, density=de.mean, density_err=de.error,
        compressibility=float(kap), compressibility_err=float(kap_err), tau_int=tau,
        bins=int(plateau.shape[0]), bin_size=int(bs * (nb // plateau.shape[0])), converged=converged,
        notes=tuple(notes), site_density=sd, site_density_err=sd_err,
        bonds=np.stack([model.bi, model.bj], axis=1), bond_kinetic=kin, bond_kinetic_err=kin_err,
        green_distance=g_dist, green=g_val, green_err=g_err, green_pairs=g_pairs,
        distance_kind=green.kind, green_matrix=g_mat, condensate_fraction=float(cf),
        condensate_fraction_err=float(cf_err),
        mean_operators=float(mean[0]), string_length=int(chain.ops.size), loops_per_sweep=int(chain.counters[1]),
        seconds=float(seconds), bond_hopping=model.tb * model.gauge[model.bi] * model.gauge[model.bj], **stiff)


def merge_chains(results) -> QMCResult:
    r"""Merge independent chains (same model, different seeds) into one result.

    Each chain is an unbiased estimate; the merged value is the sweep-weighted mean
    :math:`\bar x = \sum_c s_c x_c / S` with :math:`\sigma = \sqrt{\sum_c s_c^2\sigma_c^2}/S`
    (:func:`hyperlattice.mcstats.combine_independent`), per observable and per site.

    Parameters
    ----------
    results : sequence of QMCResult
        Chains of the same model (system, sites, U, mu, t, beta, nmax), distinct seeds.

    Returns
    -------
    QMCResult
        ``chains`` = their number, ``sweeps`` and ``seconds`` summed, ``seed`` None and ``seeds``
        all seeds; ``tau_int`` the sweep-weighted mean; ``converged`` only if every chain was.

    Raises
    ------
    ValueError
        If the list is empty, holds other objects, chains of different models (the bonds' couplings
        included), or a seed twice.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons import merge_chains, qmc
    >>> runs = [qmc(hl.ring_lattice(7, 3, 1), U=4.0, mu=1.0, beta=1.0, nmax=2, sweeps=2000, seed=s,
    ...             progress=False) for s in (1, 2)]
    >>> m = merge_chains(runs)
    >>> m.chains, m.sweeps, m.seeds
    (2, 4000, (1, 2))
    """
    if isinstance(results, QMCResult):
        res = [results]
    elif isinstance(results, (list, tuple)):
        res = list(results)
    else:
        raise ValueError("results must be a list of QMCResult (independent chains of one model).")
    if not res or not all(isinstance(r, QMCResult) for r in res):
        raise ValueError("merge_chains takes a non-empty list of QMCResult.")
    ref = res[0]
    for r in res[1:]:
        for k in ("system", "sites", "U", "mu", "t", "beta", "nmax"):
            if getattr(r, k) != getattr(ref, k):
                raise ValueError(f"merge_chains needs chains of one model; {k} differs ({getattr(ref, k)!r} vs "
                                 f"{getattr(r, k)!r}).")
        if r.bonds.shape != ref.bonds.shape or not np.array_equal(r.bonds, ref.bonds):
            raise ValueError("merge_chains needs chains of one model; the bonds differ.")
        # the couplings are inputs (not computed), so they are compared exactly
        if (r.bond_hopping is None) != (ref.bond_hopping is None) or (
                r.bond_hopping is not None and not np.array_equal(r.bond_hopping, ref.bond_hopping)):
            raise ValueError("merge_chains needs chains of one model; the bonds are the same but their couplings "
                             "t_ij differ (or are unknown for some chains).")
    seeds = tuple(s for r in res for s in r.seeds)
    if len(set(seeds)) != len(seeds):
        raise ValueError("merge_chains needs independent chains, but a seed occurs twice.")
    w = np.array([r.sweeps for r in res], dtype=float)
    vals = {}
    for name in ("energy", "density", "compressibility"):
        vals[name], vals[name + "_err"] = mcstats.combine_independent(
            [getattr(r, name) for r in res], [getattr(r, name + "_err") for r in res], w)
    tot = w.sum()
    sd = sum(wc * r.site_density for wc, r in zip(w, res)) / tot
    sd_err = np.sqrt(sum((wc * r.site_density_err) ** 2 for wc, r in zip(w, res))) / tot
    kin = sum(wc * r.bond_kinetic for wc, r in zip(w, res)) / tot
    kin_err = np.sqrt(sum((wc * r.bond_kinetic_err) ** 2 for wc, r in zip(w, res))) / tot
    tau = {k: float(sum(wc * r.tau_int.get(k, math.nan) for wc, r in zip(w, res)) / tot) for k in ref.tau_int}
    g = {"green_distance": ref.green_distance, "green_pairs": ref.green_pairs, "distance_kind": ref.distance_kind,
         "green": None, "green_err": None, "green_matrix": None}
    if all(r.green is not None and r.green.shape == ref.green.shape for r in res):
        g["green"] = sum(wc * r.green for wc, r in zip(w, res)) / tot
        g["green_err"] = np.sqrt(sum((wc * r.green_err) ** 2 for wc, r in zip(w, res))) / tot
    else:
        g["green_distance"] = g["green_pairs"] = None
        g["distance_kind"] = ""
    if all(r.green_matrix is not None for r in res):
        g["green_matrix"] = sum(wc * r.green_matrix for wc, r in zip(w, res)) / tot
    cf = [r.condensate_fraction for r in res]
    if all(np.isfinite(cf)):
        g["condensate_fraction"], g["condensate_fraction_err"] = mcstats.combine_independent(
            cf, [r.condensate_fraction_err for r in res], w)
    else:
        g["condensate_fraction"] = g["condensate_fraction_err"] = math.nan
    st = {"stiffness_note": ref.stiffness_note or "not measured in every chain."}
    if all(r.stiffness is not None and r.stiffness.shape == ref.stiffness.shape for r in res):
        st = {"stiffness": sum(wc * r.stiffness for wc, r in zip(w, res)) / tot,
              "stiffness_err": np.sqrt(sum((wc * r.stiffness_err) ** 2 for wc, r in zip(w, res))) / tot,
              "stiffness_note": ""}
        for name in ("rho_s", "stiffness_geometric"):
            st[name], st[name + "_err"] = mcstats.combine_independent(
                [getattr(r, name) for r in res], [getattr(r, name + "_err") for r in res], w)
    notes = tuple(f"chain {r.seed}: {n}" for r in res for n in r.notes)
    return QMCResult(
        system=ref.system, sites=ref.sites, U=ref.U, mu=ref.mu, t=ref.t, beta=ref.beta, nmax=ref.nmax,
        sweeps=int(tot), thermalization=int(sum(r.thermalization for r in res)), seed=None, seeds=seeds,
        chains=int(sum(r.chains for r in res)), tau_int=tau,
        bins=int(sum(r.bins for r in res)), bin_size=int(max(r.bin_size for r in res)),
        converged=all(r.converged for r in res), notes=notes, site_density=sd, site_density_err=sd_err,
        bonds=ref.bonds, bond_kinetic=kin, bond_kinetic_err=kin_err,
        mean_operators=float(sum(wc * r.mean_operators for wc, r in zip(w, res)) / tot),
        string_length=int(max(r.string_length for r in res)), loops_per_sweep=int(ref.loops_per_sweep),
        seconds=float(sum(r.seconds for r in res)), bond_hopping=ref.bond_hopping, **vals, **g, **st)


_validate.guard_public(globals())
