r"""Classical Ising, XY (O(2)) and Heisenberg (O(3)) models on any graph by Monte Carlo.

.. math::

    H = -\sum_{\langle ij\rangle} J_{ij}\, s_i\cdot s_j - h \sum_i s_i^z ,
    \qquad J_{ij} = J A_{ij}, \qquad k_B = 1,

with unit spins :math:`s_i` of n = 1 (Ising, :math:`s_i = \pm 1`), 2 (XY) or 3 (Heisenberg)
components on a flake, a periodic cluster, a line graph or any symmetric matrix of couplings
:math:`A_{ij}` (weights allowed). The field couples to the spins' first component (:math:`s^z` of
the Ising and Heisenberg spins, the in-plane x axis of the XY spins).

Updates (chosen by ``update="auto"``, stated in every result)
-------------------------------------------------------------
* **Wolff clusters** (Wolff, PRL 62, 361 (1989); O(n) by the embedded Ising spins
  :math:`\sigma_i = s_i\cdot r` along a random direction r) when h = 0 and a gauge
  :math:`s_i \to g_i s_i`, :math:`g_i = \pm 1`, makes every coupling non-negative: a ferromagnet,
  or an antiferromagnet on a bipartite graph (the sublattice gauge). A measured sweep is a fixed
  number of clusters, N over the mean cluster size of the thermalisation (a count that followed the
  sizes drawn, "until N spins flipped", biases the energy of a 6-site chain by 60 standard errors).
* **Swendsen–Wang** (Swendsen & Wang, PRL 58, 86 (1987)) on request (``update="swendsen-wang"``)
  where Wolff applies: one update per sweep, every cluster reflected with probability 1/2; on the
  {7,3} flake it is 1.3 to 3 times less efficient than Wolff for the energy
  (``benchmarks/bench_spins.py --updates``), so "auto" does not pick it.
* **Heat-bath** passes over the sites otherwise (a field, frustrated or mixed-sign couplings),
  each followed for XY and Heisenberg spins by :data:`OVERRELAX` over-relaxation passes
  (reflection about the local field, which keeps the energy and decorrelates the spin waves).

Observables (per site, each with a binning error and :math:`\tau_{\mathrm{int}}`, see
:mod:`hyperlattice.mcstats`): :math:`e = \langle H\rangle/N`,
:math:`c = \beta^2(\langle H^2\rangle - \langle H\rangle^2)/N` (jackknife), :math:`m` (mean of the
field component), ``m2`` :math:`= \langle|m|^2\rangle`, ``m_abs`` :math:`= \langle|m|\rangle`,
:math:`U_4 = 1 - \langle|m|^4\rangle/(3\langle|m|^2\rangle^2)` (jackknife; 2/3 when ordered, and
for independent spins :math:`1 - (n+2)/(3n)`: 0, 1/3, 4/9 for n = 1, 2, 3),
:math:`\chi = \beta N\langle|m|^2\rangle`, their staggered versions (``_s``, with
:math:`m_s = \frac1N\sum_i \epsilon_i s_i` and :math:`\epsilon_i = \pm 1` the bipartition) on
bipartite graphs, per site and per ring the energy, the alignment :math:`\langle s_i\cdot\hat M\rangle`
with the instantaneous total moment (bulk against boundary on a flake) and the field component, and
the spin correlation :math:`\langle s_i\cdot s_j\rangle` averaged over the pairs of each distance
class (hyperbolic distance in bins of :math:`d_0/2` on flakes).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp

from .. import _validate, mcstats
from .._progress import progress_bar
from .. import _mc_chain
from ..errors import HyperlatticeError
from ..results import Column, Result, to_jsonable

__all__ = ["ClassicalResult", "classical_mc", "classical_mc_memory", "merge_classical", "SpinWarning", "MODELS",
           "OVERRELAX", "CORRELATION_MAX"]

#: the models and their number of spin components
MODELS = {"ising": 1, "xy": 2, "heisenberg": 3}
#: over-relaxation passes per heat-bath pass (XY and Heisenberg)
OVERRELAX = 2
#: largest graph whose spin correlation by distance is measured (an N x N class table)
CORRELATION_MAX = 3000
#: largest graph whose per-site observables are kept (4 x 32 bins per site); above it they are
#: accumulated per ring only (flakes) and the per-site arrays are None
SITES_MAX = 50_000
_SCALAR_BINS = 2048
#: per-sweep scalars of the kernel (its NSCALARS): E, E^2, m2, m4, |m|, m_z, ms2, ms4, |ms|, m2 improved, clusters
_NSCALARS = 11
_VECTOR_BINS = 32
_CORR_BINS = 64
_CHECKPOINT_SECONDS = 60.0
#: largest deviation ``abs(norm(s) - 1)`` of a stored XY or Heisenberg spin (the reflections keep the norm to
#: rounding, a random walk of about 1e-16 per update)
UNIT_TOL = 1e-6
#: the lock file a run holds in its checkpoint directory
_LOCK_FILE = ".spins_classical.lock"
#: the update rules' version (part of a checkpoint's fingerprint)
_RULES = "wolff-fixed-clusters/heatbath+or-2/sw"


class SpinWarning(UserWarning):
    """A classical spin chain returned, but thermalisation or the binning plateau is in doubt."""


# ----------------------------------------------------------------------------
# the model: couplings, gauge, bipartition, rings
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Model:
    sites: int
    indptr: np.ndarray
    indices: np.ndarray
    J: np.ndarray           # coupling per stored CSR entry (physical)
    gauge: np.ndarray       # g_i = +-1 with g_i g_j J_ij >= 0, or all +1 when there is none
    gauge_ok: bool
    eps: np.ndarray | None  # bipartition +-1 (None: not bipartite)
    ring: np.ndarray | None
    z: np.ndarray | None
    d0: float | None
    label: str
    kind: str


def _matrix(system):
    if sp.issparse(system) or isinstance(system, np.ndarray):
        try:
            mat = sp.csr_matrix(system)
        except (TypeError, ValueError):
            raise ValueError("the adjacency matrix must be a 2-d array of numbers.") from None
        if mat.ndim != 2 or mat.shape[0] != mat.shape[1] or mat.shape[0] == 0:
            raise ValueError(f"the adjacency matrix must be square and non-empty, got shape {mat.shape}.")
        if mat.dtype.kind not in "biufc":
            raise ValueError(f"the adjacency matrix must hold numbers, got {mat.dtype}.")
        if np.iscomplexobj(mat.data):
            if np.any(mat.data.imag != 0):
                raise ValueError("the couplings J_ij of classical spins must be real.")
            mat = sp.csr_matrix(mat.real)
        mat = sp.csr_matrix(mat, dtype=np.float64)
        if not np.all(np.isfinite(mat.data)):
            raise ValueError("the adjacency matrix must have finite entries.")
        if mat.nnz and abs(mat - mat.T).max() > 0:
            raise ValueError("the adjacency matrix must be symmetric.")
        return mat, None, None, None, "graph", f"graph of {mat.shape[0]} sites"
    if hasattr(system, "neighbours") and hasattr(system, "genus"):                  # a Cluster
        from .. import geometry

        return (sp.csr_matrix(system.adjacency(), dtype=np.float64), None, None,
                float(geometry.d0(system.p, system.q)), "cluster", f"{{{system.p},{system.q}}} cluster {system.name}")
    if getattr(type(system), "__hyperlattice_lattice__", False) is True:            # a Lattice
        from .. import geometry
        from ..graph.operators import adjacency

        lat = _validate.lattice(system)
        line = lat.kind == "line_graph"
        d0 = None if line else float(geometry.d0(lat.p, lat.q))
        return (sp.csr_matrix(adjacency(lat), dtype=np.float64), None if line else np.asarray(lat.z, dtype=complex),
                np.asarray(lat.ring, dtype=np.int64), d0, "line graph" if line else "flake",
                f"{{{lat.p},{lat.q}}} {'line graph of the flake' if line else 'flake'}, l = {lat.rings}")
    raise ValueError(f"system must be a flake, a line graph, a periodic cluster or an adjacency matrix, got "
                     f"{_validate._shown(system)}.")


def _model(system, J: float) -> _Model:
    mat, z, ring, d0, kind, label = _matrix(system)
    n = mat.shape[0]
    coo = mat.tocoo()
    keep = (coo.row != coo.col) & (coo.data != 0)        # no self-coupling (a constant for unit spins)
    mat = sp.csr_matrix((coo.data[keep], (coo.row[keep], coo.col[keep])), shape=(n, n))
    mat.sum_duplicates()
    mat.sort_indices()
    coup = J * mat.data
    indptr = mat.indptr.astype(np.int64)
    indices = mat.indices.astype(np.int64)
    K = _load_kernels()
    # a zero coupling (J = 0) constrains no sign: count it as ferromagnetic
    gauge, ok = K.two_colour(indptr, indices, np.where(coup < 0, -1, 1).astype(np.int64))
    eps, bip = K.two_colour(indptr, indices, -np.ones(indices.size, dtype=np.int64))
    gauge = gauge.astype(np.float64) if ok else np.ones(n)
    eps = eps.astype(np.float64) if bip else None
    return _Model(n, indptr, indices, coup.astype(np.float64), gauge, bool(ok), eps, ring, z, d0, label, kind)


# ----------------------------------------------------------------------------
# the result
# ----------------------------------------------------------------------------

_SCALAR_NAMES = ("e", "c", "m", "m2", "m_abs", "U4", "chi", "m2_s", "m_abs_s", "U4_s", "chi_s")


@dataclass(frozen=True, eq=False, kw_only=True)
class ClassicalResult(Result):
    r"""Thermal averages of a classical spin model from one Monte Carlo chain (or several merged).

    Attributes
    ----------
    system : str
        What was simulated (``"{7,3} flake, l = 3"``, a cluster, ``"graph of N sites"``).
    model : str
        ``"ising"``, ``"xy"`` or ``"heisenberg"``.
    sites : int
        Number of sites N.
    J, h, beta : float
        Coupling scale, field and inverse temperature (k_B = 1, energies in the unit of J's scale).
    update : str
        The update that ran (``"wolff"``, ``"swendsen-wang"``, or ``"heat-bath"`` /
        ``"heat-bath + 2 over-relaxation"``).
    update_reason : str
        Why this update.
    sweeps, thermalization : int
        Measured and thermalisation sweeps (summed over chains after :func:`merge_classical`).
    seed : int or None
        The chain's seed (None for merged chains: see ``seeds``).
    seeds : tuple of int
        The seeds of every chain.
    chains : int
        Independent chains merged.
    e, c, m, m2, m_abs, U4, chi : float
        Energy per site, specific heat per site, mean field component of the moment per site,
        :math:`\langle|m|^2\rangle`, :math:`\langle|m|\rangle`, the Binder cumulant and
        :math:`\chi = \beta N\langle|m|^2\rangle`; each with ``_err``.
    m2_s, m_abs_s, U4_s, chi_s : float
        The staggered versions (nan when the graph is not bipartite); each with ``_err``.
    m2_improved, m2_improved_err : float
        :math:`\langle|m|^2\rangle` of the cluster frame (the staggered one for a gauged
        antiferromagnet) from the clusters' improved estimator: Wolff's
        :math:`n N\langle(\sum_{i\in C}|s_i\cdot r|)^2/|C|\rangle/N^2`, Swendsen–Wang's
        :math:`n\langle\sum_C(\sum_{i\in C}|s_i\cdot r|)^2\rangle/N^2`; nan for local updates.
    tau_int : dict
        Integrated autocorrelation time in sweeps per scalar observable.
    bins, bin_size : int
        Plateau-level bins of the scalars and their length in sweeps.
    converged : bool
        Whether every binning error reached a plateau and the two halves of the run agree (4σ).
    notes : tuple of str
        What was noticed (also issued as :class:`SpinWarning`).
    clusters_per_sweep : float
        Mean Wolff clusters per sweep, or Swendsen–Wang clusters per update (0 for local updates).
    site_energy, site_alignment, site_alignment_s, site_m, and their ``_err`` : ndarray, shape (N,)
        Per site: :math:`\langle -\tfrac12\sum_j J_{ij}s_i\cdot s_j - h s_i^z\rangle`,
        :math:`\langle s_i\cdot\hat M\rangle`, :math:`\langle\epsilon_i s_i\cdot\hat M_s\rangle`
        and :math:`\langle s_i^z\rangle` (errors from 32 blocks).
    ring : ndarray of int or None
        The ring of each site (flakes).
    ring_index : ndarray of int or None
        The rings 1..l (flakes), with per ring ``ring_sites``, ``ring_energy``, ``ring_alignment``,
        ``ring_alignment_s``, ``ring_m`` and their ``_err``.
    corr_distance, corr, corr_err : ndarray or None
        Mean distance of each class, :math:`\langle s_i\cdot s_j\rangle` averaged over its pairs
        i < j, and the error (binning over the measurements); ``corr_pairs`` the pairs per class.
        Distance classes: hyperbolic distance in bins of :math:`d_0/2` (flakes), graph distance
        times :math:`d_0` (clusters), hops (other graphs); different components: distance inf.
    distance_kind : str
        ``"hyperbolic"``, ``"graph x d0"``, ``"graph (hops)"`` (with ``" from the centre"`` for
        ``correlation_from="centre"``) or ``""`` (not measured).
    seconds : float
        Wall-clock seconds (summed over chains).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins import classical_mc
    >>> r = classical_mc(hl.ring_lattice(7, 3, 2), model="ising", beta=0.3, sweeps=4000, seed=1, progress=False)
    >>> r.sites, r.update, r.e < 0
    (35, 'wolff', True)
    """

    COLUMNS = (Column("site_energy", "site_energy", "J"), Column("site_energy_err", "site_energy_err", "J"),
               Column("site_alignment", "site_alignment", "1"),
               Column("site_alignment_err", "site_alignment_err", "1"),
               Column("site_m", "site_m", "1"), Column("site_m_err", "site_m_err", "1"))

    system: str
    model: str
    sites: int
    J: float
    h: float
    beta: float
    update: str
    update_reason: str
    sweeps: int
    thermalization: int
    seed: int | None
    seeds: tuple
    chains: int
    e: float
    e_err: float
    c: float
    c_err: float
    m: float
    m_err: float
    m2: float
    m2_err: float
    m_abs: float
    m_abs_err: float
    U4: float
    U4_err: float
    chi: float
    chi_err: float
    m2_s: float
    m2_s_err: float
    m_abs_s: float
    m_abs_s_err: float
    U4_s: float
    U4_s_err: float
    chi_s: float
    chi_s_err: float
    m2_improved: float
    m2_improved_err: float
    tau_int: dict
    bins: int
    bin_size: int
    converged: bool
    notes: tuple
    clusters_per_sweep: float
    site_energy: np.ndarray | None
    site_energy_err: np.ndarray | None
    site_alignment: np.ndarray | None
    site_alignment_err: np.ndarray | None
    site_alignment_s: np.ndarray | None
    site_alignment_s_err: np.ndarray | None
    site_m: np.ndarray | None
    site_m_err: np.ndarray | None
    ring: np.ndarray | None
    ring_index: np.ndarray | None
    ring_sites: np.ndarray | None
    ring_energy: np.ndarray | None
    ring_energy_err: np.ndarray | None
    ring_alignment: np.ndarray | None
    ring_alignment_err: np.ndarray | None
    ring_alignment_s: np.ndarray | None
    ring_alignment_s_err: np.ndarray | None
    ring_m: np.ndarray | None
    ring_m_err: np.ndarray | None
    corr_distance: np.ndarray | None
    corr: np.ndarray | None
    corr_err: np.ndarray | None
    corr_pairs: np.ndarray | None
    distance_kind: str
    seconds: float

    @property
    def T(self) -> float:
        """The temperature 1/beta."""
        return 1.0 / self.beta

    def _check_loaded(self) -> str | None:
        why = super()._check_loaded()
        if why is not None:
            return why
        tol = 1e-9
        if self.model not in MODELS:
            return f"model {self.model!r} is not one of {', '.join(MODELS)}"
        if not (self.beta > 0 and math.isfinite(self.beta)):
            return f"beta = {self.beta!r} must be positive and finite"
        if self.sites < 1 or self.sweeps < 1 or self.chains < 1 or len(self.seeds) != self.chains:
            return "sites, sweeps and chains must be at least 1, with one seed per chain"
        for k in _SCALAR_NAMES + ("m2_improved",):
            err = getattr(self, k + "_err")
            if not (math.isnan(err) or err >= 0):
                return f"{k}_err = {err!r} is negative"
        # |m| <= 1 for unit spins; <|m|^4> >= <|m|^2>^2 bounds the Binder cumulant by 2/3
        for k in ("m2", "m_abs", "m2_s", "m_abs_s"):
            v = getattr(self, k)
            if not (math.isnan(v) or -tol <= v <= 1 + tol):
                return f"{k} = {v!r} lies outside [0, 1], impossible for unit spins"
        if not (-tol <= abs(self.m) <= 1 + tol or math.isnan(self.m)):
            return f"m = {self.m!r} lies outside [-1, 1], impossible for unit spins"
        for k in ("U4", "U4_s"):
            v = getattr(self, k)
            if not (math.isnan(v) or v <= 2.0 / 3.0 + 1e-6):
                return f"{k} = {v!r} exceeds 2/3, impossible for a Binder cumulant"
        if not (self.c >= -tol or math.isnan(self.c)) or not (self.chi >= -tol or math.isnan(self.chi)):
            return "the specific heat and the susceptibility cannot be negative"
        for k in ("site_energy", "site_alignment", "site_m"):
            v = getattr(self, k)
            if v is not None and v.shape != (self.sites,):
                return f"{k} has shape {v.shape}, not ({self.sites},)"
        for k in ("site_alignment", "site_m", "ring_alignment", "ring_m"):
            v = getattr(self, k)
            if v is not None and np.any(np.abs(v[np.isfinite(v)]) > 1 + tol):
                return f"{k} exceeds 1 in magnitude, impossible for unit spins"
        return None

    def summary(self) -> dict:
        """The JSON view: the scalar observables with errors, tau_int, update, the run's size and flags."""
        out = {"type": self.TYPE, "sites": self.sites}
        for k in _SCALAR_NAMES:
            out[k] = to_jsonable(getattr(self, k))
            out[k + "_err"] = to_jsonable(getattr(self, k + "_err"))
        out["tau_int"] = to_jsonable(dict(self.tau_int))
        out["update"] = self.update
        for k in ("update_reason", "system", "model", "J", "h", "beta", "sweeps", "thermalization", "seed",
                  "chains", "m2_improved", "m2_improved_err", "bins", "bin_size", "converged",
                  "clusters_per_sweep", "seconds"):
            out[k] = to_jsonable(getattr(self, k))
        out["T"] = to_jsonable(self.T)
        if self.ring_index is not None:
            out["rings"] = [{"ring": int(r), "sites": int(s), "energy": float(e), "energy_err": float(ee),
                             "alignment": float(a), "alignment_err": float(ae), "m": float(mm), "m_err": float(me)}
                            for r, s, e, ee, a, ae, mm, me in zip(self.ring_index, self.ring_sites, self.ring_energy,
                                                                  self.ring_energy_err, self.ring_alignment,
                                                                  self.ring_alignment_err, self.ring_m, self.ring_m_err)]
        out["notes"] = to_jsonable(list(self.notes))
        return out

    def table(self) -> list[dict]:
        """One row per scalar observable: ``observable, value, error, tau_int``."""
        return [{"observable": k, "value": float(getattr(self, k)), "error": float(getattr(self, k + "_err")),
                 "tau_int": float(self.tau_int.get(k, math.nan))} for k in _SCALAR_NAMES
                if not (k.endswith("_s") and math.isnan(getattr(self, k)))]

    def __str__(self) -> str:
        lines = [f"classical {self.model} model, {self.system}: J = {self.J:g}, h = {self.h:g}, beta = {self.beta:g} "
                 f"(T = {self.T:g}), update {self.update}, {self.sweeps} sweeps, {self.chains} chain(s)"]
        for r in self.table():
            lines.append(f"  {r['observable']:<8} {r['value']: .6f} +- {r['error']:.6f}   tau_int = {r['tau_int']:.2f}")
        if not self.converged:
            lines.append("  not converged: " + " ".join(self.notes))
        return "\n".join(lines)


# ----------------------------------------------------------------------------
# the chain
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Corr:
    cls: np.ndarray         # (N, N) int32 class of each pair (upper triangle used; -1: not measured)
    rows: int               # rows of cls holding measured pairs (the kernel's loop)
    every: int              # sweeps between measurements (0: off)
    pairs: np.ndarray
    distance: np.ndarray
    kind: str
    note: str


def _corr_setup(model: _Model, measure, source: str = "all") -> _Corr:
    from .. import geometry

    off = _Corr(np.zeros((1, 1), dtype=np.int32), 0, 0, np.zeros(1, dtype=np.int64), np.zeros(1), "", "")
    n = model.sites
    if measure is False:
        return off
    if n > CORRELATION_MAX:
        if measure:
            raise ValueError(f"the spin correlation by distance is measured up to {CORRELATION_MAX} sites "
                             f"(an N x N class table), the graph has {n}.")
        return _Corr(off.cls, 0, 0, off.pairs, off.distance, "",
                     f"the spin correlation is not measured above {CORRELATION_MAX} sites.")
    if source == "centre" and (model.z is None or model.ring is None):
        raise ValueError("correlation_from='centre' needs a flake (the sites of its first ring are the sources).")
    if model.z is not None:
        hbin = model.d0 / (4 if source == "centre" else 2)
        dist = np.asarray(geometry.distance(model.z[:, None], model.z[None, :], check=False), dtype=float)
        kind = "hyperbolic"
    else:
        from scipy.sparse.csgraph import shortest_path

        adj = sp.csr_matrix((np.ones(model.indices.size), model.indices, model.indptr), shape=(n, n))
        dist = shortest_path(adj, directed=False, unweighted=True)
        if model.d0 is not None:
            dist = dist * model.d0
            hbin, kind = model.d0, "graph x d0"
        else:
            hbin, kind = 1.0, "graph (hops)"
    finite = np.isfinite(dist)
    cls = np.zeros((n, n), dtype=np.int32)
    cls[finite] = np.rint(dist[finite] / hbin).astype(np.int32)
    top = int(cls.max()) + 1
    cls[~finite] = top
    use = np.triu(np.ones((n, n), dtype=bool), 1)
    if source == "centre":
        centre = model.ring == model.ring.min()
        use &= centre[:, None] | centre[None, :]
        cls[~use] = -1
    pairs = np.bincount(cls[use], minlength=top + 1)
    dsum = np.bincount(cls[use & finite], weights=dist[use & finite], minlength=top + 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(pairs > 0, dsum / np.maximum(pairs, 1), np.nan)
    mean[top] = np.inf if pairs[top] else np.nan
    rows = int(np.flatnonzero(use.any(axis=1)).max(initial=-1)) + 1
    # a measurement costs about rows x N pair products: every sweep when that is a sweep's work
    every = 1 if rows * n <= 40 * n else max(1, n // 100)
    return _Corr(cls, rows, every, pairs, mean, kind + (" from the centre" if source == "centre" else ""), "")


class _Chain:
    """The full state of one Markov chain (what a checkpoint stores)."""

    FIELDS = ("spins", "rng", "sbins", "scur", "sinfo", "vbins", "vcur", "vinfo", "cbins", "ccur", "cinfo", "counters", "cstat")

    def __init__(self, model: _Model, ncomp: int, seed: int, ncls: int, ngroups: int):
        from ..bosons._sse_kernels import seed_state

        self.rng = seed_state(seed)
        # a random start (infinite temperature), drawn from the chain's own generator stream
        gen = np.random.default_rng(seed)
        if ncomp == 1:
            spins = gen.choice([-1.0, 1.0], size=(model.sites, 1))
        else:
            spins = gen.normal(size=(model.sites, ncomp))
            spins /= np.linalg.norm(spins, axis=1, keepdims=True)
        self.spins = np.ascontiguousarray(spins)
        self.sbins = np.zeros((_SCALAR_BINS, _NSCALARS))
        self.scur = np.zeros(_NSCALARS)
        self.sinfo = np.array([0, 1, 0], dtype=np.int64)
        self.vbins = np.zeros((_VECTOR_BINS, 4 * ngroups))
        self.vcur = np.zeros(4 * ngroups)
        self.vinfo = np.array([0, 1, 0], dtype=np.int64)
        self.cbins = np.zeros((_CORR_BINS, ncls))
        self.ccur = np.zeros(ncls)
        self.cinfo = np.array([0, 1, 0], dtype=np.int64)
        self.counters = np.zeros(4, dtype=np.int64)
        self.cstat = np.zeros(2)

    def save(self, path: Path, fingerprint: str) -> None:
        # the QMC's checkpoint file: one SHA-256 over every array and the metadata, atomic write
        _mc_chain.write(path, {"fingerprint": fingerprint}, {k: getattr(self, k) for k in self.FIELDS})

    def load(self, path: Path, fingerprint: str) -> None:
        data = _mc_chain.load_chain(path, fingerprint, {k: getattr(self, k) for k in self.FIELDS},
                                    "system, model, J, h, beta, update, seed or thermalization")
        self._check_ranges(path, data)
        for k in self.FIELDS:
            setattr(self, k, data[k])

    def _check_ranges(self, path: Path, data: dict) -> None:
        """Refuse a checkpoint whose values no chain can hold (its checksum may have been recomputed
        after an edit): spins not +-1 (Ising) or not unit vectors (XY, Heisenberg, within
        :data:`UNIT_TOL`), a zero generator state, non-finite sums, bin counters out of range."""
        shown = repr(str(path))
        spins = data["spins"]
        if not np.all(np.isfinite(spins)):
            raise ValueError(f"the checkpoint {shown} holds non-finite spins; delete it to start the chain afresh.")
        if spins.shape[1] == 1:
            if not np.all(np.abs(spins) == 1.0):
                raise ValueError(f"the checkpoint {shown} holds Ising spins other than +1 and -1; delete it to "
                                 "start the chain afresh.")
        else:
            dev = float(np.max(np.abs(np.linalg.norm(spins, axis=1) - 1.0)))
            if dev > UNIT_TOL:
                raise ValueError(f"the checkpoint {shown} holds spins that are not unit vectors (|s| - 1 up to "
                                 f"{dev:.3g}, tolerance {UNIT_TOL:g}); delete it to start the chain afresh.")
        if not np.any(data["rng"]):
            raise ValueError(f"the checkpoint {shown} holds an all-zero random-number state; delete it to start "
                             "the chain afresh.")
        for k in ("sbins", "scur", "vbins", "vcur", "cbins", "ccur", "cstat"):
            if not np.all(np.isfinite(data[k])):
                raise ValueError(f"the checkpoint {shown} holds non-finite sums (field {k}); delete it to start "
                                 "the chain afresh.")
        for k, bins in (("sinfo", self.sbins), ("vinfo", self.vbins), ("cinfo", self.cbins)):
            nb, bs, cur = (int(x) for x in data[k])
            if not (0 <= nb < bins.shape[0] and bs >= 1 and bs & (bs - 1) == 0 and 0 <= cur < bs):
                raise ValueError(f"the checkpoint {shown} holds bin counters out of range (field {k}); delete it "
                                 "to start the chain afresh.")
        if np.any(data["counters"] < 0):
            raise ValueError(f"the checkpoint {shown} holds negative sweep counters; delete it to start the "
                             "chain afresh.")


def _fingerprint(model: _Model, name, J, h, beta, mode, overrelax, seed, thermalization, cevery) -> str:
    hsh = hashlib.sha256()
    for a in (model.indptr, model.indices, model.J):
        hsh.update(np.ascontiguousarray(a).tobytes())
    hsh.update(json.dumps([model.sites, name, J, h, beta, mode, overrelax, seed, thermalization, cevery, _RULES,
                           _SCALAR_BINS, _VECTOR_BINS, _CORR_BINS]).encode())
    return hsh.hexdigest()


#: address space besides the counted arrays: numba's and LLVM's code (as the bosons' SSE measured)
_RUNTIME_BYTES = 64 * 2**20


def _memory_need(n: int, nnz: int, ncomp: int, corr: bool) -> float:
    # spins, gauge, stag, field, eps, group, queue, inside; the site bins below SITES_MAX
    per_site = 8.0 * (ncomp + 7) + 1 + (8.0 * 4 * (_VECTOR_BINS + 2) if n <= SITES_MAX else 0.0)
    # CSR indices, couplings and gauged couplings, and scipy's copies while the model is built
    need = n * per_site + 40.0 * nnz + 24.0 * n + 8.0 * _SCALAR_BINS * 12
    if corr:
        # the class table (4 bytes a pair) and the set-up's temporaries: complex differences,
        # distances, masks (about 44 bytes a pair at once)
        need += n * n * 48.0
    return need


def _inputs(model, beta, T, J, h):
    if not isinstance(model, str):
        raise ValueError(f"model must be one of {', '.join(MODELS)}, got {_validate._shown(model)}.")
    name = model.strip().lower()
    if name not in MODELS:
        raise ValueError(f"unknown model {model!r}; choose one of {', '.join(MODELS)}.")
    if (beta is None) == (T is None):
        raise ValueError("give the temperature as exactly one of beta and T.")
    if beta is not None:
        beta = _validate.real("beta", beta)
        if not beta > 0:
            raise ValueError(f"beta must be positive, got {beta!r}.")
    else:
        T = _validate.real("T", T)
        if not T > 0:
            raise ValueError(f"T must be positive, got {T!r}.")
        beta = 1.0 / T
        if not math.isfinite(beta):
            raise ValueError(f"T = {T!r} is too small: beta = 1/T overflows.")
    J = _validate.real("J", J)
    h = _validate.real("h", h)
    return name, float(beta), float(J), float(h)


def _choose(model: _Model, name: str, h: float, update: str) -> tuple[int, str, str]:
    """(mode, update label, reason)."""
    update = _validate.choice("update", update, ("auto", "wolff", "swendsen-wang", "local"))
    local_label = "heat-bath" if name == "ising" else f"heat-bath + {OVERRELAX} over-relaxation"
    if model.indices.size == 0:
        return 1, local_label, "the graph has no bonds."
    can = model.gauge_ok and h == 0
    why_not = ("a field h != 0 breaks the spin-flip symmetry the clusters rely on" if h != 0 else
               "no gauge s_i -> -s_i makes every coupling ferromagnetic (frustration or mixed signs)")
    if update in ("wolff", "swendsen-wang"):
        if not can:
            what = "Wolff" if update == "wolff" else "Swendsen-Wang"
            raise ValueError(f"the {what} update needs h = 0 and couplings a gauge makes ferromagnetic: {why_not}.")
        return (0 if update == "wolff" else 2), update, "asked for."
    if update == "local":
        return 1, local_label, "asked for."
    if can:
        afm = bool(np.any(model.gauge < 0))
        return 0, "wolff", ("h = 0 and " + ("the sublattice gauge makes the antiferromagnet ferromagnetic."
                                            if afm else "every coupling is ferromagnetic."))
    return 1, local_label, why_not + "."


def classical_mc_memory(system, *, model: str, J: float = 1.0, measure_correlation=None) -> int:
    r"""Bytes a :func:`classical_mc` chain is expected to need (nothing is allocated).

    The spins, the CSR couplings, the per-site bins (4 observables x 32 bins) and, with the
    correlation measured (up to :data:`CORRELATION_MAX` sites), the N x N class table. :func:`classical_mc`
    refuses (MemoryError, one sentence) when this plus 64 MiB for the compiled kernels exceeds what
    the process may still allocate.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins import classical_mc_memory
    >>> classical_mc_memory(hl.ring_lattice(7, 3, 3), model="heisenberg") < 2**21
    True
    """
    name, _, J, _ = _inputs(model, 1.0, None, J, 0.0)
    mdl = _model(system, J)
    corr = measure_correlation is not False and mdl.sites <= CORRELATION_MAX
    return int(math.ceil(_memory_need(mdl.sites, mdl.indices.size, MODELS[name], corr)))


def classical_mc(system, *, model: str, beta: float | None = None, T: float | None = None, J: float = 1.0,
              h: float = 0.0, sweeps: int = 10000, thermalization: int | None = None, seed: int | None = None,
              update: str = "auto", checkpoint=None, measure_correlation=None, correlation_from: str = "all",
              progress=None) -> ClassicalResult:
    r"""Monte Carlo of the classical Ising, XY or Heisenberg model on a graph (one Markov chain).

    Parameters
    ----------
    system : Lattice, Cluster or matrix
        A flake or its line graph (:func:`~hyperlattice.ring_lattice`, :func:`~hyperlattice.line_graph`),
        a periodic cluster (:func:`~hyperlattice.graph.clusters.pbc_cluster`) or a symmetric
        matrix of couplings :math:`A_{ij}` (weights; :math:`J_{ij} = J A_{ij}`).
    model : {"ising", "xy", "heisenberg"}
        The spins: 1, 2 or 3 components.
    beta, T : float
        Inverse temperature or temperature (exactly one), > 0.
    J : float, optional
        Coupling scale (default 1; J < 0 antiferromagnetic).
    h : float, optional
        Field along the spins' first component (default 0).
    sweeps : int, optional
        Measured sweeps (default 10000).
    thermalization : int, optional
        Thermalisation sweeps (default ``max(100, sweeps // 10)``).
    seed : int, optional
        Seed of the chain; None draws one (stored in the result).
    update : {"auto", "wolff", "swendsen-wang", "local"}, optional
        The update (default "auto": Wolff where it applies, see the module docstring);
        "swendsen-wang" where Wolff applies, one Swendsen–Wang update per sweep.
    checkpoint : str or path, optional
        A directory: the chain is saved there every minute, at the end and when interrupted
        (atomically, with a checksum); a rerun with the same arguments (``sweeps`` may grow)
        resumes from it bit-identically. A checkpoint of other parameters is refused.
    measure_correlation : bool, optional
        Measure :math:`\langle s_i\cdot s_j\rangle` by distance class (default: up to
        :data:`CORRELATION_MAX` sites), every ``max(1, N // 100)`` sweeps (every sweep from the centre).
    correlation_from : {"all", "centre"}, optional
        The pairs of the correlation: all pairs i < j (default), or on a flake only the pairs with
        a site of the first ring (the correlation from the centre, free of the boundary's average;
        distance classes of :math:`d_0/4`).
    progress : bool, optional
        Progress bar on stderr (default: when a terminal watches).

    Returns
    -------
    ClassicalResult

    Raises
    ------
    ValueError
        On bad input, an impossible update, or a checkpoint of another run.
    MemoryError
        When the chain will not fit (said before allocating).

    Warns
    -----
    SpinWarning
        When a binning error has not reached its plateau or the two halves of the run disagree by 4σ.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.spins import classical_mc
    >>> ring = np.roll(np.eye(6), 1, axis=1) + np.roll(np.eye(6), -1, axis=1)
    >>> r = classical_mc(ring, model="ising", beta=0.5, sweeps=4000, seed=2, progress=False)
    >>> exact = -np.tanh(0.5) * (1 + np.tanh(0.5) ** 4) / (1 + np.tanh(0.5) ** 6)
    >>> bool(abs(r.e - exact) < 4 * r.e_err)
    True
    """
    name, beta, J, h = _inputs(model, beta, T, J, h)
    ncomp = MODELS[name]
    sweeps = _validate.integer("sweeps", sweeps, minimum=1)
    if thermalization is None:
        thermalization = max(100, sweeps // 10)
    thermalization = _validate.integer("thermalization", thermalization, minimum=0)
    if seed is None:
        seed = int(np.random.SeedSequence().entropy % (2**63))
    seed = _validate.integer("seed", seed, minimum=0)
    if measure_correlation is not None:
        measure_correlation = _validate.flag("measure_correlation", measure_correlation)
    mdl = _model(system, J)
    mode, label, reason = _choose(mdl, name, h, update)
    corr_on = measure_correlation is not False and mdl.sites <= CORRELATION_MAX
    K = _load_kernels()
    _validate.require_memory(f"the classical spin chain on {mdl.sites:,} sites (spins, couplings, per-site bins"
                             + (", the N x N distance classes" if corr_on else "") + " and 64 MiB for the compiled kernels)",
                             _memory_need(mdl.sites, mdl.indices.size, ncomp, corr_on) + _RUNTIME_BYTES)
    correlation_from = _validate.choice("correlation_from", correlation_from, ("all", "centre"))
    corr = _corr_setup(mdl, measure_correlation, correlation_from)
    group, ngroups = _groups(mdl)
    kern = _kern(mdl, mode, ncomp, h, beta, corr, group)
    overrelax = kern.overrelax
    chain = _Chain(mdl, ncomp, seed, corr.pairs.size, ngroups)
    fp = _fingerprint(mdl, name, J, h, beta, mode, overrelax, seed, thermalization, corr.every) + correlation_from
    ckdir = None if checkpoint is None else _validate.directory("checkpoint", checkpoint)
    with contextlib.ExitStack() as stack:
        ckpt = None
        if ckdir is not None:
            # a second run into the same directory is refused, not interleaved
            stack.enter_context(_mc_chain.locked(ckdir, _LOCK_FILE))
            ckpt = ckdir / "spins_classical_chain.npz"
            if ckpt.exists():
                chain.load(ckpt, fp)
                if chain.counters[1] > sweeps:
                    raise ValueError(f"the checkpoint already holds {int(chain.counters[1])} measured sweeps, more "
                                     f"than the {sweeps} asked for.")
        start = time.perf_counter()
        _drive(K, chain, mdl, kern, thermalization, sweeps, name, progress, ckpt, fp)
    seconds = time.perf_counter() - start
    return _analyse(chain, mdl, corr, name=name, ncomp=ncomp, J=J, h=h, beta=beta, sweeps=sweeps,
                    thermalization=thermalization, seed=seed, update=label, reason=reason, seconds=seconds)


@dataclass(frozen=True)
class _Kern:
    """What the kernel needs besides the chain: the update, the gauged couplings and field at one beta."""
    mode: int
    overrelax: int
    Jg: np.ndarray
    padd: np.ndarray
    hsite: np.ndarray
    beta: float
    stag: np.ndarray
    group: np.ndarray
    corr: _Corr

    def run(self, K, chain: "_Chain", mdl: _Model, n: int, therm: bool) -> None:
        c = self.corr
        K.run(n, therm, self.mode, self.overrelax, chain.spins, mdl.indptr, mdl.indices, self.Jg, self.padd,
              self.hsite, self.beta, mdl.gauge, self.stag, chain.rng, chain.sbins, chain.scur, chain.sinfo,
              chain.vbins, chain.vcur, chain.vinfo, self.group, c.cls, c.rows, c.every, chain.cbins, chain.ccur,
              chain.cinfo, chain.counters, chain.cstat)


def _kern(mdl: _Model, mode: int, ncomp: int, h: float, beta: float, corr: _Corr, group) -> _Kern:
    overrelax = OVERRELAX if (mode == 1 and ncomp > 1) else 0
    Jg = mdl.J * mdl.gauge[np.repeat(np.arange(mdl.sites), np.diff(mdl.indptr))] * mdl.gauge[mdl.indices]
    padd = -np.expm1(-2.0 * beta * np.maximum(Jg, 0.0))        # Ising bonds' Wolff probabilities
    stag = (mdl.eps * mdl.gauge) if mdl.eps is not None else np.zeros(mdl.sites)
    return _Kern(mode, overrelax, Jg, padd, h * mdl.gauge, beta, stag, group, corr)


def _drive(K, chain: _Chain, mdl: _Model, kern: _Kern, thermalization: int, sweeps: int, name: str, progress,
           ckpt, fp) -> None:
    """Run the chain to ``thermalization`` + ``sweeps`` sweeps in chunks of about half a second, saving
    to ``ckpt`` every minute, at the end and when interrupted."""
    last_save = time.perf_counter()
    try:
        with progress_bar(thermalization + sweeps, f"spins {name}", unit="sweep", progress=progress) as bar:
            bar.update(int(chain.counters[0] + chain.counters[1]))
            chunk = 4
            while chain.counters[0] < thermalization or chain.counters[1] < sweeps:
                therm = bool(chain.counters[0] < thermalization)
                left = (thermalization - chain.counters[0]) if therm else (sweeps - chain.counters[1])
                n = int(min(chunk, left))
                t0 = time.perf_counter()
                kern.run(K, chain, mdl, n, therm)
                dt = time.perf_counter() - t0
                bar.update(n)
                # chunks of about half a second (the split never changes the chain)
                chunk = int(max(1, min(4 * chunk, n * 0.5 / max(dt, 1e-6))))
                if ckpt is not None and time.perf_counter() - last_save > _CHECKPOINT_SECONDS:
                    chain.save(ckpt, fp)
                    last_save = time.perf_counter()
    except KeyboardInterrupt:
        if ckpt is not None:
            chain.save(ckpt, fp)
        raise
    if ckpt is not None:
        chain.save(ckpt, fp)


def _groups(mdl: _Model) -> tuple[np.ndarray, int]:
    """Where each site's local observables go: its own column (up to :data:`SITES_MAX` sites), else its
    ring's (flakes) or one column for all."""
    if mdl.sites <= SITES_MAX:
        return np.arange(mdl.sites, dtype=np.int64), mdl.sites
    if mdl.ring is not None:
        idx, pos = np.unique(mdl.ring, return_inverse=True)
        return pos.astype(np.int64).ravel(), int(idx.size)
    return np.zeros(mdl.sites, dtype=np.int64), 1


def _load_kernels():
    def load():
        from . import _classical_kernels

        return _classical_kernels

    return _mc_chain.load_kernels(load, "classical Monte Carlo")


def _block_stats(vb: np.ndarray):
    nb = vb.shape[0]
    mean = vb.mean(axis=0)
    err = vb.std(axis=0, ddof=1) / math.sqrt(nb) if nb > 1 else np.full(mean.shape, np.nan)
    return mean, err


def _analyse(chain: _Chain, mdl: _Model, corr: _Corr, *, name, ncomp, J, h, beta, sweeps, thermalization, seed,
             update, reason, seconds) -> ClassicalResult:
    nb, bs = int(chain.sinfo[0]), int(chain.sinfo[1])
    if nb < 2:
        raise HyperlatticeError("too few sweeps for an error estimate (fewer than two complete bins).")
    N = mdl.sites
    raw = chain.sbins[:nb] / bs        # bin means: E, E^2, m2, m4, |m|, m0, ms2, ms4, |ms|, m2 improved, clusters
    notes = []
    mean = raw.mean(axis=0)
    nsw = nb * bs

    def var_of(k, k2):
        return max(float(mean[k2] - mean[k] ** 2), 0.0)

    en = mcstats.binning(raw[:, 0] / N, bs, variance=var_of(0, 1) / N ** 2)
    stats = {"e": en}
    stats["m2"] = mcstats.binning(raw[:, 2], bs, variance=var_of(2, 3))
    stats["m_abs"] = mcstats.binning(raw[:, 4], bs, variance=max(float(mean[2] - mean[4] ** 2), 0.0))
    stats["m"] = mcstats.binning(raw[:, 5], bs)
    bip = mdl.eps is not None
    if bip:
        stats["m2_s"] = mcstats.binning(raw[:, 6], bs, variance=var_of(6, 7))
        stats["m_abs_s"] = mcstats.binning(raw[:, 8], bs, variance=max(float(mean[6] - mean[8] ** 2), 0.0))
    plateau = mcstats.plateau_bins(raw)
    c, c_err = mcstats.jackknife(lambda a, b: beta * beta * (b - a * a) / N, plateau[:, 0], plateau[:, 1])

    def binder(m2, m4):
        return 1.0 - m4 / (3.0 * m2 * m2) if m2 > 0 else math.nan

    u4, u4_err = mcstats.jackknife(binder, plateau[:, 2], plateau[:, 3])
    out = dict(e=en.mean, e_err=en.error, c=c, c_err=c_err, m=stats["m"].mean, m_err=stats["m"].error,
               m2=stats["m2"].mean, m2_err=stats["m2"].error, m_abs=stats["m_abs"].mean, m_abs_err=stats["m_abs"].error,
               U4=u4, U4_err=u4_err, chi=beta * N * stats["m2"].mean, chi_err=beta * N * stats["m2"].error)
    tau = {k: float(b.tau_int) for k, b in stats.items()}
    tau["c"] = tau["e"]
    tau["chi"] = tau["U4"] = tau["m2"]
    nan = math.nan
    if bip:
        us, us_err = mcstats.jackknife(binder, plateau[:, 6], plateau[:, 7])
        out.update(m2_s=stats["m2_s"].mean, m2_s_err=stats["m2_s"].error, m_abs_s=stats["m_abs_s"].mean,
                   m_abs_s_err=stats["m_abs_s"].error, U4_s=us, U4_s_err=us_err, chi_s=beta * N * stats["m2_s"].mean,
                   chi_s_err=beta * N * stats["m2_s"].error)
        tau["chi_s"] = tau["U4_s"] = tau["m2_s"]
    else:
        out.update(m2_s=nan, m2_s_err=nan, m_abs_s=nan, m_abs_s_err=nan, U4_s=nan, U4_s_err=nan, chi_s=nan,
                   chi_s_err=nan)
    if update in ("wolff", "swendsen-wang"):
        imp = mcstats.binning(raw[:, 9], bs)
        out.update(m2_improved=imp.mean, m2_improved_err=imp.error)
        tau["m2_improved"] = float(imp.tau_int)
        stats["m2_improved"] = imp
    else:
        out.update(m2_improved=nan, m2_improved_err=nan)
    converged = True
    for k, b in stats.items():
        if k == "m" and h == 0:
            continue        # zero by symmetry: its error may keep growing with the (slow) global flips
        if not b.converged:
            converged = False
            notes.append(f"the binning error of {k} has not reached a plateau ({nsw} sweeps, tau_int = "
                         f"{b.tau_int:.3g} sweeps): run longer.")
    hh = plateau.shape[0] // 2
    if hh >= 2:
        for k, label in ((0, "energy"), (2, "m2")):
            a, b = plateau[:hh, k], plateau[hh:2 * hh, k]
            sa, sb = a.std(ddof=1) / math.sqrt(hh), b.std(ddof=1) / math.sqrt(hh)
            diff = abs(a.mean() - b.mean())
            s = math.hypot(sa, sb)
            if diff > 4 * s and diff > 1e-12 * (1 + abs(a.mean())):
                converged = False
                notes.append(f"the {label} of the first and second half of the measurements differ by "
                             f"{diff / s:.1f} sigma: thermalisation ({thermalization} sweeps) was too short.")
    # per site and per ring
    vnb, vbs = int(chain.vinfo[0]), int(chain.vinfo[1])
    vb = chain.vbins[:vnb] / vbs
    ng = vb.shape[1] // 4
    blocks = [vb[:, k * ng:(k + 1) * ng] for k in range(4)]
    ring_names = ("ring_index", "ring_sites", "ring_energy", "ring_energy_err", "ring_alignment",
                  "ring_alignment_err", "ring_alignment_s", "ring_alignment_s_err", "ring_m", "ring_m_err")
    rings = {k: None for k in ring_names}
    if ng == N:
        site = [_block_stats(b) for b in blocks]
    else:
        site = [(None, None)] * 4
        notes.append(f"per-site observables are kept up to {SITES_MAX:,} sites; above, per ring only.")
    if mdl.ring is not None:
        idx, pos = np.unique(mdl.ring, return_inverse=True)
        pos = pos.ravel()
        cnt = np.bincount(pos, minlength=idx.size)
        per = []
        for b in blocks:
            if ng == N:
                rb = np.stack([np.bincount(pos, weights=row, minlength=idx.size) / cnt for row in b])
            else:
                rb = b / cnt
            per.append(_block_stats(rb))
        rings = dict(ring_index=idx, ring_sites=cnt, ring_energy=per[0][0], ring_energy_err=per[0][1],
                     ring_alignment=per[1][0], ring_alignment_err=per[1][1], ring_alignment_s=per[2][0],
                     ring_alignment_s_err=per[2][1], ring_m=per[3][0], ring_m_err=per[3][1])
    if not bip:
        if ng == N:
            site[2] = (np.full(N, nan), np.full(N, nan))
        if rings["ring_index"] is not None:
            rings["ring_alignment_s"] = np.full(rings["ring_index"].size, nan)
            rings["ring_alignment_s_err"] = np.full(rings["ring_index"].size, nan)
    cd = cv = ce = cp = None
    if corr.every:
        cnb, cbs = int(chain.cinfo[0]), int(chain.cinfo[1])
        keep = corr.pairs > 0
        if cnb >= 2:
            per = chain.cbins[:cnb, keep] / (cbs * corr.pairs[keep])
            cv = per.mean(axis=0)
            ce = np.array([mcstats.binning(per[:, k]).error for k in range(per.shape[1])]) if cnb >= 4 else \
                per.std(axis=0, ddof=1) / math.sqrt(cnb)
            cd, cp = corr.distance[keep], corr.pairs[keep]
        else:
            notes.append(f"too few correlation measurements ({int(chain.counters[2])}, one every {corr.every} "
                         "sweeps) for an error: run longer.")
    if corr.note:
        notes.append(corr.note)
    for note in notes:
        if note != corr.note and not note.startswith("per-site observables"):
            warnings.warn(note, SpinWarning, stacklevel=3)
    bins = int(plateau.shape[0])
    return ClassicalResult(
        system=mdl.label, model=name, sites=N, J=J, h=h, beta=beta, update=update, update_reason=reason,
        sweeps=sweeps, thermalization=thermalization, seed=seed, seeds=(seed,), chains=1, **out, tau_int=tau,
        bins=bins, bin_size=int(bs * (nb // bins)), converged=converged, notes=tuple(notes),
        clusters_per_sweep=float(mean[10]),
        site_energy=site[0][0], site_energy_err=site[0][1], site_alignment=site[1][0], site_alignment_err=site[1][1],
        site_alignment_s=site[2][0], site_alignment_s_err=site[2][1], site_m=site[3][0], site_m_err=site[3][1],
        ring=mdl.ring, **rings, corr_distance=cd, corr=cv, corr_err=ce, corr_pairs=cp,
        distance_kind=corr.kind if cv is not None else "", seconds=float(seconds))


def merge_classical(results) -> ClassicalResult:
    r"""Merge independent chains (same model and parameters, different seeds) into one result.

    The sweep-weighted mean of every observable with the propagated error
    (:func:`hyperlattice.mcstats.combine_independent`), per observable, site, ring and distance class.

    Raises
    ------
    ValueError
        If the list is empty, holds other objects, chains of different models, or a seed twice.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins import classical_mc, merge_classical
    >>> runs = [classical_mc(hl.ring_lattice(7, 3, 1), model="xy", beta=1.0, sweeps=1000, seed=s, progress=False)
    ...         for s in (1, 2)]
    >>> m = merge_classical(runs)
    >>> m.chains, m.sweeps, m.seeds
    (2, 2000, (1, 2))
    """
    res, seeds, w = _mc_chain.chains_to_merge(results, ClassicalResult, "merge_classical",
                                              ("system", "model", "sites", "J", "h", "beta", "update"))
    ref = res[0]
    tot = float(w.sum())
    vals = _mc_chain.merged_scalars(res, w, _SCALAR_NAMES + ("m2_improved",))
    arrays = {}
    for k in ("site_energy", "site_alignment", "site_alignment_s", "site_m", "ring_energy", "ring_alignment",
              "ring_alignment_s", "ring_m"):
        arrays[k], arrays[k + "_err"] = _mc_chain.weighted_arrays(res, w, k)
    same_corr = all(r.corr is not None and ref.corr is not None and r.corr.shape == ref.corr.shape for r in res)
    cv, ce = _mc_chain.weighted_arrays(res, w, "corr") if same_corr else (None, None)
    corr = dict(corr_distance=ref.corr_distance if same_corr else None, corr_pairs=ref.corr_pairs if same_corr else None,
                corr=cv, corr_err=ce, distance_kind=ref.distance_kind if same_corr else "")
    return ClassicalResult(
        system=ref.system, model=ref.model, sites=ref.sites, J=ref.J, h=ref.h, beta=ref.beta, update=ref.update,
        update_reason=ref.update_reason, **_mc_chain.merged_run(res, w, seeds), **vals,
        clusters_per_sweep=float(sum(wc * r.clusters_per_sweep for wc, r in zip(w, res)) / tot), **arrays,
        ring=ref.ring, ring_index=ref.ring_index, ring_sites=ref.ring_sites, **corr)


_validate.guard_public(globals())
