r"""The centre marker of big flakes by a Chebyshev expansion of the projector.

The hyperbolic local marker (:mod:`hyperlattice.topology.markers`) at a site needs only the
block :math:`P_{DD}` of the projector on the geodesic disk D around it. Following Varjas,
Fruchart, Akhmerov and Perez-Piskunow (PRR 2, 013229 (2020)), :math:`P = \theta(E_F - H)` is
expanded in Chebyshev polynomials of the rescaled :math:`\tilde H = H / a` (a above the
spectral radius, from Gershgorin's bound),

.. math:: P \approx \sum_{n=0}^{N-1} g_n c_n T_n(\tilde H), \quad
          c_0 = 1 - \frac{\arccos x_F}{\pi}, \quad c_n = -\frac{2\sin(n \arccos x_F)}{n\pi},

with :math:`x_F = E_F/a` and the Jackson kernel :math:`g_n` (Weiße et al., RMP 78, 275 (2006)),
and applied to the unit vectors of D only: N sparse products with ``|D|`` vectors, never a dense
matrix, so the cost grows linearly with the flake. The rows of D of the result are all the
marker needs.

Convergence estimate: the same recursion gives the expansion with N/2 moments for free (its
own Jackson kernel, summed alongside); the marker's error is estimated by the difference of the
two, and a ConvergenceWarning is raised when it exceeds ``tol``. The expansion converges once the
kernel's resolution :math:`\pi a / N` is well below the bulk gap at the centre (reported,
from the ring-1 local density of states of the same moments).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass

import numpy as np

from .. import _validate
from ..errors import ConvergenceWarning
from ..results import Result
from .markers import _geometry, _kitaev, _alpha0, _rows, _sectors
from .models import MODELS, model_hamiltonian, model_terms

__all__ = ["CentreMarker", "centre_marker", "projector_columns"]

#: memory for the three Chebyshev blocks of one batch of vectors (bytes)
BATCH_BYTES = 256 * 2 ** 20


def _jackson(n: int) -> np.ndarray:
    from ..graph.kpm import jackson_kernel

    return jackson_kernel(n)


def _scale(H) -> float:
    """Gershgorin bound on the spectral radius, with 1 % margin (the expansion needs ``|H/a|`` < 1)."""
    return 1.01 * float(np.max(np.asarray(abs(H).sum(axis=1)).ravel()))


def projector_columns(H, columns, fermi: float = 0.0, moments: int = 256) -> tuple[np.ndarray, np.ndarray, dict]:
    r"""Rows ``columns`` of :math:`P e_c` for every c in ``columns``, by the Chebyshev expansion (N and N/2).

    Parameters
    ----------
    H : scipy.sparse matrix
        A Hermitian Hamiltonian.
    columns : array_like of int
        Row indices c (the block :math:`P_{cc'}` is returned).
    fermi : float, optional
        Fermi level (default 0), inside the spectrum's bound.
    moments : int, optional
        Chebyshev moments N (even, 16 to 100,000; default 256).

    Returns
    -------
    (P_N, P_half, info)
        The block with N moments, with N/2 moments, and ``{"scale", "memory_bytes",
        "diag_moments"}`` (the moments :math:`\langle c|T_n|c\rangle`, shape (N, len(columns))).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> from hyperlattice.topology.kpm_marker import projector_columns
    >>> H = sp.diags([-1.0, 1.0]).tocsr()
    >>> P, _, _ = projector_columns(H, [0, 1], fermi=0.0, moments=64)
    >>> [round(float(x), 3) for x in P.diagonal().real]
    [1.0, 0.0]
    """
    import scipy.sparse as sp

    if not sp.issparse(H) or H.shape[0] != H.shape[1]:
        raise ValueError("H must be a square scipy.sparse matrix.")
    H = sp.csr_matrix(H, dtype=np.complex128)
    n = H.shape[0]
    cols = _validate.site_indices("columns", columns, n)
    moments = _validate.integer("moments", moments, minimum=16, maximum=100_000)
    moments += moments % 2
    a = _scale(H)
    ef = _validate.real("fermi", fermi)
    if not -a < ef < a:
        raise ValueError(f"the Fermi level {ef:g} lies outside the spectrum's bound [-{a:.4g}, {a:.4g}].")
    x = ef / a
    th = np.arccos(x)
    nn = np.arange(1, moments)
    c = np.concatenate([[1 - th / np.pi], -2 * np.sin(nn * th) / (nn * np.pi)])
    w_full = c * _jackson(moments)
    w_half = np.zeros(moments)
    w_half[: moments // 2] = c[: moments // 2] * _jackson(moments // 2)
    Ht = (H / a).tocsr()
    batch = max(1, min(len(cols), int(BATCH_BYTES // (3 * 16 * n))))
    P_full = np.zeros((len(cols), len(cols)), dtype=np.complex128)
    P_half = np.zeros_like(P_full)
    diag = np.zeros((moments, len(cols)))
    for s in range(0, len(cols), batch):
        sel = np.arange(s, min(s + batch, len(cols)))
        t0 = np.zeros((n, len(sel)), dtype=np.complex128)
        t0[cols[sel], np.arange(len(sel))] = 1.0
        t1 = Ht @ t0
        for k in range(moments):
            if k == 0:
                tk = t0
            elif k == 1:
                tk = t1
            else:
                tk = 2 * (Ht @ t1) - t0
                t0, t1 = t1, tk
            rows = tk[cols]
            P_full[:, sel] += w_full[k] * rows
            if w_half[k] != 0:
                P_half[:, sel] += w_half[k] * rows
            diag[k, sel] = rows[sel, np.arange(len(sel))].real
    info = {"scale": a, "memory_bytes": int(3 * 16 * n * batch + H.data.nbytes + H.indices.nbytes),
            "diag_moments": diag}
    herm = lambda m: 0.5 * (m + m.conj().T)  # noqa: E731
    return herm(P_full), herm(P_half), info


@dataclass(frozen=True, eq=False, kw_only=True)
class CentreMarker(Result):
    """The hyperbolic local marker at the centre of a flake by the Chebyshev expansion.

    Attributes
    ----------
    model : str
        The model.
    parameters : dict
        Its parameters, with ``moments``, ``radius``, ``fermi``.
    sites : int
        Sites of the flake.
    marker : float
        The local marker averaged over the evaluated ring-1 sites (Bianco–Resta sign).
    marker_by_ring : ndarray, shape (1,)
        Ring 1 only (the expansion is applied at the centre).
    marker_error : float
        Estimated error: the difference between the marker with N and N/2 moments.
    kitaev : float
        Kitaev's sum centred at the flake's centre, same radius.
    evaluated_sites : ndarray of int
        The ring-1 sites evaluated (two neighbours when the flake has its rotation symmetry, all of
        ring 1 with disorder or flux).
    vectors : int
        Unit vectors the projector was applied to.
    gap : float
        Gap of the ring-1 local DOS around the Fermi level (resolution ``pi a / N``).
    resolution : float
        The kernel's energy resolution pi a / N.
    memory_bytes : int
        Peak memory of the expansion's vectors and the sparse H.
    seconds : float
        Wall time of the expansion.
    method : str
        ``"kpm"``.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.kpm_marker import centre_marker
    >>> res = centre_marker(hl.ring_lattice(8, 3, 3), "qwz", M=1.0, moments=256)
    >>> round(res.marker, 1)
    -1.0
    """

    NOT_TABULAR = "one marker at the centre with its diagnostics"

    model: str
    parameters: dict
    sites: int
    marker: float
    marker_by_ring: np.ndarray
    marker_error: float
    kitaev: float
    evaluated_sites: np.ndarray
    vectors: int
    gap: float
    resolution: float
    memory_bytes: int
    seconds: float
    method: str

    def summary(self) -> dict:
        """The CLI's JSON (the keys of the dense route; ``bott`` is null: it needs all eigenvectors)."""
        return {"model": self.model, "sites": self.sites, "marker": self.marker,
                "marker_by_ring": [float(x) for x in self.marker_by_ring], "marker_error": self.marker_error,
                "kitaev": self.kitaev, "bott": None, "gap": self.gap, "resolution": self.resolution,
                "vectors": self.vectors, "memory_bytes": self.memory_bytes, "method": self.method,
                "parameters": self.parameters}


def _ldos_gap(diag: np.ndarray, a: float, fermi: float) -> float:
    """Gap of the Jackson-smoothed ring-1 LDOS around the Fermi level (density below 1/10 of its mean)."""
    mu = diag.mean(axis=1)
    m = len(mu)
    g = _jackson(m)
    x = np.cos(np.pi * (np.arange(4 * m) + 0.5) / (4 * m))
    T = np.cos(np.outer(np.arange(m), np.arccos(x)))
    rho = (mu[0] * g[0] + 2 * (mu[1:, None] * g[1:, None] * T[1:]).sum(axis=0)) / (np.pi * np.sqrt(1 - x * x))
    e = x * a
    order = np.argsort(e)
    e, rho = e[order], rho[order] / a
    thresh = 0.1 / (e[-1] - e[0])        # a tenth of the mean density of a normalised LDOS
    low = rho < thresh
    i = int(np.searchsorted(e, fermi))
    i = min(max(i, 0), len(e) - 1)
    if not low[i]:
        return 0.0
    lo = i
    while lo > 0 and low[lo - 1]:
        lo -= 1
    hi = i
    while hi < len(e) - 1 and low[hi + 1]:
        hi += 1
    return float(e[hi] - e[lo])


def centre_marker(graph, model: str = "qwz", *, M: float = 1.0, t2: float = 0.2, phi: float = np.pi / 2,
                  flux: float = 0.0, disorder: float = 0.0, seed: int = 0, fermi: float = 0.0,
                  moments: int = 256, radius: float | None = None, tol: float = 0.02,
                  frame: str = "chord") -> CentreMarker:
    r"""The hyperbolic local marker at a flake's centre without diagonalising (Chebyshev projector).

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        An open flake.
    model : {"qwz", "haldane"}
        The model (Kane–Mele's spin Chern number needs the split of the occupied space by
        :math:`P s_z P`, which this route does not form: use the dense route).
    M, t2, phi, flux, disorder, seed : optional
        Model parameters (:func:`~hyperlattice.topology.models.model_terms`).
    fermi : float, optional
        Fermi level, default 0 (the middle of the bulk gap of QWZ and of Haldane at phi = pi/2).
    moments : int, optional
        Chebyshev moments N, default 256.
    radius : float, optional
        Radius of the marker's disk (metric), default 4 bond lengths.
    tol : float, optional
        Warn when the estimated error exceeds this (default 0.02).
    frame : {"chord", "tangent", "transport"}, optional
        QWZ bond frame (:func:`~hyperlattice.topology.models.model_terms`), default ``"chord"``.

    Returns
    -------
    CentreMarker

    Raises
    ------
    ValueError
        Bad parameters, Kane–Mele, a Fermi level outside the spectrum's bound.

    Warns
    -----
    ConvergenceWarning
        When the N vs N/2 difference exceeds ``tol``.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.kpm_marker import centre_marker
    >>> res = centre_marker(hl.ring_lattice(8, 3, 3), "qwz", M=1.0, moments=256)
    >>> res.vectors > 0, res.marker_error < 0.05
    (True, True)
    """
    from ..graph.solvers import single_threaded_blas

    model = _validate.choice("model", model, MODELS)
    if model == "kane-mele":
        raise ValueError("the Chebyshev centre marker supports qwz and haldane; Kane-Mele's spin Chern number "
                         "needs the dense route (flake_topology).")
    tol = _validate.real("tol", tol, minimum=1e-12, maximum=10.0)
    geo = _geometry(graph)
    r = 4 * geo.bond if radius is None else _validate.real("radius", radius, minimum=1e-3, maximum=1e3)
    terms = model_terms(graph, model, M=M, t2=t2, phi=phi, flux=flux, disorder=disorder, seed=seed, frame=frame)
    d = terms.orbitals
    H = model_hamiltonian(terms)
    ring1 = np.flatnonzero(geo.ring == geo.ring.min())
    symmetric = disorder == 0.0 and flux == 0.0 and getattr(graph, "rotation", None) is not None
    evaluated = ring1[:2] if symmetric else ring1
    centre = 0j if geo.hyperbolic else complex(geo.z.mean())
    disks = [np.flatnonzero(geo.distance(geo.z[i], geo.z) <= r) for i in evaluated]
    disks.append(np.flatnonzero(geo.distance(centre, geo.z) <= r))
    union = np.unique(np.concatenate(disks))
    cols = _rows(union, d)
    start = time.perf_counter()
    with single_threaded_blas():
        P_full, P_half, info = projector_columns(H, cols, fermi=fermi, moments=moments)
    seconds = time.perf_counter() - start
    pos = {int(s): k for k, s in enumerate(union)}

    def marker_at(P, c, sites):
        local = np.array([pos[int(s)] for s in sites])
        rows = _rows(local, d)
        sec = np.repeat(_sectors(geo.recentre(c, geo.z[sites]), _alpha0(geo, c, sites)), d)
        return _kitaev(P[np.ix_(rows, rows)], sec)

    vals = [marker_at(P_full, geo.z[i], disk) for i, disk in zip(evaluated, disks[:-1])]
    half = [marker_at(P_half, geo.z[i], disk) for i, disk in zip(evaluated, disks[:-1])]
    m, mh = float(np.mean(vals)), float(np.mean(half))
    kit = marker_at(P_full, centre, disks[-1])
    err = abs(m - mh)
    if err > tol:
        warnings.warn(f"the centre marker changed by {err:.2g} between {moments // 2} and {moments} Chebyshev "
                      "moments: raise moments (the kernel's resolution must be well below the gap).",
                      ConvergenceWarning, stacklevel=2)
    ring_rows = np.array([k for k, s in enumerate(union) if geo.ring[s] == geo.ring.min()])
    diag = info["diag_moments"][:, _rows(ring_rows, d)]
    gap = _ldos_gap(diag, info["scale"], float(fermi))
    params = dict(M=M, t2=t2, phi=phi, flux=flux, disorder=disorder, seed=seed, fermi=float(fermi),
                  moments=moments, radius=float(r), frame=frame)
    return CentreMarker(model=model, parameters=params, sites=len(geo.z), marker=m, marker_by_ring=np.array([m]),
                        marker_error=err, kitaev=float(kit), evaluated_sites=evaluated.astype(np.int64),
                        vectors=len(cols), gap=gap, resolution=float(np.pi * info["scale"] / moments),
                        memory_bytes=int(info["memory_bytes"]), seconds=float(seconds), method="kpm")


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
