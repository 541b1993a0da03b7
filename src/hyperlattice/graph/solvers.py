r"""Eigensolver internals shared by the spectrum front ends: neighbour tables and kernels.

A Hamiltonian block (the whole :math:`H = -tA + V`, or one angular-momentum block
:math:`H_m` built by :mod:`hyperlattice.graph.symmetry`) is handed to the solvers as a
:class:`~hyperlattice.graph.operators.SectorTable`: a fixed-width neighbour table, row ``i`` acting as

.. math:: (H x)_i = d_i x_i + \sum_k w_{ik}\, x_{c_{ik}} .

On these graphs every row has at most a few entries (q for the lattice, 2(q - 1) for the line
graph, a handful more inside a sector block), so a dense ``(rows, width)`` table is smaller
and faster to stream than CSR and feeds one fused numba kernel.

Solvers:

:func:`_chebyshev_lowest`
    *Chebyshev-accelerated Lanczos.* ARPACK's own work per step (re-orthogonalisation
    against its whole basis) costs far more than one sparse matrix-vector product on these
    graphs, and the plain ``eigsh(A, which="LA")`` spends most of its time there. ARPACK is
    therefore run on :math:`T_d((H - c)/w)`, a degree-d Chebyshev polynomial that maps the bulk
    of the spectrum :math:`[c, E_{\max}]` into :math:`[-1, 1]` and stretches the wanted low
    levels below c (monotonically, d even). One ARPACK step then costs d products, which run
    in the fused kernel. The cut c comes from a short Lanczos run: its Ritz values bound the
    true levels from above (Cauchy interlacing), so the wanted levels lie below c; a result
    with a level above c is rejected and recomputed with a larger c.
:func:`_dense_lowest`
    LAPACK ``eigh`` of the block as a dense matrix (small blocks).

:func:`_residuals` gives :math:`\|H\psi - E\psi\|` with the true block and
:func:`_check_residuals` turns a residual above the tolerance into a
:class:`~hyperlattice.errors.ConvergenceError` (a
:class:`~hyperlattice.errors.ConvergenceWarning` within a factor 100).
:func:`_single_threaded_blas` runs ARPACK's many small BLAS calls on one thread.

The numba kernel is compiled on first use (and cached on disk), never at import.
"""

from __future__ import annotations

import contextlib
import functools
import warnings
from typing import Callable, Iterator

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import ConvergenceError, ConvergenceWarning
from .operators import SectorTable, full_table  # noqa: F401  (old import path of both)

# the neighbour tables (SectorTable, full_table) live in graph/operators.py, below the symmetry
# module and this one; they are imported above for the solvers and for old import paths
__all__: list[str] = []

ProgressFn = Callable[[str], None]


# ----------------------------------------------------------------------------
# kernels (numba, compiled on first use, never at import)
# ----------------------------------------------------------------------------

_KERNEL = None


def _kernel() -> Callable:
    """Fused Chebyshev step ``out = alpha*((H - cen) y) - beta*yprev`` on a neighbour table.

    Serial on purpose: on a shared 2-core machine a parallel loop waits for descheduled
    threads (measured 12 ms instead of 0.45 ms per product at 100k rows under load).
    """
    global _KERNEL
    if _KERNEL is None:
        import numba

        @numba.njit(cache=True)
        def step(cols, weights, diag, cen, alpha, beta, y, yprev, out):  # pragma: no cover - jitted
            n, width = cols.shape
            for i in range(n):
                acc = (diag[i] - cen) * y[i]
                for k in range(width):
                    acc += weights[i, k] * y[cols[i, k]]
                out[i] = alpha * acc - beta * yprev[i]

        _KERNEL = step
    return _KERNEL


@functools.lru_cache(maxsize=1)
def blas_thread_controls() -> tuple:
    """``(setter, getter)`` of the thread count of every BLAS library loaded in this process.

    Found by threadpoolctl (OpenBLAS, MKL, BLIS, FlexiBLAS, Apple Accelerate: whatever numpy
    and scipy loaded), once: the scan of the loaded libraries costs a few ms, and numpy's and
    scipy's BLAS are loaded by the time this module is imported.
    """
    from threadpoolctl import ThreadpoolController

    out = []
    for lib in ThreadpoolController().lib_controllers:
        if lib.user_api == "blas":
            out.append((lib.set_num_threads, lib.get_num_threads))
    return tuple(out)


@contextlib.contextmanager
def single_threaded_blas() -> Iterator[None]:
    """Run ARPACK's many small BLAS calls on one thread, restoring the setting afterwards.

    On vectors of 1e5-1e6 entries a multi-threaded OpenBLAS spends more on waking its
    threads than on the arithmetic, and on a loaded 2-core machine each call can wait for a
    descheduled thread: measured 15x slower ARPACK runs (5.1 s vs 0.34 s for sector m = 0 at
    rings = 12). The libraries are those of :func:`blas_thread_controls`.
    """
    restore = []
    for setter, getter in blas_thread_controls():
        restore.append((setter, int(getter())))
        setter(1)
    try:
        yield
    finally:
        for setter, old in restore:
            setter(old)


#: the name used inside the package before the guard became public
_single_threaded_blas = single_threaded_blas


def _dtype(table: SectorTable, x: np.ndarray) -> np.dtype:
    return np.result_type(table.weights.dtype, x.dtype, np.float64)


def _matvec(table: SectorTable, x: np.ndarray) -> np.ndarray:
    """H x for a table and a vector or an (n, k) block."""
    if x.ndim == 2:
        return np.column_stack([_matvec(table, x[:, c]) for c in range(x.shape[1])]) if x.shape[1] else x.copy()
    x = np.ascontiguousarray(x, dtype=_dtype(table, x))
    out = np.empty_like(x)
    _kernel()(table.cols, table.weights, table.diag, 0.0, 1.0, 0.0, x, x, out)
    return out


# ----------------------------------------------------------------------------
# solvers
# ----------------------------------------------------------------------------

def _residuals(table: SectorTable, vecs: np.ndarray, energies: np.ndarray) -> np.ndarray:
    r""":math:`\|H v_k - E_k v_k\|` for each column of ``vecs`` (normalised), with the true block."""
    hv = _matvec(table, vecs)
    return np.linalg.norm(hv - vecs * energies[None, :], axis=0)


def _check_residuals(res: np.ndarray, tol: float, what: str) -> None:
    """Raise above 100 tol (or on a non-finite residual), warn between tol and 100 tol."""
    worst = float(np.max(res)) if res.size else 0.0
    if not np.isfinite(worst) or worst > 100 * tol:
        raise ConvergenceError(f"{what}: residual {worst:.2e} exceeds the tolerance {tol:.1e}.")
    if worst > tol:
        # stacklevel 4: the user's call of lowest_levels (via its _sector/_full helper)
        warnings.warn(f"{what}: residual {worst:.2e} slightly exceeds the tolerance {tol:.1e}.",
                      ConvergenceWarning, stacklevel=4)


def _plain_lanczos(matvec, v: np.ndarray, steps: int) -> np.ndarray:
    """Ritz values (ascending) of ``steps`` plain Lanczos steps from the start vector ``v``.

    Run without re-orthogonalisation: in so few steps none of the clustered low levels
    converges, which is when orthogonality would be lost. The Ritz values are upper bounds of
    the lowest levels.
    """
    v = v / np.linalg.norm(v)
    v_old = np.zeros_like(v)
    alphas, betas = [], []
    beta = 0.0
    for _ in range(min(steps, v.size)):
        w = matvec(v) - beta * v_old
        a = float(np.vdot(v, w).real)
        w -= a * v
        alphas.append(a)
        beta = float(np.linalg.norm(w))
        if beta < 1e-12:
            break
        betas.append(beta)
        v_old, v = v, w / beta
    k = len(alphas)
    return sla.eigh_tridiagonal(np.array(alphas), np.array(betas[: k - 1]), eigvals_only=True)


def _ritz_values(table: SectorTable, steps: int, rng: np.random.Generator) -> np.ndarray:
    """Ritz values of a short plain Lanczos run on a sector table: upper bounds of the lowest levels."""
    dt = np.complex128 if table.is_complex else np.float64
    kern = _kernel()

    def matvec(x):
        out = np.empty_like(x)
        kern(table.cols, table.weights, table.diag, 0.0, 1.0, 0.0, x, x, out)
        return out

    return _plain_lanczos(matvec, rng.standard_normal(table.size).astype(dt), steps)


def _chebyshev_lowest(table: SectorTable, k: int, tol: float, progress: ProgressFn | None, label: str,
                      degree: int = 32, partial: bool = False) -> tuple[np.ndarray, np.ndarray, dict]:
    """k lowest eigenpairs of a table by ARPACK on a Chebyshev polynomial (see module doc).

    With ``partial`` the pairs whose residual exceeds ``tol`` are dropped instead of returned
    (the caller completes degenerate pairs a single Krylov start vector cannot see).
    Returns ``(energies, vectors, info)`` with the energies ascending and ``info`` counting
    matrix-vector products and restarts.
    """
    n = table.size
    rng = np.random.default_rng(12345)
    lo, hi = table.bounds()
    theta = _ritz_values(table, 60, rng)
    # theta[k] >= lambda_{k+1} >= lambda_k (interlacing): every wanted level lies below c.
    # Halfway to the next Ritz value keeps c clear of a level that sits exactly at theta[k]
    # (a converged Ritz value), where the polynomial would not lift it above 1.
    if theta.shape[0] > k + 1:
        c = 0.5 * (float(theta[k]) + float(theta[k + 1]))
    else:
        c = float(theta[min(k, theta.shape[0] - 1)]) + 1e-3 * (hi - lo)
    c = min(c, hi - 1e-3 * (hi - lo))
    dt = np.complex128 if table.is_complex else np.float64
    kern = _kernel()
    info = {"products": 0, "restarts": 0}
    arpack_tol = 1e-14
    for attempt in range(6):
        cen = 0.5 * (c + hi)
        half = 0.5 * (hi - c)
        y0 = np.empty(n, dtype=dt)
        y1 = np.empty(n, dtype=dt)
        y2 = np.empty(n, dtype=dt)
        steps = [0]

        def cheb(x, cen=cen, half=half) -> np.ndarray:
            x = np.ascontiguousarray(np.ravel(x), dtype=dt)
            kern(table.cols, table.weights, table.diag, cen, 1.0 / half, 0.0, x, x, y1)
            a, b = x, y1
            for _ in range(degree - 1):
                out = y2 if a is not y2 else y0
                if out is b:
                    out = y0 if b is not y0 else y2
                kern(table.cols, table.weights, table.diag, cen, 2.0 / half, 1.0, b, a, out)
                a, b = b, out
            steps[0] += 1
            if progress is not None and steps[0] % 5 == 0:
                progress(f"{label}: {steps[0] * degree} products")
            return b.copy()

        op = spla.LinearOperator((n, n), matvec=cheb, dtype=dt)
        ncv = min(n, max(2 * k + 1, k + 16))
        v0 = rng.standard_normal(n).astype(dt)
        try:
            _, vecs = spla.eigsh(op, k=k, which="LA", ncv=ncv, tol=arpack_tol, v0=v0, maxiter=5000)
        except spla.ArpackNoConvergence as exc:  # pragma: no cover - depends on the matrix
            raise ConvergenceError(f"{label}: ARPACK did not converge ({exc}).") from exc
        info["products"] += steps[0] * degree
        # Rayleigh quotients with the true block (the polynomial's eigenvalues are only a proxy)
        vecs /= np.linalg.norm(vecs, axis=0)[None, :]
        hv = _matvec(table, vecs)
        energies = np.real(np.einsum("ij,ij->j", vecs.conj(), hv))
        order = np.argsort(energies)
        energies, vecs = energies[order], vecs[:, order]
        if np.all(energies < c):
            res = np.linalg.norm(_matvec(table, vecs) - vecs * energies[None, :], axis=0)
            if np.all(res <= tol) or attempt >= 2:
                if partial:
                    # a Krylov run sees one state of an exactly degenerate pair: the slots it
                    # cannot fill hold unconverged mixtures; the caller completes the pairs
                    good = res <= tol
                    return energies[good], vecs[:, good], info
                return energies, vecs, info
            # accurate enough in the polynomial's terms but not in H's: tighten and go again
            arpack_tol = 0.0
            degree = min(2 * degree, 48)
        else:
            # fewer than k levels below c: the polynomial folded some of them; widen
            c = c + 0.5 * (hi - c)
        info["restarts"] += 1
    raise ConvergenceError(f"{label}: could not bracket the {k} lowest levels.")  # pragma: no cover


def _dense_lowest(table: SectorTable, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The k lowest eigenpairs of a (small) table by LAPACK ``eigh`` on its dense matrix."""
    mat = table.to_csr().toarray()
    k = min(k, mat.shape[0])
    w, v = sla.eigh(mat, subset_by_index=[0, k - 1])
    return w, v


# ----------------------------------------------------------------------------
# symmetric factorisations, shift-invert and Sylvester inertia: graph/factor.py (the one layer)
# ----------------------------------------------------------------------------

def _dense_block_lowest(mat: sp.spmatrix, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The k lowest eigenvalues of a small sparse block by LAPACK ``eigh`` of all of it, and their residuals."""
    w, v = sla.eigh(mat.toarray())
    e, v = w[:k], v[:, :k]
    return e, np.linalg.norm(mat @ v - v * e[None, :], axis=0)


def _lanczos_ritz(mat: sp.spmatrix, steps: int) -> np.ndarray:
    """Ritz values of a short plain Lanczos run on a real symmetric matrix (upper bounds, ascending)."""
    return _plain_lanczos(lambda x: mat @ x, np.random.default_rng(12345).standard_normal(mat.shape[0]), steps)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
