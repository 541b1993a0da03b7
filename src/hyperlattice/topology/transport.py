r"""Two-terminal conductance of a flake through wide-band leads (Landauer–Caroli).

Two leads are attached to two arcs of the flake's edge. A wide-band lead coupled with strength
:math:`\gamma` (units of the hopping t) to every orbital of its contact sites adds the
energy-independent self-energy :math:`\Sigma_{L,R} = -\tfrac{i}{2}\Gamma_{L,R}`,
:math:`\Gamma_{L,R} = \gamma\,\Pi_{L,R}` (:math:`\Pi` the projector on the contact rows): the
same input–output coupling as the device room's ports (:mod:`hyperlattice.device.transmission`),
here with a matrix-valued Hamiltonian. The retarded Green function is
:math:`G^R(E) = (E - H - \Sigma_L - \Sigma_R)^{-1}` and the Caroli formula (Caroli, Combescot,
Nozières and Saint-James, J. Phys. C 4, 916 (1971); Meir and Wingreen, PRL 68, 2512 (1992))

.. math::

    G = \frac{e^2}{h}\,T(E),\qquad T(E) = \mathrm{Tr}[\Gamma_L G^R \Gamma_R G^A]
      = \gamma^2 \sum_{l \in L,\, r \in R} |G^R_{lr}(E)|^2

gives the linear conductance at zero temperature in units of :math:`e^2/h` (every orbital is one
spin-less channel; Kane–Mele's two spins are two orbitals, so its T counts both).

One sparse LU of :math:`E - H - \Sigma` per energy (SuperLU), solved for the columns of the right
contact. Current conservation, :math:`G^R - G^A = -iG^A(\Gamma_L + \Gamma_R)G^R`, gives T a
second time from the same columns, :math:`T = \gamma\sum_{r}(-2\,\mathrm{Im}\,G^R_{rr}) -
\gamma^2\sum_{r,r'\in R}|G^R_{r'r}|^2` (what enters the right lead minus what it reflects); the
difference of the two forms is the error of the solve and is reported (``error``).

In the bulk gap of a Chern insulator only the chiral edge channels carry current: each edge
between the contacts carries one channel in one direction, so :math:`T = |C|` once the leads
absorb the edge channel (contacts longer than the channel's decay length along the edge, and
:math:`\gamma` of the order of the bandwidth). Outside the gap bulk states enter and T is not
quantised.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..results import Column, Result
from .markers import _geometry, _rows
from .models import model_hamiltonian, model_terms

__all__ = ["Conductance", "conductance", "edge_contacts", "MAX_ROWS", "MAX_ENERGIES"]

#: the sparse LU route is refused above this many rows (the {8,3} l = 7 flake has 80,656)
MAX_ROWS = 200_000
#: most energies one call takes
MAX_ENERGIES = 100_000
#: the two forms of T differing by more than this (times the contact rows) warns: the solve lost its digits
RECIPROCITY_TOL = 1e-8
#: right-hand sides per SuperLU solve (its solve slows down more than linearly with many at once)
_BLOCK = 16


def edge_contacts(graph, arc: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """The default contacts: the edge sites within two opposite arcs of the flake's boundary.

    The boundary is every site of degree below the bulk degree and, on a {p,q} flake, the whole
    outer ring. Seen from the flake's centre (in the chart recentred there), the left contact is
    the boundary sites whose polar angle lies within ``arc``·π of π, the right contact those
    within ``arc``·π of 0: each contact spans the fraction ``arc`` of the full turn.

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        An open flake.
    arc : float, optional
        Fraction of the full turn each contact spans, in (0, 0.5]; default 0.25 (a quarter).

    Returns
    -------
    left, right : ndarray of int
        Site indices of the two contacts, ascending.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.topology.transport import edge_contacts
    >>> left, right = edge_contacts(hl.ring_lattice(8, 3, 3))
    >>> len(left), len(right)
    (39, 39)
    """
    arc = _validate.real("arc", arc, minimum=1e-6, maximum=0.5)
    if arc >= 0.5:
        raise ValueError("arc must be below one half: the two contacts would overlap.")
    geo = _geometry(graph)
    edge = geo.boundary
    if geo.hyperbolic:
        edge = np.union1d(edge, np.flatnonzero(geo.ring == geo.ring.max()))
    centre = 0j if geo.hyperbolic else complex(geo.z.mean())
    theta = np.angle(geo.recentre(centre, geo.z[edge]))
    # a site exactly on an arc's end would be in or out by rounding: the ends are widened by a tolerance
    tol = 1e-9
    right = edge[np.abs(theta) <= arc * np.pi + tol]
    left = edge[np.abs(np.angle(-np.exp(1j * theta))) <= arc * np.pi + tol]
    if len(left) == 0 or len(right) == 0:
        raise ValueError(f"no boundary site lies within an arc of {arc:g} of a turn: widen the contacts.")
    return np.sort(left), np.sort(right)


@dataclass(frozen=True, eq=False, kw_only=True)
class Conductance(Result):
    r"""The two-terminal conductance of a flake against energy, in units of :math:`e^2/h`.

    Attributes
    ----------
    model : str
        The model.
    parameters : dict
        Its parameters and the leads' (``coupling`` γ in t, ``arc``).
    energies : ndarray, shape (F,)
        Energies E (units of t).
    conductance : ndarray, shape (F,)
        :math:`T_{LR}(E)`, the conductance in units of :math:`e^2/h`.
    error : ndarray, shape (F,)
        The difference between T and its current-conservation form: zero up to the rounding of
        the solve.
    left, right : ndarray of int
        The contacts' sites.
    sites : int
        Sites of the flake.
    method : str
        ``"sparse LU"``.

    Examples
    --------
    >>> from hyperlattice.topology import square_flake
    >>> from hyperlattice.topology.transport import conductance
    >>> g = conductance(square_flake(10), "qwz", M=1.0, energies=[0.0])
    >>> round(float(g.conductance[0]), 2)
    1.0
    """

    COLUMNS = (Column("energy", "energies", "t"), Column("conductance", "conductance", "e^2/h"),
               Column("error", "error", "e^2/h"))

    model: str
    parameters: dict
    energies: np.ndarray
    conductance: np.ndarray
    error: np.ndarray
    left: np.ndarray
    right: np.ndarray
    sites: int
    method: str

    def summary(self) -> dict:
        """The CLI's JSON: energies (t), conductance and error (e²/h), contacts and parameters."""
        return {"model": self.model, "sites": self.sites, "units": {"energy": "t", "conductance": "e^2/h"},
                "energy": [float(x) for x in self.energies],
                "conductance_e2h": [float(x) for x in self.conductance],
                "error_e2h": [float(x) for x in self.error], "left_sites": len(self.left),
                "right_sites": len(self.right), "method": self.method, "parameters": self.parameters}


def _energies(energies) -> np.ndarray:
    e = _validate.real_array("energies", energies)
    e = np.atleast_1d(e).astype(float).ravel()
    if e.size == 0:
        raise ValueError("energies must hold at least one energy.")
    if e.size > MAX_ENERGIES:
        raise ValueError(f"at most {MAX_ENERGIES:,} energies per call, got {e.size:,}.")
    if not np.all(np.isfinite(e)):
        raise ValueError("energies must be finite numbers.")
    return e


def conductance(graph, model: str = "qwz", *, energies=(0.0,), M: float = 1.0, t2: float = 0.2,
                phi: float = np.pi / 2, rashba: float = 0.0, flux: float = 0.0, disorder: float = 0.0,
                seed: int = 0, coupling: float = 2.0, arc: float = 0.25, contacts=None,
                frame: str = "chord") -> Conductance:
    r"""Two-terminal conductance :math:`G = (e^2/h)\,\mathrm{Tr}[\Gamma_L G^R \Gamma_R G^A]` (module docstring).

    Parameters
    ----------
    graph : Lattice or PlaneGraph
        An open flake.
    model : {"qwz", "haldane", "kane-mele"}
        The model.
    energies : float or array of float, optional
        Energies E (units of t); default ``(0.0,)``, the middle of the gap.
    M, t2, phi, rashba, flux, disorder, seed, frame : optional
        Model parameters (:func:`~hyperlattice.topology.models.model_terms`).
    coupling : float, optional
        γ, the wide-band leads' coupling to every orbital of a contact site (units of t, the
        broadening :math:`\Gamma`), default 2.
    arc : float, optional
        Fraction of the full turn each default contact spans (:func:`edge_contacts`), default 0.25.
    contacts : (sequence of int, sequence of int), optional
        The left and right contact sites instead of the default arcs (disjoint, non-empty).

    Returns
    -------
    Conductance

    Raises
    ------
    ValueError
        Bad model parameters, non-finite energies, overlapping or empty contacts, more than
        :data:`MAX_ROWS` rows, or an energy at which :math:`E - H - \Sigma` is singular (an
        eigenstate with no weight on either contact, exactly at E).
    """
    e = _energies(energies)
    gamma = _validate.real("coupling", coupling, minimum=1e-12, maximum=1e12)
    geo = _geometry(graph)
    n = len(geo.z)
    if contacts is None:
        left, right = edge_contacts(graph, arc)
    else:
        if not isinstance(contacts, (tuple, list)) or len(contacts) != 2:
            raise ValueError("contacts must be a pair (left sites, right sites).")
        left = np.unique(_validate.site_indices("contacts[0]", contacts[0], n))
        right = np.unique(_validate.site_indices("contacts[1]", contacts[1], n))
        if len(left) == 0 or len(right) == 0:
            raise ValueError("each contact needs at least one site.")
        if np.intersect1d(left, right).size:
            raise ValueError("the two contacts share a site; they must be disjoint.")
    terms = model_terms(graph, model, M=M, t2=t2, phi=phi, rashba=rashba, flux=flux, disorder=disorder, seed=seed,
                        frame=frame)
    d = terms.orbitals
    rows = n * d
    if rows > MAX_ROWS:
        raise ValueError(f"the conductance of {rows:,} rows is refused (at most {MAX_ROWS:,}).")
    # SuperLU's fill on these planar-like graphs stays within ~100 entries per row (measured); 16 bytes each
    _validate.require_memory("the sparse LU of E - H - Sigma", 16.0 * 200 * rows)
    rl, rr = _rows(left, d), _rows(right, d)
    H = model_hamiltonian(terms).tocsc().astype(np.complex128)
    gam = np.zeros(rows)
    gam[rl] = gamma
    gam[rr] = gamma
    heff = (H - sp.diags(0.5j * gam)).tocsc()
    ident = sp.identity(rows, dtype=np.complex128, format="csc")
    from scipy.sparse.linalg import splu

    t_lr = np.empty(e.size)
    err = np.empty(e.size)
    singular = ("E - H - Sigma is singular at E = {:.12g}: a state with no weight on either contact sits "
                "exactly there; move the energy.")
    for f, E in enumerate(e):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error", sp.SparseEfficiencyWarning)
                lu = splu((E * ident - heff).tocsc(), permc_spec="COLAMD")
            # SuperLU's solve slows down more than linearly with many right-hand sides: blocks of 16
            x = np.empty((len(rr), len(rr)), np.complex128), np.empty((len(rl), len(rr)), np.complex128)
            for a in range(0, len(rr), _BLOCK):
                b = np.zeros((rows, min(_BLOCK, len(rr) - a)), np.complex128, order="F")
                b[rr[a:a + _BLOCK], np.arange(b.shape[1])] = 1.0
                col = lu.solve(b)
                x[0][:, a:a + b.shape[1]] = col[rr]
                x[1][:, a:a + b.shape[1]] = col[rl]
        except (RuntimeError, sp.SparseEfficiencyWarning):
            raise ValueError(singular.format(E)) from None
        g_rr, g_lr = x
        if not (np.all(np.isfinite(g_rr)) and np.all(np.isfinite(g_lr))):
            raise ValueError(singular.format(E))
        t_lr[f] = gamma * gamma * float(np.sum(np.abs(g_lr) ** 2))
        # current conservation, column by column: -2 Im G_rr = gamma sum_k |G_kr|^2 over all contact rows k
        t_cons = gamma * float(-2.0 * np.sum(np.diag(g_rr).imag)) - gamma * gamma * float(np.sum(np.abs(g_rr) ** 2))
        err[f] = abs(t_lr[f] - t_cons)
    if np.any(err > RECIPROCITY_TOL * np.maximum(1.0, len(rr) * 1.0)):
        from ..errors import ConvergenceWarning

        warnings.warn(f"the transmission and the current-conservation sum differ by {err.max():.1e}: the sparse "
                      "solve lost digits (a level with almost no weight on the contacts sits near one of the "
                      "energies).", ConvergenceWarning, stacklevel=2)
    params = dict(M=M, t2=t2, phi=phi, rashba=rashba, flux=flux, disorder=disorder, seed=seed, frame=frame,
                  coupling=gamma, arc=arc if contacts is None else None)
    return Conductance(model=model, parameters=params, energies=e, conductance=t_lr, error=err,
                       left=left, right=right, sites=n, method="sparse LU")


from .._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
