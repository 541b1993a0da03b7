r"""The spin-1/2 XXZ model on any graph of the package: stochastic series expansion (SSE) on the
bosons' directed-loop engine, and exact diagonalisation in :math:`S^z` blocks for small graphs.

.. math::

    H = \sum_{\langle ij\rangle} J_{ij}\,\big(S^x_iS^x_j + S^y_iS^y_j + \Delta\,S^z_iS^z_j\big)
        - h \sum_i S^z_i , \qquad J_{ij} = J A_{ij},

at inverse temperature β (k_B = 1; energies in the unit of J's number, β in its inverse).

Mapping onto hard-core bosons
-----------------------------
:math:`S^+_i = b_i^\dagger`, :math:`S^z_i = n_i - \tfrac12` with :math:`n_i \in \{0, 1\}`, so
:math:`J(S^x_iS^x_j + S^y_iS^y_j) = \tfrac J2 (b_i^\dagger b_j + \mathrm{h.c.})`: the hopping of
the bosons' engine (:mod:`hyperlattice.bosons.sse`, :math:`H = -t\sum(b_i^\dagger b_j + \mathrm{h.c.})`)
with :math:`t_{ij} = -J_{ij}/2`. A ferromagnet (J < 0) has :math:`t > 0` on any graph; an
antiferromagnet (J > 0) is made sign-free by the gauge :math:`b_i \to \epsilon_i b_i`
(:math:`\epsilon = \pm 1` the two sublattices) when the graph is bipartite, and only then: on a
graph with an odd cycle the J > 0 model is frustrated, every sign choice leaves a negative
off-diagonal weight, and :func:`xxz_qmc` refuses it (couplings of mixed sign: when no gauge makes
every :math:`-J_{ij}\epsilon_i\epsilon_j` non-negative). The gauge is the bosons' own
(``bosons.sse._model``).

Every diagonal term lives on the bonds: with :math:`z_i` the bonds of site i,

.. math::

    h_b(n_i, n_j) = J_b\Delta\,(n_i - \tfrac12)(n_j - \tfrac12) - \frac h{z_i}(n_i - \tfrac12)
        - \frac h{z_j}(n_j - \tfrac12),

and the vertex weights are :math:`W_b(n_i, n_j) = C_b - h_b(n_i, n_j)` (diagonal) and
:math:`|J_b|/2` (a hop), with :math:`C_b = \max h_b + \epsilon_b` (:data:`OFFSET`; 0 at the
isotropic point Δ = 1, h = 0). The
:math:`J\Delta` term couples the two occupations of a bond, which the Bose–Hubbard engine's
diagonal weight (a sum of one-site terms, ``cb - esite[i, n_i] - esite[j, n_j]``) cannot carry.
The directed loops see vertex weights only through the exit-probability table, which takes any
weights: so the loop update, the operator string, the random numbers and the winding numbers are
the bosons' kernels unchanged, and :mod:`hyperlattice.spins._quantum_kernels` adds only the
diagonal update with :math:`h_b` and the spin observables along imaginary time (no line of
``bosons/`` changes).

Sign and Δ range
----------------
The shift :math:`C_b` is the bond's largest diagonal energy, so every diagonal weight is
non-negative for **every real Δ and h**; the off-diagonal weights :math:`|J_b|/2` are positive
after the gauge. The only sign condition is therefore the hopping's (bipartite graph for J > 0);
there is no Δ window to refuse. (Large :math:`|\Delta|` or h only make the chain slower: the
loops bounce more.)

Estimators (per sweep, every diagonal one averaged over the M time slices of the configuration)
----------------------------------------------------------------------------------------------------
* energy :math:`\langle H\rangle = \langle \tfrac1M\sum_p E_{\mathrm{diag}}(p)\rangle -
  \langle n_{\mathrm{offd}}\rangle/\beta` (the bosons' estimator), per site ``e``. At the
  isotropic point (Δ = 1, h = 0) the ensemble is SU(2) invariant, so
  :math:`\langle S^x_iS^x_j + S^y_iS^y_j\rangle = 2\langle S^z_iS^z_j\rangle` and
  :math:`3\langle H_{zz}\rangle` (a slice average, no operator-count noise) is a second unbiased
  estimator; ``e`` is the mean of the two (``energy_estimator = "su2"``), whose error on the
  {8,3} l = 3 flake at β = 4 is about 20 % below either alone (four seeds);
* specific heat :math:`c = (\langle n^2\rangle - \langle n\rangle^2 - \langle n\rangle)/N`
  (n operators in the string; Sandvik, PRB 56, 11678 (1997)), jackknife;
* :math:`\chi_u = \beta(\langle (S^z_{\mathrm{tot}})^2\rangle - \langle S^z_{\mathrm{tot}}\rangle^2)/N`
  (:math:`S^z_{\mathrm{tot}}` is conserved along imaginary time), jackknife;
* :math:`s_\pi = \langle M_s^2\rangle/N`, :math:`M_s = \sum_i \epsilon_i S^z_i` (bipartite graphs);
* the staggered correlation of each site :math:`\mu_i = \epsilon_i\langle S^z_i M_s\rangle/N`,
  whose mean over all sites is :math:`\langle (M_s/N)^2\rangle`: its mean over a ring of a
  flake is the squared staggered moment by ring (bulk against boundary);
* bond correlations :math:`\langle S^z_iS^z_j\rangle` (slice average) and
  :math:`\langle S^x_iS^x_j + S^y_iS^y_j\rangle = -\langle n_b\rangle/(\beta J_b)`;
* spin stiffness on periodic clusters from the winding numbers of the world lines,
  :math:`\rho_s = \langle W\cdot W\rangle/(D\beta)` (Pollock & Ceperley, PRB 36, 8343 (1987);
  Sandvik's form for spins, PRB 56, 11678 (1997)), as in the bosons' engine.

Errors: binning (:mod:`hyperlattice.mcstats`) of up to 2048 bins per chain, τ_int per
observable; site and bond arrays from 32 bins.
"""

from __future__ import annotations

import contextlib
import math
import time
import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _validate, mcstats
from .._progress import progress_bar
from .. import _mc_chain
from ..errors import HyperlatticeError
from ..results import Column, Result, to_jsonable

__all__ = ["XXZResult", "XXZExact", "xxz_qmc", "xxz_exact", "merge_xxz", "OFFSET", "ED_MAX_SITES"]

#: diagonal-vertex offset :math:`\epsilon_b` in units of :math:`|J_b|/2` away from the isotropic point.
#: At Δ = 1, h = 0 the offset is 0: the antiferromagnet then has Sandvik's deterministic operator
#: loops (PRB 59, R14157 (1999)), no bounce at any vertex, and on the {8,3} l = 3 flake at β = 4 the
#: energy efficiency 1/(σ² CPU s) with 0 beat 0.2 by 1.3x. Elsewhere a zero offset leaves vertices of
#: weight 0 that the loops must bounce off: at Δ = 0.5 (6-site rings, β = 4) τ_int of the energy
#: was 130 sweeps with 0 and 1.6-2.2 with 0.25-0.5; with h = 0.5 or Δ = -0.5 (the l = 2 flake) 0.25
#: and 0.5 gave 4-9x the efficiency of 0; 0.5 (the bosons' value) also covers the bounce-free bound
#: :math:`\epsilon_b \ge |J_b|(1 - |\Delta|)/4` of the XXZ vertex for every :math:`|\Delta| < 1` (Syljuåsen &
#: Sandvik, PRE 66, 046701 (2002)).
OFFSET = 0.5
#: the largest graph :func:`xxz_exact` diagonalises (the S^z = 0 block of 16 sites has 12,870 states)
ED_MAX_SITES = 16
_SCALAR_BINS = 2048
_VECTOR_BINS = 32
_TARGET_LEGS = 2.0
_EXIT_RULE = "least-bounce directed loops (Syljuåsen & Sandvik 2002) on the bosons' engine"


class XXZWarning(UserWarning):
    """An XXZ chain returned, but thermalisation or the binning plateau is in doubt."""


# ----------------------------------------------------------------------------
# the model
# ----------------------------------------------------------------------------

@dataclass(frozen=True)
class _Spins:
    sites: int
    bi: np.ndarray
    bj: np.ndarray
    Jb: np.ndarray          # signed bond couplings J A_ij
    tb: np.ndarray          # |J_b| / 2
    gauge: np.ndarray
    degree: np.ndarray
    stag: np.ndarray        # epsilon_i = +-1 (bipartite) or zeros
    bipartite: bool
    ring: np.ndarray | None
    label: str
    kind: str
    boson_model: object


def _two_colouring(n: int, bi: np.ndarray, bj: np.ndarray, sign: np.ndarray) -> np.ndarray | None:
    r"""A gauge :math:`\epsilon_i = \pm1` with :math:`\epsilon_i\epsilon_j = \mathrm{sign}_b` on every
    bond, or None (a cycle whose signs multiply to -1). All signs -1: a bipartition."""
    from scipy.sparse.csgraph import connected_components

    pos = sign > 0
    rows = np.concatenate([bi[pos], bi[pos] + n, bi[~pos], bi[~pos] + n])
    cols = np.concatenate([bj[pos], bj[pos] + n, bj[~pos] + n, bj[~pos]])
    g = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(2 * n, 2 * n))
    _, lab = connected_components(g, directed=False)
    if np.any(lab[:n] == lab[n:]):
        return None
    return np.where(lab[:n] < lab[n:], 1.0, -1.0)


def _spins(system, J: float) -> _Spins:
    from ..bosons import sse

    mat, _, _, kind, label = sse._matrix(system)
    n = mat.shape[0]
    up = sp.triu(mat, k=1).tocoo()
    keep = up.data != 0
    bi = up.row[keep].astype(np.int64)
    bj = up.col[keep].astype(np.int64)
    Jb = J * up.data[keep]
    if bi.size == 0:
        raise ValueError("the graph has no bonds: the spins are independent (a free spin in the field).")
    if _two_colouring(n, bi, bj, -np.sign(Jb)) is None:
        if np.all(Jb > 0):
            raise ValueError("an antiferromagnet (J > 0) on a graph with an odd cycle is frustrated and gives the "
                             "quantum Monte Carlo a sign problem; use xxz_exact on a small graph instead.")
        raise ValueError("couplings of mixed sign with a frustrated cycle (no sublattice rotation makes every "
                         "transverse coupling ferromagnetic) give the quantum Monte Carlo a sign problem; use "
                         "xxz_exact on a small graph instead.")
    model = sse._model(system, -0.5 * J)
    colours = _two_colouring(n, bi, bj, -np.ones(bi.size))
    bip = colours is not None
    ring = np.asarray(system.ring, dtype=np.int64) if kind == "flake" else None
    return _Spins(n, bi, bj, Jb, np.abs(Jb) / 2, model.gauge, model.degree,
                  colours if bip else np.zeros(n), bip, ring, label, kind, model)


def _diagonal(model: _Spins, Delta: float, h: float):
    """(h_b table (B, 2, 2), C_b, W_b table) of the bond-diagonal terms."""
    s = np.array([-0.5, 0.5])
    z = model.degree.astype(float)
    hd = (model.Jb[:, None, None] * Delta * s[None, :, None] * s[None, None, :]
          - (h / z[model.bi])[:, None, None] * s[None, :, None]
          - (h / z[model.bj])[:, None, None] * s[None, None, :])
    offset = 0.0 if (Delta == 1 and h == 0) else OFFSET
    cb = hd.reshape(-1, 4).max(axis=1) + offset * model.tb
    wdiag = cb[:, None, None] - hd
    return np.ascontiguousarray(hd), cb, np.ascontiguousarray(np.maximum(wdiag, 0.0))


def _physical(J, Delta, h, beta):
    J = _validate.real("J", J)
    Delta = _validate.real("Delta", Delta)
    h = _validate.real("h", h)
    beta = _validate.real("beta", beta)
    if not beta > 0:
        raise ValueError(f"beta must be positive, got {beta!r}.")
    if J == 0:
        raise ValueError("J = 0 leaves free spins in a field (no bond term); use a nonzero J.")
    return J, Delta, h, beta


# ----------------------------------------------------------------------------
# results
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class XXZResult(Result):
    r"""Thermal averages of the spin-1/2 XXZ model from one SSE chain (or several merged).

    Attributes
    ----------
    system : str
        What was simulated (``"{8,3} flake, l = 3"``, a cluster, ``"graph of N sites"``).
    sites : int
        Number of spins N.
    J, Delta, h, beta : float
        Couplings, field and inverse temperature.
    sweeps, thermalization : int
        Measured and thermalisation sweeps (summed over merged chains).
    seed : int or None
        The chain's seed (None for merged chains; see ``seeds``).
    seeds : tuple of int
        Seeds of every chain.
    chains : int
        Independent chains merged.
    bipartite : bool
        Whether the graph is bipartite (``s_pi`` and the staggered arrays are nan otherwise).
    e, e_err : float
        Energy per site :math:`\langle H\rangle/N` and its error.
    c, c_err : float
        Specific heat per site :math:`\beta^2(\langle H^2\rangle - \langle H\rangle^2)/N`.
    chi_u, chi_u_err : float
        Uniform susceptibility :math:`\beta(\langle (S^z_{\mathrm{tot}})^2\rangle - \langle S^z_{\mathrm{tot}}\rangle^2)/N`.
    mz, mz_err : float
        Magnetisation per site :math:`\langle S^z_{\mathrm{tot}}\rangle/N`.
    s_pi, s_pi_err : float
        Staggered structure factor :math:`\langle (\sum_i\epsilon_iS^z_i)^2\rangle/N`.
    binder, binder_err : float
        :math:`\langle M_s^4\rangle/\langle M_s^2\rangle^2` (slice averages; jackknife).
    rho_s, rho_s_err : float
        Spin stiffness :math:`\langle W\cdot W\rangle/(D\beta)` on a periodic cluster (nan otherwise;
        ``stiffness_note`` says why).
    stiffness_note : str
        Why ``rho_s`` is nan ("" when measured).
    tau_int : dict
        Integrated autocorrelation times in sweeps (energy, chi_u, s_pi, stiffness).
    bins, bin_size : int
        Plateau-level bins and their length in sweeps.
    converged : bool
        Binning plateaus reached and the two halves of the measurements agree within 4σ.
    notes : tuple of str
        What was noticed (also issued as :class:`XXZWarning`).
    stagger : ndarray of float, shape (N,)
        :math:`\epsilon_i` (zeros on a graph that is not bipartite).
    ring : ndarray of int or None
        Ring of each site on a flake.
    site_sz, site_sz_err : ndarray, shape (N,)
        :math:`\langle S^z_i\rangle`.
    site_stag, site_stag_err : ndarray, shape (N,)
        :math:`\mu_i = \epsilon_i\langle S^z_i M_s\rangle/N` (their mean is :math:`\langle (M_s/N)^2\rangle`).
    ring_stag, ring_stag_err : ndarray or None
        Mean of :math:`\mu_i` over each ring of a flake (ring 1 first), errors from the bins.
    bonds : ndarray of int, shape (B, 2)
        The bonds (i < j).
    bond_zz, bond_zz_err, bond_xy, bond_xy_err : ndarray, shape (B,)
        :math:`\langle S^z_iS^z_j\rangle` and :math:`\langle S^x_iS^x_j + S^y_iS^y_j\rangle`.
    mean_operators : float
        Mean number of operators in the string.
    string_length, loops_per_sweep : int
        Frozen after thermalisation.
    update : str
        The algorithm.
    energy_estimator : str
        ``"slice"``: :math:`\tfrac1M\sum_p E_{\mathrm{diag}}(p) - n_{\mathrm{offd}}/\beta`;
        ``"su2"`` (Δ = 1, h = 0): the mean of that and :math:`3\,\tfrac1M\sum_p H_{zz}(p)`.
    seconds : float
        Wall-clock seconds (thermalisation included; summed over merged chains).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins.quantum import xxz_qmc
    >>> r = xxz_qmc(hl.ring_lattice(8, 3, 1), J=1.0, Delta=1.0, beta=2.0, sweeps=2000, seed=1, progress=False)
    >>> r.sites, r.bipartite, r.e < 0
    (8, True, True)
    """

    COLUMNS = (Column("site", "site_index", "1"), Column("sz", "site_sz", "1"),
               Column("sz_err", "site_sz_err", "1"), Column("stag", "site_stag", "1"),
               Column("stag_err", "site_stag_err", "1"))

    system: str
    sites: int
    J: float
    Delta: float
    h: float
    beta: float
    sweeps: int
    thermalization: int
    seed: int | None
    seeds: tuple
    chains: int
    bipartite: bool
    e: float
    e_err: float
    c: float
    c_err: float
    chi_u: float
    chi_u_err: float
    mz: float
    mz_err: float
    s_pi: float
    s_pi_err: float
    binder: float
    binder_err: float
    rho_s: float
    rho_s_err: float
    stiffness_note: str
    tau_int: dict
    bins: int
    bin_size: int
    converged: bool
    notes: tuple
    stagger: np.ndarray
    ring: np.ndarray | None
    site_sz: np.ndarray
    site_sz_err: np.ndarray
    site_stag: np.ndarray
    site_stag_err: np.ndarray
    ring_stag: np.ndarray | None
    ring_stag_err: np.ndarray | None
    bonds: np.ndarray
    bond_zz: np.ndarray
    bond_zz_err: np.ndarray
    bond_xy: np.ndarray
    bond_xy_err: np.ndarray
    mean_operators: float
    string_length: int
    loops_per_sweep: int
    update: str
    seconds: float
    energy_estimator: str = "slice"

    @property
    def site_index(self) -> np.ndarray:
        """0, 1, ..., N - 1 (the table's first column)."""
        return np.arange(self.sites)

    def summary(self) -> dict:
        """The JSON view: the contract's keys with errors first, then the run's parameters and flags."""
        out = {"type": self.TYPE}
        for k in ("sites", "e", "e_err", "c", "c_err", "chi_u", "chi_u_err", "s_pi", "s_pi_err", "mz", "mz_err",
                  "binder", "binder_err", "rho_s", "rho_s_err", "stiffness_note", "system", "J", "Delta", "h",
                  "beta", "bipartite", "sweeps", "thermalization", "seed", "chains", "bins", "bin_size",
                  "converged", "mean_operators", "update", "energy_estimator", "seconds"):
            out[k] = to_jsonable(getattr(self, k))
        if not self.bipartite:
            out["s_pi"] = out["s_pi_err"] = None
        out["tau_int"] = to_jsonable(dict(self.tau_int))
        out["ring_stag"] = None if self.ring_stag is None else to_jsonable(self.ring_stag.tolist())
        out["ring_stag_err"] = None if self.ring_stag_err is None else to_jsonable(self.ring_stag_err.tolist())
        out["notes"] = list(self.notes)
        return out

    def table(self) -> list[dict]:
        """One row per scalar observable: ``observable, value, error, tau_int``."""
        rows = []
        for name, tau in (("e", "energy"), ("c", "energy"), ("chi_u", "chi_u"), ("mz", "chi_u"),
                          ("s_pi", "s_pi"), ("rho_s", "stiffness")):
            v = float(getattr(self, name))
            if name == "s_pi" and not self.bipartite or name == "rho_s" and not np.isfinite(v):
                continue
            rows.append({"observable": name, "value": v, "error": float(getattr(self, name + "_err")),
                         "tau_int": float(self.tau_int.get(tau, math.nan))})
        return rows

    def by_ring(self) -> list[dict]:
        """Rows ``ring, sites, stag, stag_err, sz`` on a flake (the staggered moment by ring).

        Raises
        ------
        ValueError
            If the graph is not a flake or not bipartite.
        """
        if self.ring is None or self.ring_stag is None:
            raise ValueError("the staggered moment by ring needs a bipartite flake (rings and sublattices).")
        rows = []
        for k, (v, err) in enumerate(zip(self.ring_stag, self.ring_stag_err)):
            sel = self.ring == k + 1
            rows.append({"ring": k + 1, "sites": int(sel.sum()), "stag": float(v), "stag_err": float(err),
                         "sz": float(self.site_sz[sel].mean())})
        return rows

    def __str__(self) -> str:
        lines = [f"XXZ SSE, {self.system}: J = {self.J:g}, Delta = {self.Delta:g}, h = {self.h:g}, "
                 f"beta = {self.beta:g}, {self.sweeps} sweeps, {self.chains} chain(s)"]
        for r in self.table():
            lines.append(f"  {r['observable']:<8} {r['value']: .6f} +- {r['error']:.6f}   tau_int = {r['tau_int']:.2f}")
        if not self.converged:
            lines.append("  not converged: " + " ".join(self.notes))
        return "\n".join(lines)


@dataclass(frozen=True, eq=False, kw_only=True)
class XXZExact(Result):
    r"""Exact thermal averages of the spin-1/2 XXZ model (full diagonalisation in :math:`S^z` blocks).

    Attributes
    ----------
    system : str
        The graph.
    sites : int
        Number of spins N.
    J, Delta, h, beta : float
        Couplings, field and inverse temperature.
    e, c, chi_u, mz, s_pi : float
        As in :class:`XXZResult` (``s_pi`` nan on a graph that is not bipartite).
    ground_energy : float
        Lowest eigenvalue of H (total).
    stagger, site_sz, site_stag : ndarray, shape (N,)
        As in :class:`XXZResult`.
    bonds : ndarray of int, shape (B, 2)
        The bonds (i < j).
    bond_zz, bond_xy : ndarray, shape (B,)
        As in :class:`XXZResult`.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins.quantum import xxz_exact
    >>> x = xxz_exact(hl.ring_lattice(8, 3, 1), J=1.0, Delta=1.0, beta=50.0)
    >>> round(x.ground_energy / 8, 6)     # the 8-site Heisenberg ring (Bethe ansatz: -0.456387)
    -0.456387
    """

    COLUMNS = (Column("sz", "site_sz", "1"), Column("stag", "site_stag", "1"))

    system: str
    sites: int
    J: float
    Delta: float
    h: float
    beta: float
    e: float
    c: float
    chi_u: float
    mz: float
    s_pi: float
    ground_energy: float
    stagger: np.ndarray
    site_sz: np.ndarray
    site_stag: np.ndarray
    bonds: np.ndarray
    bond_zz: np.ndarray
    bond_xy: np.ndarray


# ----------------------------------------------------------------------------
# exact diagonalisation in S^z blocks
# ----------------------------------------------------------------------------

def xxz_exact(system, *, J: float, Delta: float, beta: float, h: float = 0.0) -> XXZExact:
    r"""Exact thermal averages of the XXZ model by full diagonalisation in every :math:`S^z` block.

    Any sign structure (frustrated graphs included): this is the reference the SSE is tested
    against. Up to :data:`ED_MAX_SITES` sites.

    Parameters
    ----------
    system : Lattice, Cluster or adjacency matrix
        The graph; couplings :math:`J_{ij} = J A_{ij}`.
    J, Delta : float
        Exchange and anisotropy.
    beta : float
        Inverse temperature, > 0.
    h : float, optional
        Field along z (default 0).

    Returns
    -------
    XXZExact

    Raises
    ------
    ValueError
        On bad input or more than :data:`ED_MAX_SITES` sites.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins.quantum import xxz_exact
    >>> x = xxz_exact(hl.ring_lattice(8, 3, 1), J=-1.0, Delta=1.0, beta=1.0, h=0.5)
    >>> x.mz > 0, x.sites
    (True, 8)
    """
    from ..bosons import sse

    J, Delta, h, beta = _physical(J, Delta, h, beta)
    mat, _, _, _, label = sse._matrix(system)
    n = mat.shape[0]
    if n > ED_MAX_SITES:
        raise ValueError(f"exact diagonalisation takes at most {ED_MAX_SITES} sites, got {n}.")
    up = sp.triu(mat, k=1).tocoo()
    keep = up.data != 0
    bi = up.row[keep].astype(np.int64)
    bj = up.col[keep].astype(np.int64)
    Jb = J * up.data[keep]
    colours = _two_colouring(n, bi, bj, -np.ones(bi.size)) if bi.size else np.ones(n)
    stag = colours if colours is not None else np.zeros(n)
    states = np.arange(2 ** n, dtype=np.int64)
    bits = ((states[:, None] >> np.arange(n)[None, :]) & 1).astype(float) - 0.5      # S^z_i per state
    pop = (bits > 0).sum(axis=1)
    energies, weights_sz, weights_ms2, weights_site, weights_stag, weights_zz, weights_xy = [], [], [], [], [], [], []
    for k in range(n + 1):
        basis = states[pop == k]
        sz = bits[basis]
        dim = basis.size
        H = np.zeros((dim, dim))
        zz = sz[:, bi] * sz[:, bj]
        H[np.diag_indices(dim)] = zz @ (Jb * Delta) - h * sz.sum(axis=1)
        pairs = []
        for b in range(bi.size):
            differ = sz[:, bi[b]] != sz[:, bj[b]]
            src = np.flatnonzero(differ)
            dst = np.searchsorted(basis, basis[src] ^ ((1 << bi[b]) | (1 << bj[b])))
            H[dst, src] += 0.5 * Jb[b]
            pairs.append((src, dst))
        vals, vecs = np.linalg.eigh(H)
        prob = vecs ** 2                                   # |psi_n(alpha)|^2, (dim, levels)
        ms = sz @ stag
        energies.append(vals)
        weights_sz.append(np.full(dim, sz.sum(axis=1)[0] if dim else 0.0))
        weights_ms2.append(prob.T @ (ms ** 2))
        weights_site.append(prob.T @ sz)
        weights_stag.append(prob.T @ (sz * ms[:, None]))
        weights_zz.append(prob.T @ zz)
        xy = np.empty((dim, bi.size))
        for b, (src, dst) in enumerate(pairs):
            # <S^x S^x + S^y S^y> = (1/2) <S^+_i S^-_j + h.c.>: sum over the connected pairs
            xy[:, b] = 0.5 * np.einsum("ij,ij->j", vecs[src], vecs[dst])
        weights_xy.append(xy)
    E = np.concatenate(energies)
    e0 = float(E.min())
    w = np.exp(-beta * (E - e0))
    w /= w.sum()
    Sz = np.concatenate(weights_sz)
    avg = lambda parts: w @ np.concatenate(parts, axis=0)  # noqa: E731
    eav = float(w @ E)
    szav = float(w @ Sz)
    s_pi = float(avg(weights_ms2)) / n if colours is not None else math.nan
    site_stag = stag * avg(weights_stag) / n if colours is not None else np.full(n, math.nan)
    return XXZExact(system=label, sites=n, J=J, Delta=Delta, h=h, beta=beta, e=eav / n,
                    c=float(beta ** 2 * (w @ E ** 2 - eav ** 2) / n), chi_u=float(beta * (w @ Sz ** 2 - szav ** 2) / n),
                    mz=szav / n, s_pi=s_pi, ground_energy=e0, stagger=stag, site_sz=avg(weights_site),
                    site_stag=site_stag, bonds=np.stack([bi, bj], axis=1), bond_zz=avg(weights_zz),
                    bond_xy=avg(weights_xy))


# ----------------------------------------------------------------------------
# the chain
# ----------------------------------------------------------------------------

class _Chain:
    """The full state of one chain (what a checkpoint stores)."""

    FIELDS = ("ops", "state", "rng", "sbins", "scur", "sinfo", "vbins", "vcur", "vinfo", "loopstat", "counters")

    def __init__(self, n: int, nb: int, seed: int, length: int, ncol: int):
        from ..bosons import _sse_kernels as BK

        self.ops = np.full(max(16, int(length)), -1, dtype=np.int64)
        self.state = np.zeros(n, dtype=np.int64)
        self.state[::2] = 1
        self.rng = BK.seed_state(seed)
        self.sbins = np.zeros((_SCALAR_BINS, ncol))
        self.scur = np.zeros(ncol)
        self.sinfo = np.array([0, 1, 0], dtype=np.int64)
        self.vbins = np.zeros((_VECTOR_BINS, 2 * n + 2 * nb))
        self.vcur = np.zeros(2 * n + 2 * nb)
        self.vinfo = np.array([0, 1, 0], dtype=np.int64)
        self.loopstat = np.zeros(4)
        # nops, nloops, thermalisation sweeps done, measurement sweeps done
        self.counters = np.array([0, 1, 0, 0], dtype=np.int64)

    def save(self, path, fingerprint: str) -> None:
        # the QMC's checkpoint file: one SHA-256 over every array and the metadata, atomic write
        _mc_chain.write(path, {"fingerprint": fingerprint}, {k: getattr(self, k) for k in self.FIELDS})

    def load(self, path, fingerprint: str, model: "_Spins", wdiag: np.ndarray) -> None:
        """Take the chain of the checkpoint ``path`` after checking its checksum, fingerprint, dtypes and
        shapes (:func:`hyperlattice._mc_chain.load_chain`) and then its contents (:meth:`check`)."""
        data = _mc_chain.load_chain(path, fingerprint, {k: getattr(self, k) for k in self.FIELDS},
                                    "graph, J, Delta, h, beta, seed or thermalization", grow=("ops",))
        self.check({**data, "_wdiag": wdiag}, model, repr(str(path)))
        for k in self.FIELDS:
            setattr(self, k, np.array(data[k]))

    @staticmethod
    def check(data: dict, model: "_Spins", where: str) -> None:
        r"""Refuse (ValueError, one sentence) a stored chain that this chain could not have produced: an
        operator that is not -1 or :math:`4b + k` (k = 0, 1, 2) on a bond b, a spin that is not 0 or 1,
        world lines that leave 0..1 or are not periodic in imaginary time, a diagonal operator where
        its vertex weight is 0, counters that disagree with the string or the bins, a generator
        state of zeros, and bins that are not finite or lie outside what the chain can produce.
        (The checksum catches an accidental edit; this catches one whose checksum was recomputed.)"""
        def bad(what):
            return ValueError(f"the checkpoint {where} is inconsistent ({what}); delete it to start the chain afresh.")

        ops, state, counters = data["ops"], data["state"], data["counters"]
        m, n, nb = ops.size, model.sites, model.bi.size
        if m < 16 or 4 * m >= 2**31 - 1:
            raise bad(f"an operator string of length {m}")
        kind, bond = ops & 3, ops >> 2
        if np.any((ops < -1) | ((ops >= 0) & ((bond >= nb) | (kind == 3)))):
            raise bad("an operator that is not -1 or 4 b + k with a bond b and k = 0, 1, 2")
        if np.any((state < 0) | (state > 1)):
            raise bad("a spin state that is not 0 (down) or 1 (up)")
        # the world lines: an off-diagonal operator exchanges the two spins of its bond (kind 1 moves
        # the up spin from j to i, kind 2 from i to j); every site's spin stays 0 or 1 and comes
        # back to its first slice's value (periodic in imaginary time)
        live = np.flatnonzero(ops >= 0)
        lk, lb = kind[live], bond[live]
        offd = lk != 0
        step = np.where(lk[offd] == 1, 1, -1)
        site = np.concatenate([model.bi[lb[offd]], model.bj[lb[offd]]])
        delta = np.concatenate([step, -step])
        when = np.concatenate([live[offd]] * 2)
        order = np.lexsort((when, site))
        site, delta, when = site[order], delta[order], when[order]
        run = np.cumsum(delta)
        starts = np.flatnonzero(np.r_[True, site[1:] != site[:-1]]) if site.size else np.zeros(0, dtype=np.int64)
        base = np.repeat(run[starts] - delta[starts], np.diff(np.r_[starts, site.size]))
        spin = state[site] + run - base          # the spin of ``site`` just after the operator at ``when``
        if np.any((spin < 0) | (spin > 1)):
            raise bad("its world lines leave the spin values 0 and 1")
        ends = np.r_[starts[1:], site.size][: starts.size] - 1
        if site.size and np.any(spin[ends] != state[site[ends]]):
            raise bad("its world lines are not periodic in imaginary time")
        # a diagonal operator must sit where its vertex weight W_b(n_i, n_j) is positive
        dpos, db = live[~offd], lb[~offd]
        key = site.astype(np.int64) * (m + 1) + when

        def spin_at(x, p):
            k = np.searchsorted(key, x * (m + 1) + p) - 1
            hit = (k >= 0) & (site[np.maximum(k, 0)] == x) if site.size else np.zeros(x.size, bool)
            return np.where(hit, spin[np.maximum(k, 0)] if site.size else 0, state[x])

        if db.size:
            si, sj = spin_at(model.bi[db], dpos), spin_at(model.bj[db], dpos)
            if np.any(data["_wdiag"][db, si, sj] <= 0):
                raise bad("a diagonal operator where its vertex weight is zero")
        nops = int(live.size)
        if counters[0] != nops or not 1 <= counters[1] <= 4 * (nops + 16) or np.any(counters[2:] < 0):
            raise bad("its operator and loop counters")
        if not np.any(data["rng"]):
            raise bad("a generator state of zeros")
        for k in ("sbins", "scur", "vbins", "vcur", "loopstat"):
            if not np.all(np.isfinite(data[k])):
                raise bad(f"non-finite numbers in {k}")
        if np.any(data["loopstat"] < 0):
            raise bad("its loop statistics")
        sweeps = int(counters[3])
        for info, bins in (("sinfo", "sbins"), ("vinfo", "vbins")):
            filled, size, cur = (int(x) for x in data[info])
            if not (0 <= filled < data[bins].shape[0] and size >= 1 and size & (size - 1) == 0 and 0 <= cur < size):
                raise bad(f"its bin counters {info}")
            if filled * size + cur != sweeps:
                raise bad(f"its bin counters {info} disagree with its {sweeps} measured sweeps")
        # closed scalar bins: sums over ``size`` sweeps of n (0..M), S^z_tot (|.| <= N/2), M_s^2
        # (0..N^2/4) and of their squares (sum x^2 >= (sum x)^2 / size)
        filled, size = int(data["sinfo"][0]), int(data["sinfo"][1])
        sb = data["sbins"][:filled]
        tol = 1 + 1e-9
        if (np.any(sb[:, 0] < 0) or np.any(sb[:, 0] > size * m * tol) or np.any(np.abs(sb[:, 4]) > size * n / 2 * tol)
                or np.any(sb[:, 7] < 0) or np.any(sb[:, 7] > size * n * n / 4 * tol)):
            raise bad("its scalar bins lie outside what the chain can produce")
        for x, x2 in ((0, 1), (2, 3), (4, 5), (7, 8), (10, 11)):
            if np.any(sb[:, x2] * size < sb[:, x] ** 2 * (1 - 1e-9) - 1e-9):
                raise bad("its scalar bins are not sums of a quantity and of its square")


#: seconds of work between checkpoint writes
_CHECKPOINT_SECONDS = 60.0
#: the checkpoint file and the lock file in a checkpoint directory
_CHECKPOINT_FILE = "xxz_chain.npz"
_LOCK_FILE = ".xxz_chain.lock"


def _fingerprint(model: "_Spins", J, Delta, h, beta, seed, thermalization, wind) -> str:
    import hashlib
    import json

    d = hashlib.sha256()
    for a in (model.bi, model.bj, model.Jb, wind):
        d.update(np.ascontiguousarray(a).tobytes())
    d.update(json.dumps([model.sites, J, Delta, h, beta, seed, thermalization, OFFSET, _TARGET_LEGS, _SCALAR_BINS,
                         _VECTOR_BINS]).encode())
    return d.hexdigest()


def _load_kernels():
    def load():
        from . import _quantum_kernels

        return _quantum_kernels

    return _mc_chain.load_kernels(load, "quantum Monte Carlo")


def _neighbour_bonds(n: int, bi: np.ndarray, bj: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CSR lists of the bonds of each site."""
    ends = np.concatenate([bi, bj])
    bonds = np.concatenate([np.arange(bi.size), np.arange(bi.size)])
    order = np.argsort(ends, kind="stable")
    ptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(ends, minlength=n), out=ptr[1:])
    return ptr, bonds[order].astype(np.int64)


def xxz_qmc(system, *, J: float, Delta: float, beta: float, h: float = 0.0, sweeps: int = 20000,
            thermalization: int | None = None, seed: int | None = None, windings=None, checkpoint=None,
            progress=None) -> XXZResult:
    r"""SSE quantum Monte Carlo of the spin-1/2 XXZ model (one Markov chain).

    Parameters
    ----------
    system : Lattice, Cluster or adjacency matrix
        A flake (:func:`~hyperlattice.ring_lattice`), a periodic cluster
        (:func:`~hyperlattice.graph.clusters.pbc_cluster`) or a symmetric matrix A (couplings
        :math:`J_{ij} = J A_{ij}`).
    J : float
        Exchange (J > 0 antiferromagnet: bipartite graphs only; J < 0 ferromagnet: any graph).
    Delta : float
        Anisotropy (1: Heisenberg, 0: XY); any real value (see the module's notes).
    beta : float
        Inverse temperature, > 0.
    h : float, optional
        Field along z (default 0).
    sweeps : int, optional
        Measurement sweeps (default 20000).
    thermalization : int, optional
        Thermalisation sweeps (default ``max(200, sweeps // 5)``).
    seed : int, optional
        Seed; None draws one (stored in the result).
    windings : Windings or (edges, windings) or False, optional
        As in :func:`hyperlattice.bosons.qmc`: by default a periodic cluster's windings (spin
        stiffness), none on a flake or a matrix.
    checkpoint : str or path, optional
        A directory: the chain is saved there every minute and at the end, and a rerun with the
        same arguments (``sweeps`` may grow; give ``thermalization`` explicitly, its default
        depends on ``sweeps``) resumes it, bit-identically to an uninterrupted run.
    progress : bool, optional
        Progress bar on stderr (default: when a terminal watches).

    Returns
    -------
    XXZResult

    Raises
    ------
    ValueError
        On bad input or a sign problem (J > 0 on a graph with an odd cycle).
    MemoryError
        When the operator string will not fit.

    Warns
    -----
    XXZWarning
        When a binning plateau is not reached or the halves of the measurements disagree.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins.quantum import xxz_exact, xxz_qmc
    >>> ring = hl.ring_lattice(8, 3, 1)
    >>> r = xxz_qmc(ring, J=1.0, Delta=1.0, beta=2.0, sweeps=4000, seed=2, progress=False)
    >>> x = xxz_exact(ring, J=1.0, Delta=1.0, beta=2.0)
    >>> bool(abs(r.e - x.e) < 4 * r.e_err), bool(abs(r.s_pi - x.s_pi) < 4 * r.s_pi_err)
    (True, True)
    """
    from ..bosons import sse

    J, Delta, h, beta = _physical(J, Delta, h, beta)
    sweeps = _validate.integer("sweeps", sweeps, minimum=1)
    if thermalization is None:
        thermalization = max(200, sweeps // 5)
    thermalization = _validate.integer("thermalization", thermalization, minimum=0)
    if seed is None:
        seed = int(np.random.SeedSequence().entropy % (2**63))
    seed = _validate.integer("seed", seed, minimum=0)
    model = _spins(system, J)
    wind, wind_note = sse._bond_windings(system, model.boson_model, windings)
    hd, cb, wdiag = _diagonal(model, Delta, h)
    jz = model.Jb * Delta
    key = np.concatenate([model.tb[:, None], wdiag.reshape(-1, 4)], axis=1)
    _, rep, cls = np.unique(key, axis=0, return_index=True, return_inverse=True)
    QK = _load_kernels()
    wmax = np.maximum(wdiag.reshape(-1, 4).max(axis=1), model.tb)
    bound = beta * float(wmax.sum()) + 16
    n, nb = model.sites, model.bi.size
    need = (sse._BYTES_PER_OP * bound * sse._STRING_MARGIN + 8.0 * (2 * n + 2 * nb) * (_VECTOR_BINS + 4)
            + rep.size * 4096.0 + 8.0 * (n + nb) * 12)
    _validate.require_memory(f"the XXZ SSE chain (an operator string of up to {bound:,.0f} operators at "
                             f"beta = {beta:g}, its bins, and {sse._RUNTIME_BYTES // 2**20} MiB for the compiled "
                             "kernels)", need + sse._RUNTIME_BYTES)
    ptab = QK.exit_table(rep.astype(np.int64), wdiag, model.tb)
    bclass = cls.astype(np.int64).ravel()
    nptr, nbond = _neighbour_bonds(n, model.bi, model.bj)
    ndim = int(wind.shape[1])
    ncol = QK.NSCALARS + (ndim * (ndim + 1) // 2 + 1 if ndim else 0)
    chain = _Chain(n, nb, seed, min(bound / 4, 1e8), ncol)
    fp = _fingerprint(model, J, Delta, h, beta, seed, thermalization, wind)
    ckdir = None if checkpoint is None else _validate.directory("checkpoint", checkpoint)
    with contextlib.ExitStack() as stack:
        if ckdir is not None:
            stack.enter_context(_mc_chain.locked(ckdir, _LOCK_FILE))
        stop = stack.enter_context(_mc_chain.StopSignals())
        start = time.perf_counter()
        _run_chain(chain, model, fp, ckdir, stop, QK, dict(
            beta=beta, sweeps=sweeps, thermalization=thermalization, cb=cb, wdiag=wdiag, jz=jz, h=h, nptr=nptr,
            nbond=nbond, ptab=ptab, bclass=bclass, wind=wind, progress=progress))
    seconds = time.perf_counter() - start
    return _analyse(chain, model, J=J, Delta=Delta, h=h, beta=beta, sweeps=sweeps, thermalization=thermalization,
                    seed=seed, ndim=ndim, wind_note=wind_note, seconds=seconds)


def _run_chain(chain: _Chain, model: _Spins, fp: str, ckdir, stop, QK, a: dict) -> None:
    """Advance the chain of :func:`xxz_qmc` from its checkpoint (if any) to the end; on SIGINT/SIGTERM
    save it (with a checkpoint directory) and hand the signal on."""
    beta, sweeps, thermalization = a["beta"], a["sweeps"], a["thermalization"]
    ckpt = None if ckdir is None else ckdir / _CHECKPOINT_FILE
    if ckpt is not None and ckpt.exists():
        chain.load(ckpt, fp, model, a["wdiag"])
        if chain.counters[3] > sweeps:
            raise ValueError(f"the checkpoint already holds {int(chain.counters[3])} measured sweeps, more than "
                             f"the {sweeps} asked for.")
    done = chain.counters

    def stop_now():
        if ckpt is not None:
            chain.save(ckpt, fp)
            kept = f"the chain is saved in {str(ckdir)!r}: rerun the same command to resume"
        else:
            kept = "nothing kept (a checkpoint directory, --checkpoint DIR, keeps the chain for a rerun)"
        stop.reraise(f"stopped after {int(done[2] + done[3]):,} of {thermalization + sweeps:,} sweeps; {kept}")

    last_save = time.perf_counter()
    with progress_bar(thermalization + sweeps, "spins quantum", unit="sweep", progress=a["progress"]) as bar:
        bar.update(int(done[2] + done[3]))
        chunk = 16
        while done[2] < thermalization or done[3] < sweeps:
            therm = bool(done[2] < thermalization)
            left = (thermalization - done[2]) if therm else (sweeps - done[3])
            k = int(min(chunk, left))
            t0 = time.perf_counter()
            ops, nops, nloops = QK.run(k, therm, _TARGET_LEGS, chain.ops, chain.state, int(done[0]), int(done[1]),
                                       beta, model.bi, model.bj, model.tb, a["cb"], a["wdiag"], a["jz"], a["h"],
                                       model.stag, a["nptr"], a["nbond"], chain.rng, chain.sbins, chain.scur,
                                       chain.sinfo, chain.vbins, chain.vcur, chain.vinfo, chain.loopstat, a["ptab"],
                                       a["bclass"], a["wind"])
            chain.ops = ops
            done[0], done[1] = nops, nloops
            done[2 if therm else 3] += k
            bar.update(k)
            if stop.signum is not None:
                stop_now()
            dt = time.perf_counter() - t0
            # chunks of about half a second (the split never changes the chain)
            chunk = int(max(1, min(4 * chunk, k * 0.5 / max(dt, 1e-6))))
            if ckpt is not None and time.perf_counter() - last_save > _CHECKPOINT_SECONDS:
                chain.save(ckpt, fp)
                last_save = time.perf_counter()
    if ckpt is not None:
        chain.save(ckpt, fp)


def _analyse(chain: _Chain, model: _Spins, *, J, Delta, h, beta, sweeps, thermalization, seed, ndim, wind_note,
             seconds) -> XXZResult:
    from . import _quantum_kernels as QK

    nb, bs = int(chain.sinfo[0]), int(chain.sinfo[1])
    if nb < 2:
        raise HyperlatticeError("too few sweeps for an error estimate (fewer than two complete bins).")
    n = model.sites
    raw = chain.sbins[:nb] / bs
    mean = raw.mean(axis=0)
    notes = []
    if Delta == 1 and h == 0:
        # SU(2): <H> = 3 <H_zz>, so (E + 3 E_diag) / 2 is unbiased too, with the kinetic energy's
        # operator-count noise halved
        series = 0.5 * (raw[:, 2] + 3 * raw[:, 10]) / n
        var = (0.25 * (mean[3] - mean[2] ** 2) + 2.25 * (mean[11] - mean[10] ** 2)
               + 1.5 * (mean[12] - mean[2] * mean[10])) / n ** 2
        estimator = "su2"
    else:
        series = raw[:, 2] / n
        var = (mean[3] - mean[2] ** 2) / n ** 2
        estimator = "slice"
    en = mcstats.binning(series, bs, variance=max(var, 0.0))
    mzb = mcstats.binning(raw[:, 4] / n, bs, variance=max(mean[5] - mean[4] ** 2, 0.0) / n ** 2)
    s2 = mcstats.binning(raw[:, 5], bs, variance=max(mean[6] - mean[5] ** 2, 0.0))
    sp_b = mcstats.binning(raw[:, 7] / n, bs, variance=max(mean[8] - mean[7] ** 2, 0.0) / n ** 2)
    plateau = mcstats.plateau_bins(raw)
    c, c_err = mcstats.jackknife(lambda a, b: (b - a * a - a) / n, plateau[:, 0], plateau[:, 1])
    chi, chi_err = mcstats.jackknife(lambda a, b: beta * (b - a * a) / n, plateau[:, 4], plateau[:, 5])
    if model.bipartite:
        bnd, bnd_err = mcstats.jackknife(lambda a, b: b / (a * a) if a > 0 else math.nan, plateau[:, 7], plateau[:, 9])
        s_pi, s_pi_err = sp_b.mean, sp_b.error
    else:
        bnd = bnd_err = s_pi = s_pi_err = math.nan
    tau = {"energy": en.tau_int, "chi_u": s2.tau_int}
    checks = [("energy", en), ("S^z_tot^2", s2)]
    if model.bipartite:
        tau["s_pi"] = sp_b.tau_int
        checks.append(("s_pi", sp_b))
    converged = True
    rho = rho_err = math.nan
    if ndim:
        from ..bosons import sse

        st = sse._stiffness(raw[:, QK.NSCALARS - sse._SCALARS:], bs, beta, ndim, notes)
        rho, rho_err = st["rho_s"], st["rho_s_err"]
        tau["stiffness"] = st["tau"]
        converged = st["converged"]
    for name, b in checks:
        if not b.converged:
            converged = False
            notes.append(f"the binning error of {name} has not reached a plateau ({nb * bs} sweeps, tau_int = "
                         f"{b.tau_int:.3g} sweeps): run longer.")
    pl = mcstats.plateau_bins(raw[:, [2, 7]])
    half = pl.shape[0] // 2
    if half >= 2:
        for k, name in ((0, "energy"), (1, "staggered structure factor")):
            a, b = pl[:half, k], pl[half:2 * half, k]
            sig = math.hypot(a.std(ddof=1), b.std(ddof=1)) / math.sqrt(half)
            diff = abs(a.mean() - b.mean())
            if diff > 4 * sig and diff > 1e-12 * (1 + abs(a.mean())):
                converged = False
                notes.append(f"the {name} of the first and second half of the measurements differ by "
                             f"{diff / sig:.1f} sigma: thermalisation ({thermalization} sweeps) was too short.")
    if chain.loopstat[2] > 0:
        converged = False
        notes.append(f"{int(chain.loopstat[2])} sweep(s) had a directed loop longer than the cap and their loop "
                     "update was undone: run with more thermalization sweeps.")
    if float(raw[:, 0].max()) > 0.9 * chain.ops.size:
        converged = False
        notes.append(f"the operator string (length {chain.ops.size}) was nearly full during the measurements: "
                     "run with more thermalization sweeps.")
    vnb, vbs = int(chain.vinfo[0]), int(chain.vinfo[1])
    vb = chain.vbins[:vnb] / vbs
    nbd = model.bi.size

    def stats(a):
        return a.mean(axis=0), (a.std(axis=0, ddof=1) / math.sqrt(vnb) if vnb > 1 else np.full(a.shape[1:], np.nan))

    site_sz, site_sz_err = stats(vb[:, :n])
    stag_bins = vb[:, n:2 * n] / n
    site_stag, site_stag_err = stats(stag_bins)
    zz, zz_err = stats(vb[:, 2 * n:2 * n + nbd])
    xy, xy_err = stats(-vb[:, 2 * n + nbd:] / (beta * model.Jb[None, :]))
    ring_stag = ring_err = None
    if not model.bipartite:
        site_stag = np.full(n, np.nan)
        site_stag_err = np.full(n, np.nan)
    elif model.ring is not None:
        nr = int(model.ring.max())
        per = np.stack([stag_bins[:, model.ring == r].mean(axis=1) for r in range(1, nr + 1)], axis=1)
        ring_stag, ring_err = stats(per)
    for note in notes:
        warnings.warn(note, XXZWarning, stacklevel=3)
    return XXZResult(
        system=model.label, sites=n, J=J, Delta=Delta, h=h, beta=beta, sweeps=sweeps, thermalization=thermalization,
        seed=seed, seeds=(seed,), chains=1, bipartite=model.bipartite, e=en.mean, e_err=en.error,
        c=float(c), c_err=float(c_err), chi_u=float(chi), chi_u_err=float(chi_err), mz=mzb.mean, mz_err=mzb.error,
        s_pi=float(s_pi), s_pi_err=float(s_pi_err), binder=float(bnd), binder_err=float(bnd_err),
        rho_s=float(rho), rho_s_err=float(rho_err), stiffness_note=wind_note, tau_int=tau,
        bins=int(plateau.shape[0]), bin_size=int(bs * (nb // plateau.shape[0])), converged=converged,
        notes=tuple(notes), stagger=model.stag, ring=model.ring, site_sz=site_sz, site_sz_err=site_sz_err,
        site_stag=site_stag, site_stag_err=site_stag_err, ring_stag=ring_stag, ring_stag_err=ring_err,
        bonds=np.stack([model.bi, model.bj], axis=1), bond_zz=zz, bond_zz_err=zz_err, bond_xy=xy, bond_xy_err=xy_err,
        mean_operators=float(mean[0]), string_length=int(chain.ops.size), loops_per_sweep=int(chain.counters[1]),
        update=_EXIT_RULE, energy_estimator=estimator, seconds=float(seconds))


def merge_xxz(results) -> XXZResult:
    r"""Merge independent chains (same model, different seeds) into one result.

    Sweep-weighted means with the propagated errors (:func:`hyperlattice.mcstats.combine_independent`),
    per observable, site, bond and ring.

    Parameters
    ----------
    results : sequence of XXZResult
        Chains of one model (system, sites, J, Delta, h, beta), distinct seeds.

    Returns
    -------
    XXZResult

    Raises
    ------
    ValueError
        If the list is empty, holds other objects, chains of different models or a seed twice.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins.quantum import merge_xxz, xxz_qmc
    >>> runs = [xxz_qmc(hl.ring_lattice(8, 3, 1), J=1.0, Delta=1.0, beta=1.0, sweeps=4000, seed=s,
    ...                 progress=False) for s in (1, 2)]
    >>> m = merge_xxz(runs)
    >>> m.chains, m.sweeps, m.seeds
    (2, 8000, (1, 2))
    """
    res, seeds, w = _mc_chain.chains_to_merge(results, XXZResult, "merge_xxz",
                                              ("system", "sites", "J", "Delta", "h", "beta"), single=False)
    ref = res[0]
    for r in res[1:]:
        if r.bonds.shape != ref.bonds.shape or not np.array_equal(r.bonds, ref.bonds):
            raise ValueError("merge_xxz needs chains of one model; the bonds differ.")
    tot = float(w.sum())
    vals = _mc_chain.merged_scalars(res, w, ("e", "c", "chi_u", "mz", "s_pi", "binder", "rho_s"))
    a = {}
    for name in ("site_sz", "site_stag", "ring_stag", "bond_zz", "bond_xy"):
        a[name], a[name + "_err"] = _mc_chain.weighted_arrays(res, w, name)
    return XXZResult(
        system=ref.system, sites=ref.sites, J=ref.J, Delta=ref.Delta, h=ref.h, beta=ref.beta,
        **_mc_chain.merged_run(res, w, seeds), bipartite=ref.bipartite, stiffness_note=ref.stiffness_note,
        stagger=ref.stagger, ring=ref.ring, bonds=ref.bonds,
        mean_operators=float(sum(wc * r.mean_operators for wc, r in zip(w, res)) / tot),
        string_length=int(max(r.string_length for r in res)), loops_per_sweep=int(ref.loops_per_sweep),
        update=ref.update, energy_estimator=ref.energy_estimator, **vals, **a)


_validate.guard_public(globals())
