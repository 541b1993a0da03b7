r"""The topological Anderson insulator's effective medium: the self-consistent Born approximation on a flake.

Box disorder :math:`V_i \in [-W/2, W/2]` on every site (times the identity on the orbitals) has
variance :math:`W^2/12`. Averaged over the disorder to second order, self-consistently, it leaves a
uniform self-energy (Groth, Wimmer, Akhmerov, Tworzydło and Beenakker, PRL 103, 196805 (2009),
eq. (4), written on the graph):

.. math::

    \Sigma(E) = \frac{W^2}{12}\,\bar G_{ii}(E), \qquad
    G(E) = \bigl(E - H_0 - \Sigma\otimes 1 - \Sigma_{\partial}\bigr)^{-1},

with :math:`\bar G_{ii}` the 2 x 2 block of the Green function on a site of the bulk. On QWZ,
:math:`\Sigma = \Sigma_0\sigma_0 + \Sigma_z\sigma_z` renormalises the mass and the Fermi level,

.. math:: \bar M = M + \mathrm{Re}\,\Sigma_z, \qquad \bar E = E - \mathrm{Re}\,\Sigma_0,

and :math:`\Gamma = -\mathrm{Im}\,\Sigma_0` broadens the levels. The Chern phase of the
renormalised Hamiltonian is that of the clean model at :math:`\bar M`: the SCBA's boundary of the
topological Anderson insulator on the weak-disorder side is where :math:`\bar M` reaches the clean
critical mass :math:`M_c` (Groth et al.: where the renormalised mass changes sign).

On the graph. The {p,q} lattice is vertex-transitive, so the bulk block is one 2 x 2 matrix;
it is taken on the sites of ring 1 of a flake whose edge absorbs (a wide-band self-energy
:math:`\Sigma_\partial = -i\gamma/2` on every orbital of the outer ring and of every site of low
degree, as the conductance's leads): the centre then sees a lattice that continues to infinity without reflection, and on a
hyperbolic lattice the centre's Green function converges quickly with the number of rings. The
blocks of the ring-1 sites carry, besides :math:`\sigma_0` and :math:`\sigma_z`, a
:math:`\sigma_x, \sigma_y` part that points along the chord frame of each site and averages out
over the ring; its size relative to the :math:`\sigma_z` part is reported (``frame_part``). At E = 0
QWZ's particle–hole symmetry :math:`\sigma_x H^* \sigma_x = -H` makes :math:`\Sigma_0` imaginary
and :math:`\Sigma_z` real.

What the SCBA misses: interference. It has no Anderson localisation, so it gives the weak-disorder
boundary (the mass pushed across :math:`M_c`) and not the strong-disorder one, where the
topological Anderson insulator ends because the states at E localise.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..errors import ConvergenceWarning
from ..results import Column, Result
from .markers import _geometry, _rows
from .models import model_hamiltonian, model_terms

__all__ = ["ScbaScan", "ScbaBoundary", "scba", "scba_boundary"]

_SZ = np.diag([1.0, -1.0])
#: most disorder strengths (or masses) one call takes
MAX_POINTS = 10_000


def _setup(graph, absorb: float):
    """(geometry, ring-1 rows, the absorbing diagonal) of a flake for the SCBA."""
    geo = _geometry(graph)
    gamma = _validate.real("absorb", absorb, minimum=0.0, maximum=1e6)
    n = len(geo.z)
    if geo.ring.max() == geo.ring.min():
        raise ValueError("the flake needs at least two rings: ring 1 is the bulk, the edge absorbs.")
    ring1 = np.flatnonzero(geo.ring == geo.ring.min())
    # the edge as the conductance's contacts see it: sites of low degree and, on a {p,q} flake, the outer ring
    edge = geo.boundary
    if geo.hyperbolic:
        edge = np.union1d(edge, np.flatnonzero(geo.ring == geo.ring.max()))
    if np.intersect1d(edge, ring1).size:
        raise ValueError("the flake is too small: its centre touches the edge.")
    absorbing = np.zeros(2 * n, dtype=np.complex128)
    absorbing[_rows(edge, 2)] = -0.5j * gamma
    return geo, ring1, absorbing


class _LocalGreen:
    """The ring-1 blocks of :math:`(E - H_0(M) - \\Sigma - \\Sigma_\\partial)^{-1}` of QWZ on one flake."""

    def __init__(self, graph, absorb: float) -> None:
        geo, self.ring1, self.absorbing = _setup(graph, absorb)
        self.sites = len(geo.z)
        terms = model_terms(graph, "qwz", M=0.0)
        self.H0 = model_hamiltonian(terms).tocsc().astype(np.complex128)
        self.sz = sp.diags(np.tile([1.0, -1.0], self.sites)).tocsc()
        self.cols = _rows(self.ring1, 2)
        _validate.require_memory("the sparse LU of the SCBA's resolvent", 16.0 * 200 * 2 * self.sites)

    def blocks(self, energy: complex, mass: complex, s0: complex) -> np.ndarray:
        """The 2 x 2 blocks G_ii of the ring-1 sites (shape (len(ring1), 2, 2)) at E, M + Sigma_z and Sigma_0."""
        from scipy.sparse.linalg import splu

        rows = 2 * self.sites
        a = sp.diags(np.full(rows, energy - s0) - self.absorbing) - self.H0 - mass * self.sz
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", sp.SparseEfficiencyWarning)
                lu = splu(a.tocsc(), permc_spec="COLAMD")
        except (RuntimeError, sp.SparseEfficiencyWarning):
            raise ValueError(f"the SCBA's resolvent is singular at E = {energy:.6g}, mass {mass:.6g}: give the "
                             "edge a positive absorb.") from None
        b = np.zeros((rows, len(self.cols)), np.complex128, order="F")
        b[self.cols, np.arange(len(self.cols))] = 1.0
        x = lu.solve(b)[self.cols]
        k = len(self.ring1)
        return np.stack([x[2 * i:2 * i + 2, 2 * i:2 * i + 2] for i in range(k)])


def _parts(blocks: np.ndarray) -> tuple[complex, complex, float]:
    """(sigma_0 part, sigma_z part, the largest sigma_x/sigma_y part over |sigma_z part|) of the blocks."""
    g0 = complex(np.mean(blocks[:, 0, 0] + blocks[:, 1, 1]) / 2)
    gz = complex(np.mean(blocks[:, 0, 0] - blocks[:, 1, 1]) / 2)
    off = np.abs(blocks[:, 0, 1]).max() + np.abs(blocks[:, 1, 0]).max()
    return g0, gz, float(0.5 * off / max(abs(gz), 1e-300))


@dataclass(frozen=True, eq=False, kw_only=True)
class ScbaScan(Result):
    r"""The SCBA self-energy of QWZ against the disorder strength at one mass (module docstring).

    Attributes
    ----------
    parameters : dict
        ``M``, ``energy``, ``absorb`` (γ of the edge), ``tol``.
    disorder : ndarray, shape (K,)
        Box disorder strengths W (units of t).
    mass : ndarray, shape (K,)
        The renormalised mass :math:`\bar M = M + \mathrm{Re}\,\Sigma_z` (t).
    sigma_z : ndarray of complex, shape (K,)
        :math:`\Sigma_z` (t).
    sigma_0 : ndarray of complex, shape (K,)
        :math:`\Sigma_0` (t); its real part shifts the Fermi level, ``broadening`` is minus its imaginary part.
    broadening : ndarray, shape (K,)
        :math:`\Gamma = -\mathrm{Im}\,\Sigma_0` (t).
    iterations : ndarray of int, shape (K,)
        Fixed-point iterations used.
    frame_part : float
        The largest :math:`\sigma_x, \sigma_y` part of a ring-1 block over its :math:`\sigma_z` part (left out of
        :math:`\Sigma`, which keeps the rotation-invariant parts).
    sites : int
        Sites of the flake.
    method : str
        ``"scba, sparse LU"``.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.anderson import scba
    >>> s = scba(hl.ring_lattice(8, 3, 3), M=1.6, disorder=[0.0, 3.0])
    >>> [round(float(m), 2) for m in s.mass]
    [1.6, 1.28]
    """

    COLUMNS = (Column("W", "disorder", "t"), Column("mass", "mass", "t"), Column("broadening", "broadening", "t"),
               Column("sigma_z", "sigma_z", "t"), Column("sigma_0", "sigma_0", "t"),
               Column("iterations", "iterations", "1"))

    parameters: dict
    disorder: np.ndarray
    mass: np.ndarray
    sigma_z: np.ndarray
    sigma_0: np.ndarray
    broadening: np.ndarray
    iterations: np.ndarray
    frame_part: float
    sites: int
    method: str

    def summary(self) -> dict:
        """The plain view: W, the renormalised mass and the broadening (t)."""
        return {"sites": self.sites, "parameters": self.parameters, "W": [float(x) for x in self.disorder],
                "mass": [float(x) for x in self.mass], "broadening": [float(x) for x in self.broadening],
                "frame_part": self.frame_part, "method": self.method}


def _strengths(name: str, values, minimum: float = 0.0) -> np.ndarray:
    v = np.atleast_1d(_validate.real_array(name, values)).astype(float).ravel()
    if v.size == 0 or v.size > MAX_POINTS:
        raise ValueError(f"{name} must hold 1 to {MAX_POINTS:,} values, got {v.size:,}.")
    if not np.all(np.isfinite(v)) or np.any(v < minimum) or np.any(np.abs(v) > 1e6):
        raise ValueError(f"{name} must be finite numbers of at least {minimum:g} and at most 1e6 in size.")
    return v


def scba(graph, *, M: float, disorder, energy: float = 0.0, absorb: float = 2.0, tol: float = 1e-9,
         max_iter: int = 500) -> ScbaScan:
    r"""The self-consistent Born self-energy of QWZ with box disorder, on the bulk of a {p,q} flake.

    Iterates :math:`\Sigma \leftarrow (W^2/12)\,\bar G_{ii}(E;\Sigma)` (module docstring) from the
    Born value, damped by half, until :math:`|\Delta\Sigma| <` ``tol``; each W starts from the
    previous W's solution.

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        A {p,q} flake (:func:`~hyperlattice.graph.lattice.ring_lattice`) of at least two rings, or a
        Euclidean flake (:func:`~hyperlattice.topology.models.square_flake`); the edge absorbs.
    M : float
        QWZ's mass (t).
    disorder : float or array of float
        Box disorder strengths W ≥ 0 (t).
    energy : float, optional
        The energy E (t), default 0 (half filling).
    absorb : float, optional
        γ of the edge's absorbing self-energy :math:`-i\gamma/2` (t), default 2 (the conductance's
        leads).
    tol : float, optional
        Convergence of the fixed point (t), default 1e-9.
    max_iter : int, optional
        Most iterations per W (default 500); a W that does not converge warns (ConvergenceWarning).

    Returns
    -------
    ScbaScan

    Raises
    ------
    ValueError
        Not an open flake, a centre on the edge, non-finite or negative W, bad tolerances.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.anderson import scba
    >>> s = scba(hl.ring_lattice(8, 3, 3), M=1.6, disorder=2.0)
    >>> bool(s.sigma_z[0].real < 0), bool(abs(s.sigma_z[0].imag) < 1e-9)
    (True, True)
    """
    M = _validate.real("M", M, minimum=-1e6, maximum=1e6)
    W = _strengths("disorder", disorder)
    E = _validate.real("energy", energy, minimum=-1e6, maximum=1e6)
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1.0)
    max_iter = _validate.integer("max_iter", max_iter, minimum=1, maximum=100_000)
    green = _LocalGreen(graph, absorb)
    s0 = sz = 0j
    out = {k: [] for k in ("sz", "s0", "it")}
    frame = 0.0
    for w in W:
        var = w * w / 12.0
        it = 0
        while True:
            it += 1
            g0, gz, fp = _parts(green.blocks(E, M + sz, s0))
            new0, newz = var * g0, var * gz
            step = max(abs(new0 - s0), abs(newz - sz))
            s0, sz = 0.5 * (s0 + new0), 0.5 * (sz + newz)
            if step < tol:
                s0, sz = new0, newz
                break
            if it >= max_iter:
                warnings.warn(f"the SCBA at W = {w:g} did not converge in {max_iter} iterations (last step "
                              f"{step:.1e} t).", ConvergenceWarning, stacklevel=2)
                break
        frame = max(frame, fp)
        out["sz"].append(sz), out["s0"].append(s0), out["it"].append(it)
    sz_a, s0_a = np.array(out["sz"], complex), np.array(out["s0"], complex)
    return ScbaScan(parameters=dict(M=M, energy=E, absorb=float(absorb), tol=tol), disorder=W, mass=M + sz_a.real,
                    sigma_z=sz_a, sigma_0=s0_a, broadening=-s0_a.imag, iterations=np.array(out["it"], np.int64),
                    frame_part=frame, sites=green.sites, method="scba, sparse LU")


@dataclass(frozen=True, eq=False, kw_only=True)
class ScbaBoundary(Result):
    r"""The SCBA's weak-disorder boundary of the topological Anderson insulator, :math:`W_c(M)`.

    Attributes
    ----------
    parameters : dict
        ``critical_mass`` :math:`M_c` (t), ``energy``, ``absorb``, ``tol``.
    masses : ndarray, shape (K,)
        Masses M (t).
    critical_disorder : ndarray, shape (K,)
        :math:`W_c`: the box disorder at which :math:`\bar M = M_c` (t); 0 where :math:`M \le M_c`
        (topological without disorder), nan where the SCBA never renormalises M to :math:`M_c`.
    broadening : ndarray, shape (K,)
        :math:`\Gamma` at :math:`W_c` (t).
    iterations : ndarray of int, shape (K,)
        Fixed-point iterations used.
    sites : int
        Sites of the flake.
    method : str
        ``"scba, sparse LU"``.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.anderson import scba_boundary
    >>> b = scba_boundary(hl.ring_lattice(8, 3, 3), masses=[1.4, 1.6], critical_mass=1.48)
    >>> float(b.critical_disorder[0]), round(float(b.critical_disorder[1]), 2)
    (0.0, 1.57)
    """

    COLUMNS = (Column("M", "masses", "t"), Column("W_c", "critical_disorder", "t"),
               Column("broadening", "broadening", "t"), Column("iterations", "iterations", "1"))

    parameters: dict
    masses: np.ndarray
    critical_disorder: np.ndarray
    broadening: np.ndarray
    iterations: np.ndarray
    sites: int
    method: str

    def summary(self) -> dict:
        """The plain view: M, W_c and the broadening there (t)."""
        return {"sites": self.sites, "parameters": self.parameters, "M": [float(x) for x in self.masses],
                "W_c": [float(x) for x in self.critical_disorder], "broadening": [float(x) for x in self.broadening],
                "method": self.method}


def scba_boundary(graph, *, masses, critical_mass: float, energy: float = 0.0, absorb: float = 2.0,
                  tol: float = 1e-9, max_iter: int = 500) -> ScbaBoundary:
    r"""The disorder :math:`W_c(M)` at which the SCBA's renormalised mass reaches :math:`M_c`.

    Fixes :math:`\mathrm{Re}\,\Sigma_z = M_c - M` and iterates the rest of the SCBA:
    :math:`W^2 = 12 (M_c - M)/\mathrm{Re}\,\bar G_z`, :math:`\Sigma_0 = (W^2/12)\bar G_0`,
    :math:`\mathrm{Im}\,\Sigma_z = (W^2/12)\,\mathrm{Im}\,\bar G_z`, until W changes by less than
    ``tol``. For :math:`M \le M_c` the clean model is already topological: :math:`W_c = 0`.

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        A flake (see :func:`scba`).
    masses : float or array of float
        Masses M (t).
    critical_mass : float
        :math:`M_c`, the clean transition (t); on the {8,3} flake about 1.48 (docs/topology.md).
    energy, absorb, tol, max_iter : optional
        As in :func:`scba`.

    Returns
    -------
    ScbaBoundary

    Raises
    ------
    ValueError
        As :func:`scba`, and non-finite masses.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.anderson import scba, scba_boundary
    >>> lat = hl.ring_lattice(8, 3, 3)
    >>> w = float(scba_boundary(lat, masses=1.6, critical_mass=1.48).critical_disorder[0])
    >>> round(float(scba(lat, M=1.6, disorder=w).mass[0]), 6)
    1.48
    """
    Ms = _strengths("masses", masses, minimum=-1e6)
    Mc = _validate.real("critical_mass", critical_mass, minimum=-1e6, maximum=1e6)
    E = _validate.real("energy", energy, minimum=-1e6, maximum=1e6)
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1.0)
    max_iter = _validate.integer("max_iter", max_iter, minimum=1, maximum=100_000)
    green = _LocalGreen(graph, absorb)
    wc, gam, its = [], [], []
    for M in Ms:
        if M <= Mc:
            wc.append(0.0), gam.append(0.0), its.append(0)
            continue
        s0, imz, w2 = 0j, 0.0, None
        it = 0
        while True:
            it += 1
            g0, gz, _ = _parts(green.blocks(E, Mc + 1j * imz, s0))
            if not gz.real < 0:     # the Born term pushes the mass up here: no disorder reaches M_c
                w2 = np.nan
                break
            new = 12.0 * (Mc - M) / gz.real
            var = new / 12.0
            done = w2 is not None and abs(np.sqrt(new) - np.sqrt(w2)) < tol
            w2 = new if w2 is None else 0.5 * (w2 + new)
            s0, imz = 0.5 * (s0 + var * g0), 0.5 * (imz + var * gz.imag)
            if done:
                w2 = new
                break
            if it >= max_iter:
                warnings.warn(f"the SCBA boundary at M = {M:g} did not converge in {max_iter} iterations.",
                              ConvergenceWarning, stacklevel=2)
                break
        wc.append(float(np.sqrt(w2))), gam.append(float(-s0.imag)), its.append(it)
    return ScbaBoundary(parameters=dict(critical_mass=Mc, energy=E, absorb=float(absorb), tol=tol), masses=Ms,
                        critical_disorder=np.array(wc), broadening=np.array(gam), iterations=np.array(its, np.int64),
                        sites=green.sites, method="scba, sparse LU")


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
