r"""Operators on a lattice as ``scipy.sparse`` CSR matrices.

The hopping Hamiltonian of ``eq1`` with an optional on-site term is

.. math:: H = -t A + \mathrm{diag}(V), \qquad A_{ij} = 1 \text{ if } i \sim j,

with :math:`t = 1` unless given. Matrices are assembled in one shot from the lattice's
index arrays (no entry-by-entry construction), with sorted column indices.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Union

import numpy as np
import scipy.sparse as sp

from .. import _validate
from .flux import _flux, edge_phases
from .lattice import Lattice

__all__ = ["adjacency", "hamiltonian", "incidence", "onsite_values", "SectorTable", "full_table"]

OnSite = Union[None, float, np.ndarray, Callable[[np.ndarray, np.ndarray], np.ndarray]]


def _numeric_dtype(dtype) -> np.dtype:
    try:
        dt = np.dtype(dtype)
    except TypeError:
        raise ValueError(f"dtype must be a numpy number type such as float64, got {dtype!r}.") from None
    if dt.kind not in "iufc":
        raise ValueError(f"dtype must be a numpy number type such as float64, got {dt}.")
    return dt


def adjacency(lattice: Lattice, dtype=np.float64) -> sp.csr_matrix:
    """Adjacency matrix A of a lattice as a sparse CSR matrix.

    :math:`A_{ij} = 1` if sites i and j are nearest neighbours, else 0; A is N x N and
    symmetric, with sorted column indices. Sites are indexed 0-based, ring 1 first, each ring
    counterclockwise.

    Parameters
    ----------
    lattice : Lattice
        A site lattice or a line graph (e.g. from :func:`ring_lattice` or :func:`line_graph`).
    dtype : numpy dtype, optional
        A numeric dtype (integer, float or complex) of the entries; default float64.

    Returns
    -------
    scipy.sparse.csr_matrix
        The N x N adjacency matrix.

    Raises
    ------
    ValueError
        If ``lattice`` is not a :class:`Lattice` or ``dtype`` is not a numeric type.

    See Also
    --------
    hamiltonian, incidence

    Examples
    --------
    >>> import hyperlattice as hl
    >>> A = hl.adjacency(hl.ring_lattice(7, 3, 2))
    >>> A.shape, A.nnz
    ((35, 35), 84)
    >>> sorted(set(A.sum(axis=1).A1.astype(int).tolist()))   # degrees: boundary 2, interior q = 3
    [2, 3]
    """
    _validate.lattice(lattice)
    dtype = _numeric_dtype(dtype)
    indptr, indices = lattice.neighbours()
    n = lattice.sites
    data = np.ones(indices.shape[0], dtype=dtype)
    a = sp.csr_matrix((data, indices, indptr), shape=(n, n))
    a.has_sorted_indices = True
    return a


def onsite_values(lattice: Lattice, onsite: OnSite) -> np.ndarray | None:
    """Evaluate an on-site term to one real value per site.

    The term is a scalar, an array of length N, or an array-first callable
    ``onsite(z, ring) -> array`` (as in pybinding's modifiers). The term must be real, since
    :math:`H` is Hermitian (complex values with zero imaginary part are accepted);
    ``True``/``False`` are not potentials and are refused.

    Parameters
    ----------
    lattice : Lattice
        The lattice whose sites the term lives on.
    onsite : None, scalar, array of length N, or callable ``(z, ring) -> array``
        The on-site potential :math:`V_i` in units of the energy (t). A callable receives the
        complex Poincaré-disk positions ``lattice.z`` and the 1-based ring numbers
        ``lattice.ring`` and returns one value per site (or a scalar).

    Returns
    -------
    numpy.ndarray of float64, shape (N,), or None
        None for ``onsite=None``, else one finite real value per site.

    Raises
    ------
    ValueError
        If the term is not numeric, complex with a nonzero imaginary part, of the wrong
        shape, or contains NaN or infinite values.

    See Also
    --------
    hamiltonian

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.operators import onsite_values
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> v = onsite_values(lat, lambda z, ring: 1.0 * (ring == 1))
    >>> v.shape, v[:8].tolist()
    ((35,), [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0])
    """
    _validate.lattice(lattice)
    if onsite is None:
        return None
    value = onsite(lattice.z, lattice.ring) if callable(onsite) else onsite
    try:
        v = np.asarray(value)
    except (TypeError, ValueError):  # ragged or mixed lists: numpy's own text is not a sentence
        raise ValueError("the on-site term must be a number or one number per site.") from None
    if v.dtype.kind not in "iufc":
        raise ValueError(f"the on-site term must be numeric, got values of type {v.dtype}.")
    if v.dtype.kind == "c":
        if np.any(v.imag != 0):
            raise ValueError("the on-site term must be real (H = -tA + diag(V) is Hermitian), got complex values.")
        v = v.real
    if v.ndim == 0:
        v = np.full(lattice.sites, v.item())
    if v.shape != (lattice.sites,):
        raise ValueError(f"the on-site term must have one value per site ({lattice.sites}), got shape {v.shape}.")
    if not np.all(np.isfinite(v)):
        raise ValueError("the on-site term contains NaN or infinite values.")
    return v.astype(np.float64)


def hamiltonian(lattice: Lattice, t: float = 1.0, onsite: OnSite = None, flux: float = 0.0) -> sp.csr_matrix:
    r"""Hopping Hamiltonian :math:`H = -tA + \mathrm{diag}(V)` as CSR, optionally with a uniform field.

    This is the tight-binding Hamiltonian of the paper's Eq. (1) with an optional on-site
    term,

    .. math:: H = -t \sum_{\langle ij \rangle} (a_i^\dagger a_j + \mathrm{h.c.}) + \sum_i V_i n_i .

    Parameters
    ----------
    lattice : Lattice
        A site lattice or a line graph.
    t : float, optional
        Hopping amplitude (energy unit); default 1, the paper's choice.
    onsite : scalar, array of length N, or callable ``(z, ring) -> array``, optional
        Real on-site potential :math:`V_i` in the energy unit (e.g. ``-mu`` or disorder); a
        callable receives the complex site positions ``z`` and the 1-based ring numbers.
        Default None: no on-site term. See :func:`onsite_values`.
    flux : float, optional
        Flux quanta f through each p-gon face of a uniform field (see
        :mod:`hyperlattice.graph.flux` for the gauge and the sign convention): the hops get
        Peierls phases, :math:`H_{ij} = -t e^{i\theta_{ij}}`, and H is complex Hermitian.
        At f = 0 (default) H is real as without the argument. At most 1e6 in magnitude.

    Returns
    -------
    scipy.sparse.csr_matrix
        The N x N Hamiltonian with sorted indices; float64 at zero flux, complex128 otherwise.

    Raises
    ------
    ValueError
        If ``t`` or ``flux`` is not a finite real number, ``|f|`` exceeds 1e6, or the on-site
        term is not real, finite, and one value per site.

    See Also
    --------
    adjacency, onsite_values, hyperlattice.graph.disorder.disordered_hamiltonian,
    hyperlattice.graph.spectrum.lowest_levels

    References
    ----------
    .. [1] I. Boettcher et al., "Quantum simulation of hyperbolic space with circuit QED: from
       graphs to geometry", Phys. Rev. A 102, 032208 (2020), Eq. (1).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> H = hl.hamiltonian(lat, t=1.0, onsite=-0.5)
    >>> H.shape, H.dtype, float(H[0, 0]), float(H[0, 1])
    ((35, 35), dtype('float64'), -0.5, -1.0)
    >>> hl.hamiltonian(lat, flux=0.1).dtype
    dtype('complex128')
    """
    t = _validate.real("the hopping t", t)
    flux = _flux(flux)
    if flux != 0.0:
        h = _peierls(lattice, t, flux)
    else:
        h = adjacency(lattice) * (-t)
    v = onsite_values(lattice, onsite)
    if v is not None:
        dtype = np.result_type(h.dtype, v.dtype)
        h = (h.astype(dtype) + sp.diags(v.astype(dtype), format="csr")).tocsr()
        h.sort_indices()
    return h


def _peierls(lattice: Lattice, t: float, flux: float) -> sp.csr_matrix:
    """-t e^{i theta_ij} on every hop j -> i, as a sorted CSR matrix."""
    e = lattice.edges.astype(np.int64)
    n = lattice.sites
    hop = -t * np.exp(1j * edge_phases(lattice, flux))
    rows = np.concatenate([e[:, 0], e[:, 1]])
    cols = np.concatenate([e[:, 1], e[:, 0]])
    h = sp.csr_matrix((np.concatenate([hop, hop.conj()]), (rows, cols)), shape=(n, n))
    h.sort_indices()
    return h


def incidence(lattice: Lattice) -> sp.csr_matrix:
    """Site-edge incidence matrix B (N x E) of a lattice.

    :math:`B_{ie} = 1` if site i is an end of edge e (edge e is ``lattice.edges[e]``), else 0.
    For q = 3 the line graph's adjacency is :math:`B^T B - 2I` (up to the order of the line
    graph's sites).

    Parameters
    ----------
    lattice : Lattice
        A site lattice (or a line graph, whose own edges are then used).

    Returns
    -------
    scipy.sparse.csr_matrix
        The N x E float64 incidence matrix; every column has two entries 1.

    Raises
    ------
    ValueError
        If ``lattice`` is not a :class:`Lattice`.

    See Also
    --------
    adjacency, line_graph

    Examples
    --------
    >>> import hyperlattice as hl
    >>> B = hl.incidence(hl.ring_lattice(7, 3, 2))
    >>> B.shape, sorted(set(B.sum(axis=0).A1.tolist()))
    ((35, 42), [2.0])
    """
    _validate.lattice(lattice)
    e = lattice.edges
    n_e = e.shape[0]
    rows = e.T.ravel()
    cols = np.concatenate([np.arange(n_e), np.arange(n_e)])
    return sp.csr_matrix((np.ones(2 * n_e), (rows, cols)), shape=(lattice.sites, n_e))


# ----------------------------------------------------------------------------
# the neighbour table
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class SectorTable:
    """A Hamiltonian block as a fixed-width neighbour table (what the kernels consume).

    Row ``i`` of the block acts as ``(H x)_i = diag[i] x_i + sum_k weights[i, k] x[cols[i, k]]``;
    unused slots point at ``i`` itself with weight 0.

    Attributes
    ----------
    m : int or None
        Signed sector of the block, None for the whole Hamiltonian.
    cols : ndarray of int32, shape (n, width)
        Column (orbit or site, 0-based) of each slot.
    weights : ndarray of float64 or complex128, shape (n, width)
        Matrix element of each slot: :math:`-t` times the Bloch (and Peierls) phase, since
        :math:`H = -tA`.
    diag : ndarray of float64, shape (n,)
        The diagonal: the on-site energies (units of t; zeros without an on-site term).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.symmetry import sector_table
    >>> block = sector_table(hl.ring_lattice(7, 3, 2), 1)
    >>> block.m, block.size, block.is_complex
    (1, 5, True)
    >>> [round(x, 6) for x in block.bounds()]
    [-3.0, 3.0]
    """

    m: int | None
    cols: np.ndarray
    weights: np.ndarray
    diag: np.ndarray

    @property
    def size(self) -> int:
        """Dimension n of the block."""
        return int(self.diag.shape[0])

    @property
    def is_complex(self) -> bool:
        """True for complex Hermitian blocks (sectors m not in {0, p/2})."""
        return bool(np.iscomplexobj(self.weights))

    def bounds(self) -> tuple[float, float]:
        """Gershgorin bounds (lo, hi) on the spectrum of the block."""
        radius = np.abs(self.weights).sum(axis=1)
        return float(np.min(self.diag - radius)), float(np.max(self.diag + radius))

    def to_csr(self) -> sp.csr_matrix:
        """The block as a CSR matrix with sorted indices and no explicit zeros."""
        n, w = self.cols.shape
        rows = np.repeat(np.arange(n), w)
        mat = sp.csr_matrix((self.weights.ravel(), (rows, self.cols.ravel())), shape=(n, n))
        mat = mat + sp.diags(self.diag.astype(mat.dtype), format="csr")
        mat.eliminate_zeros()
        mat.sort_indices()
        return mat.tocsr()


def _fixed_width(n: int, rows: np.ndarray, cols: np.ndarray, vals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pack (row, col, value) entries into n x width arrays, padding with (row, 0)."""
    order = np.argsort(rows, kind="stable")
    rows, cols, vals = rows[order], cols[order], vals[order]
    counts = np.bincount(rows, minlength=n)
    width = max(1, int(counts.max()) if counts.size else 1)
    start = np.zeros(n, dtype=np.int64)
    np.cumsum(counts[:-1], out=start[1:])
    slot = np.arange(rows.shape[0]) - start[rows]
    table_cols = np.repeat(np.arange(n, dtype=np.int32)[:, None], width, axis=1)
    table_vals = np.zeros((n, width), dtype=vals.dtype)
    table_cols[rows, slot] = cols
    table_vals[rows, slot] = vals
    return table_cols, table_vals


def _real_onsite(lattice: Lattice, onsite: OnSite) -> np.ndarray | None:
    """The on-site term as float64 values (None if absent); a complex term must be real."""
    v = onsite_values(lattice, onsite)
    if v is None:
        return None
    if np.iscomplexobj(v):
        if np.any(v.imag != 0):
            raise ValueError("the on-site term must be real so that H is Hermitian.")
        v = v.real
    return v.astype(np.float64)


def full_table(lattice: Lattice, t: float = 1.0, onsite: OnSite = None, flux: float = 0.0) -> SectorTable:
    """The whole Hamiltonian :math:`H = -tA + V` as a fixed-width table (``m`` is None).

    With a nonzero ``flux`` the hops carry the Peierls phases of :mod:`hyperlattice.graph.flux`.

    Parameters
    ----------
    lattice : Lattice
        Site lattice or line graph.
    t : float, optional
        Hopping amplitude, the energy unit; default 1.
    onsite : scalar, array or callable, optional
        On-site term V in units of t; default None.
    flux : float, optional
        Flux quanta f per p-gon face; default 0.

    Returns
    -------
    SectorTable
        ``m`` None, ``cols`` and ``weights`` (N, width) with unused slots pointing at the row
        itself with weight 0, ``diag`` (N,); complex weights for nonzero flux.

    Raises
    ------
    ValueError
        For an invalid lattice, t, flux or on-site term.

    See Also
    --------
    hyperlattice.graph.symmetry.sector_table, hyperlattice.graph.operators.hamiltonian

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.operators import full_table
    >>> table = full_table(hl.ring_lattice(7, 3, 2))
    >>> table.m, table.size, table.cols.shape, table.is_complex
    (None, 35, (35, 3), False)
    >>> full_table(hl.ring_lattice(7, 3, 2), flux=0.1).is_complex
    True
    """
    _validate.lattice(lattice)
    t = _validate.real("the hopping t", t)
    flux = _flux(flux)
    e = lattice.edges.astype(np.int64)
    n = lattice.sites
    rows = np.concatenate([e[:, 0], e[:, 1]])
    cols = np.concatenate([e[:, 1], e[:, 0]])
    if flux != 0.0:
        hop = -t * np.exp(1j * edge_phases(lattice, flux))
        vals = np.concatenate([hop, hop.conj()])
    else:
        vals = np.full(rows.shape[0], -t)
    tc, tv = _fixed_width(n, rows, cols, vals)
    v = _real_onsite(lattice, onsite)
    diag = np.zeros(n) if v is None else v
    return SectorTable(m=None, cols=tc, weights=tv, diag=diag)



# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
