r"""The graph <-> continuum dictionary: every map between the two sides, written once.

Both sides import this module; nothing else writes these formulas. A convention change (or an
improved dictionary) is one edit here.

From the small-h expansion of the adjacency operator on a {p,q} lattice (paper, ``eq10``/``adj26``
with 3 replaced by q: the q neighbours sit at :math:`h e^{\mathrm i(\chi + 2\pi k/q)}`, whose first
and second moments vanish),

.. math:: A \approx q + \frac q4 h^2 \Delta_g, \qquad h = \tanh d_0,

and from sums as integrals, :math:`\sum_i \approx \frac1{\mathcal A}\int dV_g` (``eq11``, area per
site :math:`\mathcal A`, :func:`hyperlattice.geometry.site_area`):

* energies and eigenvalues (``spec2``, ``eq21``): a lattice energy :math:`E` (or frequency
  :math:`\omega`) corresponds to the eigenvalue :math:`\lambda = \kappa` of :math:`-\Delta_g`,

  .. math:: \lambda = \frac{4(\omega + q)}{q h^2}, \qquad E = -q + \frac q4 h^2 \kappa,
            \qquad \kappa = 1 + k^2 \text{ on the continuum spectrum};

* Green functions (``eq21``): :math:`G_{ij}(\omega) \approx \frac{4\mathcal A}{q h^2}
  G(z_i, z_j, \lambda, L)` (:func:`green_prefactor`);
* the disk radius (``eq12``): :math:`L = \sqrt{N/(N + \pi/\mathcal A)}` for a lattice of N sites
  (:func:`disk_radius`);
* many-body parameters (``eq13`` -> ``eq14``): :math:`t' = \frac q4 h^2 t`, :math:`\mu' = \mu + qt`,
  :math:`U' = \mathcal A U` (:func:`continuum_parameters`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _validate, geometry
from .results import Result

__all__ = [
    "laplacian_coefficient",
    "hopping_scale",
    "lambda_from_energy",
    "energy_from_lambda",
    "energy_from_k",
    "green_prefactor",
    "dictionary_parameters",
    "disk_radius",
    "disk_radius_for_rings",
    "ContinuumParameters",
    "continuum_parameters",
    "lattice_parameters",
    "field_from_flux",
    "flux_from_field",
]


# ----------------------------------------------------------------------------
# energies <-> eigenvalues of -Delta_g
# ----------------------------------------------------------------------------

def _value(name: str, value):
    """A real or complex scalar, or an array of them, all finite (arrays as float64/complex128)."""
    if isinstance(value, (np.ndarray, list, tuple)):
        a = _validate.complex_array(name, value)  # refuses ragged lists, strings, NaN and inf
        return a if np.asarray(value).dtype.kind == "c" else a.real.copy()
    if isinstance(value, (complex, np.complexfloating)):
        return _validate.complex_number(name, value)
    return _validate.real(name, value)


def laplacian_coefficient(q: int, h) -> float | np.ndarray:
    r"""The coefficient :math:`\frac q4 h^2` of :math:`\Delta_g` in :math:`A \approx q + \frac q4 h^2\Delta_g`
    for a q-fold star of neighbours at Euclidean distance h (after a Möbius map to the origin).

    The one place this factor is written; :func:`hopping_scale` evaluates it at :math:`h = \tanh d_0`,
    and the h-expansion of :mod:`hyperlattice.compare.scaling` at any h.
    """
    return 0.25 * q * h * h


def hopping_scale(p=7, q=3) -> float:
    r"""The factor :math:`\frac q4 h^2` of :math:`A \approx q + \frac q4 h^2\Delta_g` (``eq10``), :math:`h = \tanh d_0`.

    It converts continuum eigenvalues into lattice energies (:math:`t'/t`, ``eq14``):
    :math:`\frac34 h^2 = 0.0570...` for {7,3}.
    """
    p, q = _validate.pq(p, q, allow_infinite_p=True)
    return laplacian_coefficient(q, geometry.lattice_h(p, q))


def lambda_from_energy(omega, p=7, q=3) -> float | complex | np.ndarray:
    r""":math:`\lambda = 4(\omega + q)/(q h^2)`: the eigenvalue of :math:`-\Delta_g` that matches the
    lattice energy (or frequency) :math:`\omega` (``eq21``). Real or complex, scalar or array."""
    omega = _value("omega", omega)
    scale = hopping_scale(p, q)
    q = _validate.pq(p, q, allow_infinite_p=True)[1]
    return (np.asarray(omega) + q) / scale if np.ndim(omega) else (omega + q) / scale


def energy_from_lambda(lam, p=7, q=3) -> float | complex | np.ndarray:
    r""":math:`E = -q + \frac q4 h^2 \lambda`, the inverse of :func:`lambda_from_energy` (``spec2``)."""
    lam = _value("lam", lam)
    scale = hopping_scale(p, q)
    q = _validate.pq(p, q, allow_infinite_p=True)[1]
    return -q + scale * (np.asarray(lam) if np.ndim(lam) else lam)


def energy_from_k(k, p=7, q=3) -> float | complex | np.ndarray:
    r"""Lattice energy of a continuum level with :math:`-\Delta_g\psi = (1 + k^2)\psi` (``spec2``):
    :math:`E = -q + \frac q4 h^2 (1 + k^2)`. Real k for Dirichlet levels, complex k allowed."""
    k = np.asarray(_value("k", k))
    return energy_from_lambda(1.0 + k * k, p, q)


def green_prefactor(p=7, q=3) -> float:
    r"""The prefactor :math:`4\mathcal A/(q h^2)` of ``eq21`` (:math:`\pi/(21 h^2)` for {7,3})."""
    return geometry.site_area(p, q) / hopping_scale(p, q)


def dictionary_parameters(omega, p=7, q=3) -> tuple[complex, float]:
    r"""``(lambda, prefactor)`` of ``eq21`` for one lattice frequency :math:`\omega` (real or complex)."""
    _validate.pq(p, q)  # a lattice's Green function: p finite
    om = _validate.complex_number("omega", omega)
    return complex(lambda_from_energy(om, p, q)), green_prefactor(p, q)


def disk_radius(sites, p=7, q=3) -> float:
    r"""The effective disk radius of ``eq12``, :math:`L = \sqrt{N/(N + \pi/\mathcal A)}`, for N sites.

    Same as :func:`hyperlattice.geometry.effective_radius` (kept there for the geometry tables);
    ``sites`` is one positive integer here.
    """
    p, q = _validate.pq(p, q)
    return geometry.effective_radius(_validate.positive_int("sites", sites), p, q)


def disk_radius_for_rings(rings, p=7, q=3) -> tuple[float, float]:
    r"""``(L, x_L)`` of the disk that stands for the ``rings``-ring {p,q} lattice (``eq12``).

    :math:`L = \sqrt{N/(N + c)}` with the exact site count N and :math:`c = \pi/\mathcal A`, and
    :math:`x_L = (1 + L^2)/(1 - L^2) = (2N + c)/c` computed from N directly, which keeps full
    relative precision when :math:`1 - L \sim 10^{-9}` would lose digits in L itself. The site
    count is the graph side's combinatorics (counted, never built), so this is the one map from
    the graph to the continuum that needs it; it works up to :math:`N \approx 10^{308}`.
    """
    from .graph.lattice import site_count_float  # lazy: the continuum side imports this module

    p, q = _validate.pq(p, q)
    n_sites = site_count_float(p, q, rings)
    c = geometry.radius_constant(p, q)
    return math.sqrt(n_sites / (n_sites + c)), (2.0 * n_sites + c) / c


# ----------------------------------------------------------------------------
# magnetic flux f (quanta per p-gon face) <-> field B (issue 11)
# ----------------------------------------------------------------------------

def _face_area(p=7, q=3) -> float:
    r"""Hyperbolic area of one p-gon face in the paper's metric (curvature :math:`-4`):
    :math:`\frac14[(p-2)\pi - 2\pi p/q]` (Gauss-Bonnet: the curvature :math:`-1` area
    :math:`(p-2)\pi - p\cdot 2\pi/q` divided by 4); :math:`\pi/12` for {7,3}."""
    p, q = _validate.pq(p, q)
    return 0.25 * ((p - 2) * math.pi - 2.0 * math.pi * p / q)


def field_from_flux(f, p=7, q=3) -> float | np.ndarray:
    r"""Uniform field :math:`B = 2\pi f/\mathcal A_p` that puts ``f`` flux quanta through each
    p-gon face (:math:`\mathcal A_p` = :func:`_face_area`; :math:`\hbar = e = 1`, one quantum is
    :math:`2\pi`; positive f and B point out of the disk, counterclockwise). Scalar or array."""
    f = _value("f", f)
    if np.iscomplexobj(f):
        raise ValueError("the flux f must be real.")
    return 2.0 * math.pi * f / _face_area(p, q)


def flux_from_field(B, p=7, q=3) -> float | np.ndarray:
    r"""Inverse of :func:`field_from_flux`: :math:`f = B\mathcal A_p/(2\pi)`."""
    B = _value("B", B)
    if np.iscomplexobj(B):
        raise ValueError("the field B must be real.")
    return B * _face_area(p, q) / (2.0 * math.pi)


# ----------------------------------------------------------------------------
# many-body dictionary, ``eq13``–``eq14``
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class ContinuumParameters(Result):
    r"""Parameters of ``eq14`` for a lattice model of ``eq13`` on {p,q}.

    ``field_scale`` is :math:`1/\sqrt{\mathcal A}`: :math:`\hat\alpha(z_i) = \hat a_i/\sqrt{\mathcal A}`
    (:math:`\sqrt{28/\pi}\,\hat a_i` for {7,3}).
    """

    p: int
    q: int
    t: float
    mu: float
    U: float
    t_prime: float
    mu_prime: float
    U_prime: float
    field_scale: float
    h: float
    site_area: float

    def summary(self) -> dict:
        """The JSON printed by ``hyperlattice dictionary``."""
        return {"p": self.p, "q": self.q,
                "lattice": {"t": self.t, "mu": self.mu, "U": self.U},
                "continuum": {"t_prime": self.t_prime, "mu_prime": self.mu_prime,
                              "U_prime": self.U_prime},
                "field_scale": self.field_scale, "h": self.h, "site_area": self.site_area}


def continuum_parameters(t: float, mu: float, U: float, p: int = 7, q: int = 3) -> ContinuumParameters:
    r"""Map the lattice Bose-Hubbard parameters of ``eq13`` to those of ``eq14``.

    From :math:`A \approx q + \frac q4 h^2\Delta_g` (``eq10`` generalised),
    :math:`\sum_i \to \frac1{\mathcal A}\int dV_g` (``eq11``) and
    :math:`\hat a_i = \sqrt{\mathcal A}\,\hat\alpha(z_i)`:

    .. math:: t' = \frac q4 h^2 t,\qquad \mu' = \mu + q t,\qquad U' = \mathcal A\, U,

    i.e. :math:`t' = \frac34 h^2 t`, :math:`\mu' = \mu + 3t`, :math:`U' = \frac{\pi}{28}U` for
    {7,3}. The hopping term :math:`-t\,a^\dagger A a` contributes :math:`-qt\,a^\dagger a`,
    which shifts the chemical potential; :math:`(a^\dagger a)^2 = \mathcal A^2(\alpha^\dagger\alpha)^2`
    and the measure :math:`1/\mathcal A` leave one factor :math:`\mathcal A` on U.
    """
    p, q = _validate.pq(p, q)
    t, mu, U = (_validate.real(name, v) for name, v in (("t", t), ("mu", mu), ("U", U)))
    area = geometry.site_area(p, q)
    values = {"t_prime": hopping_scale(p, q) * t, "mu_prime": mu + q * t, "U_prime": area * U}
    for name, v in values.items():
        if not math.isfinite(v):
            raise ValueError(f"the continuum {name} = {v} overflows: the lattice parameters are too large.")
    return ContinuumParameters(p=p, q=q, t=t, mu=mu, U=U, **values,
                               field_scale=1.0 / math.sqrt(area), h=geometry.lattice_h(p, q), site_area=area)


def lattice_parameters(t_prime: float, mu_prime: float, U_prime: float, p: int = 7,
                       q: int = 3) -> ContinuumParameters:
    """Inverse of :func:`continuum_parameters`: the lattice (t, mu, U) giving (t', mu', U')."""
    p, q = _validate.pq(p, q)
    tp, mp, up = (_validate.real(name, v)
                  for name, v in (("t_prime", t_prime), ("mu_prime", mu_prime), ("U_prime", U_prime)))
    t = tp / hopping_scale(p, q)
    values = {"t": t, "mu": mp - q * t, "U": up / geometry.site_area(p, q)}
    for name, v in values.items():
        if not math.isfinite(v):
            raise ValueError(f"the lattice {name} = {v} overflows: the continuum parameters are too large.")
    return continuum_parameters(values["t"], values["mu"], values["U"], p, q)
