r"""Lowest levels of :math:`H = -tA + V` on a lattice, labelled by angular momentum.

Methods (``lowest_levels(..., method=...)``):

``"auto"`` (default)
    The fastest correct route for the request: the sector-only shift-invert route
    (:func:`hyperlattice.graph.sectors.lowest_sector_levels`, reported ``"sector-shift-invert"``)
    for the plain flake with blocks of more than 400 orbits and no on-site term, flux, single
    sector or eigenvectors; otherwise ``"sector"`` when V is rotation invariant, else ``"dense"``
    (small) or ``"sparse"``. Every factorisation goes through :mod:`hyperlattice.graph.factor`
    (CHOLMOD when installed, else SuperLU; ``Spectrum.backend`` says which ran).
``"shift-invert"``
    The sector-only route whenever it applies, else ``"sector"``.
``"sector"``
    H splits into p Bloch blocks :math:`H_m` of size N/p (:mod:`hyperlattice.graph.symmetry`).
    Sectors m and -m are complex conjugates, so only :math:`m = 0, 1, \dots, \lfloor p/2
    \rfloor` are solved. Each block is diagonalised densely when small (reported
    ``"sector-dense"``) and otherwise by shift-invert Lanczos with an inertia proof
    (:func:`hyperlattice.graph.factor.lowest_eigenpairs`, reported ``"sector-shift-invert"``;
    complex Hermitian blocks with flux). Inside a sector the lowest gap is much larger than the
    full :math:`E_1 - E_0` (which separates different sectors).
``"dense"`` / ``"sparse"``
    The full N x N matrix (needed when V breaks the rotation): LAPACK, or ARPACK on a Chebyshev
    polynomial of H (numba products); levels are still labelled by m by diagonalising the
    rotation inside each degenerate cluster of eigenvectors.

With a uniform magnetic field (``flux=f`` flux quanta per p-gon, gauge and sign convention in
:mod:`hyperlattice.graph.flux`) the gauge keeps the rotation symmetry, so the same methods
apply; but H is complex, :math:`H_{-m} \ne \overline{H_m}`, and all p sectors are solved.

The solvers themselves live in :mod:`hyperlattice.graph.factor` (shift-invert, inertia),
:mod:`hyperlattice.graph.sectors` (the sector-only route) and :mod:`hyperlattice.graph.solvers`
(fixed-width tables, Chebyshev-accelerated Lanczos, residual checks); this module chooses among
them and labels the levels. The route is chosen once, by ``_choose_route`` (a pure function of the
request; the command line asks the same rule, ``_flake_route_applies``, before building a lattice);
the blocks a route needs are built by one call (:mod:`hyperlattice.graph.sectors` for the
sector-only flakes, ``_sector_blocks`` of :mod:`hyperlattice.graph.symmetry` for a built lattice).

Every returned level carries its residual :math:`\|H\psi - E\psi\|` for the normalised
state, evaluated with the true H (a sector residual equals the full residual of the lifted
state). Residuals above ``tol`` raise :class:`~hyperlattice.errors.ConvergenceError` (or warn
with :class:`~hyperlattice.errors.ConvergenceWarning` when within a factor 100).
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np
import scipy.linalg as sla

from .. import _validate
from .._ties import classify, eigenvalue_tolerance
from ..errors import ConvergenceError
from ..results import Column, Levels, Result
from .factor import lowest_eigenpairs
from .flux import _flux
from .lattice import Lattice
from .levels import Spectrum  # noqa: F401  (defined below this module, re-exported)
from .operators import OnSite, hamiltonian, onsite_values
from .sectors import _flake_levels
from .solvers import (
    ProgressFn,
    _check_residuals,
    _chebyshev_lowest,
    _dense_lowest,
    _residuals,
    _single_threaded_blas,
    full_table,
)
from .symmetry import _lift_columns, _sector_blocks, rotation_invariant, signed_sector

__all__ = ["MatrixSpectrum", "lowest_levels", "full_spectrum", "full_spectrum_tolerance", "partition_function", "log_partition_function",
           "DENSE_MAX"]

#: Largest matrix (full or sector block) diagonalised densely by ``method="auto"``: eigh of
#: 2000 x 2000 takes well under a second here, while ARPACK start-up dominates below that.
DENSE_MAX = 2000

_METHODS = ("auto", "sector", "dense", "sparse", "shift-invert")
#: sector blocks above DENSE_MAX by shift-invert through graph/factor (else the Chebyshev Lanczos)
_SHIFT_INVERT_BLOCKS = True


@dataclass(frozen=True, eq=False, kw_only=True)
class MatrixSpectrum(Result):
    r"""Lowest levels of a Hamiltonian given as a matrix H (no lattice, so no (n, m) labels).

    Attributes
    ----------
    energies : ndarray, shape (K,)
        Ascending, in the units of the matrix H (units of t for :func:`hyperlattice.hamiltonian`).
    errors : ndarray, shape (K,)
        :math:`\|H\psi - E\psi\|` of each normalised state.
    method : str
        The route that ran: ``"dense"`` (LAPACK eigh of the full matrix) or ``"shift-invert"``
        (Lanczos on :math:`(H-\sigma)^{-1}` with an inertia count, :mod:`hyperlattice.graph.factor`).
    description : str
        One sentence on what ran.
    sites : int
        The dimension N of H.
    dtype : str
        ``"float64"`` (real symmetric H) or ``"complex128"`` (complex Hermitian H).
    backend : str
        The sparse factorisation that ran (``"cholmod"`` or ``"superlu"``), or ``""``.
    timings : dict
        Wall-clock seconds (``"solve"``, ``"total"``).
    eigenvectors : ndarray, shape (N, K), or None
        Normalised states, column k belonging to ``energies[k]``.

    Examples
    --------
    >>> from hyperlattice import hamiltonian, lowest_levels, ring_lattice
    >>> spec = lowest_levels(hamiltonian(ring_lattice(7, 3, 2)), 2)
    >>> type(spec).__name__, spec.method, spec.sites, spec.dtype
    ('MatrixSpectrum', 'dense', 35, 'float64')
    >>> [round(float(e), 4) for e in spec.energies]
    [-2.6364, -2.2833]
    """

    COLUMNS = (Column("energy", "energies", "units of H"), Column("error", "errors", "units of H"))

    energies: np.ndarray
    errors: np.ndarray
    method: str
    description: str
    sites: int
    dtype: str
    backend: str = ""
    timings: dict = field(default_factory=dict)
    eigenvectors: np.ndarray | None = None

    error_kind: ClassVar[str] = "residual"

    def __len__(self) -> int:
        return int(self.energies.shape[0])

    @property
    def residuals(self) -> np.ndarray:
        r""":math:`\|H\psi - E\psi\|` of each normalised state (the same array as ``errors``)."""
        return self.errors

    def _check_loaded(self) -> str | None:
        why = super()._check_loaded()
        if why is not None:
            return why
        e, err = self.energies, self.errors
        if e.ndim != 1 or err.shape != e.shape:
            return "energies and errors must be 1-d arrays of equal length"
        if not np.all(np.isfinite(e)) or np.any(np.diff(e) < -(err[:-1] + err[1:] + 1e-12 * max(1.0, float(np.max(np.abs(e), initial=0.0))))):
            return "the energies must be finite and ascending"
        return None


# ----------------------------------------------------------------------------
# checks and labels
# ----------------------------------------------------------------------------

def _rotation_labels(lattice: Lattice, h, energies: np.ndarray, vecs: np.ndarray,
                     keep: int, real: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Label full-matrix eigenvectors by m: diagonalise the rotation in each degenerate cluster.

    Returns (energies, vecs, m) for the first ``keep`` states. A cluster cut by the end of the
    computed states, or missing a partner, is completed by the rotated copies of its states.
    """
    p = lattice.p
    scale = max(1.0, float(np.max(np.abs(energies))))
    gaps = np.diff(energies) > 1e-8 * scale
    starts = np.concatenate([[0], np.flatnonzero(gaps) + 1])
    ends = np.concatenate([starts[1:], [energies.shape[0]]])
    out_e, out_v, out_m = [], [], []
    for a, b in zip(starts, ends):
        if a >= keep:
            break
        u = vecs[:, a:b].astype(np.complex128)
        # A Krylov method may return one state of a degenerate +-m pair only (from a single
        # start vector it cannot see the partner). The rotated copies R^s u are eigenvectors
        # of the same level, so their span closes the cluster into a rotation-invariant space.
        copies = [u]
        for _ in range(p - 1):
            copies.append(copies[-1][lattice.rotation, :])
        basis, sing, _ = np.linalg.svd(np.concatenate(copies, axis=1), full_matrices=False)
        u = basis[:, sing > 1e-8 * sing[0]]
        rot_u = u[lattice.rotation, :]          # (S psi)(i) = psi(R i) = omega^m psi(i)
        mat = u.conj().T @ rot_u
        t_form, z = sla.schur(mat, output="complex")
        lam = np.diag(t_form)
        if np.max(np.abs(np.abs(lam) - 1.0)) > 1e-6:
            raise ConvergenceError("eigenvectors of a degenerate level do not span a rotation-invariant "
                                   "space; cannot assign angular momenta.")
        ms = np.rint(np.angle(lam) * p / (2 * np.pi)).astype(int) % p
        ms = np.where(ms > p / 2, ms - p, ms)
        w = u @ z
        e = np.real(np.einsum("ij,ij->j", w.conj(), h @ w))
        # the states of one cluster are degenerate: report their common (mean) energy, ordered
        # by |m| and +m before -m as in the continuum listing
        e[:] = float(np.mean(e))
        order = np.lexsort((-ms, np.abs(ms)))
        out_e.append(e[order])
        out_v.append(w[:, order])
        out_m.append(ms[order])
    energies = np.concatenate(out_e)[:keep]
    vecs = np.concatenate(out_v, axis=1)[:, :keep]
    m = np.concatenate(out_m)[:keep]
    if real and np.all((2 * m) % p == 0):  # with flux even m = 0 states are complex
        vecs = _realify(vecs)
    return energies, vecs, m


def _realify(vecs: np.ndarray) -> np.ndarray:
    """Real representatives of states whose phase is arbitrary (m = 0 or p/2)."""
    if not np.iscomplexobj(vecs):
        return vecs
    out = np.empty(vecs.shape)
    for c in range(vecs.shape[1]):
        v = vecs[:, c]
        # the phase is fixed at the largest entry; symmetric states have several entries of equal
        # modulus whose computed order is rounding noise, so take the first index within a
        # relative 1e-8 of the maximum (the phase, and so the sign, is then the same everywhere)
        a = np.abs(v)
        k = int(np.flatnonzero(a >= a.max() * (1.0 - 1e-8))[0])
        v = v * (abs(v[k]) / v[k])
        out[:, c] = v.real / np.linalg.norm(v.real)
    return out


def _radial_index(m: np.ndarray) -> np.ndarray:
    n = np.empty(m.shape[0], dtype=int)
    seen: dict[int, int] = {}
    for idx, mm in enumerate(m.tolist()):
        seen[mm] = seen.get(mm, 0) + 1
        n[idx] = seen[mm]
    return n


# ----------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------

def lowest_levels(lattice: Lattice, levels: int = 2, *, t: float = 1.0, onsite: OnSite = None,
                  method: str = "auto", sector: int | None = None, eigenvectors: bool = False,
                  tol: float = 1e-10, progress: ProgressFn | None = None, flux: float = 0.0) -> Spectrum:
    r"""The ``levels`` lowest states of :math:`H = -tA + \mathrm{diag}(V)`, labelled by their rotation sector.

    .. math:: H = -t \sum_{\langle ij \rangle} (|i\rangle\langle j| + |j\rangle\langle i|) + \sum_i V_i |i\rangle\langle i|

    Each state is labelled by the sector of the p-fold rotation, signed (``m`` in
    :math:`(-p/2, p/2]`) and as :math:`k = m \bmod p` (``sector``), and by its index n = 1, 2, ...
    within that sector. The lattice knows the angular momentum only modulo p, so these are the
    continuum labels (n, m) only for the lowest levels of each sector; the continuum level each
    state continues is assigned by :func:`hyperlattice.compare.levels.continuum_labels`.

    Parameters
    ----------
    lattice : Lattice, or a matrix H
        From :func:`~hyperlattice.graph.lattice.ring_lattice` or :func:`~hyperlattice.graph.lattice.line_graph`
        (the line graph gives the resonator-array Hamiltonian). Or H itself: a scipy.sparse
        matrix (csr, csc, coo, ...) or a 2-d array, real symmetric or complex Hermitian up to
        :data:`hyperlattice._validate.HERMITIAN_RTOL` times its largest entry. A matrix has no
        rotation, so ``t``, ``onsite``, ``sector`` and ``flux`` are refused; ``method="auto"``
        is dense eigh up to ``DENSE_MAX`` rows, else shift-invert (``"sparse"`` means the
        same), and the result is a :class:`MatrixSpectrum` whose ``method`` names the route.
    levels : int, optional
        Number K of lowest states returned (each state of a degenerate pair counts once);
        default 2, the pair :math:`E_0 < E_1`.
    t : float, optional
        Hopping amplitude, the energy unit; default 1 (as in the paper).
    onsite : scalar, array or callable ``(z, ring) -> array``, optional
        On-site term V in units of t (see :func:`~hyperlattice.graph.operators.onsite_values`).
        A rotation-breaking V rules out ``method="sector"``. Default None.
    method : {"auto", "sector", "dense", "sparse", "shift-invert"}, optional
        ``"auto"`` (default) takes the fastest route for the request: for the plain flake (no
        on-site term, no flux, no single sector, no eigenvectors) with blocks above 400 orbits,
        shift-invert on the real mirror-reduced sector blocks built without the lattice, with an
        inertia proof that no level was missed
        (:func:`~hyperlattice.graph.sectors.lowest_sector_levels`, ``"sector-shift-invert"``);
        otherwise sectors when V is rotation invariant (each block dense when small, else
        shift-invert through :mod:`hyperlattice.graph.factor`), else dense for N <= DENSE_MAX
        and sparse above. ``"shift-invert"`` asks for the sector-only route whenever it
        applies. The method that ran is reported in :attr:`Spectrum.method`, the factorisation
        backend in :attr:`Spectrum.backend`.
    sector : int, optional
        Restrict to one sector m (``range(p)`` or signed); then K levels of that sector.
        Default None: all sectors.
    eigenvectors : bool, optional
        Return the normalised states (``Spectrum.eigenvectors``, shape (N, K)); default False.
    tol : float, optional
        Largest acceptable residual :math:`\|H\psi - E\psi\|`, in units of
        :math:`\max(|t|, \max_i |V_i|)`; default 1e-10. Above it a
        :class:`~hyperlattice.errors.ConvergenceError` is raised (a
        :class:`~hyperlattice.errors.ConvergenceWarning` if within a factor 100). The
        eigenvalue error is at most the residual (and typically its square over the gap).
    progress : bool, None or callable, optional
        A bar over the sectors (or block solves) on stderr (:mod:`hyperlattice._progress`;
        None, the default: when stderr is a terminal), or a function receiving short status
        strings.
    flux : float, optional
        Flux quanta f per p-gon face of a uniform magnetic field (Peierls phases in the
        rotation-symmetric gauge of :mod:`hyperlattice.graph.flux`; positive = counterclockwise).
        With f != 0 all p sectors are solved and +-m are no longer degenerate. Default 0.

    Returns
    -------
    Spectrum or MatrixSpectrum
        Energies ascending (``energies``, units of t) with labels (``n``, ``m``),
        ``residuals``, ``method``, ``backend``, ``timings`` and, if asked for,
        ``eigenvectors``. The continuum counterpart lists (n, m) = (1, 0), (1, 1), (1, -1),
        (1, 2), ... in the same way. For a matrix H: a :class:`MatrixSpectrum` with energies,
        residuals and the route, without labels.

    Raises
    ------
    ValueError
        Bad input, including ``levels`` above the number N of states (or, with ``sector``,
        above the N/p states of that sector), a rotation-breaking V with ``method="sector"``,
        ``sector`` with a method other than ``"sector"``/``"auto"``, or more than (N - 3)/2
        levels with ``method="sparse"``.
    MemoryError
        With ``method="dense"``, if the dense matrix and LAPACK's work space (about
        :math:`3N^2` numbers) do not fit in the available memory.
    ConvergenceError
        If a residual exceeds 100 ``tol``.

    See Also
    --------
    full_spectrum : all N eigenvalues.
    hyperlattice.graph.sectors.lowest_pair : :math:`E_0, E_1` of flakes too big to build.
    hyperlattice.continuum.spectrum.dirichlet_levels : the continuum counterpart.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (1) and Sec. III.

    Examples
    --------
    >>> from hyperlattice import lowest_levels, ring_lattice
    >>> spec = lowest_levels(ring_lattice(7, 3, 1), 3)
    >>> [round(float(e), 6) for e in spec.energies], spec.m.tolist()
    ([-2.0, -1.24698, -1.24698], [0, 1, -1])
    >>> spec = lowest_levels(ring_lattice(7, 3, 2), 4)
    >>> [round(float(e), 6) for e in spec.energies]
    [-2.636405, -2.283335, -2.283335, -1.928138]
    >>> spec.n.tolist(), spec.m.tolist()
    ([1, 1, 1, 1], [0, 1, -1, 2])
    """
    t_start = time.perf_counter()
    if _validate.is_matrix(lattice):
        _matrix_only(t=t, onsite=onsite, sector=sector, flux=flux)
        return _matrix_levels(lattice, levels, method=method, eigenvectors=eigenvectors, tol=tol,
                              t_start=t_start)
    _validate.lattice(lattice)
    levels = _validate.positive_int("levels", levels)
    method = _validate.choice("method", method, _METHODS)
    tol = _validate.solver_tolerance("tol", tol)
    t = _validate.hopping("the hopping t", t)
    eigenvectors = _validate.flag("eigenvectors", eigenvectors)
    flux = _flux(flux)
    progress = _validate.progress("progress", progress)
    if levels > lattice.sites:
        # refused for every method: a silently shorter list would look like a complete answer
        raise ValueError(f"levels = {levels:,} exceeds the {lattice.sites:,} states of this lattice.")
    p = lattice.p
    if sector is not None:
        sector = signed_sector(sector, p)
    # the route, chosen once from the request (graph/symmetry answers the one question it needs: is V
    # invariant under the rotation); then the blocks are built in one call and solved below
    route = _choose_route(method, p=p, sites=lattice.sites, kind=lattice.kind, levels=levels, t=t,
                          onsite=onsite, flux=flux, sector=sector, eigenvectors=eigenvectors,
                          symmetric=rotation_invariant(lattice, onsite))
    if route.flake:
        # the sector-only route: graph/sectors builds the flake sector by sector, its blocks, solves and
        # labels, behind one call (None: the lattice is not the plain flake it rebuilds)
        spec = _flake_levels(lattice, levels, t, tol, progress)
        if spec is not None:
            return dataclasses.replace(spec, timings={**spec.timings, "total": time.perf_counter() - t_start})
    method = route.method
    if method == "dense":
        # refused before allocating (ell = 9 would ask LAPACK for 12.2 GiB): the matrix, eigh's
        # copy of it and its work space, ~3 N^2 numbers
        _validate.require_memory(f"method='dense' on {lattice.sites:,} sites (LAPACK eigh of the full matrix)",
                                 3.0 * lattice.sites**2 * (16 if flux else 8))
    # residuals are judged relative to the energy scale of H (an absolute tolerance
    # fails for t = 1e20 with "residual 7.9e-04 exceeds the tolerance 1e-10"): tol is in units of max(|t|, max|V|)
    tol = tol * _energy_scale(lattice, t, onsite)
    with _single_threaded_blas():
        if method == "sector":
            return _sector_levels(lattice, levels, t, onsite, sector, eigenvectors, tol, progress, t_start, flux)
        return _full_levels(lattice, levels, t, onsite, method, route.symmetric, eigenvectors, tol, progress,
                            t_start, flux)


def _matrix_only(*, t=1.0, onsite=None, sector=None, flux=0.0) -> None:
    """Refuse the lattice-only options with a matrix H (they are part of H already)."""
    given = [name for name, v, default in (("t", t, 1.0), ("onsite", onsite, None), ("sector", sector, None),
                                           ("flux", flux, 0.0))
             if not (v is default or (default is not None and isinstance(v, (int, float)) and v == default))]
    if given:
        one = len(given) == 1
        raise ValueError(f"{', '.join(given)} {'is' if one else 'are'} for a lattice Hamiltonian; a matrix H "
                         f"already holds {'it' if one else 'them'}, so leave {'it' if one else 'them'} out.")


def _matrix_levels(matrix, levels, *, method, eigenvectors, tol, t_start) -> MatrixSpectrum:
    """The ``levels`` lowest eigenpairs of a Hermitian matrix: dense eigh up to DENSE_MAX rows (or
    when asked), else shift-invert through graph/factor, the package's one sparse solver layer."""
    h = _validate.hermitian_matrix("H", matrix)
    n = h.shape[0]
    levels = _validate.positive_int("levels", levels)
    method = _validate.choice("method", method, _METHODS)
    tol = _validate.solver_tolerance("tol", tol)
    eigenvectors = _validate.flag("eigenvectors", eigenvectors)
    if levels > n:
        raise ValueError(f"levels = {levels:,} exceeds the {n:,} states of this matrix.")
    if method == "sector":
        raise ValueError("method='sector' needs a lattice (its rotation); a matrix H takes 'auto', 'dense', "
                         "'sparse' or 'shift-invert'.")
    if method == "auto":
        method = "dense" if n <= DENSE_MAX or levels > n - 2 else "shift-invert"
    elif method == "sparse":
        method = "shift-invert"   # the sparse route for a general H (Chebyshev needs a lattice's table)
    if method == "shift-invert" and levels > n - 2:
        raise ValueError(f"method='shift-invert' needs at most N - 2 = {n - 2} levels; use 'dense'.")
    scale = float(abs(h).max()) if h.nnz else 0.0
    tol = tol * max(scale, 1.0)     # residuals relative to the size of H, as for a lattice
    backend = ""
    t0 = time.perf_counter()
    with _single_threaded_blas():
        if method == "dense":
            _validate.require_memory(f"method='dense' on a {n:,} x {n:,} matrix (LAPACK eigh)",
                                     3.0 * n**2 * h.dtype.itemsize)
            e, v = sla.eigh(h.toarray(), subset_by_index=[0, levels - 1])
            how = f"Dense LAPACK eigh of the {n:,} x {n:,} matrix H"
        else:
            e, v, _, info = lowest_eigenpairs(h, levels, tol=tol, label="H")
            backend = info["backend"]
            how = (f"Shift-invert Lanczos on (H - sigma)^-1 of the {n:,} x {n:,} sparse matrix H ({backend}), "
                   + ("with an inertia count proving no level was missed" if info["proved"]
                      else "without an inertia proof"))
    solve = time.perf_counter() - t0
    res = np.linalg.norm(h @ v - v * e[None, :], axis=0)
    _check_residuals(res, tol, f"{method} eigensolver")
    kind = "complex Hermitian" if h.dtype.kind == "c" else "real symmetric"
    return MatrixSpectrum(energies=np.asarray(e, dtype=float), errors=res, method=method,
                          description=f"{how}; {kind}, no lattice labels.", sites=n, dtype=h.dtype.name,
                          backend=backend, timings={"solve": solve, "total": time.perf_counter() - t_start},
                          eigenvectors=v if eigenvectors else None)


def _energy_scale(lattice, t: float, onsite) -> float:
    """max(|t|, max|V|): the unit of the residual tolerance (1 for the default t = 1, V = 0)."""
    v = onsite_values(lattice, onsite)
    top = float(np.max(np.abs(v))) if v is not None and np.size(v) else 0.0
    scale = max(abs(t), top)
    return scale if scale > 0 else 1.0


#: smallest sector block (N/p orbits) for which ``method="auto"`` takes the sector-only route: below
#: it the dense blocks of the full lattice are as fast (a few ms)
_SECTOR_ONLY_MIN = 400


@dataclass(frozen=True)
class _Route:
    """The route of a level request on a lattice, chosen once by :func:`_choose_route`.

    ``flake``: try the sector-only route first (the plain flake rebuilt sector by sector,
    :mod:`hyperlattice.graph.sectors`); ``method`` is the route that reads the built lattice
    (``"sector"``, ``"dense"`` or ``"sparse"``), taken otherwise, or when the lattice is not the plain
    flake; ``symmetric``: V is invariant under the rotation (so the levels carry sectors).
    """

    method: str
    flake: bool
    symmetric: bool


def _flake_route_applies(p: int, sites: int, levels: int, method: str, *, plain: bool, built: bool = True) -> bool:
    """True when the sector-only route answers the request and pays (the one rule, also the CLI's).

    ``plain``: the request is the plain flake H = -tA, t > 0 (no on-site term, flux, single sector or
    eigenvectors, not a line graph). ``"auto"`` takes it for blocks of more than ``_SECTOR_ONLY_MIN``
    orbits and at most half the states; ``"shift-invert"`` whenever it applies. ``built=False`` (the
    command line, before any lattice exists) lets ``"shift-invert"`` ask for any number of levels.
    """
    if not plain or sites < 2 or method not in ("auto", "shift-invert"):
        return False
    if method == "shift-invert" and not built:
        return True
    if method == "auto" and sites // p <= _SECTOR_ONLY_MIN:
        return False
    return levels <= sites // 2


def _choose_route(method: str, *, p: int, sites: int, kind: str, levels: int, t: float, onsite, flux: float,
                  sector: int | None, eigenvectors: bool, symmetric: bool) -> _Route:
    """The route of a (validated) level request: a pure function of the request, no work, no allocation.

    Raises ValueError for a request no route answers (a single sector with a full-matrix method, a
    rotation-breaking V with ``method="sector"``).
    """
    plain = (onsite is None and flux == 0.0 and sector is None and not eigenvectors and t > 0
             and kind == "sites")
    flake = _flake_route_applies(p, sites, levels, method, plain=plain)
    if method == "shift-invert":
        method = "sector"
    if method == "auto":
        method = "sector" if symmetric else ("dense" if sites <= DENSE_MAX else "sparse")
    if sector is not None and method != "sector":
        raise ValueError("a single sector needs method='sector' (or 'auto').")
    if method == "sector" and not symmetric:
        raise ValueError("the on-site term is not invariant under the p-fold rotation, so H has no "
                         "angular-momentum sectors; use method='dense' or 'sparse'.")
    return _Route(method=method, flake=flake, symmetric=symmetric)


def _sector_levels(lattice, levels, t, onsite, sector, want_vecs, tol, progress, t_start, flux=0.0) -> Spectrum:
    p = lattice.p
    timings = {"setup": time.perf_counter() - t_start}
    if sector is None and flux != 0.0:
        # with flux H is complex: H_{-m} is not the conjugate of H_m, every sector is its own
        wanted = {(m - p if m > p / 2 else m): levels for m in range(p)}   # signed: m in (-p/2, p/2]
    elif sector is None:
        # m and -m are conjugate blocks: solve m = 0..floor(p/2). The K lowest states contain at
        # most K levels of a non-degenerate sector and ceil(K/2) of a paired one.
        wanted = {m: (levels if (2 * m) % p == 0 else (levels + 1) // 2) for m in range(p // 2 + 1)}
    else:
        wanted = {sector: levels}
    # every block the request needs, built in one call (graph/symmetry: orbits, V and the phases once)
    blocks = _sector_blocks(lattice, list(wanted), t, onsite, flux=flux)
    size = blocks.size
    if sector is not None and levels > size:
        raise ValueError(f"sector {sector} has only {size} levels, fewer than the {levels} requested.")
    per_method = set()
    backends = set()
    analyses = {}
    found = []  # (energy, m, n, residual, vector or None)
    from .._progress import progress_bar

    with progress_bar(len(wanted), "sectors", unit="sector", progress=progress) as bar:
        for m, k_m in wanted.items():
            t0 = time.perf_counter()
            k_m = min(k_m, size)
            table = blocks.tables[m]
            if size <= DENSE_MAX or size < 2 * k_m + 3:  # ARPACK needs a basis larger than k + 1
                e, v = _dense_lowest(table, k_m)
                per_method.add("dense")
            elif _SHIFT_INVERT_BLOCKS:
                # shift-invert through the one factorisation layer, with its inertia check; the
                # blocks of one lattice share a sparsity pattern (hence one symbolic analysis) per type
                mat = table.to_csr()
                kind = "complex" if np.iscomplexobj(mat.data) else "real"
                e, v, _, info = lowest_eigenpairs(mat, k_m, tol=tol, label=f"sector m={m}",
                                                  analysis=analyses.get((kind, mat.nnz)))
                analyses[(kind, mat.nnz)] = info["analysis"]
                backends.add(info["backend"])
                per_method.add("shift-invert")
                bar.note(f"sector m={m}: {e.tolist()} after {info['solves']} solves")
            else:
                e, v, _ = _chebyshev_lowest(table, k_m, tol, bar.note, f"sector m={m}")
                per_method.add("sparse")
            res = _residuals(table, v, e)
            _check_residuals(res, tol, f"sector m={m}")
            timings[f"sector {m}"] = time.perf_counter() - t0
            for idx in range(e.shape[0]):
                vec = v[:, idx] if want_vecs else None
                found.append((float(e[idx]), m, idx + 1, float(res[idx]), vec))
                if (2 * m) % p and sector is None and flux == 0.0:
                    found.append((float(e[idx]), -m, idx + 1, float(res[idx]), None if vec is None else vec.conj()))
            bar.update()
    # ascending energy; degenerate partners share the energy exactly: keep +m before -m
    found.sort(key=lambda r: (r[0], abs(r[1]), -r[1]))
    found = found[:levels]
    energies = np.array([r[0] for r in found])
    ms = np.array([r[1] for r in found], dtype=int)
    ns = np.array([r[2] for r in found], dtype=int)
    res = np.array([r[3] for r in found])
    vecs = None
    if want_vecs:
        vecs = _lift_columns(blocks.orbits, [r[1] for r in found], [r[4] for r in found])
    timings["solve"] = sum(v for k, v in timings.items() if k.startswith("sector"))
    timings["total"] = time.perf_counter() - t_start
    method = "sector-" + ("shift-invert" if "shift-invert" in per_method
                          else "sparse" if "sparse" in per_method else "dense")
    solved = ", ".join(str(m) for m in wanted)
    how = {"sector-sparse": "ARPACK on a Chebyshev polynomial of",
           "sector-shift-invert": f"shift-invert Lanczos ({'/'.join(sorted(backends))} factorisation, "
                                  "inertia-checked) on",
           "sector-dense": "dense LAPACK eigh of"}[method]
    description = (f"{how[0].upper()}{how[1:]} the {size:,} x {size:,} angular-momentum block"
                   f"{'s' if len(wanted) > 1 else ''} H_m for m = {solved}"
                   + (f" with flux f = {flux:g} per p-gon" if flux != 0.0 else "")
                   + (" (sector -m is the complex conjugate of m)" if sector is None and flux == 0.0 else "") + ".")
    return Spectrum(energies=energies, n=ns, m=ms, errors=res, method=method, description=description, p=p,
                    q=lattice.q, rings=lattice.rings, sites=lattice.sites, kind=lattice.kind, timings=timings,
                    eigenvectors=vecs, flux=flux, backend="/".join(sorted(backends)), requested_sector=sector)


def _full_levels(lattice, levels, t, onsite, method, symmetric, want_vecs, tol, progress, t_start,
                 flux=0.0) -> Spectrum:
    progress = progress if callable(progress) else None  # one solve: messages, no bar
    n_sites = lattice.sites
    h = hamiltonian(lattice, t=t, onsite=onsite, flux=flux)
    if flux == 0.0 and np.iscomplexobj(h.data):
        raise ValueError("the on-site term must be real so that H is Hermitian.")
    table = full_table(lattice, t, onsite, flux) if method == "sparse" else None
    timings = {"setup": time.perf_counter() - t_start}
    t0 = time.perf_counter()
    if method == "dense":
        e, v = sla.eigh(h.toarray(), subset_by_index=[0, levels - 1])
    else:
        if n_sites < 2 * levels + 3:
            raise ValueError(f"method='sparse' needs at most (N - 3)/2 = {(n_sites - 3) // 2} levels; use 'dense'.")
        e, v, _ = _chebyshev_lowest(table, levels, tol, progress, "full lattice", partial=symmetric)
    if symmetric:
        e, v, m = _rotation_labels(lattice, h, e, v, levels, real=flux == 0.0)
        ask = levels
        while method == "sparse" and e.shape[0] < levels and n_sites >= 2 * (ask + 2) + 3:
            # ask for more states so that the unresolved pair falls inside the converged ones
            ask += 2
            e, v, _ = _chebyshev_lowest(table, ask, tol, progress, "full lattice", partial=True)
            e, v, m = _rotation_labels(lattice, h, e, v, levels, real=flux == 0.0)
        if e.shape[0] < levels:
            raise ConvergenceError(f"the sparse eigensolver resolved only {e.shape[0]} of {levels} levels; "
                                   "use method='sector' or 'dense'.")
    else:
        m = None
    timings["solve"] = time.perf_counter() - t0
    res = np.linalg.norm(h @ v - v * e[None, :], axis=0)
    _check_residuals(res, tol, f"{method} eigensolver")
    ns = np.arange(1, e.shape[0] + 1) if m is None else _radial_index(m)
    timings["total"] = time.perf_counter() - t_start
    how = "Dense LAPACK eigh of" if method == "dense" else "ARPACK on a Chebyshev polynomial of"
    labels = ("levels labelled by m by diagonalising the rotation in each degenerate cluster" if symmetric
              else "no m labels, the on-site term breaks the rotation")
    description = (f"{how} the full {n_sites:,} x {n_sites:,} Hamiltonian"
                   + (f" with flux f = {flux:g} per p-gon" if flux != 0.0 else "") + f"; {labels}.")
    return Spectrum(energies=np.asarray(e, dtype=float), n=ns, m=m, errors=res, method=method,
                    description=description, p=lattice.p, q=lattice.q, rings=lattice.rings, sites=n_sites,
                    kind=lattice.kind, timings=timings, eigenvectors=v if want_vecs else None, flux=flux)


def full_spectrum(lattice: Lattice, *, t: float = 1.0, onsite: OnSite = None,
                  max_sites: int = 50_000, flux: float = 0.0) -> np.ndarray:
    """All N eigenvalues of :math:`H = -tA + V`, ascending.

    Uses the p sector blocks (each diagonalised densely, p times less memory and about
    :math:`p^2` less work than the full matrix) when V is rotation invariant. The last bits of
    each eigenvalue depend on the BLAS kernel; :func:`full_spectrum_tolerance` gives the bound
    to use when a decision is taken on them (e.g. which levels are negative).

    Parameters
    ----------
    lattice : Lattice, or a matrix H
        A site lattice or a line graph, or H itself as a scipy.sparse matrix or 2-d array (real
        symmetric or complex Hermitian, see :func:`lowest_levels`; then ``t``, ``onsite`` and
        ``flux`` are refused).
    t : float, optional
        Hopping amplitude, the energy unit; default 1.
    onsite : scalar, array or callable ``(z, ring) -> array``, optional
        On-site term V in units of t; default None.
    max_sites : int, optional
        Largest N accepted (the full spectrum is a dense computation); default 50,000.
    flux : float, optional
        Flux quanta per p-gon of a uniform field (:mod:`hyperlattice.graph.flux`); all p
        sectors are solved in either case. Default 0.

    Returns
    -------
    numpy.ndarray of float64, shape (N,)
        The eigenvalues, ascending, in units of t.

    Raises
    ------
    ValueError
        If N exceeds ``max_sites``, or for invalid t, onsite or flux.

    See Also
    --------
    full_spectrum_tolerance, lowest_levels, partition_function

    Examples
    --------
    >>> import hyperlattice as hl
    >>> e = hl.full_spectrum(hl.ring_lattice(7, 3, 2))
    >>> e.shape, round(float(e[0]), 6), round(float(e[-1]), 6)
    ((35,), -2.636405, 2.431568)
    """
    return _full_spectrum(lattice, t=t, onsite=onsite, max_sites=max_sites, flux=flux)[0]


def full_spectrum_tolerance(lattice: Lattice, *, t: float = 1.0, onsite: OnSite = None,
                            max_sites: int = 50_000, flux: float = 0.0) -> tuple[np.ndarray, float]:
    r"""All N eigenvalues (as :func:`full_spectrum`) and the error bound of each.

    The bound is :func:`hyperlattice._ties.eigenvalue_tolerance` of the largest matrix that was
    diagonalised (one sector block, or the whole H) with :math:`\|H\| \le |t|\,\max_i
    \deg(i) + \max_i |V_i|` (the largest absolute row sum). Levels closer than this to a
    threshold are *at* it: their computed sign is rounding noise that differs between BLAS
    kernels and thread counts (the two exact zero modes of the {7,3} flake with l = 4 come out
    as :math:`\pm 5\times 10^{-16}`).

    Parameters
    ----------
    lattice, t, onsite, max_sites, flux
        As in :func:`full_spectrum`.

    Returns
    -------
    energies : numpy.ndarray of float64, shape (N,)
        Ascending, in units of t.
    tolerance : float
        Absolute error bound of every eigenvalue (about 1e-13 for N of a few hundred).

    Raises
    ------
    ValueError
        As :func:`full_spectrum`.

    See Also
    --------
    full_spectrum

    Examples
    --------
    >>> import hyperlattice as hl
    >>> energies, tol = hl.full_spectrum_tolerance(hl.ring_lattice(7, 3, 2))
    >>> len(energies), tol < 1e-12
    (35, True)
    """
    return _full_spectrum(lattice, t=t, onsite=onsite, max_sites=max_sites, flux=flux)


def _full_spectrum(lattice: Lattice, *, t: float, onsite: OnSite, max_sites: int,
                   flux: float) -> tuple[np.ndarray, float]:
    if _validate.is_matrix(lattice):
        _matrix_only(t=t, onsite=onsite, flux=flux)
        h = _validate.hermitian_matrix("H", lattice)
        max_sites = _validate.positive_int("max_sites", max_sites)
        n = h.shape[0]
        if n > max_sites:
            raise ValueError(f"the full spectrum of a {n:,} x {n:,} matrix is a dense computation; "
                             f"raise max_sites (now {max_sites:,}) if that is intended.")
        _validate.require_memory(f"the full spectrum of a {n:,} x {n:,} matrix (dense eigh)",
                                 3.0 * n**2 * h.dtype.itemsize)
        norm = float(abs(h).sum(axis=1).max()) if h.nnz else 0.0     # the largest absolute row sum
        with _single_threaded_blas():
            e = sla.eigvalsh(h.toarray())
        return e, eigenvalue_tolerance(norm, n)
    _validate.lattice(lattice)
    t = _validate.hopping("the hopping t", t)
    max_sites = _validate.positive_int("max_sites", max_sites)
    flux = _flux(flux)
    if lattice.sites > max_sites:
        raise ValueError(f"the full spectrum of {lattice.sites:,} sites is a dense computation; "
                         f"raise max_sites (now {max_sites:,}) if that is intended.")
    v = onsite_values(lattice, onsite)
    degree = np.bincount(np.asarray(lattice.edges).ravel(), minlength=lattice.sites)
    norm = abs(t) * float(degree.max(initial=0)) + (0.0 if v is None else float(np.max(np.abs(v), initial=0.0)))
    symmetric = rotation_invariant(lattice, onsite)
    n_block = -(-lattice.sites // lattice.p) if symmetric else lattice.sites  # the largest dense block
    _validate.require_memory(f"the full spectrum of {lattice.sites:,} sites (dense eigh of "
                             f"{n_block:,} x {n_block:,} blocks)", 3.0 * n_block**2 * (16 if flux else 8))
    if symmetric:
        blocks = _sector_blocks(lattice, range(lattice.p), t, onsite, flux=flux)
        parts, largest = [], 1
        for block in blocks.tables.values():
            block = block.to_csr().toarray()
            largest = max(largest, block.shape[0])
            parts.append(sla.eigvalsh(block))
        return np.sort(np.concatenate(parts)), eigenvalue_tolerance(norm, largest)
    e = sla.eigvalsh(hamiltonian(lattice, t=t, onsite=onsite, flux=flux).toarray())
    return e, eigenvalue_tolerance(norm, lattice.sites)


def _negative_levels(system, beta, t: float, onsite: OnSite) -> tuple[np.ndarray, np.ndarray]:
    """The negative energies of ``system`` (ascending) and beta as a checked array.

    "Negative" is decided robustly: a computed level within its error bound of zero is a zero
    mode (its sign is rounding noise), never counted as negative. For a lattice the bound is
    :func:`full_spectrum_tolerance`'s, for a :class:`~hyperlattice.results.Levels` its
    ``errors`` when they bound the energies, and for plain numbers none (they are taken as exact).
    """
    if isinstance(system, Lattice) or (_validate.is_matrix(system) and not isinstance(system, np.ndarray)):
        # a lattice, or a sparse matrix H (a 2-d numpy array stays a table of energies)
        energies, tol = full_spectrum_tolerance(system, t=t, onsite=onsite)
    elif isinstance(system, Levels):
        energies = np.asarray(system.energies, dtype=float)
        if not np.all(np.isfinite(energies)):
            raise ValueError("the energies must be finite numbers.")
        errs = getattr(system, "errors", None)
        tol = 0.0 if errs is None else np.nan_to_num(np.asarray(errs, dtype=float), nan=0.0, posinf=0.0)
        if np.ndim(tol) and np.shape(tol) != energies.shape:
            tol = 0.0
    else:
        energies = _validate.real_array("energies", system).ravel()
        tol = 0.0
    b = _validate.real_array("beta", beta)
    if np.any(b < 0):
        raise ValueError(f"beta must be non-negative, got {float(b.min()):g}.")
    below, _, _ = classify(energies, 0.0, tol)
    return np.sort(energies[below]), b


def _shifted_sum(neg: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r"""Z split as :math:`e^{-\beta E_0}(1 + r)`: returns :math:`(-\beta E_0,\ r)`, :math:`r \ge 0`.

    Every term of r is at most 1, so nothing overflows but the prefactor; a product
    :math:`\beta (E_n - E_0)` beyond the float range is an exact zero term.
    """
    with np.errstate(over="ignore"):
        shift = -b * neg[0]
        rest = np.exp(-np.multiply.outer(b, neg[1:] - neg[0])).sum(axis=-1)
    return shift, rest


def partition_function(system, beta, *, t: float = 1.0, onsite: OnSite = None) -> np.ndarray | float:
    r"""Graph partition function summed over negative energies (inset of the paper's Fig. 2).

    .. math:: Z(\beta) = \sum_n \Theta(-E_n)\, e^{-\beta E_n}
              = e^{-\beta E_0} \sum_n \Theta(-E_n)\, e^{-\beta (E_n - E_0)}

    evaluated in the second form (shifted by the ground energy :math:`E_0`), so that only
    the prefactor can overflow.

    Parameters
    ----------
    system : Lattice, sparse matrix H, Levels (e.g. a Spectrum) or array of energies
        A lattice or a scipy.sparse Hamiltonian (its full spectrum is computed, see
        :func:`full_spectrum`) or given levels in units of t. Plain numbers are taken as exact;
        a :class:`~hyperlattice.results.Levels` with ``errors`` uses them as the zero-mode bound.
    beta : float or array
        Inverse temperature(s) :math:`\beta \ge 0`, in units of 1/t.
    t, onsite
        Hamiltonian parameters when ``system`` is a lattice (defaults t = 1, no on-site term);
        ignored otherwise.

    Returns
    -------
    float or numpy.ndarray
        Z for each beta (the shape of ``beta``). Levels with :math:`E_n \ge 0` are left out,
        as in the paper, to cut off energies outside the continuum approximation (Z = 0 if
        no level is negative); so are zero modes, levels within their error bound of 0
        (:func:`full_spectrum_tolerance`), whose computed sign is rounding noise.

    Raises
    ------
    ValueError
        If beta is negative, the energies are not finite, or Z exceeds the float range (about
        1.8e308) for some beta; then use :func:`log_partition_function`.

    See Also
    --------
    log_partition_function, full_spectrum

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Fig. 2 (inset).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> round(hl.partition_function(lat, 1.0), 6)
    86.231052
    >>> [round(z, 6) for z in hl.partition_function(lat, [0.0, 2.0]).tolist()]  # Z(0) counts E < 0
    [16.0, 639.577029]
    >>> round(hl.partition_function([-1.0, -0.5, 0.3], 2.0), 6)
    10.107338
    """
    neg, b = _negative_levels(system, beta, t, onsite)
    if neg.size == 0:
        z = np.zeros(b.shape)
    else:
        shift, rest = _shifted_sum(neg, b)
        with np.errstate(over="ignore"):
            z = np.exp(shift) * (1.0 + rest)
        if not np.all(np.isfinite(z)):
            k = int(np.flatnonzero(~np.isfinite(np.ravel(z)))[0])
            raise ValueError(f"Z(beta) exceeds the float range at beta = {float(np.ravel(b)[k]):g} "
                             f"(log Z = {float(np.ravel(shift + np.log1p(rest))[k]):.6g}); "
                             "use log_partition_function for log Z instead.")
    return float(z) if np.ndim(z) == 0 else z


def log_partition_function(system, beta, *, t: float = 1.0, onsite: OnSite = None) -> np.ndarray | float:
    r"""Logarithm of the partition function of :func:`partition_function`, for any beta.

    .. math:: \ln Z(\beta) = -\beta E_0 + \ln\Big(1 + \sum_{n > 0} \Theta(-E_n)\,
              e^{-\beta (E_n - E_0)}\Big)

    (log-sum-exp shifted by the ground energy :math:`E_0`); finite where Z itself overflows,
    and tends to :math:`-\beta E_0` at low temperature (the paper's Fig. 2 inset).

    Parameters
    ----------
    system, beta, t, onsite
        As in :func:`partition_function`.

    Returns
    -------
    float or numpy.ndarray
        :math:`\ln Z` for each beta (the shape of ``beta``).

    Raises
    ------
    ValueError
        If no level is negative (then Z = 0 and its logarithm is :math:`-\infty`), if
        :math:`\beta |E_0|` itself exceeds the float range, or for invalid input as in
        :func:`partition_function`.

    See Also
    --------
    partition_function

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Fig. 2 (inset).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> round(hl.log_partition_function(lat, 1000.0), 6)   # -beta E0 with E0 = -2.636405
    2636.404937
    """
    neg, b = _negative_levels(system, beta, t, onsite)
    if neg.size == 0:
        raise ValueError("no level is negative, so Z = 0 and log Z is minus infinity.")
    shift, rest = _shifted_sum(neg, b)
    log_z = shift + np.log1p(rest)
    if not np.all(np.isfinite(log_z)):
        raise ValueError(f"beta * |E0| exceeds the float range for beta = {float(np.max(b)):g}.")
    return float(log_z) if np.ndim(log_z) == 0 else log_z


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
