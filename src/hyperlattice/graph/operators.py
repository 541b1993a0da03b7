r"""Operators on a lattice as ``scipy.sparse`` CSR matrices.

The hopping Hamiltonian of ``eq1`` with an optional on-site term is

.. math:: H = -t A + \mathrm{diag}(V), \qquad A_{ij} = 1 \text{ if } i \sim j,

with :math:`t = 1` unless given. Matrices are assembled in one shot from the lattice's
index arrays (no entry-by-entry construction), with sorted column indices.
"""

from __future__ import annotations

from typing import Callable, Union

import numpy as np
import scipy.sparse as sp

from .. import _validate
from .flux import _flux, edge_phases
from .lattice import Lattice

__all__ = ["adjacency", "hamiltonian", "incidence", "onsite_values"]

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
    """Adjacency matrix A (N x N, symmetric, entries 1) in CSR format with sorted indices."""
    _validate.lattice(lattice)
    dtype = _numeric_dtype(dtype)
    indptr, indices = lattice.neighbours()
    n = lattice.sites
    data = np.ones(indices.shape[0], dtype=dtype)
    a = sp.csr_matrix((data, indices, indptr), shape=(n, n))
    a.has_sorted_indices = True
    return a


def onsite_values(lattice: Lattice, onsite: OnSite) -> np.ndarray | None:
    """Evaluate an on-site term: a scalar, an array of length N, or an array-first
    callable ``onsite(z, ring) -> array`` (as in pybinding's modifiers).

    Returns None for ``onsite=None``, else one finite real value per site (float64). The
    term must be real, since :math:`H` is Hermitian (complex values with zero imaginary part
    are accepted); ``True``/``False`` are not potentials and are refused.
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

    Parameters
    ----------
    lattice : Lattice
        A site lattice or a line graph.
    t : float
        Hopping amplitude (energy unit); the paper's choice is t = 1.
    onsite : scalar, array of length N, or callable ``(z, ring) -> array``, optional
        Real on-site potential :math:`V_i` (e.g. ``-mu`` or disorder).
    flux : float
        Flux quanta f through each p-gon face of a uniform field (see
        :mod:`hyperlattice.graph.flux` for the gauge and the sign convention): the hops get
        Peierls phases, :math:`H_{ij} = -t e^{i\theta_{ij}}`, and H is complex Hermitian.
        At f = 0 (default) H is real as without the argument.

    Returns
    -------
    scipy.sparse.csr_matrix
        Sorted indices; float64 at zero flux, complex128 otherwise.
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
    """Site-edge incidence matrix B (N x E), :math:`B_{ie} = 1` if site i is an end of edge e.

    For q = 3 the line graph's adjacency is :math:`B^T B - 2I`.
    """
    _validate.lattice(lattice)
    e = lattice.edges
    n_e = e.shape[0]
    rows = e.T.ravel()
    cols = np.concatenate([np.arange(n_e), np.arange(n_e)])
    return sp.csr_matrix((np.ones(2 * n_e), (rows, cols)), shape=(lattice.sites, n_e))


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
