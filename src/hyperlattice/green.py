r"""Graph Green functions, the lattice/continuum dictionary ``eq21`` and the distance collapse.

Graph side (``eq20``): :math:`G_{ij}(\omega) = [(H-\omega)^{-1}]_{ij}` with :math:`H = -tA`
(plus optional on-site terms), for real or complex :math:`\omega`.

Dictionary (``eq21``, generalised to {p,q})
-------------------------------------------
Following ``path5``/``path6``: write :math:`G_{ij}` as the Gaussian integral
:math:`\langle\theta_i\theta_j\rangle` with weight
:math:`\exp[-\frac12\sum_{ij}\theta_i(H-\omega)_{ij}\theta_j]`. For a {p,q} lattice the
small-h expansion of the adjacency operator is :math:`A \approx q + \frac q4 h^2\Delta_g`
(``adj26`` with 3 replaced by q: the q neighbours sit at :math:`h e^{\mathrm i(\chi+2\pi k/q)}`,
whose first and second moments vanish), so
:math:`H - \omega \approx -\frac q4 h^2\Delta_g - (\omega + q) = \frac q4 h^2(-\Delta_g - \lambda)`
with :math:`\lambda = 4(\omega+q)/(qh^2)`. With :math:`\sum_i \approx \frac1{\mathcal A}\int dV`
(``eq11``, :math:`\mathcal A` the area per site, :func:`hyperlattice.geometry.site_area`) the
exponent becomes :math:`-\frac12 C'\int dV\,\theta(-\Delta_g-\lambda)\theta` with
:math:`C' = qh^2/(4\mathcal A)`, and by ``path2`` the two-point function is :math:`G/C'`:

.. math:: G_{ij}(\omega) \approx \frac{4\mathcal A}{q h^2}\,
          G\Bigl(z_i, z_j, \lambda = \frac{4(\omega+q)}{qh^2}, L\Bigr),

with :math:`L` from ``eq12``. For {7,3}, :math:`\mathcal A = \pi/28` gives :math:`\pi/(21h^2)`.

Correlation analysis (``Fig3``, right panels)
----------------------------------------------
For a source site :math:`i`: pairs :math:`(d_{ij}, F_j)`, binned means and standard deviations
versus distance, and a collapse number

.. math:: S = \Bigl[\frac{\sum_b n_b\sigma_b^2}{\sum_b n_b|\mu_b|^2}\Bigr]^{1/2},

the rms spread within distance bins relative to the rms bin mean (0 for a function of
distance alone). Conformal (automorphism) invariance emerges as :math:`S\to 0` for large
:math:`\ell`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .geometry import distance, lattice_h, site_area
from .lattice import Lattice, check_lattice
from .operators import hamiltonian

__all__ = [
    "graph_green",
    "GraphResolvent",
    "dictionary_parameters",
    "continuum_column",
    "compare_green",
    "GreenComparison",
    "correlation_pairs",
    "bin_by_distance",
    "BinnedCorrelation",
    "collapse_measure",
    "relative_l2",
]

_DENSE_MAX = 4000          # full matrices / eigendecompositions only up to this many sites
_ON_SPECTRUM = 1e3         # |omega - E_n| below this many ulps of ||H|| counts as "on the spectrum"


def _as_omegas(omega) -> tuple[np.ndarray, bool]:
    arr = np.asarray(omega)
    if arr.dtype.kind not in "biufc":
        raise ValueError(f"omega must be a real or complex number, got {omega!r}.")
    arr = arr.astype(complex)
    if not np.all(np.isfinite(arr)):
        raise ValueError("omega must be finite (no NaN or inf).")
    if arr.ndim > 1:
        raise ValueError("omega must be a number or a one-dimensional array of numbers.")
    return np.atleast_1d(arr), arr.ndim == 0


def _check_site(name: str, site, n: int) -> int:
    if isinstance(site, (bool, np.bool_)) or not isinstance(site, (int, np.integer)):
        raise ValueError(f"{name} must be an integer site index, got {site!r}.")
    if not 0 <= int(site) < n:
        raise ValueError(f"{name} = {site} is not a site of this lattice (valid: 0..{n - 1}).")
    return int(site)


def _check_sites(name: str, sites, n: int) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(sites))
    if arr.dtype.kind not in "iu":
        raise ValueError(f"{name} must be integer site indices.")
    if arr.size and (arr.min() < 0 or arr.max() >= n):
        raise ValueError(f"{name} contains indices outside 0..{n - 1}.")
    return arr.astype(np.int64)


class GraphResolvent:
    r"""The resolvent :math:`(H-\omega)^{-1}` of one lattice Hamiltonian for many :math:`\omega`.

    ``method="dense"`` diagonalises :math:`H = V\,\mathrm{diag}(E)\,V^T` once
    (:math:`O(N^3)`); afterwards a column costs :math:`O(N^2)` per :math:`\omega` via
    ``eq20`` and the distance of :math:`\omega` to the spectrum is known exactly. That pays
    for :math:`N \lesssim 4000` and more than a few :math:`\omega`. ``method="sparse"``
    factorises :math:`H-\omega` (SuperLU, COLAMD; the fill-in is tiny on these graphs, see
    NUMERICS-NOTES) once per :math:`\omega` (the factorization of the last :math:`\omega` is
    kept, so several sources at one :math:`\omega` reuse it). ``"auto"`` picks sparse.

    Parameters
    ----------
    system : Lattice or sparse/dense matrix
        A lattice (then :math:`H` = :func:`hyperlattice.operators.hamiltonian`) or :math:`H`.
    t : float
        Hopping amplitude (lattice input only).
    onsite : callable, array or None
        On-site term (lattice input only), as in :func:`~hyperlattice.operators.hamiltonian`.
    method : {"auto", "dense", "sparse"}

    Raises
    ------
    ValueError
        On a non-square or non-symmetric matrix, an unknown method, ``dense`` above
        ``_DENSE_MAX`` sites, and (in the evaluation methods) for :math:`\omega` on the real
        spectrum to within rounding.
    """

    def __init__(self, system, *, t: float = 1.0, onsite=None, method: str = "auto"):
        if isinstance(system, Lattice):
            H = hamiltonian(system, t=t, onsite=onsite)
        else:
            H = sp.csr_matrix(system) if not sp.issparse(system) else system.tocsr()
            if H.shape[0] != H.shape[1]:
                raise ValueError("the Hamiltonian must be a square matrix.")
            if abs(H - H.T).max() > 1e-12 * max(1.0, abs(H).max()) if H.nnz else False:
                raise ValueError("the Hamiltonian must be real symmetric (Hermitian hopping).")
        if method not in ("auto", "dense", "sparse"):
            raise ValueError(f"method must be 'auto', 'dense' or 'sparse', got {method!r}.")
        self.H = H.astype(float).tocsc()
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

    # -- spectrum checks -------------------------------------------------------
    def _tol(self, omega: complex) -> float:
        return _ON_SPECTRUM * np.finfo(float).eps * max(1.0, self.norm + abs(omega))

    def _on_spectrum_error(self, omega: complex, detail: str) -> ValueError:
        return ValueError(
            f"omega = {omega:g} lies on (or within rounding of) the real spectrum of H ({detail}); "
            "the graph Green function does not exist there. Give omega a small imaginary part.")

    def _eigh(self):
        if self._eig is None:
            self._eig = sla.eigh(self.H.toarray())
        return self._eig

    def _factor(self, omega: complex):
        if self._lu is not None and self._lu_omega == omega:
            return self._lu
        shift = omega.real if omega.imag == 0 else omega      # real arithmetic for real omega
        M = (self.H - shift * sp.identity(self.n, format="csc")).tocsc()
        try:
            lu = spla.splu(M, permc_spec="COLAMD")
        except RuntimeError as exc:     # SuperLU: "Factor is exactly singular"
            raise self._on_spectrum_error(omega, "singular factorization") from exc
        piv = np.abs(lu.U.diagonal())
        if piv.size and piv.min() <= self._tol(omega):
            raise self._on_spectrum_error(omega, f"LU pivot {piv.min():.1e}")
        self._lu, self._lu_omega = lu, omega
        return lu

    # -- evaluation ------------------------------------------------------------
    def columns(self, omega, sources) -> np.ndarray:
        r"""Columns :math:`G_{\cdot j}(\omega)` for the given sources: array ``(N, len(sources))``."""
        om, _ = _as_omegas(omega)
        if om.size != 1:
            raise ValueError("columns() takes one omega; use graph_green for several.")
        omega = complex(om[0])
        src = _check_sites("sources", sources, self.n)
        if self.method == "dense":
            E, V = self._eigh()
            dist = np.min(np.abs(E - omega))
            if dist <= self._tol(omega):
                raise self._on_spectrum_error(omega, f"distance {dist:.1e} to an eigenvalue")
            out = (V / (E - omega)) @ V[src].T
        else:
            lu = self._factor(omega)
            rhs = np.zeros((self.n, src.size), dtype=float if omega.imag == 0 else complex)
            rhs[src, np.arange(src.size)] = 1.0
            out = lu.solve(rhs)
            # ||(H - omega)^{-1}||_2 = 1/dist(omega, spectrum) for symmetric H: a column this
            # large means the factorization was done within rounding of an eigenvalue
            big = np.max(np.linalg.norm(out, axis=0)) if src.size else 0.0
            if not np.all(np.isfinite(out)) or big * self._tol(omega) >= 1.0:
                raise self._on_spectrum_error(omega, f"column norm {big:.1e}")
        return out.astype(complex)

    def column(self, omega, source) -> np.ndarray:
        r"""One column :math:`G_{\cdot j}(\omega)` (all targets i for source j), shape ``(N,)``."""
        source = _check_site("source", source, self.n)
        return self.columns(omega, [source])[:, 0]

    def entries(self, omega, rows, cols) -> np.ndarray:
        r"""Entries :math:`G_{r_k c_k}(\omega)` for paired index arrays (one solve per distinct column)."""
        rows = _check_sites("rows", rows, self.n)
        cols = _check_sites("cols", cols, self.n)
        rows, cols = np.broadcast_arrays(rows, cols)
        ucols, inv = np.unique(cols, return_inverse=True)
        block = self.columns(omega, ucols)
        return block[rows, inv]

    def matrix(self, omega) -> np.ndarray:
        r"""The full matrix :math:`G(\omega)` (only for :math:`N \le` ``_DENSE_MAX``)."""
        if self.n > _DENSE_MAX:
            raise ValueError(f"the full Green matrix is limited to {_DENSE_MAX} sites (this lattice has {self.n}).")
        return self.columns(omega, np.arange(self.n))


def graph_green(lattice, omega, source=None, targets=None, *, t: float = 1.0, onsite=None,
                method: str = "auto") -> np.ndarray:
    r"""Graph Green function ``eq20``, :math:`G_{ij}(\omega) = [(H-\omega)^{-1}]_{ij}`, :math:`H=-tA`.

    Parameters
    ----------
    lattice : Lattice or matrix
        The lattice (or :math:`H` itself).
    omega : complex or 1-d array_like
        Frequency; real values must not lie on the spectrum. Several values reuse one
        eigendecomposition when ``method="dense"`` (worth it for many :math:`\omega` and
        :math:`N \lesssim 4000`).
    source : int, sequence of int, or None
        Source site(s) j (0-based). ``None``: the full matrix (small lattices only).
    targets : int or sequence of int, optional
        Restrict the result to these target sites i.
    t, onsite, method
        See :class:`GraphResolvent`.

    Returns
    -------
    ndarray of complex
        Shape ``(N,)`` for one source, ``(N, k)`` for k sources, ``(N, N)`` for ``source=None``
        (first axis restricted to ``targets`` if given); a leading axis of length
        ``len(omega)`` if ``omega`` is an array.

    Raises
    ------
    ValueError
        Bad site index, NaN omega, omega on the spectrum, too large for a full matrix.
    """
    res = lattice if isinstance(lattice, GraphResolvent) else GraphResolvent(
        lattice, t=t, onsite=onsite, method=method)
    oms, scalar = _as_omegas(omega)
    if source is None:
        if res.n > _DENSE_MAX:
            raise ValueError(f"the full Green matrix is limited to {_DENSE_MAX} sites (this lattice has {res.n}).")
        src = np.arange(res.n)
        one = False
    elif np.ndim(source) == 0:
        src = np.array([_check_site("source", source, res.n)])
        one = True
    else:
        src = _check_sites("source", source, res.n)
        one = False
    tg = None
    if targets is not None:
        tg = _check_sites("targets", targets, res.n)
        if np.ndim(targets) == 0:
            tg = tg[:1]
    out = []
    for w in oms:
        block = res.columns(complex(w), src)
        if tg is not None:
            block = block[tg]
        if one:
            block = block[:, 0]
        if targets is not None and np.ndim(targets) == 0:
            block = block[0]
        out.append(block)
    return out[0] if scalar else np.stack(out)


# ----------------------------------------------------------------------------
# the dictionary eq21
# ----------------------------------------------------------------------------

def dictionary_parameters(omega, p=7, q=3) -> tuple[complex, float]:
    r"""``(lambda, prefactor)`` of the generalised ``eq21``: :math:`\lambda = 4(\omega+q)/(qh^2)`,
    prefactor :math:`4\mathcal A/(qh^2)` (:math:`\pi/(21h^2) = 0.5` ... for {7,3}, ``path6``)."""
    om, scalar = _as_omegas(omega)
    if not scalar:
        raise ValueError("dictionary_parameters takes one omega.")
    h = lattice_h(p, q)
    lam = 4.0 * (complex(om[0]) + q) / (q * h * h)
    return lam, 4.0 * site_area(p, q) / (q * h * h)


def continuum_column(lattice: Lattice, omega, source: int, *, tol: float = 1e-12):
    r"""Right-hand side of ``eq21`` at every site i for source j: :math:`\frac{4\mathcal A}{qh^2}G(z_i,z_j,\lambda,L)`.

    Uses :math:`L` of ``eq12`` (``lattice.radius``); sites beyond :math:`L` get the analytic
    continuation of ``green33`` (``extend=True``). The source entry is ``inf`` (coincident
    points). Returns ``(values, info)`` with :class:`hyperlattice.continuum.green.GreenInfo`.
    """
    from .continuum.green import continuum_green

    check_lattice(lattice, kind="sites")
    source = _check_site("source", source, lattice.sites)
    lam, pref = dictionary_parameters(omega, lattice.p, lattice.q)
    vals, info = continuum_green(lattice.z, lattice.z[source], lam, lattice.radius, tol=tol,
                                 extend=True, return_info=True)
    vals = np.asarray(vals, complex)
    out = np.empty_like(vals)
    out.real = pref * vals.real            # part-wise: keeps inf + 0j at the source
    out.imag = pref * vals.imag
    return out, info


def relative_l2(graph: np.ndarray, continuum: np.ndarray, exclude: int | None = None) -> float:
    r""":math:`\|G^{\rm graph} - G^{\rm cont}\|_2 / \|G^{\rm graph}\|_2` over all sites but ``exclude``."""
    g = np.asarray(graph, complex)
    c = np.asarray(continuum, complex)
    keep = np.ones(g.shape, bool)
    if exclude is not None:
        keep[exclude] = False
    return float(np.linalg.norm(g[keep] - c[keep]) / np.linalg.norm(g[keep]))


@dataclass(frozen=True)
class GreenComparison:
    """Graph column and continuum prediction (``eq21``) for one source and one omega."""

    p: int
    q: int
    rings: int
    source: int
    omega: complex
    lam: complex
    radius: float
    prefactor: float
    graph: np.ndarray = field(repr=False)
    continuum: np.ndarray = field(repr=False)
    distance: np.ndarray = field(repr=False)
    rel_l2: float
    terms: int
    tail_estimate: float

    def summary(self) -> dict:
        """The JSON summary of the ``green`` command."""
        return {"p": self.p, "q": self.q, "rings": self.rings, "site": self.source,
                "omega": self.omega, "lambda": self.lam, "radius": self.radius,
                "rel_l2": self.rel_l2}


def compare_green(lattice: Lattice, omega, source: int, *, tol: float = 1e-12,
                  resolvent: GraphResolvent | None = None) -> GreenComparison:
    r"""Graph column :math:`G_{\cdot j}(\omega)` against the generalised ``eq21``.

    ``rel_l2`` is the relative L2 distance over all sites except the source.
    """
    check_lattice(lattice, kind="sites")
    source = _check_site("source", source, lattice.sites)
    om, scalar = _as_omegas(omega)
    if not scalar:
        raise ValueError("compare_green takes one omega.")
    omega = complex(om[0])
    res = resolvent if resolvent is not None else GraphResolvent(lattice)
    g = res.column(omega, source)
    c, info = continuum_column(lattice, omega, source, tol=tol)
    lam, pref = dictionary_parameters(omega, lattice.p, lattice.q)
    d = distance(lattice.z, lattice.z[source])
    return GreenComparison(p=lattice.p, q=lattice.q, rings=lattice.rings, source=source, omega=omega,
                           lam=lam, radius=lattice.radius, prefactor=pref, graph=g, continuum=c,
                           distance=d, rel_l2=relative_l2(g, c, exclude=source), terms=info.terms,
                           tail_estimate=info.tail_estimate)


# ----------------------------------------------------------------------------
# correlation analysis
# ----------------------------------------------------------------------------

def correlation_pairs(lattice: Lattice, source: int, values) -> tuple[np.ndarray, np.ndarray]:
    r"""The list of pairs :math:`(d_{ij}, F_j)` for source i, all j except i, sorted by distance."""
    source = _check_site("source", source, lattice.sites)
    v = np.asarray(values)
    if v.shape != (lattice.sites,):
        raise ValueError(f"values must have one entry per site ({lattice.sites}), got shape {v.shape}.")
    d = distance(lattice.z, lattice.z[source])
    keep = np.arange(lattice.sites) != source
    order = np.argsort(d[keep], kind="stable")
    return d[keep][order], v[keep][order]


@dataclass(frozen=True)
class BinnedCorrelation:
    """Means and standard deviations of F in distance bins (empty bins dropped)."""

    edges: np.ndarray
    centre: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    count: np.ndarray


def bin_by_distance(dist, values, width: float | None = None, edges=None) -> BinnedCorrelation:
    r"""Bin :math:`F` by hyperbolic distance: mean and (population) standard deviation per bin.

    Default bins have width :math:`d_0/2` of {7,3} (0.141), fine enough to resolve the
    distance dependence and coarse enough to hold several sites each. Complex values: the
    std is :math:`\sqrt{\langle|F-\mu|^2\rangle}`.
    """
    d = np.asarray(dist, float)
    v = np.asarray(values)
    if d.shape != v.shape or d.ndim != 1:
        raise ValueError("distances and values must be one-dimensional arrays of equal length.")
    if d.size == 0 or not np.all(np.isfinite(d)) or not np.all(np.isfinite(v)):
        raise ValueError("distances and values must be finite and non-empty.")
    if edges is None:
        if width is None:
            from .geometry import d0
            width = 0.5 * d0(7, 3)
        if not (width > 0 and math.isfinite(width)):
            raise ValueError("the bin width must be a positive number.")
        edges = np.arange(0.0, d.max() + width, width)
        if edges[-1] <= d.max():
            edges = np.append(edges, edges[-1] + width)
    edges = np.asarray(edges, float)
    idx = np.clip(np.searchsorted(edges, d, side="right") - 1, 0, len(edges) - 2)
    nb = len(edges) - 1
    count = np.bincount(idx, minlength=nb)
    s1 = np.bincount(idx, weights=v.real, minlength=nb) + 1j * np.bincount(idx, weights=v.imag, minlength=nb) \
        if np.iscomplexobj(v) else np.bincount(idx, weights=v, minlength=nb)
    nz = count > 0
    mean = np.zeros(nb, s1.dtype)
    mean[nz] = s1[nz] / count[nz]
    dev2 = np.abs(v - mean[idx]) ** 2
    var = np.bincount(idx, weights=dev2, minlength=nb)
    std = np.zeros(nb)
    std[nz] = np.sqrt(var[nz] / count[nz])
    centre = 0.5 * (edges[:-1] + edges[1:])
    return BinnedCorrelation(edges=edges, centre=centre[nz], mean=mean[nz], std=std[nz], count=count[nz])


def collapse_measure(dist, values, width: float | None = None) -> float:
    r"""Collapse number :math:`S = [\sum_b n_b\sigma_b^2 / \sum_b n_b|\mu_b|^2]^{1/2}` (module docstring).

    0 when F is a function of distance alone (up to the bin width), larger when sites at
    equal distance disagree.
    """
    b = bin_by_distance(dist, values, width=width)
    den = float(np.sum(b.count * np.abs(b.mean) ** 2))
    if den == 0:
        raise ValueError("the values vanish identically; the collapse number is undefined.")
    return float(np.sqrt(np.sum(b.count * b.std ** 2) / den))
