r"""Graph Green functions (``eq20``): :math:`G_{ij}(\omega) = [(H-\omega)^{-1}]_{ij}`.

:math:`H = -tA` (plus optional on-site terms), for real or complex :math:`\omega`. Small
lattices use one dense eigendecomposition for many frequencies; large ones a sparse LU per
frequency. The comparison with the continuum through the dictionary ``eq21`` lives in
:mod:`hyperlattice.compare.green`.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from .. import _validate
from .lattice import Lattice
from .operators import hamiltonian

__all__ = ["graph_green", "GraphResolvent"]

_DENSE_MAX = 4000          # full matrices / eigendecompositions only up to this many sites
_ON_SPECTRUM = 1e3         # |omega - E_n| below this many ulps of ||H|| counts as "on the spectrum"


def _is_scalar(x) -> bool:
    """One site index (as opposed to a list of them); decided without np.asarray on odd input."""
    return bool(np.isscalar(x) or (isinstance(x, np.ndarray) and x.ndim == 0))


def _as_omegas(omega) -> tuple[np.ndarray, bool]:
    """One frequency or a 1-d array of them, as complex128 (and whether it was a scalar)."""
    arr = _validate.complex_array("omega", omega, ndim=(0, 1))
    return np.atleast_1d(arr), arr.ndim == 0


class GraphResolvent:
    r"""The resolvent :math:`(H-\omega)^{-1}` of one lattice Hamiltonian for many :math:`\omega`.

    ``method="dense"`` diagonalises :math:`H = V\,\mathrm{diag}(E)\,V^T` once
    (:math:`O(N^3)`); afterwards a column costs :math:`O(N^2)` per :math:`\omega` via
    ``eq20`` and the distance of :math:`\omega` to the spectrum is known exactly. That pays
    for :math:`N \lesssim 4000` and more than a few :math:`\omega`. ``method="sparse"``
    factorises :math:`H-\omega` through :mod:`hyperlattice.graph.factor` once per :math:`\omega`
    (below the spectrum an :math:`LDL^T`/Cholesky without pivoting, CHOLMOD when installed, whose
    pivots prove :math:`\omega < E_0`; elsewhere SuperLU's pivoted LU; the fill-in is tiny on these
    graphs) and keeps the factorization of the last :math:`\omega`, so several sources at one
    :math:`\omega` reuse it; ``backend`` records what ran. ``"auto"`` picks sparse.

    A complex Hermitian :math:`H` (Peierls phases of a flux, :mod:`hyperlattice.graph.flux`) is
    kept complex: ``dense`` then uses :math:`V^\dagger` in ``eq20`` and ``sparse`` factorises the
    complex :math:`H - \omega` (Cholesky-type below the band, where it is Hermitian positive definite).

    Parameters
    ----------
    system : Lattice or sparse/dense matrix
        A lattice (then :math:`H` = :func:`hyperlattice.graph.operators.hamiltonian`) or :math:`H`,
        real symmetric or complex Hermitian.
    t : float
        Hopping amplitude (lattice input only).
    onsite : callable, array or None
        On-site term (lattice input only), as in :func:`~hyperlattice.graph.operators.hamiltonian`.
    method : {"auto", "dense", "sparse"}
        See above; default ``"auto"`` (sparse).

    Raises
    ------
    ValueError
        On a non-square or non-Hermitian matrix, an unknown method, ``dense`` above
        ``_DENSE_MAX`` sites, and (in the evaluation methods) for :math:`\omega` on the real
        spectrum to within rounding.

    Notes
    -----
    :math:`\omega` is in the unit of H (units of t for a lattice with t = 1); rows and columns
    are sites, 0-based ring by ring. With this sign convention :math:`G(\omega) > 0` on the
    diagonal below the band.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.green import GraphResolvent
    >>> res = GraphResolvent(hl.ring_lattice(7, 3, 2))
    >>> g = res.column(-3.5, 0)
    >>> res.method, g.shape, round(float(g[0].real), 6), round(float(g[1].real), 6)
    ('sparse', (35,), 0.412092, 0.14892)
    """

    def __init__(self, system, *, t: float = 1.0, onsite=None, method: str = "auto") -> None:
        method = _validate.choice("method", method, ("auto", "dense", "sparse"))
        t = _validate.real("the hopping t", t)
        if isinstance(system, Lattice):
            H = hamiltonian(system, t=t, onsite=onsite)
        else:
            if t != 1.0 or onsite is not None:
                raise ValueError("t and onsite apply to a lattice; a matrix H is used as given.")
            # the one door for matrices: Hermitian up to rounding, then symmetrised; float64, or
            # complex128 when an entry has a nonzero imaginary part
            H = _validate.hermitian_matrix("the Hamiltonian", system)
        if isinstance(system, Lattice) and np.iscomplexobj(H.data):
            if np.any(H.data.imag != 0):
                raise ValueError("the on-site term must be real so that H is Hermitian.")
            H = H.real
        self.H = H.astype(complex if np.iscomplexobj(H.data) else float).tocsc()
        self.n = H.shape[0]
        if method == "auto":
            method = "sparse"
        if method == "dense" and self.n > _DENSE_MAX:
            raise ValueError(f"the dense method is limited to {_DENSE_MAX} sites (this lattice has {self.n}).")
        self.method = method
        self.norm = float(abs(self.H).sum(axis=0).max()) if self.H.nnz else 0.0   # ||H||_1 >= ||H||_2
        self._eig = None
        self._lu = None
        self._lu_omega = None
        self._analysis = None      # graph/factor analysis for omega below the band (Cholesky-type)
        self._general = None       # graph/factor analysis for the pivoted LU elsewhere
        self.backend = ""          # the factorisation backend of the last sparse omega
        # a lower bound of the spectrum (Gershgorin): below it H - omega is positive definite
        d = self.H.diagonal()
        off = np.asarray(abs(self.H).sum(axis=1)).ravel() - np.abs(d)
        self._lower = float(np.min(d.real - off)) if self.n else 0.0     # a Hermitian diagonal is real

    # -- spectrum checks -------------------------------------------------------
    def _tol(self, omega: complex) -> float:
        return _ON_SPECTRUM * np.finfo(float).eps * max(1.0, self.norm + abs(omega))

    def _on_spectrum_error(self, omega: complex, detail: str) -> ValueError:
        return ValueError(
            f"omega = {omega:g} lies on (or within rounding of) the real spectrum of H ({detail}); "
            "the graph Green function does not exist there. Give omega a small imaginary part.")

    def _eigh(self) -> tuple[np.ndarray, np.ndarray]:
        if self._eig is None:
            self._eig = sla.eigh(self.H.toarray())
        return self._eig

    def _factor(self, omega: complex):
        """The factorisation of H - omega (graph/factor), cached for the last omega.

        Below the spectrum a Cholesky-type factorisation without pivoting (CHOLMOD when installed)
        is tried first: its success proves omega < E0 and it is the fastest. Elsewhere (inside the
        band, complex omega) a pivoted LU, stable for an indefinite or non-Hermitian H - omega.
        """
        from .factor import FactorizationError, analyze

        if self._lu is not None and self._lu_omega == omega:
            return self._lu
        shift = omega.real if omega.imag == 0 else omega      # real arithmetic for real omega
        what = f"H - omega of the {self.n:,}-site lattice"
        try:
            lu = None
            if omega.imag == 0 and omega.real < self._lower:
                if self._analysis is None:
                    self._analysis = analyze(self.H, what=what)
                lu = self._analysis.factor(shift, positive=True)
                if not lu.positive_definite:
                    lu = None
            if lu is None:
                if self._general is None:
                    self._general = analyze(self.H, backend="superlu", what=what)
                lu = self._general.factor(shift, pivoting=True)
        except FactorizationError as exc:     # exactly singular: omega is an eigenvalue
            raise self._on_spectrum_error(omega, "singular factorization") from exc
        if lu.kind == "LU":
            piv = np.abs(lu._lu.U.diagonal())
            if piv.size and piv.min() <= self._tol(omega):
                raise self._on_spectrum_error(omega, f"LU pivot {piv.min():.1e}")
        self._lu, self._lu_omega = lu, omega
        self.backend = lu.backend
        return lu

    # -- evaluation ------------------------------------------------------------
    def columns(self, omega, sources) -> np.ndarray:
        r"""Columns :math:`G_{\cdot j}(\omega)` for the given sources: array ``(N, len(sources))``.

        Parameters
        ----------
        omega : complex
            One frequency, off the real spectrum of H.
        sources : sequence of int
            Source sites j (0-based).

        Returns
        -------
        numpy.ndarray of complex128, shape (N, len(sources))
            Column k is :math:`G_{\cdot j_k}(\omega)`.
        """
        om, _ = _as_omegas(omega)
        if om.size != 1:
            raise ValueError("columns() takes one omega; use graph_green for several.")
        omega = complex(om[0])
        src = _validate.site_indices("sources", sources, self.n)
        if self.method == "dense":
            E, V = self._eigh()
            dist = np.min(np.abs(E - omega))
            if dist <= self._tol(omega):
                raise self._on_spectrum_error(omega, f"distance {dist:.1e} to an eigenvalue")
            out = (V / (E - omega)) @ V[src].conj().T
        else:
            lu = self._factor(omega)
            rhs = np.zeros((self.n, src.size), dtype=float if omega.imag == 0 and self.H.dtype == float else complex)
            rhs[src, np.arange(src.size)] = 1.0
            out = lu.solve(rhs)
            # ||(H - omega)^{-1}||_2 = 1/dist(omega, spectrum) for Hermitian H: a column this
            # large means the factorization was done within rounding of an eigenvalue
            big = np.max(np.linalg.norm(out, axis=0)) if src.size else 0.0
            if not np.all(np.isfinite(out)) or big * self._tol(omega) >= 1.0:
                raise self._on_spectrum_error(omega, f"column norm {big:.1e}")
        return out.astype(complex)

    def column(self, omega, source) -> np.ndarray:
        r"""One column :math:`G_{\cdot j}(\omega)` (all targets i for source j), shape ``(N,)``.

        Parameters
        ----------
        omega : complex
            One frequency, off the real spectrum of H.
        source : int
            The source site j (0-based).

        Returns
        -------
        numpy.ndarray of complex128, shape (N,)
            :math:`G_{ij}(\omega)` for every target i.
        """
        source = _validate.site_index("source", source, self.n)
        return self.columns(omega, [source])[:, 0]

    def entries(self, omega, rows, cols) -> np.ndarray:
        r"""Entries :math:`G_{r_k c_k}(\omega)` for paired index arrays (one solve per distinct column).

        Parameters
        ----------
        omega : complex
            One frequency, off the real spectrum of H.
        rows, cols : sequence of int
            Paired site indices (0-based); a length-1 array pairs with every entry of the other.

        Returns
        -------
        numpy.ndarray of complex128
            :math:`G_{r_k c_k}(\omega)`, one per pair.
        """
        rows = _validate.site_indices("rows", rows, self.n)
        cols = _validate.site_indices("cols", cols, self.n)
        if rows.size != cols.size and 1 not in (rows.size, cols.size):
            raise ValueError(f"rows and cols must pair up: got {rows.size} rows and {cols.size} cols.")
        rows, cols = np.broadcast_arrays(rows, cols)
        ucols, inv = np.unique(cols, return_inverse=True)
        block = self.columns(omega, ucols)
        return block[rows, inv]


def graph_green(lattice, omega, source=None, targets=None, *, t: float = 1.0, onsite=None,
                method: str = "auto") -> np.ndarray:
    r"""Graph Green function :math:`G_{ij}(\omega) = [(H-\omega)^{-1}]_{ij}` of :math:`H = -tA + V`.

    This is the paper's Eq. (18) (``eq20``),

    .. math:: G_{ij}(\omega) = \sum_{n=1}^N \frac{\psi_n(i)\psi_n^*(j)}{E_n-\omega},

    evaluated by a sparse factorisation of :math:`H - \omega` or, for many :math:`\omega`
    on small lattices, from one dense eigendecomposition (:class:`GraphResolvent`). Below the
    band, :math:`\omega < E_0`, it is compared with the continuum Green function through the
    dictionary :math:`\lambda = 4(\omega + q)/(q h^2)` (Eq. (19)).

    Parameters
    ----------
    lattice : Lattice or matrix
        The lattice (then :math:`H` = :func:`~hyperlattice.graph.operators.hamiltonian`) or
        :math:`H` itself (sparse or dense), real symmetric or complex Hermitian (a flux
        Hamiltonian, ``hamiltonian(lattice, flux=f)``).
    omega : complex or 1-d array_like
        Frequency :math:`\omega`, in units of t; real values must not lie on the spectrum.
        Several values reuse one eigendecomposition when ``method="dense"`` (worth it for many
        :math:`\omega` and :math:`N \lesssim 4000`).
    source : int, sequence of int, or None, optional
        Source site(s) j (0-based, ring 1 first, each ring counterclockwise). ``None``
        (default): the full matrix (small lattices only, N <= 4000).
    targets : int or sequence of int, optional
        Restrict the result to these target sites i (0-based); default: all sites.
    t : float, optional
        Hopping amplitude (lattice input only); default 1.
    onsite : scalar, array or callable, optional
        On-site term V in units of t (lattice input only); default None.
    method : {"auto", "dense", "sparse"}, optional
        See :class:`GraphResolvent`; ``"auto"`` (default) picks sparse.

    Returns
    -------
    numpy.ndarray of complex128
        Shape ``(N,)`` for one source, ``(N, k)`` for k sources, ``(N, N)`` for ``source=None``
        (first axis restricted to ``targets`` if given); a leading axis of length
        ``len(omega)`` if ``omega`` is an array. Units of 1/t.

    Raises
    ------
    ValueError
        Bad site index, NaN omega, omega on the spectrum (to within rounding), a non-Hermitian
        matrix, ``t``/``onsite`` given with a matrix, or a lattice too large for a
        full matrix or the dense method (more than 4000 sites).

    See Also
    --------
    GraphResolvent, hyperlattice.continuum.green.continuum_green,
    hyperlattice.compare.green.compare_green

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eqs. (18) and (19).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> g = hl.graph_green(lat, -3.5, source=0)
    >>> g.shape, round(float(g[0].real), 6), round(float(g[1].real), 6)
    ((35,), 0.412092, 0.14892)
    >>> G = hl.graph_green(lat, [-3.5, -4.0], source=0, targets=[0, 1])
    >>> G.shape
    (2, 2)
    """
    res = lattice if isinstance(lattice, GraphResolvent) else GraphResolvent(
        lattice, t=t, onsite=onsite, method=method)
    oms, scalar = _as_omegas(omega)
    if source is None:
        if res.n > _DENSE_MAX:
            raise ValueError(f"the full Green matrix is limited to {_DENSE_MAX} sites (this lattice has {res.n}).")
        src = np.arange(res.n)
        one = False
    elif _is_scalar(source):
        src = np.array([_validate.site_index("source", source, res.n)])
        one = True
    else:
        src = _validate.site_indices("source", source, res.n)
        one = False
    tg = None
    if targets is not None:
        one_target = _is_scalar(targets)
        tg = (np.array([_validate.site_index("targets", targets, res.n)]) if one_target
              else _validate.site_indices("targets", targets, res.n))
    out = []
    for w in oms:
        block = res.columns(complex(w), src)
        if tg is not None:
            block = block[tg]
        if one:
            block = block[:, 0]
        if tg is not None and one_target:
            block = block[0]
        out.append(block)
    return out[0] if scalar else np.stack(out)


# every public function above checks its annotated argument types at the door (issue 19)
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
