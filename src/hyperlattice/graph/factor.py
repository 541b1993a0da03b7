r"""The one sparse-direct layer: factorise :math:`H - \sigma` once, solve, count, refactorise.

Every factorisation of the package goes through :func:`factorize` (and :func:`analyze` when
several shifts of one matrix are wanted): the sector eigensolvers (shift-invert and Sylvester
inertia), the Green functions above and below the band, the boundary correlators, the qubit bound
states and the disorder Green functions. A feature never carries a private solver.

Backends
--------
``"cholmod"``
    CHOLMOD through scikit-sparse (optional: ``pip install "hyperlattice[cholmod]"`` with Debian's
    ``libsuitesparse-dev``). The symbolic analysis (AMD ordering, elimination tree) is done once
    per sparsity pattern; every shift reuses it (``cholesky(A, beta=-σ)``). For a shift below the
    spectrum a supernodal :math:`LL^T` is used, whose success *proves* positive definiteness; for
    an inertia count anywhere else a simplicial :math:`LDL^T` without pivoting.
``"superlu"``
    SciPy's SuperLU, always present. For a real symmetric or complex Hermitian :math:`H - \sigma`
    it runs as an :math:`LDL^T` (``SymmetricMode``, no off-diagonal pivots, COLAMD order): when
    the row and column permutations agree, the diagonal of :math:`U` is :math:`D` and its signs
    give the inertia (checked every time; otherwise no count is claimed). The column order of the
    first factorisation is kept and reused at every further shift.

``"auto"`` takes CHOLMOD when it is importable, else SuperLU, silently (the environment variable
``HYPERLATTICE_FACTOR_BACKEND=superlu`` hides CHOLMOD, as if it were not installed: the
SuperLU-only configuration of CI and the benchmarks); an explicit
``backend="cholmod"`` without scikit-sparse warns (:class:`SolverFallbackWarning`) and runs SuperLU.
The backend that ran is recorded on every :class:`Factor` (``factor.backend``).

Memory known before work
------------------------
:func:`analyze` estimates the bytes of the factor before any numeric work: with CHOLMOD from its
own symbolic analysis (the exact column counts of :math:`L` for its ordering, by an
elimination-tree pass), with SuperLU from the fill measured on these graphs (:math:`L+U` holds at
most :data:`_SUPERLU_FILL` times the entries of :math:`H`; measured 4.4–4.5 for {7,3} flakes up to
ℓ = 10 and 1.8–4.2 for their sector blocks). A factor that will not fit in
:func:`available_memory` (the least of free RAM, the address-space limit ``RLIMIT_AS`` minus what
the process already maps, and the cgroup limit) is refused with :class:`FactorMemoryError`, one
sentence with the needed and available bytes. An allocation failure inside a backend
(``SUPERLU_MALLOC fails``, CHOLMOD out of memory, numpy ``MemoryError``) is turned into the same
sentence; any other backend error into :class:`FactorizationError`.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .. import _validate
from ..errors import ConvergenceError, HyperlatticeError
from .solvers import _lanczos_ritz

__all__ = ["Factor", "SymbolicAnalysis", "analyze", "factorize", "shift_invert_lowest", "lowest_eigenpairs",
           "available_memory",
           "cholmod_available",
           "resolve_backend", "FactorMemoryError", "FactorizationError", "SolverFallbackWarning", "BACKENDS"]

BACKENDS = ("auto", "cholmod", "superlu")
#: nnz(L + U) / nnz(H - sigma) bound of SuperLU (COLAMD, symmetric mode) on these graphs; measured
#: 4.37-4.53 on {7,3} flakes (l = 6..10) and 1.8-4.2 on their sector blocks, with margin
_SUPERLU_FILL = 6.0
#: address space SuperLU reserves per entry of H - sigma (its initial L/U workspaces are sized by a fill
#: factor of 20, mostly untouched pages): measured 820-900 B on {7,3} sector blocks (l = 12, 13);
#: counts against RLIMIT_AS, not against free RAM
_SUPERLU_ADDRESS = 1000
#: bytes per stored factor entry beyond the value itself (row index, supernode padding, workspace)
_ENTRY_OVERHEAD = 8
#: bytes per unknown of the backends' workspaces (permutations, elimination tree, counts, one RHS)
_PER_ROW = 96


class FactorMemoryError(HyperlatticeError, MemoryError):
    """A factorisation that will not fit in the memory available (refused before work, or failed allocating)."""


class FactorizationError(HyperlatticeError):
    """A sparse factorisation failed (singular matrix at the shift, backend error)."""


class SolverFallbackWarning(UserWarning):
    """The factorisation backend asked for is not installed; the fallback named in the message ran."""


# ----------------------------------------------------------------------------
# memory
# ----------------------------------------------------------------------------

available_memory = _validate.available_memory
_memory_limits = _validate.memory_limits


def _gb(nbytes: float) -> str:
    return f"{nbytes / 1024**3:.2f} GB" if nbytes >= 0.1 * 1024**3 else f"{nbytes / 1024**2:.0f} MB"


def _refusal(what: str, needed: float, available: float, allowed: bool = False) -> FactorMemoryError:
    where = "allowed by max_bytes" if allowed else "available to this process"
    return FactorMemoryError(f"the sparse factorisation of {what} needs about {_gb(needed)}, more than the "
                             f"{_gb(available)} {where}.")


# ----------------------------------------------------------------------------
# backends
# ----------------------------------------------------------------------------

#: environment variable that hides CHOLMOD from the package (``superlu``): the SuperLU-only
#: configuration, for CI and the benchmarks, without uninstalling scikit-sparse; read at every
#: call, so subprocesses (the CLI) inherit it
BACKEND_ENV = _validate.FACTOR_BACKEND_ENV


def _cholmod():
    """scikit-sparse's CHOLMOD module, or None (an optional accelerator, never required).

    None as well when the environment variable :data:`BACKEND_ENV` is ``superlu`` (CHOLMOD then
    behaves exactly as if it were not installed); ``auto``, ``cholmod`` or unset change nothing,
    and any other value is refused (ValueError).
    """
    if _validate.factor_backend_env() == "superlu":      # refuses a value it does not know
        return None
    try:
        from sksparse import cholmod
    except ImportError:
        return None
    return cholmod


def cholmod_available() -> bool:
    """True when CHOLMOD (scikit-sparse) can be imported.

    Returns
    -------
    bool
        Whether the ``"cholmod"`` backend can run.

    See Also
    --------
    resolve_backend

    Examples
    --------
    >>> from hyperlattice.graph.factor import cholmod_available
    >>> isinstance(cholmod_available(), bool)
    True
    """
    return _cholmod() is not None


def resolve_backend(backend: str = "auto") -> str:
    """The backend that will run for ``backend`` ("auto", "cholmod", "superlu"; "splu" = "superlu").

    An explicit ``"cholmod"`` without scikit-sparse warns once (:class:`SolverFallbackWarning`)
    and returns ``"superlu"``; ``"auto"`` takes CHOLMOD when it is installed.

    Parameters
    ----------
    backend : {"auto", "cholmod", "superlu", "splu"}, optional
        The backend asked for; default ``"auto"``.

    Returns
    -------
    str
        ``"cholmod"`` or ``"superlu"``.

    Raises
    ------
    ValueError
        For an unknown backend name.

    Warns
    -----
    SolverFallbackWarning
        When ``"cholmod"`` is asked for but scikit-sparse is not installed.

    See Also
    --------
    cholmod_available, factorize

    Examples
    --------
    >>> from hyperlattice.graph.factor import cholmod_available, resolve_backend
    >>> resolve_backend("splu")
    'superlu'
    >>> resolve_backend("auto") == ("cholmod" if cholmod_available() else "superlu")
    True
    """
    if backend == "splu":
        backend = "superlu"
    backend = _validate.choice("backend", backend, BACKENDS)
    if backend == "auto":
        return "cholmod" if _cholmod() is not None else "superlu"
    if backend == "cholmod" and _cholmod() is None:
        warnings.warn("backend='cholmod' asked for, but scikit-sparse is not installed (pip install "
                      "'scikit-sparse<0.5' with libsuitesparse-dev); SuperLU ran instead.",
                      SolverFallbackWarning, stacklevel=3)
        return "superlu"
    return backend


_SYMBOLIC: dict = {}


def _symbolic_kernel():
    """Numba elimination-tree pass: column counts of the Cholesky factor of a permuted pattern."""
    if "counts" in _SYMBOLIC:
        return _SYMBOLIC["counts"]
    import numba

    @numba.njit(cache=True)
    def counts(n, ap, ai, perm, iperm):        # pragma: no cover - compiled
        # Liu's row-subtree walk on P A P^T: for each column k, every i < k of its pattern climbs
        # the elimination tree until a node already marked for k; each step is one entry L[k, i]
        parent = np.full(n, -1, np.int64)
        flag = np.empty(n, np.int64)
        colcount = np.ones(n, np.int64)
        for k in range(n):
            flag[k] = k
            c = perm[k]
            for p in range(ap[c], ap[c + 1]):
                i = iperm[ai[p]]
                if i < k:
                    while flag[i] != k:
                        if parent[i] == -1:
                            parent[i] = k
                        colcount[i] += 1
                        flag[i] = k
                        i = parent[i]
        return colcount

    _SYMBOLIC["counts"] = counts
    return counts


def _factor_counts(pattern: sp.csc_matrix, perm: np.ndarray) -> tuple[int, float]:
    """Entries of L (diagonal included) and the flops of its factorisation, for the symmetric order ``perm``."""
    n = pattern.shape[0]
    perm = np.asarray(perm, dtype=np.int64)
    iperm = np.empty(n, dtype=np.int64)
    iperm[perm] = np.arange(n, dtype=np.int64)
    # the kernel reads column perm[k] of A with its rows renamed by iperm as column k of P A P^T:
    # no permuted copy is made (it needs no sorted rows)
    cc = _symbolic_kernel()(n, pattern.indptr, pattern.indices, perm, iperm).astype(np.float64)
    return int(cc.sum()), float(np.einsum("i,i->", cc, cc))


def _as_square(mat, what: str, name: str = "mat") -> sp.csc_matrix:
    """``mat`` as a CSC matrix of float64 or complex128, refused in one sentence when it is not one."""
    if not sp.issparse(mat):
        try:
            arr = np.asarray(mat)
        except (ValueError, TypeError):
            arr = None
        if arr is None or arr.ndim != 2 or arr.dtype.kind not in "biufc":
            raise ValueError(f"{name} ({what}) must be a square sparse or dense matrix of numbers.")
        mat = sp.csc_matrix(arr)
    if mat.shape[0] != mat.shape[1] or mat.shape[0] == 0:
        raise ValueError(f"{name} ({what}) must be a non-empty square matrix, got shape {mat.shape}.")
    if mat.dtype.kind not in "biufc":
        raise ValueError(f"{name} ({what}) must hold numbers, got dtype {mat.dtype}.")
    if type(mat) is not sp.csc_matrix:
        mat = sp.csc_matrix(mat)      # a CSC matrix is kept as it is: its format flags stay known
    if mat.dtype not in (np.float64, np.complex128):
        mat = mat.astype(np.complex128 if np.iscomplexobj(mat.data) else np.float64)
    if not np.all(np.isfinite(mat.data)):
        raise ValueError(f"{name} ({what}) has entries that are NaN or infinite.")
    return mat


def _text(name: str, value) -> str:
    if not isinstance(value, str):
        raise ValueError(f"{name} must be a string, got {_validate._shown(value)}.")
    return value


def _shift(value):
    """A finite real or complex shift sigma."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, complex, np.number)):
        raise ValueError(f"sigma must be a real or complex number, got {_validate._shown(value)}.")
    try:
        z = complex(value)
    except (OverflowError, TypeError, ValueError):
        raise ValueError(f"sigma must be a finite number, got {_validate._shown(value)}.") from None
    if not (np.isfinite(z.real) and np.isfinite(z.imag)):
        raise ValueError(f"sigma must be a finite number, got {_validate._shown(value)}.")
    return z if z.imag != 0 else z.real


def _with_diagonal(mat: sp.csc_matrix) -> sp.csc_matrix:
    """The matrix with every diagonal entry stored, explicit zeros kept (every shift has one pattern)."""
    n = mat.shape[0]
    # canonical (sorted indices, no duplicates) with every diagonal entry stored already, as the
    # blocks the package builds for the analysis: a copy is all that is needed
    canonical = mat.has_canonical_format
    mat = mat.copy()
    if not canonical:
        mat.sum_duplicates()
    if mat.nnz:
        pos = _diag_kernel()(mat.indptr, mat.indices)
        if np.all(pos >= 0):
            if np.iscomplexobj(mat.data):
                # a Hermitian diagonal is real (see below)
                mat.data[pos] = mat.data[pos].real
            return mat
    cols = np.repeat(np.arange(n, dtype=np.int64), np.diff(mat.indptr))
    on_diag = mat.indices == cols
    missing = np.ones(n, dtype=bool)
    missing[cols[on_diag]] = False
    if np.any(missing):
        # insert an explicit zero at the sorted place of every missing diagonal entry (O(nnz))
        before = np.bincount(cols[mat.indices < cols], minlength=n)
        where = (mat.indptr[:-1] + before)[missing]
        add = np.flatnonzero(missing)
        # the new entries land at where + (number inserted before them); the old ones fill the rest
        slot = np.zeros(mat.nnz + add.shape[0], dtype=bool)
        slot[where + np.arange(add.shape[0])] = True
        indices = np.empty(slot.shape[0], dtype=np.int64)
        indices[slot] = add
        indices[~slot] = mat.indices
        data = np.zeros(slot.shape[0], dtype=mat.dtype)
        data[~slot] = mat.data
        indptr = mat.indptr.astype(np.int64) + np.concatenate([[0], np.cumsum(missing)])
        out = sp.csc_matrix((data, indices, indptr), shape=mat.shape)
        out.has_sorted_indices = True
    else:
        out = mat
    if np.iscomplexobj(out.data):
        # a Hermitian diagonal is real; a rounding-level imaginary part (a rotation phase summed in
        # a sector block) makes CHOLMOD refuse the matrix as not positive definite
        pos = _diag_positions(out)
        out.data[pos] = out.data[pos].real
    return out


# ----------------------------------------------------------------------------
# the symbolic analysis and the factor
# ----------------------------------------------------------------------------

class SymbolicAnalysis:
    """The shift-independent part of the factorisation of one sparsity pattern.

    Parameters
    ----------
    mat : sparse matrix
        H, real symmetric or complex Hermitian (the pattern is analysed; missing diagonal
        entries are stored as zeros so that every shift fits the pattern).
    backend : {"auto", "cholmod", "superlu"}, optional
        See :func:`resolve_backend`; default ``"auto"``.
    what : str, optional
        Name of the matrix in error messages; default ``"H - sigma"``.
    max_bytes : int, optional
        Memory budget in bytes (default: what this process may use).
    ordered : bool, optional
        The rows are already in a fill-reducing order (derived by the caller from another
        analysis, as the rotation-sector blocks of m = 0 take theirs from the real blocks'):
        CHOLMOD keeps it (its natural ordering, postordered) instead of computing a minimum-degree
        ordering; SuperLU ignores it. Default False.

    Attributes
    ----------
    backend : {"cholmod", "superlu"}
        The backend that runs.
    n : int
        Dimension.
    complex : bool
        True for a complex Hermitian matrix.
    factor_entries : int
        Entries of the factor (CHOLMOD: exact for its ordering; SuperLU: the bound, or the count
        of the first factorisation once it ran).
    bytes_needed : int
        Estimated peak bytes of one numeric factorisation (factor plus one shifted copy of H).
    exact : bool
        True when ``factor_entries`` comes from the ordering itself, not from the fill bound.
    permutation : numpy.ndarray or None
        CHOLMOD's fill-reducing ordering (row ``permutation[i]`` is eliminated i-th); None for
        SuperLU, whose column order is chosen at the first factorisation.

    Raises
    ------
    FactorMemoryError
        If the factorisation would not fit in ``max_bytes`` or the memory available.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.factor import analyze
    >>> an = analyze(hl.hamiltonian(hl.ring_lattice(7, 3, 2)), backend="superlu")
    >>> an.backend, an.n, an.complex
    ('superlu', 35, False)
    >>> an.factor(-2.4).negatives          # one level (E0 = -2.636 t) lies below -2.4 t
    1
    """

    def __init__(self, mat, backend: str = "auto", *, what: str = "H - sigma", max_bytes: int | None = None,
                 ordered: bool = False):
        self.what = what
        self.backend = resolve_backend(backend)
        self.matrix = _with_diagonal(_as_square(mat, what))
        self.n = self.matrix.shape[0]
        self.complex = bool(np.iscomplexobj(self.matrix.data))
        self.max_bytes = max_bytes
        self._item = 16 if self.complex else 8
        self._cholmod_ldl = None      # simplicial LDL^T analysis (inertia anywhere)
        self._cholmod_llt = None      # supernodal LL^T analysis (positive definite, faster)
        self._perm = None             # SuperLU: the column order of the first factorisation
        self._ordering = "natural" if ordered else "amd"
        self.permutation = None
        self.exact = False
        self.supernodal = False
        nnz_a = self.matrix.nnz
        if self.backend == "cholmod":
            self._check(self._bytes(2 * nnz_a), "the symbolic analysis")
            cholmod = _cholmod()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")   # CHOLMOD warns on complex-to-real conversions
                    self._cholmod_ldl = cholmod.analyze(self.matrix, mode="simplicial",
                                                        ordering_method=self._ordering)
                perm = self.permutation = np.asarray(self._cholmod_ldl.P(), dtype=np.int64)
                self.factor_entries, flops = _factor_counts(self.matrix, perm)
                # CHOLMOD's own rule: supernodal pays when flops / nnz(L) >= 40; on these graphs the
                # fill is tiny and the simplicial LDL^T is 5x faster (0.010 s vs 0.052 s at l = 10)
                self.supernodal = flops >= 40.0 * self.factor_entries
            except MemoryError:
                raise _refusal(what, self._bytes(2 * nnz_a), available_memory()) from None
            except Exception as exc:  # noqa: BLE001 - any backend error becomes one sentence
                raise _backend_error(exc, what) from None
            self.exact = True
        else:
            # lower triangle and diagonal of L, as the CHOLMOD count (L + U is twice that)
            self.factor_entries = int(_SUPERLU_FILL * nnz_a / 2) + self.n
        self.bytes_needed = self._bytes(self.factor_entries)
        self._check(self.bytes_needed, "")

    def _require_hermitian(self) -> None:
        """Refuse a matrix that is not symmetric (Hermitian): an LDL^T of it counts nothing (a
        non-symmetric matrix was factorised and its "inertia" reported as proved). Once per matrix."""
        if getattr(self, "_hermitian_of", None) is self.matrix:
            return
        m = self.matrix
        tpos = self._transpose_positions()
        if tpos is not None:
            # one gather over the values: entry k of H^+ sits at tpos[k] of the (structurally
            # symmetric) analysed pattern, so no transposed copy of H is built for every shift
            data = m.data
            mod = np.abs(data)
            scale = float(mod.max())
            gap = float(np.abs(data - data[tpos].conj()).max())
        else:
            scale = float(abs(m).max()) if m.nnz else 0.0
            gap = float(abs(m - m.conj().T).max()) if m.nnz else 0.0
        if gap > _validate.HERMITIAN_RTOL * scale:
            kind = "Hermitian" if self.complex else "symmetric"
            raise ValueError(f"{self.what} must be {kind} for an LDL^T factorisation and its eigenvalue count "
                             f"(max |H - H^+| = {gap:.3g}, largest entry {scale:.3g}); pivoting=True factorises "
                             "any matrix by a plain LU.")
        self._hermitian_of = m
        if tpos is not None:
            # every column holds its diagonal entry, so no column is empty for reduceat
            self._norm = float(np.add.reduceat(mod, m.indptr[:-1]).max())     # ||H||_1 >= ||H||_2
            self._norm_of = m

    @property
    def norm(self) -> float:
        """The 1-norm of the matrix held (an upper bound of its 2-norm), computed when first needed
        (the symmetry check computes it on the way)."""
        if getattr(self, "_norm_of", None) is not self.matrix:
            m = self.matrix
            self._norm = float(abs(m).sum(axis=0).max()) if m.nnz else 0.0
            self._norm_of = m
        return self._norm

    @norm.setter
    def norm(self, value: float) -> None:
        self._norm, self._norm_of = float(value), self.matrix

    def _transpose_positions(self) -> np.ndarray | None:
        """Position in ``matrix.data`` of the transposed partner of every entry, for a structurally
        symmetric analysed pattern (computed once per pattern); None when the pattern is not symmetric."""
        # every matrix an analysis holds is on its analysed pattern (factor, view and with_values
        # check or keep it), so the map is computed once per analysis
        cached = getattr(self, "_tpos", None)
        if cached is not None:
            return cached[0]
        m = self.matrix
        tpos = None
        if m.nnz:
            # the transpose of the pattern with the entry numbers as values: for a symmetric pattern
            # (sorted, canonical: _with_diagonal) it has the same layout, and its values are the map
            t = sp.csc_matrix((np.arange(m.nnz, dtype=np.int64), m.indices, m.indptr), shape=m.shape).T.tocsc()
            if np.array_equal(t.indptr, m.indptr) and np.array_equal(t.indices, m.indices):
                tpos = np.asarray(t.data, dtype=np.int64)
        self._tpos = (tpos,)
        return tpos

    def _bytes(self, factor_entries: int) -> int:
        per_entry = self._item + _ENTRY_OVERHEAD
        copies = 2 if self.backend == "superlu" else 1          # SuperLU stores L and U
        # the factor, one shifted copy of H, and the workspaces
        return int(copies * factor_entries * per_entry + 2 * self.matrix.nnz * per_entry + _PER_ROW * self.n)

    def _check(self, needed: int, stage: str) -> None:
        if self.max_bytes is not None:
            if needed > int(self.max_bytes):
                raise _refusal(self.what, needed, int(self.max_bytes), True)
            return
        resident, address = _memory_limits()
        if needed > resident:
            raise _refusal(self.what, needed, min(resident, address if address is not None else resident))
        if address is not None:
            # SuperLU reserves far more address space than it touches: that counts against RLIMIT_AS
            reserve = max(needed, _SUPERLU_ADDRESS * self.matrix.nnz) if self.backend == "superlu" else needed
            if reserve > address:
                raise FactorMemoryError(
                    f"the sparse factorisation of {self.what} needs about {_gb(reserve)} of address space"
                    f"{' (SuperLU reserves its workspace up front)' if self.backend == 'superlu' else ''}, more "
                    f"than the {_gb(address)} left under this process's address-space limit.")

    def shifted(self, sigma) -> sp.csc_matrix:
        """:math:`H - \\sigma` with the analysed pattern (a new array).

        Parameters
        ----------
        sigma : float or complex
            The shift, in the units of H.

        Returns
        -------
        scipy.sparse.csc_matrix
            :math:`H - \\sigma` (complex when ``sigma`` is complex).
        """
        out = self.matrix.copy()
        diag = _diag_positions(out)
        if np.iscomplexobj(sigma) and not self.complex:
            out = out.astype(np.complex128)
        out.data[diag] -= sigma
        return out

    def factor(self, sigma: float = 0.0, *, positive: bool = False, matrix=None, pivoting: bool = False,
               symmetric: bool = False) -> "Factor":
        """Numeric factorisation of :math:`H - \\sigma` reusing this analysis (see :func:`factorize`).

        ``matrix``: another matrix with the same sparsity pattern (the real sector blocks of
        m = 1..p/2 share one), which then replaces the analysed values.

        Parameters
        ----------
        sigma : float or complex, optional
            The shift, in the units of H; default 0.
        positive, pivoting : bool, optional
            As in :func:`factorize`; default False.
        matrix : sparse matrix, optional
            New values on the analysed pattern.
        symmetric : bool, optional
            The caller built ``matrix`` (real, CSC, on the analysed pattern itself) symmetric to
            rounding, as the rotation-sector blocks are built (:mod:`hyperlattice.graph.sectors`),
            so the check of its symmetry (a pass over its values at every factorisation) is
            skipped; ignored for any other matrix. Default False.

        Returns
        -------
        Factor
            The numeric factorisation.

        Raises
        ------
        ValueError
            If ``matrix`` does not have the analysed pattern or type.
        """
        symmetric = _validate.flag("symmetric", symmetric)
        if matrix is not None:
            if (type(matrix) is sp.csc_matrix and not self.complex and matrix.dtype == np.float64
                    and matrix.shape == self.matrix.shape and np.array_equal(matrix.indptr, self.matrix.indptr)
                    and np.array_equal(matrix.indices, self.matrix.indices)):
                # a real matrix on the analysed pattern itself (the sector blocks of one kind): its
                # values are copied onto the analysed index arrays, without a conversion or a
                # diagonal scan, and the pattern-level data (transposed positions) is kept
                if not np.all(np.isfinite(matrix.data)):
                    raise ValueError(f"mat ({self.what}) has entries that are NaN or infinite.")
                mat = sp.csc_matrix((matrix.data.copy(), self.matrix.indices, self.matrix.indptr),
                                    shape=self.matrix.shape)
                # the constructor copies the index arrays: share the analysed ones instead
                mat.indices, mat.indptr = self.matrix.indices, self.matrix.indptr
                mat.has_sorted_indices = True
                if symmetric:
                    # built symmetric by the caller: the check's pass over the values is skipped (the
                    # norm, needed only when a tie is asked about, is computed then)
                    self._hermitian_of = mat
            else:
                mat = _with_diagonal(_as_square(matrix, self.what))
                if (mat.shape != self.matrix.shape or not np.array_equal(mat.indptr, self.matrix.indptr)
                        or not np.array_equal(mat.indices, self.matrix.indices)):
                    raise ValueError("the matrix does not have the analysed sparsity pattern.")
                if np.iscomplexobj(mat.data) != self.complex:
                    raise ValueError("the matrix is not of the analysed type (real or complex).")
                # the same pattern: keep the analysed index arrays (and what was learnt from them)
                mat = sp.csc_matrix((mat.data, self.matrix.indices, self.matrix.indptr), shape=self.matrix.shape)
                mat.has_sorted_indices = True
            self.matrix = mat
        return Factor(self, sigma, positive=positive, pivoting=pivoting)

    def view(self, matrix) -> "SymbolicAnalysis":
        """This analysis for another matrix of the same pattern (checked once, here), sharing the ordering.

        Every :meth:`factor` of the view factorises ``matrix`` without checking it again: the
        rotation-sector blocks of one lattice (:mod:`hyperlattice.graph.green`) share one
        analysis and are refactorised at every shift. A real matrix may use a complex analysis.

        Parameters
        ----------
        matrix : sparse matrix
            The values, on the analysed pattern.

        Returns
        -------
        SymbolicAnalysis
            A shallow copy holding ``matrix``.

        Raises
        ------
        ValueError
            If ``matrix`` does not have the analysed pattern, or is complex for a real analysis.
        """
        import copy

        mat = _as_square(matrix, self.what)
        same = (mat.shape == self.matrix.shape and np.array_equal(mat.indptr, self.matrix.indptr)
                and np.array_equal(mat.indices, self.matrix.indices))
        if same:                          # the analysed pattern (diagonal stored): a copy will do
            mat = mat.copy()
            if np.iscomplexobj(mat.data):
                pos = _diag_positions(mat)
                mat.data[pos] = mat.data[pos].real
        else:
            mat = _with_diagonal(mat)
        if (mat.shape != self.matrix.shape or not np.array_equal(mat.indptr, self.matrix.indptr)
                or not np.array_equal(mat.indices, self.matrix.indices)):
            raise ValueError("the matrix does not have the analysed sparsity pattern.")
        if np.iscomplexobj(mat.data) and not self.complex:
            raise ValueError("a complex matrix needs a complex analysis.")
        if self.complex and not np.iscomplexobj(mat.data):
            mat = mat.astype(np.complex128)
        out = copy.copy(self)
        out.matrix = mat
        return out

    def with_values(self, data) -> "SymbolicAnalysis":
        """This analysis for new values on its own pattern, ``data`` in the order of ``self.matrix.data``.

        The cheap form of :meth:`view` for a caller that builds its matrices on the analysed
        pattern itself (the rotation-sector blocks of :mod:`hyperlattice.graph.green`): there is no
        pattern to compare, only the values are checked (their number, finite, real for a real
        analysis); a complex diagonal is made real (a Hermitian diagonal is real). ``data`` is
        taken over, not copied, when it already has the analysis' type.

        Parameters
        ----------
        data : array_like, shape (nnz,)
            The values, entry by entry as in ``self.matrix.data``.

        Returns
        -------
        SymbolicAnalysis
            A shallow copy holding the matrix of those values (the pattern arrays are shared).

        Raises
        ------
        ValueError
            If the number of values is not that of the pattern, a value is not finite, or the
            values are complex for a real analysis.
        """
        import copy

        data = np.asarray(data)
        if data.shape != self.matrix.data.shape:
            raise ValueError(f"{data.size} values do not fit the analysed pattern of {self.matrix.nnz} entries.")
        if np.iscomplexobj(data) and not self.complex:
            raise ValueError("a complex matrix needs a complex analysis.")
        data = data.astype(np.complex128 if self.complex else np.float64, copy=False)
        if not np.all(np.isfinite(data)):
            raise ValueError(f"the values for {self.what} are NaN or infinite.")
        if self.complex:
            pos = getattr(self, "_diag_pos", None)
            if pos is None:
                pos = self._diag_pos = _diag_positions(self.matrix)
            data[pos] = data[pos].real
        mat = sp.csc_matrix((data, self.matrix.indices, self.matrix.indptr), shape=self.matrix.shape)
        mat.has_sorted_indices = True
        out = copy.copy(self)
        out.matrix = mat
        return out

    def __repr__(self) -> str:
        return (f"<SymbolicAnalysis {self.backend} n={self.n} factor entries "
                f"{'=' if self.exact else '<='} {self.factor_entries:,}, about {_gb(self.bytes_needed)}>")


_DIAG_CACHE: dict = {}


def _diag_kernel():
    """Numba scan: position of the diagonal entry of every column of a CSC pattern, -1 when absent."""
    if "diag" in _SYMBOLIC:
        return _SYMBOLIC["diag"]
    import numba

    @numba.njit(cache=True)
    def diag(indptr, indices):                 # pragma: no cover - compiled
        n = indptr.shape[0] - 1
        pos = np.full(n, -1, np.int64)
        for k in range(n):
            for p in range(indptr[k], indptr[k + 1]):
                if indices[p] == k:
                    pos[k] = p
                    break
        return pos

    _SYMBOLIC["diag"] = diag
    return diag


def _diag_positions(mat: sp.csc_matrix) -> np.ndarray:
    """Positions of the diagonal entries in ``mat.data`` (every diagonal entry is stored, once)."""
    pos = _diag_kernel()(mat.indptr, mat.indices)
    if np.any(pos < 0):  # pragma: no cover - _with_diagonal stores every diagonal entry
        raise FactorizationError("internal: the analysed pattern lacks diagonal entries.")
    return pos


def _backend_error(exc: BaseException, what: str) -> HyperlatticeError:
    text = str(exc)
    low = text.lower()
    if isinstance(exc, MemoryError) or "malloc" in low or "out of memory" in low or "memory" in low:
        return FactorMemoryError(f"the sparse factorisation of {what} ran out of memory "
                                 f"({_gb(available_memory())} available to this process).")
    if "singular" in low or "not positive definite" in low:
        # CHOLMOD's LDL^T names a zero pivot "not positive definite" (it needs no definiteness)
        return FactorizationError(f"{what} is singular to working precision (the shift is an eigenvalue).")
    first = text.splitlines()[0][:120] if text else type(exc).__name__
    return FactorizationError(f"the sparse factorisation of {what} failed ({type(exc).__name__}: {first}).")


class Factor:
    r"""A numeric factorisation of :math:`H - \sigma` (from :func:`factorize` or :meth:`SymbolicAnalysis.factor`).

    Parameters
    ----------
    analysis : SymbolicAnalysis
        The symbolic analysis of H.
    sigma : float or complex
        The shift, in the units of H (a complex σ with nonzero imaginary part gives an LU).
    positive, pivoting : bool, optional
        As in :func:`factorize`; default False.

    Attributes
    ----------
    backend : {"cholmod", "superlu"}
        What ran.
    sigma : float or complex
        The shift.
    negatives : int or None
        Number of eigenvalues of H below σ (Sylvester's law of inertia), or None when the
        factorisation proves nothing (SuperLU took off-diagonal pivots, σ is complex, or
        ``pivoting`` was asked for).
    proved : bool
        True when ``negatives`` is proved by the factorisation (False on a :attr:`tie`).
    tie : bool
        σ lies within rounding of an eigenvalue: the count may be off by the tied levels.
    positive_definite : bool
        :math:`H - \sigma` proved positive definite (σ below the spectrum).
    kind : str
        ``"LL^T"``, ``"LDL^T"`` or ``"LU"``.
    analysis : SymbolicAnalysis
        The analysis it reuses.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.factor import factorize
    >>> H = hl.hamiltonian(hl.ring_lattice(7, 3, 2))
    >>> f = factorize(H, -3.0, backend="superlu")
    >>> f.kind, f.negatives, f.proved, f.positive_definite    # -3 t lies below the spectrum
    ('LDL^T', 0, True, True)
    >>> x = f.solve(np.ones(35))
    >>> bool(np.allclose(H @ x + 3.0 * x, 1.0))
    True
    >>> f.refactor(-2.4).negatives
    1
    """

    def __init__(self, analysis: SymbolicAnalysis, sigma, *, positive: bool = False, pivoting: bool = False):
        self.analysis = analysis
        self.backend = analysis.backend
        self.n = analysis.n
        hermitian = not (np.iscomplexobj(sigma) and complex(sigma).imag != 0)
        self.sigma = float(np.real(sigma)) if hermitian else complex(sigma)
        self.negatives = None
        self._counted = False
        self._tie = None
        self.positive_definite = False
        what = analysis.what
        if hermitian and not pivoting:
            analysis._require_hermitian()
        try:
            if not hermitian or pivoting:
                self._general(sigma)
            elif self.backend == "cholmod":
                self._cholmod(positive)
            else:
                self._superlu()
        except HyperlatticeError:
            raise
        except MemoryError:
            raise _refusal(what, analysis.bytes_needed, available_memory()) from None
        except Exception as exc:  # noqa: BLE001 - SuperLU / CHOLMOD errors become one sentence
            raise _backend_error(exc, f"{what} at {self._label()}") from None

    def _label(self) -> str:
        return f"sigma = {self.sigma:.12g}"

    # -- CHOLMOD --
    def _cholmod(self, positive: bool) -> None:
        cholmod = _cholmod()
        an = self.analysis
        shifted = an.matrix
        beta = -self.sigma
        if positive and an.supernodal:
            if an._cholmod_llt is None:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    an._cholmod_llt = cholmod.analyze(shifted, mode="supernodal", ordering_method=an._ordering)
            try:
                self._f = an._cholmod_llt.cholesky(shifted, beta=beta)
            except cholmod.CholmodNotPositiveDefiniteError:
                pass
            else:
                self.kind = "LL^T"
                self.negatives, self._counted, self.positive_definite = 0, True, True
                return
        # the simplicial LDL^T: CHOLMOD does not pivot, so D holds the inertia (all D > 0 proves
        # positive definiteness as well as a Cholesky factorisation would)
        self._f = an._cholmod_ldl.cholesky(shifted, beta=beta)
        self.kind = "LDL^T"
        d = np.real(np.asarray(self._f.D()))
        self._count(d)

    # -- SuperLU --
    def _superlu(self) -> None:
        an = self.analysis
        m = an.shifted(self.sigma)
        if an._perm is None:
            lu = spla.splu(m, permc_spec="COLAMD", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
            if np.array_equal(lu.perm_r, lu.perm_c):
                # keep the column order: later shifts skip COLAMD (the pattern is the same)
                an._perm = np.argsort(lu.perm_c)
                an.factor_entries = int(lu.L.nnz)
                an.exact = True
            self._perm = None
        else:
            perm = an._perm
            mp = m[perm][:, perm].tocsc()
            lu = spla.splu(mp, permc_spec="NATURAL", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
            self._perm = perm
        self._lu = lu
        self.kind = "LDL^T"
        if np.array_equal(lu.perm_r, lu.perm_c):
            self._count(np.real(lu.U.diagonal()))
        # else: an off-diagonal pivot was taken, so the diagonal of U proves no inertia

    def _general(self, sigma) -> None:
        an = self.analysis
        m = an.shifted(sigma)
        self._lu = spla.splu(m, permc_spec="COLAMD")
        self._perm = None
        self.kind = "LU"

    def _count(self, d: np.ndarray) -> None:
        if not np.all(np.isfinite(d)) or np.any(d == 0):
            raise FactorizationError(f"the factorisation of {self.analysis.what} at {self._label()} met a zero "
                                     "pivot (the shift is an eigenvalue to working precision).")
        self.negatives = int(np.count_nonzero(d < 0))
        self._counted = True
        self.positive_definite = self.negatives == 0
        self.pivots = d

    # -- the count, and whether sigma ties with an eigenvalue --
    @property
    def tie(self) -> bool:
        """True when σ lies within rounding of an eigenvalue of H, so that the count of eigenvalues
        below it is undecided (``proved`` is then False); False for an LU, which counts nothing.

        Rounding is :func:`hyperlattice._ties.eigenvalue_tolerance` of H - σ (16 n ε ‖H - σ‖₁). A
        tie is found from a pivot of that size, or from one solve: ‖b‖/‖(H - σ)⁻¹b‖ bounds the
        distance from σ to the spectrum (computed on first use, then kept).
        """
        if self._tie is None:
            self._tie = False
            if self._counted:
                from .._ties import eigenvalue_tolerance

                an = self.analysis
                delta = eigenvalue_tolerance(an.norm + abs(self.sigma), self.n)
                d = getattr(self, "pivots", None)
                if d is not None and d.size and float(np.min(np.abs(d))) <= delta:
                    self._tie = True
                else:
                    b = np.random.default_rng(0).standard_normal(self.n)
                    with np.errstate(over="ignore", invalid="ignore"):
                        x = self.solve(b)
                        size = float(np.linalg.norm(x))
                    self._tie = not np.isfinite(size) or float(np.linalg.norm(b)) <= delta * size
        return self._tie

    @property
    def proved(self) -> bool:
        """True when ``negatives`` is proved by the factorisation: counted by an LDL^T/LL^T, and σ
        does not tie with an eigenvalue (:attr:`tie`)."""
        return self._counted and not self.tie

    # -- use --
    def solve(self, b: np.ndarray) -> np.ndarray:
        r""":math:`(H - \sigma)^{-1} b` for one (shape (n,)) or many (shape (n, k)) right-hand sides.

        Parameters
        ----------
        b : array_like, shape (n,) or (n, k)
            Right-hand side(s), real or complex.

        Returns
        -------
        numpy.ndarray
            The solution(s), of the shape of ``b``.
        """
        b = np.asarray(b)
        try:
            if self.backend == "cholmod" and hasattr(self, "_f"):
                if np.iscomplexobj(b) and not self.analysis.complex:
                    return self._f.solve_A(b.real) + 1j * self._f.solve_A(b.imag)
                return self._f.solve_A(b)
            if self._perm is None:
                return self._solve_lu(b)
            perm = self._perm
            y = self._solve_lu(b[perm])
            out = np.empty_like(y)
            out[perm] = y
            return out
        except MemoryError:
            raise _refusal(self.analysis.what, b.nbytes * 3, available_memory()) from None

    def _solve_lu(self, b: np.ndarray) -> np.ndarray:
        lu = self._lu
        if np.iscomplexobj(b) and lu.L.dtype != np.complex128:
            return lu.solve(np.ascontiguousarray(b.real)) + 1j * lu.solve(np.ascontiguousarray(b.imag))
        return lu.solve(np.asarray(b, dtype=lu.L.dtype))

    def refactor(self, sigma, *, positive: bool = False, pivoting: bool = False) -> "Factor":
        """A new factor at another shift, reusing the symbolic analysis.

        Parameters
        ----------
        sigma : float or complex
            The new shift, in the units of H.
        positive, pivoting : bool, optional
            As in :func:`factorize`; default False.

        Returns
        -------
        Factor
            The factorisation at ``sigma``.
        """
        return Factor(self.analysis, sigma, positive=positive, pivoting=pivoting)

    def __repr__(self) -> str:
        return (f"<Factor {self.backend} {self.kind} n={self.n} sigma={self.sigma} negatives={self.negatives} "
                f"proved={self.proved}>")


def analyze(mat, *, backend: str = "auto", what: str = "H - sigma", max_bytes: int | None = None,
            ordered: bool = False) -> SymbolicAnalysis:
    """The symbolic analysis of a real symmetric or complex Hermitian sparse matrix H (shift-independent).

    The fill-reducing ordering and the size of the factor depend on the sparsity pattern only,
    so one analysis serves every shift σ (:meth:`SymbolicAnalysis.factor`) and every block of
    the same pattern.

    Parameters
    ----------
    mat : sparse matrix, shape (n, n)
        H (only its pattern and values are used; symmetric/Hermitian is assumed, not checked).
    backend : {"auto", "cholmod", "superlu"}, optional
        See the module docstring and :func:`resolve_backend`; default ``"auto"``.
    what : str, optional
        How the matrix is named in error messages; default ``"H - sigma"``.
    max_bytes : int, optional
        Budget in bytes; default the memory available to the process (:func:`available_memory`).
    ordered : bool, optional
        The rows are already in a fill-reducing order: CHOLMOD keeps it instead of computing
        one (:class:`SymbolicAnalysis`); default False.

    Returns
    -------
    SymbolicAnalysis
        ``backend``, ``n``, ``complex``, ``factor_entries``, ``bytes_needed`` and ``exact``.

    Raises
    ------
    ValueError
        For a matrix that is not square and sparse-convertible, or an unknown backend.
    FactorMemoryError
        When the estimated factor will not fit (one sentence with the needed and available bytes).

    See Also
    --------
    factorize

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.factor import analyze
    >>> a = analyze(hl.hamiltonian(hl.ring_lattice(7, 3, 3)), backend="superlu")
    >>> a.backend, a.n, a.complex
    ('superlu', 112, False)
    >>> a.factor(-2.0).negatives      # levels of H below -2
    12
    """
    what = _text("what", what)
    if max_bytes is not None:
        max_bytes = _validate.positive_int("max_bytes", max_bytes)
    return SymbolicAnalysis(mat, backend, what=what, max_bytes=max_bytes, ordered=_validate.flag("ordered", ordered))


def factorize(mat, sigma=0.0, *, backend: str = "auto", analysis: SymbolicAnalysis | None = None,
              positive: bool = False, pivoting: bool = False, what: str = "H - sigma",
              max_bytes: int | None = None) -> Factor:
    r"""Factorise :math:`H - \sigma` once, for solves and the inertia count.

    By Sylvester's law of inertia, the signs of the pivots of an :math:`LDL^T` (or the
    success of a Cholesky :math:`LL^T`) count the eigenvalues of H below σ.

    Parameters
    ----------
    mat : sparse matrix
        H, real symmetric or complex Hermitian (ignored when ``analysis`` is given).
    sigma : float or complex, optional
        Shift, in the units of H; default 0. A complex σ (with nonzero imaginary part) gives a
        plain LU with pivoting (SuperLU; no inertia).
    backend : {"auto", "cholmod", "superlu"}, optional
        See :func:`resolve_backend`; default ``"auto"``.
    analysis : SymbolicAnalysis, optional
        Reuse a previous analysis of the same pattern (a new shift costs the numeric part only).
    positive : bool, optional
        σ is expected below the spectrum: CHOLMOD tries a supernodal :math:`LL^T` first, whose
        success proves it (``factor.positive_definite``); on failure the :math:`LDL^T` counts.
        Default False.
    pivoting : bool, optional
        A plain LU with partial pivoting (SuperLU) even for a real shift: stable inside the
        spectrum, where an :math:`LDL^T` without pivoting may not be; no inertia. Default False.
    what : str, optional
        Name of the matrix in error messages; default ``"H - sigma"``.
    max_bytes : int, optional
        Memory budget in bytes (default: :func:`available_memory`).

    Returns
    -------
    Factor
        ``backend``, ``sigma``, ``kind`` (``"LL^T"``, ``"LDL^T"`` or ``"LU"``), ``negatives``
        (eigenvalues below σ, or None), ``proved``, ``positive_definite``; ``solve(b)`` solves
        :math:`(H - \sigma)x = b`.

    Raises
    ------
    ValueError
        For invalid input.
    FactorMemoryError
        The factor will not fit (refused before work), or a backend ran out of memory.
    ValueError
        Also for a matrix that is not symmetric (Hermitian), unless ``pivoting`` (or a complex σ)
        asks for a plain LU.
    FactorizationError
        Zero pivot (σ an eigenvalue to working precision) or another backend failure. A σ
        within rounding of an eigenvalue that still factorises is reported as ``factor.tie``
        (and ``proved`` False).

    See Also
    --------
    analyze, lowest_eigenpairs, shift_invert_lowest

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.factor import factorize
    >>> H = hl.hamiltonian(hl.ring_lattice(7, 3, 3))
    >>> f = factorize(H, -3.0, backend="superlu", positive=True)
    >>> f.negatives, f.positive_definite       # E0 = -2.7867 lies above -3
    (0, True)
    >>> factorize(H, -2.0, backend="superlu").negatives
    12
    """
    sigma = _shift(sigma)
    positive = _validate.flag("positive", positive)
    pivoting = _validate.flag("pivoting", pivoting)
    if analysis is not None and not isinstance(analysis, SymbolicAnalysis):
        raise ValueError(f"analysis must be a SymbolicAnalysis from analyze(), got {_validate._shown(analysis)}.")
    if analysis is None:
        if pivoting or (np.iscomplexobj(sigma) and complex(sigma).imag != 0):
            backend = "superlu"   # a pivoted LU is SuperLU's job; no CHOLMOD analysis to pay for
        analysis = analyze(mat, backend=backend, what=what, max_bytes=max_bytes)
    return analysis.factor(sigma, positive=positive, pivoting=pivoting)


#: Lanczos basis of the shift-invert runs (measured: 19 solves per level at 12, the fewest).
_NCV = 12
_ARPACK_TOLS = (1e-10, 1e-14)


def shift_invert_lowest(mat, k: int, factor: Factor, tol: float, label: str):
    r"""The k lowest eigenpairs of a Hermitian matrix above the shift of ``factor``, by Lanczos on :math:`(H - \sigma)^{-1}`.

    ``factor`` must show no eigenvalue below its shift (then the largest eigenvalues of the
    inverse are the lowest of H). Energies are Rayleigh quotients with H itself.

    Parameters
    ----------
    mat : sparse matrix, shape (n, n)
        H, real symmetric or complex Hermitian.
    k : int
        Number of eigenpairs, 1 <= k <= n - 2.
    factor : Factor
        A factorisation of :math:`H - \sigma` from :func:`factorize` with σ below the wanted
        levels.
    tol : float
        Residual target :math:`\|H\psi - E\psi\|`, in the units of H; ARPACK is run again more
        tightly when a residual exceeds tol / 10.
    label : str
        Name of the matrix in messages.

    Returns
    -------
    energies : numpy.ndarray of float64, shape (k,)
        Ascending.
    vectors : numpy.ndarray, shape (n, k)
        Normalised eigenvectors; real for a real H.
    residuals : numpy.ndarray of float64, shape (k,)
        :math:`\|H\psi - E\psi\|` of each.
    solves : int
        Number of solves with the factor.

    Raises
    ------
    ValueError
        If ``factor`` is not a Factor or belongs to a matrix of another size, or for invalid
        k, tol or label.
    ConvergenceError
        If ARPACK does not converge.

    See Also
    --------
    lowest_eigenpairs, factorize

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.factor import factorize, shift_invert_lowest
    >>> H = hl.hamiltonian(hl.ring_lattice(7, 3, 3))
    >>> f = factorize(H, -3.0, backend="superlu", positive=True)
    >>> e, v, res, solves = shift_invert_lowest(H, 2, f, 1e-10, "flake")
    >>> [round(float(x), 6) for x in e], v.shape, bool(res.max() < 1e-10)
    ([-2.786702, -2.626896], (112, 2), True)
    """
    from ..errors import ConvergenceError

    if not isinstance(factor, Factor):
        raise ValueError(f"factor must be a Factor from factorize(), got {_validate._shown(factor)}.")
    label = _text("label", label)
    mat = _as_square(mat, label)
    n = mat.shape[0]
    if n != factor.n:
        raise ValueError(f"mat has {n} rows but the factor was made for {factor.n}.")
    k = _validate.positive_int("k", k, maximum=max(n - 2, 1))
    tol = _validate.positive_real("tol", tol)
    dtype = np.complex128 if np.iscomplexobj(mat.data) else np.float64
    solves = [0]

    def op(v):
        solves[0] += 1
        return factor.solve(np.asarray(v, dtype=dtype).ravel())

    lin = spla.LinearOperator((n, n), matvec=op, dtype=dtype)
    ncv = min(n, max(2 * k + 1, _NCV))
    # ARPACK's Lanczos basis (n x ncv) and work vectors, then the k vectors and H times them:
    # refused before allocating (a k near n, as a highly degenerate lowest level asks for, is n^2)
    needed = (ncv + 2 * k + 4) * n * np.dtype(dtype).itemsize
    if needed > available_memory():
        raise FactorMemoryError(f"the Lanczos basis for the {k} lowest levels of {label} ({n} rows) needs about "
                                f"{_gb(needed)}, more than the {_gb(available_memory())} available to this process.")
    v0 = np.random.default_rng(12345).standard_normal(n).astype(dtype)
    # ARPACK's tolerance is relative to the eigenvalues 1/(E - x) of the inverse; a loose first
    # try usually leaves a residual of H far below tol already (and the eigenvalue error is about
    # residual^2 / gap); a tight one follows only when the residual misses tol / 10.
    for arpack_tol in _ARPACK_TOLS:
        try:
            _, vecs = spla.eigsh(lin, k=k, which="LA", ncv=ncv, tol=arpack_tol, v0=v0, maxiter=2000)
        except spla.ArpackNoConvergence as exc:  # pragma: no cover - depends on the matrix
            raise ConvergenceError(f"{label}: ARPACK did not converge ({exc}).") from exc
        vecs /= np.linalg.norm(vecs, axis=0)[None, :]
        hv = mat @ vecs
        energies = np.real(np.einsum("ij,ij->j", vecs.conj(), hv))
        order = np.argsort(energies)
        energies, vecs, hv = energies[order], vecs[:, order], hv[:, order]
        res = np.linalg.norm(hv - vecs * energies[None, :], axis=0)
        if np.all(res <= 0.1 * tol):
            break
    return energies, vecs, res, solves[0]


def _proved_shift_lowest(mat, k: int, analysis: SymbolicAnalysis, tol: float, label: str, *, what: str,
                         below: float | None = None, ritz: np.ndarray | None = None, scale: float = 1.0,
                         symmetric: bool = False):
    r"""The k lowest eigenvalues of a real symmetric block: a shift σ below them, proved, then shift-invert.

    σ starts just below ``below`` (a known lower bound of the block's levels, 1e-6 ``scale`` under
    it) or just below the k-th Ritz value of ``ritz`` (upper bounds of the levels, ascending) and
    steps down, doubling its distance, until the factorisation of :math:`B - \sigma` (from
    ``analysis``, the block's symbolic analysis) shows no eigenvalue below it; Lanczos on
    :math:`(B - \sigma)^{-1}` (:func:`shift_invert_lowest`) then gives the k lowest.

    Returns ``(energies, residuals, sigma, solves)``; raises ConvergenceError when no shift below
    the block's lowest level is found in 60 steps (``what`` names the block). ``symmetric``: the
    block was built symmetric (:meth:`SymbolicAnalysis.factor`).
    """
    if below is not None:
        theta = np.array([below])
        delta = 1e-6 * scale
    else:
        theta = ritz
        spread = max(float(theta[-1] - theta[0]), 1e-3 * scale)
        # theta[k-1] >= the k-th level (interlacing): step below it until the factor proves nothing below sigma
        delta = max(float(theta[min(k, theta.shape[0] - 1)] - theta[min(k, theta.shape[0]) - 1]), 1e-4 * spread)
    for _ in range(60):
        sigma = float(theta[min(k, theta.shape[0]) - 1]) - delta
        factor = analysis.factor(sigma, positive=True, matrix=mat, symmetric=symmetric)
        if factor.negatives == 0 or factor.negatives is None:
            break
        delta *= 2.0
    else:  # pragma: no cover - the spectrum is bounded by the Gershgorin disc
        raise ConvergenceError(f"{what}: no shift below its lowest level found.")
    e, v, res, solves = shift_invert_lowest(mat, k, factor, tol, label)
    del v
    return e, res, sigma, solves


def lowest_eigenpairs(mat, k: int, *, tol: float = 1e-10, backend: str = "auto", label: str = "block",
                      max_bytes: int | None = None, analysis: SymbolicAnalysis | None = None):
    r"""The k lowest eigenpairs of a sparse Hermitian matrix by shift-invert Lanczos, with an inertia proof.

    A short plain Lanczos run bounds the k-th level from above (Ritz values); σ steps down from it
    until the factorisation of :math:`H - \sigma` proves nothing below σ; ARPACK on
    :math:`(H - \sigma)^{-1}` gives the k lowest; a last factorisation just above the k-th level
    counts the levels below it (Sylvester), and a level ARPACK missed is fetched by a second run.

    Parameters
    ----------
    mat : sparse matrix, shape (n, n)
        H, real symmetric or complex Hermitian, n >= 3.
    k : int
        Number of eigenpairs, 1 <= k <= n - 2.
    tol : float, optional
        Residual target, in the units of H; default 1e-10.
    backend : {"auto", "cholmod", "superlu"}, optional
        See :func:`resolve_backend`; default ``"auto"``.
    label : str, optional
        Name of the matrix in messages; default ``"block"``.
    max_bytes : int, optional
        Memory budget in bytes (default: :func:`available_memory`).
    analysis : SymbolicAnalysis, optional
        Reuse an analysis of the same pattern.

    Returns
    -------
    energies : numpy.ndarray of float64, shape (k,)
        Ascending.
    vectors : numpy.ndarray, shape (n, k)
        Normalised eigenvectors.
    residuals : numpy.ndarray of float64, shape (k,)
        :math:`\|H\psi - E\psi\|`.
    info : dict
        ``{"backend", "sigma", "solves", "proved", "analysis"}``.

    Raises
    ------
    ValueError
        For invalid input (fewer than 3 rows, k out of range, an analysis of another kind).
    FactorMemoryError
        If a factorisation will not fit.
    ConvergenceError
        If no shift below the lowest level is found or ARPACK does not converge.

    See Also
    --------
    shift_invert_lowest, hyperlattice.graph.sectors.lowest_sector_levels

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.factor import lowest_eigenpairs
    >>> H = hl.hamiltonian(hl.ring_lattice(7, 3, 3))
    >>> e, v, res, info = lowest_eigenpairs(H, 3, backend="superlu")
    >>> [round(float(x), 6) for x in e], info["proved"]
    ([-2.786702, -2.626896, -2.626896], True)
    """
    label = _text("label", label)
    mat = _as_square(mat, label)
    n = mat.shape[0]
    if n < 3:
        raise ValueError(f"mat ({label}) must have at least 3 rows for a Lanczos run, got {n}.")
    k = _validate.positive_int("k", k, maximum=n - 2)
    tol = _validate.positive_real("tol", tol)
    if analysis is not None and not isinstance(analysis, SymbolicAnalysis):
        raise ValueError(f"analysis must be a SymbolicAnalysis from analyze(), got {_validate._shown(analysis)}.")
    if max_bytes is not None:
        max_bytes = _validate.positive_int("max_bytes", max_bytes)
    an = analysis if analysis is not None else analyze(mat, backend=backend, what=label, max_bytes=max_bytes)

    def ritz():
        if not np.iscomplexobj(mat.data):
            return _lanczos_ritz(mat, 40)
        # a complex Hermitian block: Ritz values of its real symmetric 2n embedding (each level twice)
        emb = sp.bmat([[mat.real, -mat.imag], [mat.imag, mat.real]], format="csr")
        return _lanczos_ritz(emb, 60)

    theta = ritz()
    kk = min(k, n - 2)
    # theta[j] >= the kk-th level (interlacing; the complex embedding holds every level twice)
    j = min(2 * kk if np.iscomplexobj(mat.data) else kk, theta.shape[0]) - 1
    spread = max(float(theta[-1] - theta[0]), 1e-12)
    delta = max(float(theta[min(j + 1, theta.shape[0] - 1)] - theta[j]), 1e-4 * spread)
    for _ in range(80):
        sigma = float(theta[j]) - delta
        factor = an.factor(sigma, positive=True, matrix=mat)
        if factor.negatives == 0 or factor.negatives is None:
            break
        delta *= 2.0
    else:  # pragma: no cover - the spectrum is bounded by the Gershgorin disc
        raise ConvergenceError(f"{label}: no shift below its lowest level found.")
    proved = False
    for _ in range(4):
        e, v, res, solves = shift_invert_lowest(mat, kk, factor, tol, label)
        # the count just above the kk-th level: more levels below it means ARPACK missed one
        x = float(e[-1]) + 2.0 * float(res[-1]) + 1e-10 * max(1.0, abs(float(e[-1])))
        check = an.factor(x, matrix=mat)
        if check.negatives is None or check.negatives <= kk or kk >= n - 2:
            proved = check.negatives is not None and factor.negatives is not None
            break
        kk = min(check.negatives, n - 2)        # refused in shift_invert_lowest if it will not fit
        factor = an.factor(sigma, positive=True, matrix=mat)
    info = {"backend": an.backend, "sigma": sigma, "solves": solves, "proved": proved, "analysis": an}
    return e[:k], v[:, :k], res[:k], info


# every public function above checks its arguments at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
