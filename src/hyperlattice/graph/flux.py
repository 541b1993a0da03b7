r"""A uniform magnetic field on the graph: Peierls phases in a rotation-symmetric gauge.

Convention
----------
A lattice gets a uniform field of ``flux = f`` flux quanta through each p-gon face of the
{p,q} tiling. The Hamiltonian is

.. math:: H = -t \sum_{i \sim j} e^{i\theta_{ij}}\, c_i^\dagger c_j + \sum_i V_i c_i^\dagger c_i,
          \qquad \theta_{ij} = \int_{z_j}^{z_i} A = -\theta_{ji},

(a particle of unit charge, :math:`\hbar = 1`, flux quantum :math:`2\pi`), the integral taken
along the geodesic edge from site j to site i. Positive f is a counterclockwise flux: the
phases summed counterclockwise around a face add up to :math:`+2\pi f \times` (area of the
face / area of one p-gon).

The gauge
---------
With the paper's metric :math:`ds^2 = |dz|^2/(1-|z|^2)^2` (curvature -4, area element
:math:`dx\,dy/(1-r^2)^2`) the one-form

.. math:: A = \frac{B r^2}{2(1 - r^2)}\, d\phi = \frac{B\, \mathrm{Im}(\bar z\, dz)}{2(1 - |z|^2)}

has :math:`dA = B\, r\,dr\,d\phi/(1-r^2)^2`, a uniform field B (the disk of radius r has area
:math:`\pi r^2/(1-r^2)`), and is invariant under rotations about the origin, so the p-fold
rotation of the flake stays a symmetry of H. A has no dr part, so by Stokes the integral of A
along the geodesic from a to b is B times the signed area of the geodesic triangle (0, a, b)
(the radial sides contribute nothing). That area is

.. math:: S(0, a, b) = \tfrac12 \arg(1 - a \bar b) \in (-\pi/4, \pi/4),

counterclockwise positive: the Möbius map :math:`w = (z - a)/(1 - \bar a z)` moves a to the
origin, where the angle defect :math:`(\pi - \alpha - \beta - \gamma)/4` of the triangle
reduces to this argument (checked in the tests against the angle defect and against
quadrature of A). It needs no cancellation: :math:`\mathrm{Re}(1 - a\bar b) > 0` for points
in the disk. The field strength follows from :math:`B \cdot A_p = 2\pi f` with the p-gon
area :math:`A_p = ((p-2)\pi - 2\pi p/q)/4` in curvature -4.
"""

from __future__ import annotations

import numpy as np

from .. import _validate
from .lattice import Lattice

__all__ = ["pgon_area", "field_strength", "triangle_area", "edge_phases", "faces", "face_areas",
           "face_fluxes", "check_face_fluxes"]


#: Largest |f| accepted: the phases are B x area with B = 2 pi f / A_p, so beyond about 1e6
#: flux quanta per p-gon their absolute rounding error (|theta| x 1e-16) exceeds 1e-9.
MAX_FLUX = 1e6


def _flux(value) -> float:
    """The flux f as a checked float (the one door for every function taking ``flux``)."""
    f = _validate.real("the flux f", value)
    if abs(f) > MAX_FLUX:
        raise ValueError(f"the flux f must be at most {MAX_FLUX:g} flux quanta per p-gon in magnitude "
                         f"(beyond it the Peierls phases lose their precision), got {f:g}.")
    return f


def pgon_area(p: int, q: int) -> float:
    r"""Hyperbolic area of one p-gon face of the {p,q} tiling, :math:`((p-2)\pi - 2\pi p/q)/4`.

    In the paper's metric (curvature -4, hence the 1/4 of the Gauss-Bonnet angle defect).
    """
    p, q = _validate.pq(p, q)
    return ((p - 2) * np.pi - 2 * np.pi * p / q) / 4.0


def field_strength(flux, p: int, q: int) -> float:
    r"""The uniform field B with ``flux`` quanta through one p-gon: :math:`B = 2\pi f / A_p`.

    (Local to the graph side until the dictionary carries the f <-> B map.)
    """
    return 2 * np.pi * _flux(flux) / pgon_area(p, q)


def triangle_area(a, b) -> np.ndarray:
    r"""Signed hyperbolic area :math:`\tfrac12\arg(1 - a\bar b)` of the geodesic triangle (0, a, b).

    Counterclockwise (0 -> a -> b) positive; curvature -4 metric. Vectorised over a and b.
    """
    a = np.asarray(a, dtype=np.complex128)
    b = np.asarray(b, dtype=np.complex128)
    return 0.5 * np.angle(1.0 - a * np.conj(b))


def edge_phases(lattice: Lattice, flux) -> np.ndarray:
    r"""Peierls phases :math:`\theta_{ij} = \int_{z_j}^{z_i} A` for the rows (i, j) of ``lattice.edges``.

    Returns float64 of shape (E,); the phase of the reverse hop j <- i is the negative.
    """
    _validate.lattice(lattice)
    b = field_strength(flux, lattice.p, lattice.q)
    e = lattice.edges.astype(np.int64)
    z = np.asarray(lattice.z, dtype=np.complex128)
    return b * triangle_area(z[e[:, 1]], z[e[:, 0]])


def _tangent_angles(z: np.ndarray, i: np.ndarray, j: np.ndarray) -> np.ndarray:
    """Direction of the geodesic from z_i towards z_j at z_i (Möbius map of z_i to 0; conformal)."""
    zi, zj = z[i], z[j]
    w = (zj - zi) / (1.0 - np.conj(zi) * zj)
    return np.angle(w)


def faces(lattice: Lattice) -> list[np.ndarray]:
    """The bounded faces of the embedded graph (geodesic edges), each a ccw cycle of sites.

    Built from the rotation system: the neighbours of every site sorted by the direction of
    the geodesic edge at the site; following each directed edge u -> v with the next
    neighbour of v clockwise after u traces the face on its left. The one clockwise cycle
    (the outer face) is dropped.
    """
    _validate.lattice(lattice)
    z = np.asarray(lattice.z, dtype=np.complex128)
    indptr, indices = lattice.neighbours()
    n = lattice.sites
    src = np.repeat(np.arange(n), np.diff(indptr))
    ang = _tangent_angles(z, src, indices.astype(np.int64))
    order = np.lexsort((ang, src))  # ccw around every site
    nb = indices[order].astype(np.int64)
    # position of dart (u, v) in u's ccw list, for the lookup "v's list, where is u"
    pos = {}
    for k in range(nb.shape[0]):
        pos[(int(src[k]), int(nb[k]))] = k
    used = np.zeros(nb.shape[0], dtype=bool)
    out = []
    for k0 in range(nb.shape[0]):
        if used[k0]:
            continue
        cycle = []
        k = k0
        while not used[k]:
            used[k] = True
            u, v = int(src[k]), int(nb[k])
            cycle.append(u)
            kv = pos[(v, u)]                       # u in v's ccw list
            lo, hi = indptr[v], indptr[v + 1]
            k = lo + (kv - lo - 1) % (hi - lo)     # the previous one ccw = next clockwise
        cyc = np.array(cycle, dtype=np.int64)
        zc = z[cyc]
        if np.sum(triangle_area(zc, np.roll(zc, -1))) > 0:
            out.append(cyc)
    return out


def face_areas(lattice: Lattice, cycles: list[np.ndarray]) -> np.ndarray:
    r"""Hyperbolic areas of geodesic polygons from their angles: :math:`((k-2)\pi - \sum\alpha)/4`.

    Independent of :func:`triangle_area` (Gauss-Bonnet with the interior angles measured by
    Möbius maps), so it checks the phases.
    """
    z = np.asarray(lattice.z, dtype=np.complex128)
    areas = np.empty(len(cycles))
    for c, cyc in enumerate(cycles):
        prev, nxt = np.roll(cyc, 1), np.roll(cyc, -1)
        alpha = np.mod(_tangent_angles(z, cyc, prev) - _tangent_angles(z, cyc, nxt), 2 * np.pi)
        areas[c] = ((cyc.shape[0] - 2) * np.pi - np.sum(alpha)) / 4.0
    return areas


def face_fluxes(lattice: Lattice, flux, cycles: list[np.ndarray] | None = None,
                phases: np.ndarray | None = None) -> np.ndarray:
    """Sum of the Peierls phases counterclockwise around each bounded face (not reduced mod 2 pi)."""
    if cycles is None:
        cycles = faces(lattice)
    if phases is None:
        phases = edge_phases(lattice, flux)
    e = lattice.edges.astype(np.int64)
    lookup = {}
    for k in range(e.shape[0]):
        i, j = int(e[k, 0]), int(e[k, 1])
        lookup[(i, j)] = phases[k]        # theta_ij: hop j -> i
        lookup[(j, i)] = -phases[k]
    out = np.empty(len(cycles))
    for c, cyc in enumerate(cycles):
        nxt = np.roll(cyc, -1)
        # going u -> v picks up theta_{vu}
        out[c] = sum(lookup[(int(v), int(u))] for u, v in zip(cyc, nxt))
    return out


def check_face_fluxes(lattice: Lattice, flux, tol: float = 1e-12) -> float:
    r"""Largest deviation of a face flux from :math:`2\pi f \times` area / p-gon area.

    Raises ValueError if it exceeds ``tol`` (relative to :math:`\max(1, 2\pi|f|)`).
    """
    f = _flux(flux)
    tol = _validate.positive_real("tol", tol)
    cycles = faces(lattice)
    want = 2 * np.pi * f * face_areas(lattice, cycles) / pgon_area(lattice.p, lattice.q)
    got = face_fluxes(lattice, f, cycles)
    dev = float(np.max(np.abs(got - want))) if cycles else 0.0
    if dev > tol * max(1.0, 2 * np.pi * abs(f)):
        raise ValueError(f"face fluxes deviate from 2 pi f x area ratio by {dev:.2e}.")
    return dev
