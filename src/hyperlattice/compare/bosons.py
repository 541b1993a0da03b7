r"""Interacting bosons, graph against continuum: the Gross–Pitaevskii condensate through the dictionary.

For a flake of ℓ rings with N bosons (filling n = N / sites) and interaction U, the graph side is
the discrete GP ground state of :math:`-tA` (:func:`hyperlattice.bosons.gp.gp_ground_state`)
and its Bogoliubov spectrum; the continuum side is the GP state on the Dirichlet disk of the
paper's radius :math:`L(\ell)` (Eq. 10) with :math:`t' = \frac q4h^2t`, :math:`U' = \mathcal A U`
(:func:`hyperlattice.continuum.gp.disk_gp`), whose lattice chemical potential is
:math:`\mu = \mu_c - qt`. Compared: μ, the density per site against the geodesic radius
(:math:`\mathcal A|\varphi|^2` on the continuum side) and the lowest Bogoliubov frequencies.

Where it holds: the continuum replaces :math:`-tA` by :math:`-qt - t'\Delta_g`, the first term of
a gradient expansion on the scale d0, so it needs a condensate that varies slowly on the lattice
scale: a healing length :math:`\xi = \sqrt{t'/(U'n_0)} \gg d_0`. Strong interactions (Un ≳ t)
make ξ ≲ d0 and the dictionary's μ drifts away; the boundary layer of width ~ξ next to the
Dirichlet edge is where the two profiles differ most (the flake's outer ring has fewer
neighbours, the disk a sharp wall).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .. import _validate
from ..results import Column, Result

__all__ = ["GPComparison", "gp_comparison", "MottGapComparison", "mott_gap_comparison", "mean_field_gap"]


@dataclasses.dataclass(frozen=True, eq=False)
class GPComparison(Result):
    r"""GP ground states and Bogoliubov frequencies of flakes and their continuum disks.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    filling : float
        Bosons per site n (N = n × sites on both sides).
    U, t : float
        Lattice interaction and hopping (one energy unit, that of t); the chemical potentials and
        Bogoliubov frequencies in ``rows`` are in that unit, distances in the paper's metric.
    rows : list of dict
        One per ℓ: ``rings, sites, particles, mu_graph, mu_continuum, mu_rel_diff, xi, xi_over_d0,
        bogoliubov_graph, bogoliubov_continuum, bogoliubov_j, residual_graph, residual_continuum``.
    profiles : list of dict
        One per ℓ: ``rho`` (geodesic radius of each ring's sites, mean), ``graph`` (mean density per
        site of each ring), ``continuum`` (:math:`\mathcal A|\varphi|^2` at the same radii).
    d0 : float
        Lattice spacing (geodesic).

    Examples
    --------
    >>> from hyperlattice.compare.bosons import gp_comparison
    >>> cmp = gp_comparison(7, 3, rings=(2,), U=0.5, modes=3, cells=200)
    >>> row = cmp.rows[0]
    >>> row["sites"], row["particles"], [round(float(w), 4) for w in row["bogoliubov_graph"]]
    (35, 35.0, [0.0, 0.4868, 0.4868])
    >>> print(f"{row['mu_graph']:.4f} {row['mu_continuum']:.4f}")
    -1.9540 -1.6160
    """

    p: int
    q: int
    filling: float
    U: float
    t: float
    rows: list
    profiles: list
    d0: float

    def summary(self) -> dict:
        return {"p": self.p, "q": self.q, "filling": self.filling, "U": self.U, "t": self.t, "d0": self.d0,
                "rows": self.rows}


def gp_comparison(p: int = 7, q: int = 3, rings=(3, 4, 5, 6, 7), *, filling: float = 1.0, U: float = 0.5,
                  t: float = 1.0, modes: int = 5, cells: int = 800) -> GPComparison:
    r"""Graph vs continuum GP ground state and Bogoliubov spectrum for flakes of several ℓ.

    Parameters
    ----------
    p, q : int, optional
        Schläfli symbol, :math:`(p-2)(q-2) > 4`. Default {7,3}.
    rings : sequence of int, optional
        Flakes, 1 to 14 rings each (Bogoliubov on the graph: dense up to 3000 sites,
        shift-invert above). Default ``(3, 4, 5, 6, 7)``.
    filling : float, optional
        n = N/sites > 0. Default 1.
    U : float, optional
        Interaction (>= 0, in the energy units of ``t``). Default 0.5.
    t : float, optional
        Hopping (> 0). Default 1.
    modes : int, optional
        Bogoliubov frequencies compared (Goldstone mode included), 2 to 50. Default 5.
    cells : int, optional
        Radial cells of the continuum solution (error ~ cells⁻², 1e-6 relative in μ at 800).
        Default 800.

    Returns
    -------
    GPComparison
        ``rows`` (one dict per ℓ: ``mu_graph``, ``mu_continuum``, ``mu_rel_diff``, the healing
        length ``xi`` and ``xi_over_d0``, the Bogoliubov frequencies of both sides, residuals)
        and ``profiles`` (density against geodesic radius, both sides), with ``d0``.

    Raises
    ------
    ValueError
        If {p,q} is not hyperbolic or an argument is out of its range.
    hyperlattice.errors.ConvergenceError
        If a graph Bogoliubov matrix is not positive definite (the state found is not a GP
        ground state).

    See Also
    --------
    hyperlattice.bosons.gp.gp_ground_state, hyperlattice.bosons.gp.bogoliubov
    hyperlattice.continuum.gp.disk_gp

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020): the continuum Bose–Hubbard
       model and its parameters :math:`t'`, :math:`U'` (source labels ``eq13``, ``eq14``).

    Examples
    --------
    >>> from hyperlattice.compare.bosons import gp_comparison
    >>> cmp = gp_comparison(7, 3, rings=(2,), U=0.5, modes=3, cells=200)
    >>> row = cmp.rows[0]
    >>> row["sites"], [round(float(w), 4) for w in row["bogoliubov_graph"]]
    (35, [0.0, 0.4868, 0.4868])
    >>> print(f"{row['mu_graph']:.4f} {row['mu_continuum']:.4f}")
    -1.9540 -1.6160
    """
    from ..bosons.gp import bogoliubov, gp_ground_state
    from ..continuum.gp import disk_bogoliubov, disk_gp, healing_length
    from ..dictionary import continuum_parameters, disk_radius_for_rings
    from ..geometry import d0 as lattice_d0
    from ..graph.lattice import ring_lattice

    p, q = _validate.pq(p, q)
    ells = _validate.int_list("rings", rings, minimum=1, maximum=14)
    n = _validate.positive_real("filling", filling)
    U = _validate.real("U", U, minimum=0.0)
    t = _validate.positive_real("t", t)
    modes = _validate.integer("modes", modes, minimum=2, maximum=50)
    cp = continuum_parameters(t, 0.0, U, p, q)
    dd = lattice_d0(p, q)
    rows, profiles = [], []
    for ell in ells:
        lat = ring_lattice(p, q, ell)
        N = n * lat.sites
        g = gp_ground_state(lat, N, U, t)
        L, _ = disk_radius_for_rings(ell, p, q)
        c = disk_gp(L, cp.t_prime, cp.U_prime, N, cells=cells)
        xi = healing_length(c)
        kb = min(modes, lat.sites - 2)
        bg = bogoliubov(g, lat, kb).frequencies if U > 0 else np.array([])
        bc = disk_bogoliubov(c, kb) if U > 0 else None
        mu_c = c.mu_c - q * t
        rows.append({"rings": ell, "sites": lat.sites, "particles": N, "mu_graph": g.mu, "mu_continuum": mu_c,
                     "mu_rel_diff": (mu_c - g.mu) / abs(g.mu) if g.mu else math.nan,
                     "xi": xi, "xi_over_d0": xi / dd,
                     "bogoliubov_graph": bg.tolist(),
                     "bogoliubov_continuum": bc.frequencies.tolist() if bc is not None else [],
                     "bogoliubov_j": bc.angular_momenta.tolist() if bc is not None else [],
                     "residual_graph": g.residual, "residual_continuum": c.residual})
        rho_site = np.arctanh(np.abs(np.asarray(lat.z)))
        ring = np.asarray(lat.ring)
        rho_ring = np.array([rho_site[ring == k].mean() for k in range(1, ell + 1)])
        dens_ring = np.array([g.density[ring == k].mean() for k in range(1, ell + 1)])
        cont = cp.site_area * np.interp(rho_ring, c.rho, c.f**2, right=0.0)
        profiles.append({"rings": ell, "rho": rho_ring.tolist(), "graph": dens_ring.tolist(),
                         "continuum": cont.tolist(), "rho_max": c.rho_max})
    return GPComparison(p=p, q=q, filling=n, U=U, t=t, rows=rows, profiles=profiles, d0=dd)


def mean_field_gap(lambda_max: float, t_over_U, filling: int = 1) -> float | np.ndarray:
    r"""The mean-field Mott gap :math:`\Delta/U = \sqrt{(1 - x)^2 - 4nx}`, :math:`x = \lambda_{\max} t/U`.

    The width in :math:`\mu/U` of the lobe of filling n at hopping t (the two roots of
    :math:`t\lambda_{\max} g_n(\mu) = 1`); 0 beyond the tip.

    Parameters
    ----------
    lambda_max : float
        Largest adjacency eigenvalue of the graph (> 0).
    t_over_U : float or array_like of float
        Hopping over interaction, >= 0.
    filling : int, optional
        Lobe filling n >= 1. Default 1.

    Returns
    -------
    float or ndarray
        :math:`\Delta/U`, of the shape of ``t_over_U``; 1 at t = 0, 0 beyond the lobe tip.

    Raises
    ------
    ValueError
        If ``lambda_max`` is not positive, ``filling`` < 1 or a ``t_over_U`` is negative.

    See Also
    --------
    hyperlattice.bosons.meanfield.mott_lobe

    Examples
    --------
    >>> from hyperlattice.compare.bosons import mean_field_gap
    >>> [round(float(g), 6) for g in mean_field_gap(3.0, [0.0, 0.02, 0.2])]
    [1.0, 0.802247, 0.0]
    """
    lam = _validate.positive_real("lambda_max", lambda_max)
    n = _validate.integer("filling", filling, minimum=1, maximum=10**6)
    x = lam * (_validate.real_array("t_over_U", t_over_U) if np.ndim(t_over_U) else
               np.asarray(_validate.real("t_over_U", t_over_U, minimum=0.0)))
    if np.any(x < 0):
        raise ValueError("t_over_U must be >= 0.")
    disc = (1.0 - x) ** 2 - 4.0 * n * x
    gap = np.where((disc > 0) & (x < 1.0), np.sqrt(np.clip(disc, 0.0, None)), 0.0)
    return float(gap) if gap.ndim == 0 else gap


@dataclasses.dataclass(frozen=True, eq=False)
class MottGapComparison(Result):
    r"""The charge gap of a small system at filling n: exact diagonalisation against mean field.

    Attributes
    ----------
    label : str
        What the system is (e.g. ``"{7,3} flake, l = 1"``).
    sites, particles, nmax : int
        M, N (filling times M) and the occupation cutoff of the exact diagonalisation.
    lambda_max : float
        Of the graph (mean field's only input).
    lambda_max_continuum : float or None
        The continuum disk's (flakes only), for the continuum mean-field gap.
    t_over_U, gap_ed, gap_mean_field, gap_continuum : ndarray
        Gaps in units of U (the continuum column NaN for a cluster).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.bosons import mott_gap_comparison
    >>> cmp = mott_gap_comparison(hl.ring_lattice(7, 3, 1), [0.0, 0.05])
    >>> cmp.label, cmp.particles, cmp.nmax, round(cmp.lambda_max, 4)
    ('{7,3} flake, l = 1', 7, 8, 2.0)
    >>> [round(float(g), 4) for g in cmp.gap_ed], [round(float(g), 4) for g in cmp.gap_mean_field]
    ([1.0, 0.7134], [1.0, 0.6403])
    """

    COLUMNS = (Column("t_over_U", "t_over_U", "1"), Column("gap_ed", "gap_ed", "U"),
               Column("gap_mean_field", "gap_mean_field", "U"), Column("gap_continuum", "gap_continuum", "U"))

    label: str
    sites: int
    particles: int
    nmax: int
    lambda_max: float
    lambda_max_continuum: float | None
    t_over_U: np.ndarray
    gap_ed: np.ndarray
    gap_mean_field: np.ndarray
    gap_continuum: np.ndarray

    def rows(self) -> list[dict]:
        return [{"t_over_U": float(t), "gap_ed": float(a), "gap_mean_field": float(b), "gap_continuum": float(c)}
                for t, a, b, c in zip(self.t_over_U, self.gap_ed, self.gap_mean_field, self.gap_continuum)]

    def summary(self) -> dict:
        return {"label": self.label, "sites": self.sites, "particles": self.particles, "nmax": self.nmax,
                "lambda_max": self.lambda_max, "lambda_max_continuum": self.lambda_max_continuum,
                "rows": self.rows()}


def mott_gap_comparison(system, t_over_U=(0.0, 0.02, 0.04, 0.06, 0.08, 0.1, 0.15, 0.2), *, filling: int = 1,
                        nmax: int | None = None) -> MottGapComparison:
    r"""Exact charge gap :math:`E_0(N+1) + E_0(N-1) - 2E_0(N)` (N = n × sites) against the mean-field gap.

    Parameters
    ----------
    system : Lattice or Cluster
        Small: the basis of N + 1 bosons must fit (the heptagon ``ring_lattice(7, 3, 1)`` is exact
        with the default nmax).
    t_over_U : sequence of float, optional
        Hopping values (U = 1), each >= 0. Default ``(0, 0.02, ..., 0.2)``.
    filling : int, optional
        Filling n, 1 to 100. Default 1.
    nmax : int, optional
        Occupation cutoff, 1 to N + 1; default N + 1 (no truncation).

    Returns
    -------
    MottGapComparison
        ``t_over_U`` and the gaps in units of U: ``gap_ed`` (exact), ``gap_mean_field`` (graph
        mean field with ``lambda_max``) and ``gap_continuum`` (mean field with the continuum
        disk's ``lambda_max_continuum``; NaN for a cluster).

    Raises
    ------
    ValueError
        If ``system`` is not a Lattice or Cluster, ``t_over_U`` is empty or negative, or an
        argument is out of range.
    MemoryError
        When the basis of N + 1 bosons would not fit.

    See Also
    --------
    hyperlattice.bosons.ed.charge_gap, mean_field_gap

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.bosons import mott_gap_comparison
    >>> cmp = mott_gap_comparison(hl.ring_lattice(7, 3, 1), [0.0, 0.05])
    >>> cmp.particles, cmp.nmax
    (7, 8)
    >>> [round(float(g), 4) for g in cmp.gap_ed], [round(float(g), 4) for g in cmp.gap_mean_field]
    ([1.0, 0.7134], [1.0, 0.6403])
    """
    from ..bosons.ed import charge_gap
    from ..bosons.meanfield import _system_label, largest_adjacency_eigenvalue

    n = _validate.integer("filling", filling, minimum=1, maximum=100)
    ts = _validate.real_array("t_over_U", t_over_U, ndim=1)
    if ts.size == 0 or np.any(ts < 0):
        raise ValueError("t_over_U must be a non-empty list of values >= 0.")
    sites = int(system.sites) if hasattr(system, "sites") else None
    if sites is None:
        raise ValueError(f"system must be a Lattice or a Cluster, got {_validate._shown(system)}.")
    N = n * sites
    nmax = N + 1 if nmax is None else _validate.integer("nmax", nmax, minimum=1, maximum=N + 1)
    lam = largest_adjacency_eigenvalue(system)
    lam_c = None
    if hasattr(system, "ring_offsets") and getattr(system, "kind", "sites") == "sites":
        from ..continuum.spectrum import continuum_levels

        e0 = -float(continuum_levels(system.p, system.q, rings=system.rings, levels=1).energies[0])
        lam_c = e0 if e0 > 0 else None
    ed = np.array([charge_gap(system, N, nmax, 1.0, t=float(t)).gap for t in ts])
    mf = mean_field_gap(lam, ts, n)
    cont = mean_field_gap(lam_c, ts, n) if lam_c is not None else np.full(ts.shape, np.nan)
    return MottGapComparison(label=_system_label(system), sites=sites, particles=N, nmax=nmax, lambda_max=lam,
                             lambda_max_continuum=lam_c, t_over_U=ts, gap_ed=ed, gap_mean_field=mf,
                             gap_continuum=cont)


# every public function above checks its arguments at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
