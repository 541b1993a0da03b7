r"""Both sides of a transmission measurement: the lattice's S₂₁ against the continuum's near the band bottom.

For resonators on the sites of a {p,q} flake, :math:`H = \omega_0 - J A = \omega_0 + J H_1` with
:math:`H_1 = -A` the package's t = 1 Hamiltonian, so the port block of the resolvent is

.. math::

    g_0(\omega) = U^T(z - H)^{-1}U = -\tfrac{1}{J}\, G_{r_q r_p}(x),\qquad
    x = \frac{\omega + i\kappa_{int}/2 - \omega_0}{J},

with :math:`G(x) = (H_1 - x)^{-1}` the graph Green function. The dictionary (Boettcher et al., Phys.
Rev. A 102, 032208 (2020), Eq. 19; :func:`hyperlattice.dictionary.dictionary_parameters`) maps it
onto the continuum: :math:`G_{ij}(x) \approx \frac{4\mathcal A}{qh^2}\, G(z_i, z_j, \lambda, L)`,
:math:`\lambda = 4(x + q)/(qh^2)`, the Dirichlet Green function of the disk of radius L
(:func:`hyperlattice.continuum.green.continuum_green`). The continuum has no value at coincident points,
so its S₂₁ is the weak-coupling one, :math:`S_{21} = -i\sqrt{\kappa_1\kappa_2}\, g_{0,21}`; the
lattice's is the exact input–output S₂₁ (:func:`hyperlattice.device.transmission`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import _validate
from ..results import Column, Result
from .resonators import resonator_device
from .transmission import _omegas, transmission

__all__ = ["TransmissionComparison", "continuum_transmission"]


@dataclass(frozen=True, eq=False, kw_only=True)
class TransmissionComparison(Result):
    r"""``|S₂₁|²`` of a flake device, lattice against continuum (through the dictionary).

    Attributes
    ----------
    omega : ndarray
        Frequencies (the user's units).
    lattice : ndarray
        ``|S₂₁|²`` of the lattice (exact input–output).
    continuum : ndarray
        ``|S₂₁|²`` from the continuum Green function (weak coupling).
    ports : tuple of str
        The two port sites.
    distance : float
        Hyperbolic distance between the two port sites (curvature −4 metric, units of the disk).
    lowest_levels : ndarray
        The lattice's lowest levels in device units (ω₀ + J E), where its peaks sit.
    p, q, rings : int
        The flake.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import continuum_transmission
    >>> cmp = continuum_transmission(hl.ring_lattice(7, 3, 3), np.linspace(-3.3, -3.1, 3), ports=("0", "10"),
    ...                              kappa_int=0.05, kappa_port=0.002)
    >>> bool(np.all(np.abs(cmp.continuum / cmp.lattice - 1) < 0.5))
    True
    """

    COLUMNS: ClassVar[tuple] = (Column("omega", "omega", "user's frequency unit"),
                                Column("lattice", "lattice", "1"), Column("continuum", "continuum", "1"))

    omega: np.ndarray
    lattice: np.ndarray
    continuum: np.ndarray
    ports: tuple
    distance: float
    lowest_levels: np.ndarray
    p: int = 7
    q: int = 3
    rings: int = 0


def continuum_transmission(lattice, omegas, *, ports, omega0: float = 0.0, J: float = 1.0, kappa_int: float,
                           kappa_port: float, tol: float = 1e-10) -> TransmissionComparison:
    r"""``|S₂₁|²`` of a device on the sites of a flake, lattice and continuum, at every frequency.

    Parameters
    ----------
    lattice : Lattice
        A {p,q} flake (``ring_lattice``; sites, not a line graph: the dictionary is the site lattice's).
    omegas : array_like
        Frequencies (the user's units); the continuum holds near the band bottom, ω ≈ ω₀ − qJ (J > 0).
    ports : pair of str
        The two port sites ("i").
    omega0, J : float, optional
        Bare frequency and coupling (J ≠ 0); defaults 0 and 1.
    kappa_int : float
        Internal loss (> 0: the continuum Green function is taken off the real axis).
    kappa_port : float
        κ of both ports (> 0; the continuum side is the weak-coupling form, κ_port ≪ κ_int fits it best).
    tol : float, optional
        Relative tolerance of the continuum series; default 1e-10.

    Returns
    -------
    TransmissionComparison

    Raises
    ------
    ValueError
        A line graph, J = 0, κ ≤ 0, unknown or coincident port sites.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import continuum_transmission
    >>> cmp = continuum_transmission(hl.ring_lattice(7, 3, 3), [-3.2], ports=("0", "10"), kappa_int=0.05,
    ...                              kappa_port=0.002)
    >>> cmp.ports, round(cmp.distance, 4)
    (('0', '10'), 0.6068)
    """
    from ..continuum.green import continuum_green
    from ..dictionary import dictionary_parameters
    from ..geometry import distance as hyperbolic_distance
    from ..graph.operators import adjacency

    lat = _validate.lattice(lattice, kind="sites")
    w = _omegas(omegas)
    J = _validate.real("J", J)
    if J == 0:
        raise ValueError("J = 0 leaves no band: the continuum limit needs a coupling.")
    omega0 = _validate.real("omega0", omega0)
    kappa_int = _validate.positive_real("kappa_int", kappa_int)
    kappa_port = _validate.positive_real("kappa_port", kappa_port)
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1e-2)
    if not isinstance(ports, (list, tuple)) or len(ports) != 2:
        raise ValueError(f"ports must be a pair of site names, got {_validate._shown(ports)}.")
    dev = resonator_device(lat, omega0=omega0, J=J, kappa_int=kappa_int,
                           ports=[(ports[0], kappa_port), (ports[1], kappa_port)])
    a, b = (int(dev.port_index[0]), int(dev.port_index[1]))
    tr = transmission(dev, w)
    cont = np.empty(w.size, np.complex128)
    for k, om in enumerate(w):
        x = (om + 0.5j * kappa_int - omega0) / J
        lam, pref = dictionary_parameters(x, lat.p, lat.q)
        g = complex(continuum_green(lat.z[b], lat.z[a], lam, lat.radius, tol=tol, extend=True))
        cont[k] = -1j * kappa_port * (-(1.0 / J) * pref * g)
    n_low = min(6, lat.sites)
    import scipy.sparse.linalg as spla

    if lat.sites > 400:
        e = np.sort(spla.eigsh((-adjacency(lat)).astype(float), k=n_low, which="SA", return_eigenvectors=False))
    else:
        e = np.linalg.eigvalsh((-adjacency(lat)).toarray())[:n_low]
    return TransmissionComparison(omega=w, lattice=tr.power, continuum=np.abs(cont) ** 2, ports=dev.ports,
                                  distance=float(hyperbolic_distance(lat.z[a], lat.z[b])),
                                  lowest_levels=omega0 + J * e, p=lat.p, q=lat.q, rings=lat.rings)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
