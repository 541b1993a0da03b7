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
face / area of one p-gon). In the continuum limit the hops become the covariant derivative
:math:`\nabla - iA`, i.e. :math:`-\Delta_B` with :math:`(\nabla - iA)^2`; for f > 0 the term
:math:`-B L_z` favours positive angular momentum, and the lowest levels of a flake carry
m = 0, 1, 2, ... (mod p) in the labels of :mod:`hyperlattice.graph.symmetry`.

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

Faces and checks
----------------
:func:`faces` enumerates the bounded faces of the embedded graph (rotation system), :func:`face_areas`
measures them by their angles (Gauss-Bonnet, independent of the phases) and
:func:`check_face_fluxes` verifies that each carries :math:`2\pi f \times` area / :math:`A_p`.
:func:`hyperlattice.graph.butterfly.butterfly` gives all levels against f sector by sector (the hyperbolic
Hofstadter butterfly).
"""

from __future__ import annotations

import numbers

import numpy as np

from .. import _validate
from ..dictionary import field_from_flux
from .lattice import Lattice


__all__ = ["pgon_area", "field_strength", "triangle_area", "edge_phases", "faces", "face_areas",
           "face_fluxes", "check_face_fluxes", "MAX_FLUX"]


#: Largest ``|f|`` accepted: the phases are B x area with B = 2 pi f / A_p, so beyond about 1e6
#: flux quanta per p-gon their absolute rounding error (``|theta|`` x 1e-16) exceeds 1e-9.
MAX_FLUX = 1e6


def _flux(value) -> float:
    """The flux f as a checked float (the one door for every function taking ``flux``)."""
    f = _validate.real("the flux f", value)
    if abs(f) > MAX_FLUX:
        raise ValueError(f"the flux f must be at most {MAX_FLUX:g} flux quanta per p-gon in magnitude "
                         f"(beyond it the Peierls phases lose their precision), got {f:g}.")
    return f


def pgon_area(p: int, q: int) -> float:
    r"""Hyperbolic area of one p-gon face of the {p,q} tiling.

    .. math:: A_p = \frac{(p-2)\pi - 2\pi p/q}{4}

    in the paper's metric :math:`ds^2 = (dx^2+dy^2)/(1-|z|^2)^2` (curvature -4, hence the 1/4
    of the Gauss-Bonnet angle defect).

    Parameters
    ----------
    p, q : int
        Hyperbolic Schläfli symbol, :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    float
        The area :math:`A_p` in units of the metric (dimensionless, curvature -4).

    Raises
    ------
    ValueError
        For a non-hyperbolic or non-integer {p,q}.

    See Also
    --------
    field_strength, face_areas

    Examples
    --------
    >>> from hyperlattice.graph.flux import pgon_area
    >>> round(pgon_area(7, 3), 6)   # pi/12
    0.261799
    """
    p, q = _validate.pq(p, q)
    return ((p - 2) * np.pi - 2 * np.pi * p / q) / 4.0


def field_strength(flux, p: int, q: int) -> float:
    r"""The uniform field B with ``flux`` quanta through one p-gon: :math:`B = 2\pi f / A_p`.

    The map itself is the dictionary's (:func:`hyperlattice.dictionary.field_from_flux`); this
    adds the flux range check of this module.

    Parameters
    ----------
    flux : float
        Flux quanta f through one p-gon face (positive = counterclockwise), at most 1e6 in
        magnitude.
    p, q : int
        Hyperbolic Schläfli symbol.

    Returns
    -------
    float
        B per unit area of the metric (curvature -4), with flux quantum :math:`2\pi`.

    Raises
    ------
    ValueError
        If ``flux`` is not a finite real number of magnitude at most 1e6, or {p,q} is invalid.

    See Also
    --------
    pgon_area, hyperlattice.dictionary.field_from_flux

    Examples
    --------
    >>> from hyperlattice.graph.flux import field_strength
    >>> round(field_strength(0.1, 7, 3), 6)
    2.4
    """
    return float(field_from_flux(_flux(flux), p, q))


def triangle_area(a, b) -> np.ndarray:
    r"""Signed hyperbolic area :math:`\tfrac12\arg(1 - a\bar b)` of the geodesic triangle (0, a, b).

    Counterclockwise (0 -> a -> b) positive; curvature -4 metric. The value lies in
    :math:`(-\pi/4, \pi/4)`. Vectorised over a and b (broadcast).

    Parameters
    ----------
    a, b : complex or array_like of complex
        Points of the Poincaré disk, :math:`|z| < 1`.

    Returns
    -------
    numpy.ndarray of float64
        The signed areas (0-d for scalar input).

    Raises
    ------
    ValueError
        If a point is not finite or lies outside the open unit disk.

    See Also
    --------
    edge_phases, face_areas

    Examples
    --------
    >>> from hyperlattice.graph.flux import triangle_area
    >>> round(float(triangle_area(0.3, 0.3j)), 6), round(float(triangle_area(0.3j, 0.3)), 6)
    (0.044879, -0.044879)
    """
    a = _validate.disk_points("a", a)
    b = _validate.disk_points("b", b)
    return 0.5 * np.angle(1.0 - a * np.conj(b))


def _cycles(n: int, cycles) -> list[np.ndarray]:
    """Face cycles as int64 arrays of site indices (at least 3 sites each)."""
    if isinstance(cycles, (str, bytes, dict, np.ndarray)) or not isinstance(cycles, (list, tuple)):
        raise ValueError(f"cycles must be a list of site-index arrays (one per face), got {type(cycles).__name__}.")
    out = []
    for c, cyc in enumerate(cycles):
        arr = _validate.site_indices(f"cycles[{c}]", cyc, n)
        if arr.shape[0] < 3:
            raise ValueError(f"cycles[{c}] must have at least 3 sites, got {arr.shape[0]}.")
        out.append(arr)
    return out


def edge_phases(lattice: Lattice, flux) -> np.ndarray:
    r"""Peierls phases :math:`\theta_{ij} = \int_{z_j}^{z_i} A` for the rows (i, j) of ``lattice.edges``.

    The integral runs along the geodesic edge in the rotation-symmetric gauge of this module;
    it equals B times the signed area of the triangle (0, z_j, z_i) (:func:`triangle_area`).

    Parameters
    ----------
    lattice : Lattice
        A site lattice or a line graph.
    flux : float
        Flux quanta f through one p-gon face (positive = counterclockwise).

    Returns
    -------
    numpy.ndarray of float64, shape (E,)
        :math:`\theta_{ij}` of the hop j -> i for edge ``(i, j)``; the phase of the reverse hop
        is the negative.

    Raises
    ------
    ValueError
        For an invalid lattice or flux (``|f|`` above 1e6).

    See Also
    --------
    hyperlattice.graph.operators.hamiltonian, face_fluxes

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.flux import edge_phases
    >>> edge_phases(hl.ring_lattice(7, 3, 2), 0.1).shape
    (42,)
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

    Parameters
    ----------
    lattice : Lattice
        A site lattice, or a line graph whose drawing is plane (q = 3).

    Returns
    -------
    list of numpy.ndarray of int64
        One array of 0-based site indices per bounded face, in counterclockwise order.

    Raises
    ------
    ValueError
        If the drawing is not a plane graph (Euler's formula fails), as for the line graph of
        a {p,q} flake with q > 3, where the q edges at a vertex form a complete graph.

    See Also
    --------
    face_areas, face_fluxes

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.flux import faces
    >>> cycles = faces(hl.ring_lattice(7, 3, 2))
    >>> len(cycles), sorted({len(c) for c in cycles})
    (8, [7])
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
    traced = 0
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
        traced += 1
        cyc = np.array(cycle, dtype=np.int64)
        zc = z[cyc]
        if np.sum(triangle_area(zc, np.roll(zc, -1))) > 0:
            out.append(cyc)
    # Euler: a connected plane graph has E - V + 2 faces, all but the outer one ccw. Edges
    # that cross (the line graph for q > 3 joins all q edges at a vertex) break this.
    expected = int(lattice.edges.shape[0]) - n + 2
    if traced != expected or len(out) != expected - 1:
        raise ValueError(f"the embedded graph is not a plane graph (its edges cross: {traced} faces traced, "
                         f"Euler needs {expected}), so its faces are not defined; the phases still are.")
    return out


def face_areas(lattice: Lattice, cycles: list[np.ndarray]) -> np.ndarray:
    r"""Hyperbolic areas of geodesic polygons from their angles: :math:`((k-2)\pi - \sum\alpha)/4`.

    Independent of :func:`triangle_area` (Gauss-Bonnet with the interior angles measured by
    Möbius maps), so it checks the phases.

    Parameters
    ----------
    lattice : Lattice
        Anything with an array ``z`` of Poincaré-disk site positions.
    cycles : list of array_like of int
        Polygons as counterclockwise cycles of 0-based site indices (e.g. from :func:`faces`).

    Returns
    -------
    numpy.ndarray of float64, shape (len(cycles),)
        The areas in the curvature -4 metric.

    Raises
    ------
    ValueError
        If ``lattice`` has no valid site positions or a cycle holds invalid site indices.

    See Also
    --------
    faces, pgon_area

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.flux import face_areas, faces
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> [round(a, 6) for a in face_areas(lat, faces(lat))[:2].tolist()]   # pgon_area(7, 3)
    [0.261799, 0.261799]
    """
    # only the positions are read (duck-typed: anything with a ``z`` array of disk points)
    if not hasattr(lattice, "z") or isinstance(lattice, (str, bytes, numbers.Number)):
        raise ValueError(f"lattice must be a Lattice (anything with site positions z), got {type(lattice).__name__}.")
    z = _validate.disk_points("the site positions lattice.z", lattice.z)
    cycles = _cycles(z.size, cycles)
    areas = np.empty(len(cycles))
    for c, cyc in enumerate(cycles):
        prev, nxt = np.roll(cyc, 1), np.roll(cyc, -1)
        alpha = np.mod(_tangent_angles(z, cyc, prev) - _tangent_angles(z, cyc, nxt), 2 * np.pi)
        areas[c] = ((cyc.shape[0] - 2) * np.pi - np.sum(alpha)) / 4.0
    return areas


def face_fluxes(lattice: Lattice, flux, cycles: list[np.ndarray] | None = None,
                phases: np.ndarray | None = None) -> np.ndarray:
    r"""Sum of the Peierls phases counterclockwise around each bounded face (not reduced mod 2 pi).

    Parameters
    ----------
    lattice : Lattice
        A site lattice (or a plane line graph).
    flux : float
        Flux quanta f per p-gon face; used when ``phases`` is not given.
    cycles : list of array_like of int, optional
        Face cycles (counterclockwise, 0-based site indices); default :func:`faces`.
    phases : array_like of float, shape (E,), optional
        Phases of ``lattice.edges``; default :func:`edge_phases` at ``flux``.

    Returns
    -------
    numpy.ndarray of float64, shape (len(cycles),)
        The flux through each face in radians (:math:`2\pi f` for a p-gon).

    Raises
    ------
    ValueError
        For invalid input, phases of the wrong shape, or a cycle stepping between sites that
        are not neighbours.

    See Also
    --------
    check_face_fluxes, faces

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.flux import face_fluxes
    >>> ff = face_fluxes(hl.ring_lattice(7, 3, 2), 0.1)
    >>> round(float(ff[0]), 6)   # 2 pi x 0.1
    0.628319
    """
    _validate.lattice(lattice)
    cycles = faces(lattice) if cycles is None else _cycles(lattice.sites, cycles)
    if phases is None:
        phases = edge_phases(lattice, flux)
    else:
        phases = _validate.real_array("phases", phases, ndim=1, shape=(lattice.edges.shape[0],))
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
        try:
            out[c] = sum(lookup[(int(v), int(u))] for u, v in zip(cyc, nxt))
        except KeyError as exc:
            raise ValueError(f"cycles[{c}] steps between sites {exc.args[0][1]} and {exc.args[0][0]}, "
                             "which are not neighbours (a face cycle follows edges).") from None
    return out


def check_face_fluxes(lattice: Lattice, flux, tol: float = 1e-12) -> float:
    r"""Largest deviation of a face flux from :math:`2\pi f \times` area / p-gon area.

    The sanity check of the gauge: the Peierls phases summed counterclockwise around every
    bounded face (:func:`face_fluxes`) must equal :math:`2\pi f` times the face's area
    (measured independently by its angles, :func:`face_areas`) over :func:`pgon_area`.

    Parameters
    ----------
    lattice : Lattice
        A site lattice (or a plane line graph).
    flux : float
        Flux quanta f per p-gon face (positive = counterclockwise).
    tol : float, optional
        Accepted deviation relative to :math:`\max(1, 2\pi|f|)`; default 1e-12.

    Returns
    -------
    float
        The largest absolute deviation in radians (0.0 for a lattice without bounded faces).

    Raises
    ------
    ValueError
        If the deviation exceeds ``tol``, or for invalid input (including a non-plane
        drawing, see :func:`faces`).

    See Also
    --------
    face_fluxes, face_areas

    Examples
    --------
    >>> import hyperlattice as hl
    >>> hl.check_face_fluxes(hl.ring_lattice(7, 3, 2), 0.1) < 1e-12
    True
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


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
