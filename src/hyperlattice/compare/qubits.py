r"""Circuit-QED qubits below the band: graph vs continuum exchange J(d) and bound-state size.

The graph side is :mod:`hyperlattice.graph.qubits`; the continuum side is ``eq21``:
:math:`J_{ij} = g^2G_{ij}(\omega_q) \approx g^2\frac{4\mathcal A}{qh^2}G(z_i, z_j, \lambda(\omega_q), L)`
(:func:`hyperlattice.compare.green.continuum_column`, the Dirichlet disk of ``eq12``).

Line graph (the resonator array)
--------------------------------
With :math:`B` the site–edge incidence matrix, the line-graph adjacency is :math:`B^TB - 2`, so
:math:`H_{LG} - \omega = s - B^TB` with :math:`s = 2 - \omega`, and the push-through identity gives

.. math:: G^{LG}(\omega) = \frac1s\bigl[\mathbb 1 + B^T(s - BB^T)^{-1}B\bigr],
          \qquad BB^T = D + A,

so, with :math:`D = q` in the interior, :math:`(s - BB^T)^{-1} = G^{\rm site}(\omega + q - 2)`: a
resonator–resonator propagator is :math:`1/s` times the sum of the four site propagators between
the endpoints of the two edges, at the shifted frequency :math:`\omega' = \omega + q - 2`
(exact up to the degree of the outer-ring sites). Its continuum counterpart replaces each of the four
terms by ``eq21``; :func:`exchange_comparison` does this for ``kind == "line_graph"``.

Bound-state size
----------------
The photon profile decays as :math:`G(d) \propto e^{-2\Delta d}` at large d (the :math:`L = 1`
propagator :math:`\frac1{2\pi}Q_{\Delta-1}(\cosh 2d)`), so its decay length is at most
:math:`1/(2\Delta) \le 1 = 2R` as the detuning goes to zero at the continuum BF bound
:math:`\Delta \to 1/2`: the curvature limits the size of the bound state (Bienias et al.,
PRL 128, 013601 (2022), "curvature-limited size"). On a finite flake the detuning is measured from
the lattice band bottom :math:`E_0(\ell)`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import _validate
from ..continuum.massive import delta_from_mass2, mass2_from_omega
from ..dictionary import dictionary_parameters
from ..geometry import distance
from ..graph.lattice import Lattice
from ..graph.qubits import BelowBandResolvent, _coupling, _decay_length, _real_omega, _resolvent_for, bound_state
from ..results import Column, Result


__all__ = ["ExchangeComparison", "exchange_comparison", "BoundStateSizes", "bound_state_sizes"]

_MAX_POINTS = 200


def _continuum_site_column(lat: Lattice, omega: float, source: int) -> np.ndarray:
    """eq21 (Dirichlet disk of eq12) at every site for one source; inf at the source."""
    from ..continuum.green import continuum_green

    lam, pref = dictionary_parameters(omega, lat.p, lat.q)
    vals = continuum_green(lat.z, lat.z[source], lam.real, lat.radius, extend=True, tol=1e-10)
    out = pref * np.real(vals)
    out[source] = math.inf
    return out


def _parent(lat: Lattice) -> Lattice:
    """The site lattice whose line graph ``lat`` is (rebuilt: a line graph keeps only its parent edges)."""
    from ..graph.lattice import ring_lattice

    return ring_lattice(lat.p, lat.q, lat.rings)


def _continuum_column(lat: Lattice, omega: float, source: int) -> np.ndarray:
    if lat.kind == "sites":
        return _continuum_site_column(lat, omega, source)
    parent = _parent(lat)
    s = 2.0 - omega
    w = omega + lat.q - 2
    a, b = (int(v) for v in lat.parent_edges[source])
    ends = np.asarray(lat.parent_edges)
    cols = [_continuum_site_column(parent, w, a), _continuum_site_column(parent, w, b)]
    total = np.zeros(lat.sites)
    for col in cols:
        with np.errstate(invalid="ignore"):
            total += col[ends[:, 0]] + col[ends[:, 1]]
    out = total / s
    out[source] = math.inf
    return out


@dataclass(frozen=True, eq=False, kw_only=True)
class ExchangeComparison(Result):
    r"""Exchange :math:`J(d) = g^2G_{j_0 i}(\omega_q)` from one qubit site to every other site, graph and continuum.

    Attributes
    ----------
    p, q, rings : int
        The flake (Schläfli symbol and rings).
    kind : str
        ``"sites"`` or ``"line_graph"``.
    site : int
        The first qubit's site :math:`j_0`, 0-based (the second qubit is any other site i).
    omega_q, g : float
        Qubit frequency (below the band) and coupling, in units of t; J is in units of t too.
    distance : ndarray
        Hyperbolic distance :math:`d(z_i, z_{j_0})` (paper's metric).
    graph, continuum : ndarray
        :math:`J` on the graph and from ``eq21`` (inf at :math:`j_0`).
    rel_l2 : float
        Relative L2 distance over all sites but :math:`j_0` (and, on a line graph, but the resonators
        sharing an endpoint with it, where the continuum needs a coincident point: NaN there).
    bins, graph_mean, continuum_mean : ndarray
        Binned means against distance (bin width :math:`d_0/2`) for tables and plots.
    decay_length_graph, decay_length_continuum : float
        :math:`\xi` of :math:`J \propto e^{-d/\xi}` fitted on both columns the same way (2–6 edge lengths).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> ex = hl.exchange_comparison(hl.ring_lattice(7, 3, 4), -3.2, 0.1)
    >>> ex.kind, ex.site, ex.graph.shape, f"{ex.rel_l2:.4f}"
    ('sites', 0, (315,), '0.0643')
    """

    #: one row per site i (the binned means ``bins``, ``graph_mean``, ``continuum_mean`` are not rows of it)
    COLUMNS = (Column("distance", "distance", "hyperbolic distance"), Column("graph", "graph", "t"),
               Column("continuum", "continuum", "t"))

    p: int
    q: int
    rings: int
    kind: str
    site: int
    omega_q: float
    g: float
    distance: np.ndarray = field(repr=False)
    graph: np.ndarray = field(repr=False)
    continuum: np.ndarray = field(repr=False)
    rel_l2: float
    bins: np.ndarray = field(repr=False)
    graph_mean: np.ndarray = field(repr=False)
    continuum_mean: np.ndarray = field(repr=False)
    decay_length_graph: float
    decay_length_continuum: float

    def table(self) -> list[list[float]]:
        """Rows ``[d, J_graph, J_continuum, relative difference]`` of the binned means."""
        return [[float(d), float(a), float(b), float((a - b) / a)]
                for d, a, b in zip(self.bins, self.graph_mean, self.continuum_mean) if np.isfinite(a)]

    def summary(self) -> dict:
        """p, q, rings, kind, site, omega_q, g, rel_l2, decay lengths."""
        keys = ("p", "q", "rings", "kind", "site", "omega_q", "g", "rel_l2", "decay_length_graph",
                "decay_length_continuum")
        return {k: getattr(self, k) for k in keys}


def exchange_comparison(lattice: Lattice, omega_q, g, site: int = 0, *,
                        resolvent: BelowBandResolvent | None = None) -> ExchangeComparison:
    r"""Graph :math:`J_{j_0 i} = g^2G_{j_0i}(\omega_q)` against ``eq21`` for all i (line graphs through the
    identity of the module docstring).

    Parameters
    ----------
    lattice : Lattice
        A {p,q} flake (``ring_lattice``) or its line graph (the resonator array).
    omega_q : float
        Qubit frequency (units of t), below the band of the lattice
        (:math:`\omega_q < E_0(\ell)`, checked exactly).
    g : float
        Qubit-photon coupling (units of t), nonzero.
    site : int, optional
        The first qubit's site :math:`j_0` (0-based; a resonator on a line graph). Default 0.
    resolvent : BelowBandResolvent, optional
        Reuse a factorization of :math:`H - \omega_q` (several sites at one frequency).

    Returns
    -------
    ExchangeComparison
        ``graph`` and ``continuum`` exchange :math:`J` (units of t) to every site, the hyperbolic
        ``distance`` to :math:`j_0`, ``rel_l2``, the binned means ``graph_mean`` and
        ``continuum_mean`` on ``bins``, and the fitted decay lengths (NaN when the flake is too
        small for the 2–6 edge-length window).

    Raises
    ------
    ValueError
        Bad input, g = 0 or :math:`g^2` overflowing, :math:`\omega_q` not below the band.

    See Also
    --------
    bound_state_sizes : the exact bound states and their size.
    hyperlattice.compare.green.continuum_column : the continuum column.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (19) (source label ``eq21``).
    .. [2] P. Bienias et al., Phys. Rev. Lett. 128, 013601 (2022).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> lat = hl.ring_lattice(7, 3, 4)
    >>> ex = hl.exchange_comparison(lat, -3.2, 0.1)
    >>> print(f"{ex.rel_l2:.4f}")
    0.0643
    >>> ex_lg = hl.exchange_comparison(hl.line_graph(hl.ring_lattice(7, 3, 3)), -5.0, 0.1)
    >>> print(ex_lg.kind, f"{ex_lg.rel_l2:.4f}")
    line_graph 0.0713
    """
    lat = _validate.lattice(lattice)
    site = _validate.site_index("site", site, lat.sites)
    omega_q = _real_omega("omega_q", omega_q)
    g = _coupling(g)
    if g == 0.0:
        # J = g^2 G vanishes identically: the relative error and the decay lengths would be 0/0
        raise ValueError("g must be nonzero: with g = 0 the exchange J = g^2 G vanishes and there is nothing to compare.")
    res = _resolvent_for(resolvent, lat)
    gcol = g * g * res.column(omega_q, site)
    ccol = g * g * _continuum_column(lat, omega_q, site)
    d = distance(lat.z, lat.z[site])
    # line graph: resonators sharing an endpoint with j0 need the coincident site propagator,
    # which the continuum does not have (inf): they are left out (NaN) together with j0
    ccol[~np.isfinite(ccol)] = math.nan
    ccol[site] = math.inf
    keep = np.isfinite(ccol)
    rel = float(np.linalg.norm(gcol[keep] - ccol[keep]) / np.linalg.norm(gcol[keep]))
    width = 0.5 * lat.d0
    idx = np.floor(d / width).astype(int)
    nb = int(idx.max()) + 1
    cnt = np.bincount(idx[keep], minlength=nb)
    with np.errstate(invalid="ignore", divide="ignore"):
        gm = np.bincount(idx[keep], gcol[keep], minlength=nb) / cnt
        cm = np.bincount(idx[keep], ccol[keep], minlength=nb) / cnt
    ok = cnt > 0
    bins = (np.arange(nb) + 0.5) * width
    gc_pos = np.where(np.isfinite(ccol) & (ccol > 0), ccol, 0.0)
    return ExchangeComparison(p=lat.p, q=lat.q, rings=lat.rings, kind=lat.kind, site=site, omega_q=omega_q, g=g,
                              distance=d, graph=gcol, continuum=ccol, rel_l2=rel, bins=bins[ok], graph_mean=gm[ok],
                              continuum_mean=cm[ok], decay_length_graph=_decay_length(lat, d, gcol),
                              decay_length_continuum=_decay_length(lat, d, gc_pos))


@dataclass(frozen=True, eq=False, kw_only=True)
class BoundStateSizes(Result):
    r"""Bound-state size against detuning for one qubit, graph and continuum.

    Energies and frequencies are in units of t; sizes and lengths in the paper's metric.

    Attributes
    ----------
    p, q, rings, site : int
        The flake and the qubit's site (0-based).
    kind : str
        ``"sites"`` or ``"line_graph"``.
    g : float
        Coupling.
    e0 : float
        Band bottom :math:`E_0(\ell)` of the lattice.
    omega_q : ndarray
        Qubit frequencies.
    detuning : ndarray
        :math:`E_0 - \omega_q > 0`.
    energy : ndarray
        Exact bound-state energies.
    size_graph : ndarray
        :math:`\langle d\rangle = \sum_i|\phi_i|^2d_i/\sum_i|\phi_i|^2` of the exact photon profile over
        the sites other than the qubit's (where the continuum diverges).
    size_continuum : ndarray
        The same for the continuum profile ``eq21`` (site lattices only; NaN for line graphs).
    decay_length_graph : ndarray
        Fitted decay length of the exact profile.
    decay_length_asymptotic : ndarray
        :math:`1/(2\Delta(\omega_q))` of the continuum (NaN beyond the continuum BF bound).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.qubits import bound_state_sizes
    >>> bs = bound_state_sizes(hl.ring_lattice(7, 3, 4), [-3.0, -3.5], 0.1)
    >>> [round(float(x), 4) for x in bs.detuning], [round(float(x), 4) for x in bs.size_graph]
    ([0.1534, 0.6534], [0.5638, 0.3691])
    """

    COLUMNS = (Column("omega_q", "omega_q", "t"), Column("detuning", "detuning", "t"), Column("energy", "energy", "t"),
               Column("size_graph", "size_graph", "hyperbolic distance"), Column("size_continuum", "size_continuum", "hyperbolic distance"),
               Column("decay_length_graph", "decay_length_graph", "hyperbolic distance"),
               Column("decay_length_asymptotic", "decay_length_asymptotic", "hyperbolic distance"))

    p: int
    q: int
    rings: int
    kind: str
    site: int
    g: float
    e0: float
    omega_q: np.ndarray
    detuning: np.ndarray
    energy: np.ndarray
    size_graph: np.ndarray
    size_continuum: np.ndarray
    decay_length_graph: np.ndarray
    decay_length_asymptotic: np.ndarray

    def table(self) -> list[list[float]]:
        """Rows ``[omega_q, detuning, E_b, <d>_graph, <d>_continuum, xi_graph, 1/(2 Delta)]``."""
        return [[float(v) for v in row] for row in zip(self.omega_q, self.detuning, self.energy, self.size_graph,
                                                        self.size_continuum, self.decay_length_graph,
                                                        self.decay_length_asymptotic)]


def _mean_distance(amplitude: np.ndarray, d: np.ndarray) -> float:
    w = amplitude**2
    return float(np.sum(w * d) / np.sum(w))


def bound_state_sizes(lattice: Lattice, omegas_q, g, site: int = 0) -> BoundStateSizes:
    r"""Exact bound states (:func:`hyperlattice.graph.qubits.bound_state`) for each :math:`\omega_q` and their sizes.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} flake or its line graph.
    omegas_q : array_like of float
        Qubit frequencies (units of t), each below the band; 1 to 200 of them.
    g : float
        Qubit-photon coupling (units of t).
    site : int, optional
        The qubit's site (0-based). Default 0.

    Returns
    -------
    BoundStateSizes
        Per frequency: ``detuning`` :math:`E_0 - \omega_q`, the bound-state ``energy``, the mean
        distance of the photon profile ``size_graph`` and ``size_continuum`` (NaN on line graphs),
        the fitted ``decay_length_graph`` and the continuum's ``decay_length_asymptotic``
        :math:`1/(2\Delta)`.

    Raises
    ------
    ValueError
        Bad input, no or too many frequencies, a frequency not below the band.

    See Also
    --------
    exchange_comparison

    References
    ----------
    .. [1] P. Bienias et al., Phys. Rev. Lett. 128, 013601 (2022), "curvature-limited size".

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.qubits import bound_state_sizes
    >>> bs = bound_state_sizes(hl.ring_lattice(7, 3, 4), [-3.0, -3.5], 0.1)
    >>> [round(float(x), 4) for x in bs.detuning]
    [0.1534, 0.6534]
    >>> [round(float(x), 4) for x in bs.size_graph]
    [0.5638, 0.3691]
    """
    from ..graph.spectrum import lowest_levels

    lat = _validate.lattice(lattice)
    site = _validate.site_index("site", site, lat.sites)
    om = _validate.real_array("omegas_q", omegas_q, ndim=1)
    if om.size == 0 or om.size > _MAX_POINTS:
        raise ValueError(f"give between 1 and {_MAX_POINTS} qubit frequencies, got {om.size}.")
    g = _validate.real("g", g)
    res = BelowBandResolvent(lat)
    e0 = float(lowest_levels(lat, 1).energies[0])
    E, sg, sc, xg, xa = (np.empty(om.size) for _ in range(5))
    for k, w in enumerate(om):
        bs = bound_state(lat, site, float(w), g, resolvent=res)
        E[k], xg[k] = bs.energy, bs.decay_length
        off = np.arange(lat.sites) != site     # the continuum diverges at the qubit: compare off it
        sg[k] = _mean_distance(bs.photon[off], bs.distance[off])
        sc[k] = (_mean_distance(np.abs(_continuum_site_column(lat, float(w), site)[off]), bs.distance[off])
                 if lat.kind == "sites" else math.nan)
        m2 = float(mass2_from_omega(float(w), lat.p, lat.q)) if lat.kind == "sites" else \
            float(mass2_from_omega(float(w) + lat.q - 2, lat.p, lat.q))
        xa[k] = 1.0 / (2.0 * float(delta_from_mass2(m2))) if m2 >= -1.0 else math.nan
    return BoundStateSizes(p=lat.p, q=lat.q, rings=lat.rings, kind=lat.kind, site=site, g=g, e0=e0, omega_q=om,
                           detuning=e0 - om, energy=E, size_graph=sg, size_continuum=sc, decay_length_graph=xg,
                           decay_length_asymptotic=xa)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
