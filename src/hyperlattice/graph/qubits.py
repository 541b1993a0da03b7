r"""Below the band: the lattice propagator as a positive-definite solve, and circuit-QED qubits.

Qubits of frequency :math:`\omega_q` below the photon band, each coupled with strength g to one
site (of a {p,q} lattice, or of its line graph, the resonator array of the devices), in the
single-excitation sector:

.. math:: \mathcal H = \begin{pmatrix} H & gB \\ gB^T & \omega_q \mathbb 1_K \end{pmatrix},
          \qquad H = -tA,\quad B_{j_k k} = 1,

(rotating-wave Jaynes–Cummings lattice, one excitation). Eliminating the photons exactly (Schur
complement) gives the qubit block :math:`\omega_q - g^2 B^T G(E) B` with
:math:`G(E) = (H - E)^{-1}` (``eq20``). Hence

* **bound state** of one qubit on site :math:`j_0`: :math:`E_b` solves
  :math:`E - \omega_q + g^2 G_{j_0j_0}(E) = 0`, unique below the band bottom :math:`E_0` (the left
  side increases monotonically from :math:`-\infty` to :math:`+\infty` on :math:`(-\infty, E_0)`), and
  the photon amplitude is :math:`\phi = g\,G(E_b)e_{j_0}` (qubit amplitude :math:`-1` before
  normalization). To leading order in g, :math:`E_b \approx \omega_q - g^2G_{j_0j_0}(\omega_q)` and
  :math:`\phi \propto G_{\cdot j_0}(\omega_q)`; the normalized profiles differ by :math:`O(g^2)`
  because :math:`E_b - \omega_q = O(g^2)`.
* **effective spin model** to order :math:`g^2`:
  :math:`H_{\rm spin} = \sum_{kl} h_{kl}\sigma_k^+\sigma_l^-`,
  :math:`h = \omega_q\mathbb 1 - g^2 B^TG(\omega_q)B`, i.e. a Lamb shift
  :math:`-g^2G_{j_kj_k}(\omega_q)` and the exchange

  .. math:: H_{\rm spin} \ni -\sum_{k<l} J_{kl}(\sigma_k^+\sigma_l^- + \mathrm{h.c.}),
            \qquad J_{kl} = g^2 G_{j_kj_l}(\omega_q) > 0

  (below the band every entry of :math:`G` is positive). Bienias, Boettcher, Belyansky, Kollár
  and Gorshkov, PRL 128, 013601 (2022) study these bound states and exchange couplings.

The solves use :class:`BelowBandResolvent`: one sparse factorization per frequency through
:mod:`hyperlattice.graph.factor` (symbolic analysis once per lattice), whose success as a Cholesky
factorization (or the pivot signs of its :math:`LDL^T`) gives the inertia of :math:`H - \omega`
(Sylvester's law): it proves :math:`\omega < E_0`, so "below the band" is checked exactly, at no
extra cost. It is shared with
:mod:`hyperlattice.compare.boundary` (the boundary correlators of the massive scalar).
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..errors import ConvergenceError
from ..geometry import distance
from ..results import Column, Grid, INDEX, Result
from .lattice import Lattice
from .operators import hamiltonian


__all__ = [
    "BelowBandResolvent",
    "qubit_hamiltonian",
    "BoundState",
    "bound_state",
    "SpinModel",
    "spin_model",
    "MAX_QUBITS",
]

#: largest number of qubits of one spin model (its coupling matrix is dense, K x K)
MAX_QUBITS = 20_000
_NEWTON_MAX = 60


#: largest coupling magnitude g / t accepted: circuit-QED couplings are g << t; beyond, the numbers mean nothing
#: physically (and g^2 G overflowed to inf from g ~ 1e154)
MAX_COUPLING = 1e6


def _coupling(g, t: float = 1.0) -> float:
    """The qubit-photon coupling g: a finite real number with :math:`|g| \\le` :data:`MAX_COUPLING` t."""
    g = _validate.real("g", g)
    t = _validate.positive_real("the hopping t", t)
    if abs(g) > MAX_COUPLING * t:
        raise ValueError(f"g = {g:g} is more than {MAX_COUPLING:g} t: far beyond the circuit-QED regime "
                         "(g << t) that the qubit models describe.")
    return g


def _unit(v: np.ndarray) -> np.ndarray:
    """``v / |v|`` without underflow (entries of ~1e-200 gave 0/0)."""
    big = float(np.max(np.abs(v))) if v.size else 0.0
    if big == 0.0:
        return v.astype(float)
    w = v / big
    return w / np.linalg.norm(w)


def _resolvent_for(resolvent, lat: Lattice, t: float = 1.0) -> "BelowBandResolvent":
    """The ``resolvent=`` argument of a function of ``lat``: a new :class:`BelowBandResolvent` for
    None, else one of this lattice and hopping (anything else was an AttributeError deep inside, or
    a resolvent of another lattice silently gave that lattice's numbers); one sentence if not."""
    if resolvent is None:
        return BelowBandResolvent(lat, t=t)
    if not isinstance(resolvent, BelowBandResolvent):
        raise ValueError(f"resolvent must be a BelowBandResolvent of this lattice (or None), "
                         f"got {type(resolvent).__name__}.")
    other = resolvent.lattice
    if other is not lat and (other.sites != lat.sites or not np.array_equal(other.edges, lat.edges)):
        raise ValueError(f"resolvent belongs to another lattice ({other.sites} sites; this one has {lat.sites}); "
                         "make it with BelowBandResolvent(lattice).")
    if resolvent.t != t:
        raise ValueError(f"resolvent was made with hopping t = {resolvent.t:g}, not t = {t:g}.")
    return resolvent


def _real_omega(name: str, omega) -> float:
    """A real frequency: complex values with a zero imaginary part are accepted."""
    if isinstance(omega, (complex, np.complexfloating)):
        w = _validate.complex_number(name, omega)
        if w.imag != 0:
            raise ValueError(f"{name} must be real (a frequency below the band), got {w}.")
        return w.real
    return _validate.real(name, omega)


class BelowBandResolvent:
    r""":math:`G(\omega) = (H - \omega)^{-1}` for real :math:`\omega` below the spectrum of :math:`H`.

    Parameters
    ----------
    system : Lattice
        The lattice (``kind`` ``"sites"`` or ``"line_graph"``); :math:`H = -tA`.
    t : float
        Hopping (default 1).
    method : {"auto", "cholmod", "superlu"}
        The factorisation backend of :mod:`hyperlattice.graph.factor` (``"auto"``: CHOLMOD when
        installed, else SuperLU; ``"ldl"``, the former default, means ``"auto"``). The symbolic
        analysis is done once per resolvent; every :math:`\omega` costs one numeric factorisation.
        H and the mirror-even blocks are built once per lattice and hopping and shared by all its
        resolvents (held weakly by the lattice).

    Notes
    -----
    **Below the band, proved.** :math:`H - \omega` is factorised without pivoting (CHOLMOD
    :math:`LL^T`, or SuperLU as :math:`LDL^T`); success of the Cholesky factorisation, or all pivots
    :math:`D_{kk} > 0`, proves it positive definite (Sylvester's law of inertia), i.e.
    :math:`\omega < E_0`; otherwise the :math:`LDL^T` pivots count the levels at or below
    :math:`\omega` for the error message. So "below the band" is checked exactly, by the
    factorisation itself.

    **Accuracy.** :math:`H - \omega` is then a nonsingular M-matrix (off-diagonal entries
    :math:`\le 0`): its Cholesky factor has entries :math:`\le 0` below the diagonal and the
    triangular solves for a right-hand side :math:`e_j \ge 0` add terms of one sign only, so every
    entry of the column, down to :math:`G_{ij} \sim 10^{-21}` across an :math:`\ell = 10` flake,
    comes with a small *relative* error (measured 2e-13 against ``spsolve``). Krylov solvers (CG,
    multi-shift CG) give a small *normwise* residual and cannot resolve these entries; the boundary
    fit needs them.

    **A source on a mirror axis** (:meth:`column`; e.g. the first outer-ring site of the {7,3}
    flakes with ℓ = 4, 10): the column is even under the reflection :math:`\sigma` through that
    axis, so it is solved in the mirror-even block :math:`B^T H B` (:math:`B` the orthonormal even
    basis: :math:`e_i` for a site on the axis, :math:`(e_i + e_{\sigma i})/\sqrt2` for a pair),
    half the size of H, and read back as :math:`G_{ij} = B_{i,c(i)} x_{c(i)}`. The block is again
    an M-matrix (B has non-negative entries), so the relative accuracy above holds, and it keeps
    the ground state (a non-negative ground state u of H gives the even, non-negative
    :math:`u + \sigma u`: Perron–Frobenius), so its positive definiteness still proves
    :math:`\omega < E_0`. The reflection :math:`z \mapsto e^{2i\arg z_j}\bar z` is found from
    the coordinates and accepted only when it maps the edge set onto itself exactly. Rotation
    sectors are *not* used for single columns: their Fourier sum cancels the O(1) correlators of
    the source's images down to entries of ~1e-21 and would lose the relative accuracy.

    :math:`\omega` is in the unit of t; rows and columns are sites, 0-based ring by ring.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.qubits import BelowBandResolvent
    >>> res = BelowBandResolvent(hl.ring_lattice(7, 3, 3))
    >>> g = res.column(-3.5, 0)
    >>> g.shape, round(float(g[0]), 6), round(float(g[1]), 6)
    ((112,), 0.415206, 0.151157)
    >>> res.factor(-3.5).positive_definite        # the proof that -3.5 t lies below E0
    True
    """

    def __init__(self, system: Lattice, *, t: float = 1.0, method: str = "auto") -> None:
        from .factor import resolve_backend

        lat = _validate.lattice(system)
        t = _validate.positive_real("the hopping t", t)
        method = _validate.choice("method", method, ("auto", "cholmod", "superlu", "ldl"))
        self.method = "auto" if method == "ldl" else method
        self.backend = resolve_backend(self.method)
        self.lattice = lat
        self.t = t
        self._structure = _Structure.of(lat, t)
        self.n = lat.sites
        self._analysis = None
        self._factor = None
        self._omega = None
        #: what solved the last column: backend, factor kind and the matrix (full H or mirror-even block)
        self.route = ""
        self._mirrors = []          # this resolvent's mirror-even reductions (factor caches; see _mirror)

    @property
    def H(self) -> sp.csc_matrix:
        """:math:`H = -tA` (CSC, float64), built once per lattice and hopping."""
        return self._structure.hamiltonian(self.lattice)

    @property
    def _no_mirror(self) -> set:
        """Sources known to lie on no mirror axis (shared by the resolvents of one lattice)."""
        return self._structure.no_mirror

    def factor(self, omega):
        """The factorisation of :math:`H - \\omega` (a :class:`~hyperlattice.graph.factor.Factor`, cached for
        the last omega); ValueError unless omega lies below :math:`E_0`.

        Parameters
        ----------
        omega : float
            Real frequency in units of t, below the lowest level :math:`E_0`.

        Returns
        -------
        Factor
            The positive definite factorisation of :math:`H - \\omega`.

        Raises
        ------
        ValueError
            If the factorisation shows that omega is not below :math:`E_0`.
        """
        from .factor import FactorizationError, analyze

        omega = _real_omega("omega", omega)
        if self._factor is not None and self._omega == omega:
            return self._factor
        if self._analysis is None:
            self._analysis = analyze(self.H, backend=self.backend,
                                     what=f"H - omega of the {self.n:,}-site lattice")
        try:
            f = self._analysis.factor(omega, positive=True)
        except FactorizationError:
            raise ValueError(f"omega = {omega:g} is not safely below the band: the factorisation of H - omega "
                             "met a zero pivot (omega within rounding of a level).") from None
        if f.negatives is None:
            raise ValueError(f"omega = {omega:g}: the factorization of H - omega needed off-diagonal pivots; "
                             "omega is not safely below the band.")
        if f.negatives:
            raise ValueError(f"omega = {omega:g} is not below the band: {f.negatives} level(s) of H lie at or "
                             "below it (the propagator below the band needs omega < E0, the lattice BF bound).")
        self._factor, self._omega = f, omega
        return f

    def columns(self, omega, sources) -> np.ndarray:
        r"""Columns :math:`G_{\cdot j}(\omega)` for the given sources, real array ``(N, k)``.

        Parameters
        ----------
        omega : float
            Real frequency in units of t, below :math:`E_0`.
        sources : sequence of int
            Source sites j (0-based).

        Returns
        -------
        numpy.ndarray of float64, shape (N, len(sources))
            Column k is :math:`G_{\cdot j_k}(\omega)` (positive entries, units of 1/t).
        """
        src = _validate.site_indices("sources", sources, self.n)
        omega = _real_omega("omega", omega)
        f = self.factor(omega)
        rhs = np.zeros((self.n, src.size))
        rhs[src, np.arange(src.size)] = 1.0
        out = f.solve(rhs)
        if not np.all(np.isfinite(out)):
            raise ValueError(f"omega = {omega}: the solve overflowed (omega within rounding of E0).")
        self.route = f"{f.backend} {f.kind} of H ({self.n:,} rows)"
        return out

    def column(self, omega, source) -> np.ndarray:
        r"""One column :math:`G_{\cdot j}(\omega)`, shape ``(N,)`` (mirror-even block when j is on a mirror axis).

        Parameters
        ----------
        omega : float
            Real frequency in units of t, below :math:`E_0`.
        source : int
            The source site j (0-based).

        Returns
        -------
        numpy.ndarray of float64, shape (N,)
            :math:`G_{ij}(\omega)` for every site i (units of 1/t).
        """
        source = _validate.site_index("source", source, self.n)
        omega = _real_omega("omega", omega)
        return self._column_at(omega, source, None)

    def _column_at(self, omega: float, source: int, sites: np.ndarray | None) -> np.ndarray:
        """:meth:`column` after its checks, read back at ``sites`` only (all sites for None)."""
        mirror = self._mirror(source)
        if mirror is None:
            out = self.columns(omega, [source])[:, 0]
            return out if sites is None else out[sites]
        f = mirror.factor(omega, self)
        rhs = np.zeros(mirror.dim)
        rhs[mirror.cls[source]] = 1.0
        x = f.solve(rhs)
        out = (mirror.weight * x[mirror.cls] if sites is None
               else mirror.weight[sites] * x[mirror.cls[sites]])
        if not np.all(np.isfinite(out)):
            raise ValueError(f"omega = {omega}: the solve overflowed (omega within rounding of E0).")
        self.route = f"{f.backend} {f.kind} of the mirror-even block ({mirror.dim:,} of {self.n:,} rows)"
        return out

    def _mirror(self, source: int) -> "_MirrorEven | None":
        """The mirror-even reduction whose axis holds ``source``, or None (no such symmetry, or too small)."""
        for m in self._mirrors:
            if m.perm[source] == source:
                return m
        if self.n < _MIRROR_MIN:
            return None
        block = self._structure.mirror(self.lattice, source)
        if block is None:
            return None
        m = _MirrorEven(block, self.backend)
        self._mirrors.append(m)
        return m


class _Structure:
    """What depends on the lattice and the hopping only, shared by every resolvent of that lattice.

    H and the mirror-even blocks (the reflections, class maps and block matrices) are the matrices
    the solves start from, like the H handed to a plain sparse solver: building them again for
    every resolvent (a new frequency list, a new call of ``boundary_correlator``) was 60 % of a
    one-source column at l = 10. The symbolic analysis and the factors are *not* kept here: they
    belong to one resolvent and one backend. Held weakly by the lattice (a frozen object); it holds
    no reference back to it, so a lattice and its structure are freed together.
    """

    _cache: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()

    def __init__(self, t: float) -> None:
        self.t = t
        self._H = None
        self.mirrors = []           # _MirrorBlock found so far
        self.no_mirror = set()      # sources known to lie on no mirror axis
        self.tree = None

    @classmethod
    def of(cls, lat: Lattice, t: float) -> "_Structure":
        try:
            per_t = cls._cache.setdefault(lat, {})
        except TypeError:           # pragma: no cover - a lattice that cannot be weakly referenced
            return cls(t)
        if t not in per_t:
            per_t[t] = cls(t)
        return per_t[t]

    def hamiltonian(self, lat: Lattice) -> sp.csc_matrix:
        if self._H is None:
            H = hamiltonian(lat, t=self.t).tocsc().astype(float)
            H.sort_indices()
            self._H = H
        return self._H

    def mirror(self, lat: Lattice, source: int) -> "_MirrorBlock | None":
        for m in self.mirrors:
            if m.perm[source] == source:
                return m
        if source in self.no_mirror:
            return None
        m = _MirrorBlock.find(self, lat, source)
        if m is None:
            self.no_mirror.add(source)
            return None
        self.mirrors.append(m)
        return m


#: smallest lattice whose single columns use the mirror-even block (below, the full solve is instant)
_MIRROR_MIN = 2_000


def _ring_reflection(lat: Lattice, axis: complex) -> np.ndarray | None:
    """Candidate reflection through the axis of ``axis`` from the ring layout (sites of a ring counterclockwise).

    A reflection that fixes the centre keeps every ring and reverses its cyclic order: ring k is
    mapped by ``r -> (c_k - r) mod n_k``, with c_k twice the position of the site nearest the axis
    (or that minus/plus one when the axis passes between two sites). O(N), vectorised; the caller
    checks the candidate against the coordinates and the edges.
    """
    off = np.asarray(lat.ring_offsets, dtype=np.int64)
    n = int(off[-1])
    if off[0] != 0 or n != lat.sites or np.any(np.diff(off) <= 0):
        return None
    a = np.angle(np.asarray(lat.z) * (abs(axis) / axis))     # angle from the axis, (-pi, pi]
    absa = np.abs(a)
    starts, sizes = off[:-1], np.diff(off)
    mins = np.minimum.reduceat(absa, starts)
    hit = np.flatnonzero(absa == np.repeat(mins, sizes))
    r0 = hit[np.searchsorted(hit, starts)]                    # first site of each ring nearest the axis
    local = r0 - starts
    on_axis = absa[r0] <= 1e-6 * np.pi / sizes
    c2 = 2 * local + np.where(on_axis, 0, np.where(a[r0] > 0, -1, 1))
    ring_of = np.repeat(np.arange(sizes.shape[0]), sizes)
    pos = np.arange(n, dtype=np.int64) - starts[ring_of]
    return starts[ring_of] + (c2[ring_of] - pos) % sizes[ring_of]


class _MirrorBlock:
    r"""The mirror-even block :math:`B^T H B` of a reflection :math:`\sigma` (see :class:`BelowBandResolvent`).

    Structure only (reflection, class map, weights, the block with every diagonal entry stored and
    sorted indices, ready for :func:`~hyperlattice.graph.factor.analyze`); shared per lattice.
    """

    def __init__(self, perm: np.ndarray, H: sp.csc_matrix, what: str) -> None:
        n = perm.shape[0]
        idx = np.arange(n)
        fixed = perm == idx
        lead = idx <= perm
        pos = np.cumsum(lead) - 1
        self.perm = perm
        self.cls = pos[np.minimum(idx, perm)]
        self.dim = int(lead.sum())
        self.weight = np.where(fixed, 1.0, math.sqrt(0.5))
        # B^T H B from the lead rows only: for a pair {a, sigma a} the row of sigma a repeats that of
        # a (H commutes with sigma), so row c(a) = f_a w_a sum_k w_k H_ak with f_a = 2 for a pair;
        # the diagonal is stored (explicit zeros) so that every shift has the analysed pattern
        coo = H.tocoo()
        rows = coo.row if coo.row.dtype == np.int64 else coo.row.astype(np.int64)
        on = lead[rows]
        r, k = rows[on], coo.col[on]
        f = np.where(fixed[r], 1.0, 2.0) * self.weight[r] * self.weight[k]
        d = np.arange(self.dim)
        block = sp.csc_matrix((np.concatenate([f * coo.data[on], np.zeros(self.dim)]),
                               (np.concatenate([self.cls[r], d]), np.concatenate([self.cls[k], d]))),
                              shape=(self.dim, self.dim))
        block.sum_duplicates()
        self.block = block
        self.what = what

    @classmethod
    def find(cls, st: "_Structure", lat: Lattice, source: int) -> "_MirrorBlock | None":
        """The reflection through the axis of ``source`` when it is a symmetry of the graph, else None."""
        z = np.asarray(lat.z)
        zj = complex(z[source])
        if abs(zj) == 0.0:
            return None
        zr = (zj / abs(zj)) ** 2 * np.conj(z)
        # a candidate only: the map must match every site closely (well inside the local spacing,
        # which shrinks like 1 - |z|^2 towards the rim) and then be an exact automorphism of the graph
        tol = 1e-9 + 1e-6 * (1.0 - np.abs(z) ** 2)
        perm = _ring_reflection(lat, zj)
        if perm is None or not np.all(np.abs(z[perm] - zr) <= tol):
            from scipy.spatial import cKDTree   # any other layout: nearest site to every mirror image

            if st.tree is None:
                st.tree = cKDTree(np.column_stack([z.real, z.imag]))
            dist, perm = st.tree.query(np.column_stack([zr.real, zr.imag]))
            if not np.all(dist <= tol):
                return None
            perm = perm.astype(np.int64)
        n = perm.shape[0]
        if perm[source] != source or not np.array_equal(perm[perm], np.arange(n)):
            return None
        # every edge maps onto an edge of H (a bijection of the sites mapping the E edges into the E
        # edges maps them onto): the nonzeros of the CSC H, keyed column * n + row, are sorted
        e = np.asarray(lat.edges, dtype=np.int64)
        H = st.hamiltonian(lat)
        keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(H.indptr)) * n + H.indices
        mapped = perm[e[:, 1]] * n + perm[e[:, 0]]
        at = np.minimum(np.searchsorted(keys, mapped), keys.shape[0] - 1)
        if not np.array_equal(keys[at], mapped):
            return None
        return cls(perm, H, f"the mirror-even block of H - omega ({n:,}-site lattice)")


class _MirrorEven:
    """One resolvent's use of a :class:`_MirrorBlock`: its backend, analysis and last factor."""

    def __init__(self, block: _MirrorBlock, backend: str) -> None:
        self.structure = block
        self.perm, self.cls, self.dim, self.weight = block.perm, block.cls, block.dim, block.weight
        self.block, self.what = block.block, block.what
        self.backend = backend
        self._analysis = None
        self._factor = None
        self._omega = None

    def factor(self, omega: float, res: "BelowBandResolvent"):
        """Factorisation of the block minus omega, cached; ValueError unless omega lies below E0."""
        from .factor import FactorizationError, analyze

        if self._factor is not None and self._omega == omega:
            return self._factor
        if self._analysis is None:
            self._analysis = analyze(self.block, backend=self.backend, what=self.what)
        try:
            f = self._analysis.factor(omega, positive=True)
        except FactorizationError:
            raise ValueError(f"omega = {omega:g} is not safely below the band: the factorisation of H - omega "
                             "met a zero pivot (omega within rounding of a level).") from None
        if f.negatives is None:
            raise ValueError(f"omega = {omega:g}: the factorization of H - omega needed off-diagonal pivots; "
                             "omega is not safely below the band.")
        if f.negatives:
            raise ValueError(f"omega = {omega:g} is not below the band: {f.negatives} level(s) of the mirror-even "
                             "block of H lie at or below it (the propagator below the band needs omega < E0, the "
                             "lattice BF bound).")
        self._factor, self._omega = f, omega
        return f


def _sites(lat: Lattice, sites) -> np.ndarray:
    if np.isscalar(sites) or (isinstance(sites, np.ndarray) and sites.ndim == 0):
        sites = [sites]
    idx = _validate.site_indices("sites", sites, lat.sites)
    if idx.size == 0:
        raise ValueError("give at least one qubit site.")
    if idx.size > MAX_QUBITS:
        raise ValueError(f"at most {MAX_QUBITS} qubits are supported (their couplings form a dense matrix), "
                         f"got {idx.size}.")
    if np.unique(idx).size != idx.size:
        raise ValueError("each site carries at most one qubit; the sites contain repeats.")
    return idx


def qubit_hamiltonian(lattice: Lattice, sites, omega_q, g, *, t: float = 1.0) -> sp.csr_matrix:
    r"""The single-excitation Hamiltonian of K qubits coupled to a lattice of resonators.

    .. math:: \mathcal H = \begin{pmatrix} H & gB\\ gB^T & \omega_q \mathbb 1_K\end{pmatrix},
              \qquad H = -tA,\quad B_{j_k k} = 1

    (module docstring): the rotating-wave Jaynes–Cummings lattice with one excitation.

    Parameters
    ----------
    lattice : Lattice
        Sites or line graph (the resonators).
    sites : int or sequence of int
        The sites :math:`j_k` (0-based) the K qubits couple to, distinct.
    omega_q : float
        Qubit frequency, in units of t.
    g : float
        Qubit-photon coupling, in units of t.
    t : float, optional
        Hopping amplitude, positive; default 1.

    Returns
    -------
    scipy.sparse.csr_matrix
        Shape ``(N + K, N + K)``: photons first (rows 0..N-1), then the K qubits.

    Raises
    ------
    ValueError
        For an invalid lattice, bad or repeated sites, non-finite ``omega_q`` or ``g``, or
        :math:`t \le 0`.

    See Also
    --------
    bound_state, spin_model

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.qubits import qubit_hamiltonian
    >>> H = qubit_hamiltonian(hl.ring_lattice(7, 3, 3), [0, 3], -3.5, 0.2)
    >>> H.shape, float(H[112, 0]), float(H[112, 112])
    ((114, 114), 0.2, -3.5)
    """
    lat = _validate.lattice(lattice)
    idx = _sites(lat, sites)
    omega_q = _validate.real("omega_q", omega_q)
    g = _validate.real("g", g)
    H = hamiltonian(lat, t=_validate.positive_real("the hopping t", t)).astype(float)
    k = idx.size
    B = sp.csr_matrix((np.full(k, g), (idx, np.arange(k))), shape=(lat.sites, k))
    return sp.bmat([[H, B], [B.T, omega_q * sp.identity(k)]], format="csr")


@dataclass(frozen=True, eq=False, kw_only=True)
class BoundState(Result):
    r"""The photon bound state of one qubit below the band, exact and to leading order in g.

    Attributes
    ----------
    p, q, rings : int
        Schläfli symbol and rings of the flake.
    kind : str
        ``"sites"`` or ``"line_graph"``.
    site : int
        The qubit's site :math:`j_0` (0-based).
    omega_q, g : float
        Qubit frequency and coupling, units of t (the resonators have :math:`H = -tA`).
    energy : float
        Exact bound-state energy :math:`E_b` (root of :math:`E - \omega_q + g^2G_{j_0j_0}(E)`).
    energy_leading : float
        :math:`\omega_q - g^2G_{j_0j_0}(\omega_q)`.
    qubit_weight : float
        :math:`|a|^2` of the normalized eigenvector (the rest is photonic).
    photon : ndarray, shape (N,)
        Exact photon profile :math:`\propto G_{\cdot j_0}(E_b)`, unit norm, positive.
    leading : ndarray, shape (N,)
        Leading-order profile :math:`\propto G_{\cdot j_0}(\omega_q)`, unit norm.
    profile_error : float
        :math:`\|\text{photon} - \text{leading}\|_2` (:math:`O(g^2)`).
    residual : float
        :math:`\|\mathcal H v - E_b v\|` of the full normalized eigenvector.
    distance : ndarray, shape (N,)
        Hyperbolic distance of each site from the qubit (paper's metric).
    size : float
        :math:`\langle d\rangle = \sum_i |\phi_i|^2 d_i`, the mean distance of the photon from the qubit.
    decay_length : float
        :math:`\xi` of :math:`G \propto e^{-d/\xi}`, fitted to :math:`\ln\phi` against d over the sites
        between 2 and 6 edge lengths from the qubit that are at least 3 edge lengths inside the
        outer ring (NaN when there are fewer than 10 such sites).

    Notes
    -----
    Energies (``energy``, ``energy_leading``) are in units of t; distances, ``size`` and
    ``decay_length`` in the paper's metric :math:`|dz|^2/(1-|z|^2)^2`.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> b = hl.bound_state(hl.ring_lattice(7, 3, 3), 0, -3.5, 0.2)
    >>> round(b.energy, 6), round(b.energy_leading, 6), round(b.qubit_weight, 6)
    (-3.516434, -3.516608, 0.989664)
    >>> b.photon.shape, round(b.size, 4)
    ((112,), 0.1286)
    """

    #: one row per site (the photon profiles; site i is row i)
    COLUMNS = (Column("distance", "distance", "hyperbolic distance"), Column("photon", "photon", "1"),
               Column("leading", "leading", "1"))

    p: int
    q: int
    rings: int
    kind: str
    site: int
    omega_q: float
    g: float
    energy: float
    energy_leading: float
    qubit_weight: float
    photon: np.ndarray = field(repr=False)
    leading: np.ndarray = field(repr=False)
    profile_error: float
    residual: float
    distance: np.ndarray = field(repr=False)
    size: float
    decay_length: float

    def summary(self) -> dict:
        """Scalars only: p, q, rings, kind, site, omega_q, g, energy, energy_leading, qubit_weight,
        profile_error, residual, size, decay_length."""
        keys = ("p", "q", "rings", "kind", "site", "omega_q", "g", "energy", "energy_leading", "qubit_weight",
                "profile_error", "residual", "size", "decay_length")
        return {k: getattr(self, k) for k in keys}


def _decay_length(lat: Lattice, d: np.ndarray, profile: np.ndarray) -> float:
    """Fit ln(profile) = a - d/xi over 2 d0 <= d <= 6 d0, away from the outer rings (edge effects)."""
    d0 = lat.d0
    inner = lat.ring <= lat.rings - 3
    sel = inner & (d >= 2 * d0) & (d <= 6 * d0) & (profile > 0)
    if np.count_nonzero(sel) < 10:
        return math.nan
    slope = np.polyfit(d[sel], np.log(profile[sel]), 1)[0]
    return float(-1.0 / slope) if slope < 0 else math.nan


def bound_state(lattice: Lattice, site: int, omega_q, g, *, t: float = 1.0,
                resolvent: BelowBandResolvent | None = None, tol: float = 1e-13) -> BoundState:
    r"""The single-excitation bound state of one qubit on ``site``, exact and to leading order.

    The energy :math:`E_b` solves :math:`E - \omega_q + g^2 G_{j_0j_0}(E) = 0` below the band
    bottom :math:`E_0` (Newton's method from :math:`\omega_q`), with :math:`G(E) = (H-E)^{-1}`
    the graph Green function (the paper's Eq. (18)); the photon profile is
    :math:`\phi = g\,G(E_b)e_{j_0}`. To leading order in g,
    :math:`E_b \approx \omega_q - g^2G_{j_0j_0}(\omega_q)`.

    Parameters
    ----------
    lattice : Lattice
        Sites or line graph (the resonators).
    site : int
        The qubit's site :math:`j_0` (0-based).
    omega_q : float
        Qubit frequency in units of t, below the band (:math:`\omega_q < E_0`).
    g : float
        Coupling in units of t, :math:`g \ne 0`.
    t : float, optional
        Hopping amplitude, positive; default 1.
    resolvent : BelowBandResolvent, optional
        Reuse a resolvent of the same lattice.
    tol : float, optional
        Relative tolerance of the Newton iteration for :math:`E_b`; default 1e-13.

    Returns
    -------
    BoundState
        ``energy`` (:math:`E_b`), ``energy_leading``, ``qubit_weight``, ``photon`` and
        ``leading`` profiles (unit norm), ``profile_error``, ``residual``, ``distance`` of each
        site from the qubit, ``size`` and ``decay_length``.

    Raises
    ------
    ValueError
        Bad input, :math:`\omega_q` not below the band.
    ConvergenceError
        If the Newton iteration for :math:`E_b` does not converge (not expected: the secular
        function is increasing and convex, so Newton from :math:`\omega_q` converges monotonically).

    See Also
    --------
    spin_model, hyperlattice.graph.green.graph_green

    References
    ----------
    .. [1] P. Bienias, I. Boettcher, R. Belyansky, A. J. Kollár and A. V. Gorshkov, Phys. Rev.
       Lett. 128, 013601 (2022).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> b = hl.bound_state(hl.ring_lattice(7, 3, 3), 0, -3.5, 0.2)
    >>> round(b.energy, 6), round(b.energy_leading, 6), round(b.qubit_weight, 6)
    (-3.516434, -3.516608, 0.989664)
    """
    lat = _validate.lattice(lattice)
    site = _validate.site_index("site", site, lat.sites)
    omega_q = _real_omega("omega_q", omega_q)
    g = _coupling(g, t)
    if g == 0:
        raise ValueError("g must be nonzero (at g = 0 the qubit does not dress the photons).")
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1e-3)
    res = _resolvent_for(resolvent, lat, t)
    g2 = g * g
    col0 = res.column(omega_q, site)              # refuses omega_q above E0
    e_lead = omega_q - g2 * col0[site]
    # Newton on f(E) = E - omega_q + g^2 G_jj(E): G_jj(E) = sum_n psi_n(j)^2/(E_n - E) is increasing
    # and convex below the band, so f is too (f' = 1 + g^2 (G^2)_jj). Started at a point above the
    # root, where f > 0, the tangent of a convex increasing function lands between the root and the
    # current point: the iterates decrease monotonically to E_b and never leave the band gap.
    # The start: G_jj(E) >= 1/(E_top - E) with E_top <= t * (largest degree), so the root lies below
    # the E_up solving (omega_q - E)(E_top - E) = g^2; from omega_q itself a large g took ~log2(g)
    # doubling steps (g = 1e15 did not converge in 60), from E_up a handful.
    e_top = t * float(np.bincount(np.asarray(lat.edges).ravel(), minlength=lat.sites).max()) if lat.sites else 0.0
    e_top = max(e_top, omega_q)
    E = min(omega_q, 0.5 * (omega_q + e_top) - math.hypot(0.5 * (e_top - omega_q), g))   # no overflow
    col = col0 if E == omega_q else res.column(E, site)
    for _ in range(_NEWTON_MAX):
        f = E - omega_q + g2 * col[site]
        fp = 1.0 + g2 * float(col @ col)
        E_new = E - f / fp
        col = res.column(E_new, site)
        if abs(E_new - E) <= tol * max(1.0, abs(E_new)):
            E = E_new
            break
        E = E_new
    else:
        raise ConvergenceError(f"the bound-state energy did not converge in {_NEWTON_MAX} Newton steps "
                               f"(last E = {E:.15g}).")
    phi = g * col
    norm2 = float(phi @ phi) + 1.0
    v = np.concatenate([phi, [-1.0]]) / math.sqrt(norm2)
    Hq = qubit_hamiltonian(lat, [site], omega_q, g, t=t)
    residual = float(np.linalg.norm(Hq @ v - E * v))
    photon = _unit(np.abs(col))       # scaled first: far below the band |phi|^2 underflowed to 0/0
    lead = _unit(col0)
    if not (np.all(np.isfinite(photon)) and np.all(np.isfinite(lead)) and math.isfinite(residual)
            and math.isfinite(E) and math.isfinite(e_lead)):
        # decay_length may be NaN by design (too few sites to fit); nothing else may
        raise ValueError("bound_state: the result for these arguments is not a finite number (it lies beyond "
                         "the float64 range, about 1.8e308); use a smaller |g| or |omega_q|.")
    d = distance(lat.z, lat.z[site])
    size = float(np.sum(photon**2 * d))
    return BoundState(p=lat.p, q=lat.q, rings=lat.rings, kind=lat.kind, site=site, omega_q=omega_q, g=g,
                      energy=float(E), energy_leading=float(e_lead), qubit_weight=1.0 / norm2, photon=photon,
                      leading=lead, profile_error=float(np.linalg.norm(photon - lead)), residual=residual,
                      distance=d, size=size, decay_length=_decay_length(lat, d, photon))


@dataclass(frozen=True, eq=False, kw_only=True)
class SpinModel(Result):
    r"""The effective XY spin model of K qubits to order :math:`g^2` (module docstring).

    :math:`H_{\rm spin} = \sum_{kl} h_{kl}\sigma_k^+\sigma_l^-` with :math:`h = \omega_q - g^2 B^TG(\omega_q)B`:
    diagonal :math:`\omega_q + \delta\omega_k` (Lamb shift :math:`\delta\omega_k = -g^2G_{j_kj_k}`),
    off-diagonal :math:`-J_{kl}`, :math:`J_{kl} = g^2G_{j_kj_l}(\omega_q)`.

    Attributes
    ----------
    p, q, rings : int
        Schläfli symbol and rings of the flake.
    kind : str
        ``"sites"`` or ``"line_graph"``.
    sites : ndarray of int, shape (K,)
        Lattice sites of the qubits (0-based).
    omega_q, g : float
        Qubit frequency and coupling, units of t.
    couplings : ndarray, shape (K, K)
        :math:`J_{kl}` (zero diagonal), units of t.
    lamb_shift : ndarray, shape (K,)
        :math:`\delta\omega_k = -g^2G_{j_kj_k}(\omega_q)`, units of t.
    distance : ndarray, shape (K, K)
        Hyperbolic distances between the qubits (paper's metric).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> s = hl.spin_model(hl.ring_lattice(7, 3, 3), [0, 1, 3], -3.5, 0.2)
    >>> [(k, l, round(j, 6)) for k, l, j in s.edges()]
    [(0, 1, 0.006046), (0, 2, 0.001074), (1, 2, 0.00228)]
    >>> [round(x, 6) for x in s.matrix().toarray()[0].tolist()]   # omega_q + Lamb shift, -J
    [-3.516608, -0.006046, -0.001074]
    """

    #: the K x K couplings and distances on the qubit axes (k, l), with the per-qubit site and Lamb shift
    GRID = Grid(coords=(Column("k", INDEX, "1"), Column("l", INDEX, "1")),
                variables=(Column("site", "sites", "1", ("k",)), Column("lamb_shift", "lamb_shift", "t", ("k",)),
                           Column("coupling", "couplings", "t", ("k", "l")),
                           Column("distance", "distance", "hyperbolic distance", ("k", "l"))))

    p: int
    q: int
    rings: int
    kind: str
    sites: np.ndarray
    omega_q: float
    g: float
    couplings: np.ndarray = field(repr=False)
    lamb_shift: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)

    def matrix(self, threshold: float = 0.0) -> sp.csr_matrix:
        r"""The single-excitation matrix :math:`h` (K x K, scipy CSR); couplings with
        :math:`|J| < \text{threshold}\cdot\max|J|` dropped (0 keeps all).

        Parameters
        ----------
        threshold : float, optional
            Relative cut in [0, 1]; default 0.

        Returns
        -------
        scipy.sparse.csr_matrix, shape (K, K)
            :math:`h` in units of t: :math:`\omega_q + \delta\omega_k` on the diagonal, :math:`-J_{kl}` off it.
        """
        threshold = _validate.real("threshold", threshold, minimum=0.0, maximum=1.0)
        J = np.array(self.couplings)
        if J.size and threshold > 0:
            J[np.abs(J) < threshold * np.abs(J).max()] = 0.0
        h = sp.csr_matrix(-J)
        h = h + sp.diags(self.omega_q + np.asarray(self.lamb_shift))
        return h.tocsr()

    def edges(self, threshold: float = 0.0) -> list[tuple[int, int, float]]:
        r"""Edge list ``[(k, l, J_kl), ...]`` with k < l (qubit indices 0..K-1; ``sites[k]`` is the
        lattice site), couplings with :math:`|J| < \text{threshold}\cdot\max|J|` dropped.

        Parameters
        ----------
        threshold : float, optional
            Relative cut in [0, 1]; default 0.

        Returns
        -------
        list of (int, int, float)
            ``(k, l, J_kl)`` with :math:`J_{kl}` in units of t.
        """
        threshold = _validate.real("threshold", threshold, minimum=0.0, maximum=1.0)
        J = np.asarray(self.couplings)
        k, l = np.triu_indices(J.shape[0], 1)
        vals = J[k, l]
        keep = np.abs(vals) >= threshold * (np.abs(vals).max() if vals.size else 0.0)
        return [(int(a), int(b), float(v)) for a, b, v in zip(k[keep], l[keep], vals[keep])]

    def summary(self) -> dict:
        """p, q, rings, kind, qubits, omega_q, g, the largest coupling and the Lamb-shift range."""
        J = np.asarray(self.couplings)
        off = J[~np.eye(J.shape[0], dtype=bool)] if J.size else J
        return {"p": self.p, "q": self.q, "rings": self.rings, "kind": self.kind, "qubits": int(len(self.sites)),
                "omega_q": self.omega_q, "g": self.g, "max_coupling": float(off.max()) if off.size else 0.0,
                "lamb_shift_min": float(np.min(self.lamb_shift)), "lamb_shift_max": float(np.max(self.lamb_shift))}


def spin_model(lattice: Lattice, sites, omega_q, g, *, t: float = 1.0,
               resolvent: BelowBandResolvent | None = None) -> SpinModel:
    r"""Effective exchange :math:`J_{kl} = g^2G_{j_kj_l}(\omega_q)` and Lamb shifts of qubits on ``sites``.

    To order :math:`g^2`,
    :math:`H_{\rm spin} = \sum_{kl} h_{kl}\sigma_k^+\sigma_l^-` with
    :math:`h = \omega_q\mathbb 1 - g^2 B^TG(\omega_q)B`: Lamb shifts
    :math:`-g^2G_{j_kj_k}(\omega_q)` and exchange :math:`-J_{kl}`. One factorization and K
    solves (each column gives a row of J).

    Parameters
    ----------
    lattice : Lattice
        Sites or line graph (the resonators).
    sites : sequence of int
        The qubits' sites :math:`j_k` (0-based), distinct; at most :data:`MAX_QUBITS` (20,000).
    omega_q : float
        Qubit frequency in units of t, below the band (:math:`\omega_q < E_0`).
    g : float
        Coupling in units of t.
    t : float, optional
        Hopping amplitude, positive; default 1.
    resolvent : BelowBandResolvent, optional
        Reuse a resolvent of the same lattice.

    Returns
    -------
    SpinModel
        ``sites``, ``couplings`` (K, K) :math:`J_{kl}` with zero diagonal (units of t),
        ``lamb_shift`` (K,), ``distance`` (K, K) hyperbolic distances between the qubits;
        ``.matrix()`` gives h as a sparse matrix.

    Raises
    ------
    ValueError
        Bad or repeated sites, :math:`\omega_q` not below the band, more than :data:`MAX_QUBITS`.

    See Also
    --------
    bound_state, hyperlattice.compare.qubits.exchange_comparison

    References
    ----------
    .. [1] P. Bienias, I. Boettcher, R. Belyansky, A. J. Kollár and A. V. Gorshkov, Phys. Rev.
       Lett. 128, 013601 (2022).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> s = hl.spin_model(hl.ring_lattice(7, 3, 3), [0, 1, 3], -3.5, 0.2)
    >>> [round(j, 6) for j in s.couplings[0].tolist()]
    [0.0, 0.006046, 0.001074]
    >>> [round(x, 6) for x in s.lamb_shift.tolist()]
    [-0.016608, -0.016608, -0.016608]
    """
    lat = _validate.lattice(lattice)
    idx = _sites(lat, sites)
    omega_q = _real_omega("omega_q", omega_q)
    g = _coupling(g, t)
    res = _resolvent_for(resolvent, lat, t)
    G = np.empty((idx.size, idx.size))
    chunk = max(1, int(2**26 // (8 * lat.sites)))      # (N, chunk) right-hand sides within ~64 MB
    for a in range(0, idx.size, chunk):
        cols = res.columns(omega_q, idx[a:a + chunk])
        G[:, a:a + chunk] = cols[idx]
    G = 0.5 * (G + G.T)     # symmetric up to rounding of the solves
    J = g * g * G
    lamb = -np.diag(J).copy()
    np.fill_diagonal(J, 0.0)
    d = distance(lat.z[idx][:, None], lat.z[idx][None, :])
    return SpinModel(p=lat.p, q=lat.q, rings=lat.rings, kind=lat.kind, sites=idx, omega_q=omega_q, g=g,
                     couplings=J, lamb_shift=lamb, distance=d)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

# a coupling or shift beyond the float64 range is refused, never returned as inf/NaN
_guard_public(globals(), finite=("spin_model",))
