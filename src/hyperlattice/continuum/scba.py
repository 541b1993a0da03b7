r"""Disorder in the continuum: the self-consistent Born approximation (SCBA).

With the package's convention :math:`G(\omega) = (H-\omega)^{-1}` (``eq20``) and on-site disorder
of variance :math:`w^2 = \langle V_i^2\rangle` (uncorrelated between sites), the averaged Green
function is :math:`\langle G\rangle = (H_0 - \omega - \Sigma)^{-1}`. The SCBA keeps the
non-crossing diagrams, :math:`\Sigma = w^2\,G_{\rm loc}(\omega + \Sigma)`, so the averaged Green
function is the *clean* one at the shifted complex frequency

.. math:: \tilde\omega = \omega + w^2\,G_{\rm loc}(\tilde\omega), \qquad
          \langle G_{ij}(\omega)\rangle \approx G^{(0)}_{ij}(\tilde\omega)
          \approx \frac{4\mathcal A}{qh^2}\,G\bigl(z_i, z_j, \lambda(\tilde\omega), L\bigr)

(the last step is ``eq21``, :func:`hyperlattice.dictionary.dictionary_parameters`). To first order
in :math:`w^2`, :math:`\tilde\omega = \omega + w^2 G_{\rm loc}(\omega)`: the leading
:math:`W^2` correction. :math:`\operatorname{Im}\tilde\omega > \operatorname{Im}\omega`: disorder
gives the particle a finite lifetime (an elastic mean free path).

The local Green function in the continuum
-----------------------------------------
The continuum Green function diverges logarithmically at coincident points, so
:math:`G_{\rm loc}` needs the lattice scale. Here it is the resolvent of the continuum density of
states per site with a cutoff fixed by counting states: the Plancherel density of
:math:`-\Delta_g` on the infinite disk of curvature :math:`-4` per unit area is
:math:`\rho(\lambda) = \tanh(\pi k/2)/(4\pi)`, :math:`\lambda = 1 + k^2 \ge 1` (its large-k limit
is Weyl's :math:`1/4\pi`); a site carries area :math:`\mathcal A` (``eq11``) and exactly one
state, which fixes the cutoff :math:`\lambda_c` by
:math:`\mathcal A\int_1^{\lambda_c}\rho\,d\lambda = 1`, i.e.
:math:`k_c^2 = 4\pi/\mathcal A + \tfrac13` (the :math:`\tfrac13 = \int_0^\infty 2k(1-\tanh\frac{\pi k}2)dk`
is exact, :math:`4\eta(2)/\pi^2`). With :math:`E(\lambda) = -q + \frac q4h^2\lambda` (``spec2``)

.. math:: G_{\rm loc}(\omega) = \frac{\mathcal A}{4\pi}\int_1^{\lambda_c}
          \frac{\tanh(\pi k/2)\,d\lambda}{E(\lambda) - \omega}
          = \frac{\mathcal A}{4\pi s}\ln\frac{E_c-\omega}{E_1-\omega}
          - \frac{\mathcal A}{4\pi}\int_0^{\infty}\frac{2k\,(1-\tanh\frac{\pi k}2)\,dk}{E(1+k^2)-\omega},

:math:`s = \frac q4 h^2`. The last integral decays like :math:`e^{-\pi k}` and is done by adaptive
quadrature with a checked error (its upper limit :math:`k_c` is replaced by :math:`\infty`, an
error below :math:`e^{-\pi k_c} < 10^{-14}` for {7,3}). For {7,3}: :math:`\lambda_c = 113.3`,
:math:`E_c = 3.46`, against the lattice band edge 3 — the continuum knows the band bottom and
only roughly its top, so :math:`\operatorname{Re}G_{\rm loc}`, which collects the whole band, is
the least reliable part; :class:`hyperlattice.compare.disorder` measures it against the graph.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy import integrate

from .. import _validate, geometry
from ..dictionary import hopping_scale, lambda_from_energy
from ..errors import ConvergenceError
from ..results import Result

__all__ = ["SCBAResult", "scba", "continuum_local_green", "band_cutoff"]

_MAX_ITER = 10_000
#: largest variance accepted: the self-energy ~ w^2/bandwidth would dwarf the band and the
#: fixed point of the SCBA (a semicircle of width ~ w) is no longer about this lattice
_MAX_VARIANCE = 1e12


def band_cutoff(p: int = 7, q: int = 3) -> tuple[float, float]:
    r"""The cutoff ``(lambda_c, E_c)`` of the continuum density of states (one state per site).

    :math:`\lambda_c = 1 + 4\pi/\mathcal A + \tfrac13` and :math:`E_c = E(\lambda_c)` (module
    docstring; :math:`\mathcal A` is the area per site).

    Parameters
    ----------
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.

    Returns
    -------
    lam_c : float
        Cutoff eigenvalue of :math:`-\Delta_g`.
    E_c : float
        The corresponding lattice energy :math:`-q + \frac q4 h^2\lambda_c` in units of t.

    Raises
    ------
    ValueError
        If {p,q} is not a hyperbolic tessellation.

    Examples
    --------
    >>> from hyperlattice.continuum.scba import band_cutoff
    >>> lam_c, e_c = band_cutoff(7, 3)
    >>> print(f"{lam_c:.6f} {e_c:.6f}")
    113.333333 3.465475
    """
    p, q = _validate.pq(p, q)
    area = geometry.site_area(p, q)
    lam_c = 1.0 + 4.0 * math.pi / area + 1.0 / 3.0
    return lam_c, -q + hopping_scale(p, q) * lam_c


def continuum_local_green(omega, p: int = 7, q: int = 3, *, tol: float = 1e-11) -> complex:
    r"""The continuum local Green function per site :math:`G_{\rm loc}(\omega)` (module docstring).

    The resolvent of the continuum density of states per site, with the cutoff of
    :func:`band_cutoff`; convention :math:`G = (H - \omega)^{-1}` (Eq. (18)).

    Parameters
    ----------
    omega : complex
        Lattice frequency in units of t; real values must lie outside the continuum band
        :math:`[E_1, E_c]` (inside it the resolvent needs :math:`\operatorname{Im}\omega \neq 0`).
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3); need :math:`(p-2)(q-2) > 4`.
    tol : float, optional
        Absolute tolerance of the tail quadrature relative to the size of the result
        (default 1e-11, between 1e-14 and 1e-2).

    Returns
    -------
    complex
        :math:`G_{\rm loc}(\omega)`.

    Raises
    ------
    ValueError
        For real omega inside the band, or bad input.
    ConvergenceError
        If the quadrature's error estimate exceeds ``tol``.

    See Also
    --------
    scba

    Examples
    --------
    >>> from hyperlattice.continuum.scba import continuum_local_green
    >>> print(f"{continuum_local_green(-3.5).real:.6f}")
    0.390332
    >>> g = continuum_local_green(-2.5 + 0.1j)
    >>> print(f"{g.real:.6f} {g.imag:.6f}")
    0.410094 0.452403
    """
    p, q = _validate.pq(p, q)
    om = _validate.complex_number("omega", omega)
    tol = _validate.real("tol", tol, minimum=1e-14, maximum=1e-2)
    s = hopping_scale(p, q)
    area = geometry.site_area(p, q)
    _, e_c = band_cutoff(p, q)
    e_1 = -q + s
    if om.imag == 0 and e_1 <= om.real <= e_c:
        raise ValueError(f"omega = {om.real:g} lies inside the continuum band [{e_1:.6g}, {e_c:.6g}]; "
                         "give it a small positive imaginary part.")
    if om.imag < 0:
        # G(conj w) = conj G(w): the lower half plane by symmetry keeps one branch of the log
        return complex(np.conj(continuum_local_green(np.conj(om), p, q, tol=tol)))
    # E - omega stays in the closed lower half plane: the principal log has no cut in between
    main = (area / (4.0 * math.pi * s)) * (np.log(complex(e_c - om)) - np.log(complex(e_1 - om)))

    def integrand(k: float, part: int) -> float:
        v = 2.0 * k * (2.0 / (math.exp(math.pi * k) + 1.0)) / (e_1 + s * k * k - om)  # 1 - tanh(x/2) = 2/(e^x+1)
        return v.real if part == 0 else v.imag

    scale = abs(main) + 1e-300
    # the resonance E(1 + k^2) = Re omega, where the integrand peaks for small Im omega
    k_res = math.sqrt(max(om.real - e_1, 0.0) / s)
    points = [k_res] if 0.0 < k_res < 40.0 else None
    parts = []
    for part in (0, 1):
        with warnings.catch_warnings():
            # quad's own roundoff warning is replaced by the explicit check of its estimate below
            warnings.simplefilter("ignore", integrate.IntegrationWarning)
            val, err = integrate.quad(integrand, 0.0, 40.0, args=(part,), epsabs=0.1 * tol * scale, epsrel=0.0,
                                      limit=400, points=points)
        if not err <= tol * scale:
            raise ConvergenceError(f"the tail of the continuum local Green function did not converge "
                                   f"(error estimate {err:.1e} > {tol:.1e}).")
        parts.append(val)
    tail = (area / (4.0 * math.pi)) * complex(parts[0], parts[1])
    return complex(main - tail)


@dataclass(frozen=True, eq=False, kw_only=True)
class SCBAResult(Result):
    r"""The SCBA fixed point for one frequency and one disorder variance.

    All frequencies and energies are in units of t (the lattice hopping, :math:`H = -tA + V`).

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    omega : complex
        The frequency asked for.
    variance : float
        :math:`w^2 = \langle V^2\rangle` in units of :math:`t^2`
        (:func:`hyperlattice.graph.disorder.onsite_variance`).
    self_energy : complex
        :math:`\Sigma = \tilde\omega - \omega`.
    omega_shifted : complex
        :math:`\tilde\omega`: the clean Green function there is the averaged one.
    lam : complex
        :math:`\lambda(\tilde\omega)` of ``eq21``, the argument of the continuum Green function.
    born : complex
        The first-order (non-self-consistent) :math:`w^2 G_{\rm loc}(\omega)`.
    iterations : int
        Fixed-point iterations taken.
    residual : float
        :math:`|\tilde\omega - \omega - w^2G_{\rm loc}(\tilde\omega)|` at the end (checked against ``tol``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> r = hl.scba(-3.5, 0.1, 7, 3)
    >>> print(f"{r.omega_shifted.real:.6f} {r.self_energy.real:.6f} {r.born.real:.6f}")
    -3.459925 0.040075 0.039033
    """

    p: int
    q: int
    omega: complex
    variance: float
    self_energy: complex
    omega_shifted: complex
    lam: complex
    born: complex
    iterations: int
    residual: float

    def summary(self) -> dict:
        """All fields as plain JSON (complex numbers as re/im)."""
        return {"p": self.p, "q": self.q, "omega": self.omega, "variance": self.variance,
                "self_energy": self.self_energy, "omega_shifted": self.omega_shifted, "lambda": self.lam,
                "born": self.born, "iterations": self.iterations, "residual": self.residual}


def scba(omega, variance: float, p: int = 7, q: int = 3, *, local: Callable[[complex], complex] | None = None,
         tol: float = 1e-12, max_iter: int = 2000, damping: float = 0.5) -> SCBAResult:
    r"""Solve the SCBA fixed point :math:`\tilde\omega = \omega + w^2 G_{\rm loc}(\tilde\omega)` (module docstring).

    The disorder-averaged Green function is then the clean one at :math:`\tilde\omega`.

    Parameters
    ----------
    omega : complex
        Lattice frequency in units of t with :math:`\operatorname{Im}\omega \ge 0` (retarded
        side); real only outside the band.
    variance : float
        On-site disorder variance :math:`w^2 \ge 0` (:math:`W^2/12` for box disorder of width W),
        in units of :math:`t^2`.
    p : int, optional
        Polygon size of the {p,q} lattice (default 7).
    q : int, optional
        Coordination number (default 3).
    local : callable, optional
        :math:`G_{\rm loc}(\omega)`; default :func:`continuum_local_green` (the continuum side).
        A graph's site-averaged local Green function may be passed to run the same SCBA on the graph.
    tol : float, optional
        Convergence: the residual must fall below ``tol * max(1, |omega~|)`` (default 1e-12).
    max_iter : int, optional
        Largest number of fixed-point iterations (default 2000).
    damping : float, optional
        Mixing :math:`0 < \alpha \le 1` of the fixed-point update (default 0.5: robust near band
        edges).

    Returns
    -------
    SCBAResult
        Frozen result with ``omega``, ``variance``, ``self_energy`` (:math:`\Sigma`),
        ``omega_shifted`` (:math:`\tilde\omega`), ``lam`` (:math:`\lambda(\tilde\omega)` of
        Eq. (19)), ``born`` (first-order :math:`w^2 G_{\rm loc}(\omega)`), ``iterations`` and
        ``residual``.

    Raises
    ------
    ValueError
        If :math:`\operatorname{Im}\omega < 0`, the variance is negative or too large, or another
        argument is invalid.
    ConvergenceError
        If the fixed point is not reached in ``max_iter`` steps (the residual is stated) or is
        not finite.

    See Also
    --------
    continuum_local_green, hyperlattice.compare.disorder.compare_scba

    Examples
    --------
    >>> import hyperlattice as hl
    >>> r = hl.scba(-3.5, 0.1, 7, 3)
    >>> print(f"{r.self_energy.real:.6f} {r.born.real:.6f}")
    0.040075 0.039033
    >>> r = hl.scba(-2.5 + 0.05j, 0.1)
    >>> print(f"{r.omega_shifted.real:.6f} {r.omega_shifted.imag:.6f}")
    -2.460400 0.095699
    """
    p, q = _validate.pq(p, q)
    om = _validate.complex_number("omega", omega)
    if om.imag < 0:
        raise ValueError(f"omega must have Im omega >= 0 (retarded side), got {om:g}.")
    w2 = _validate.real("variance", variance, minimum=0.0, maximum=_MAX_VARIANCE)
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1e-2)
    max_iter = _validate.positive_int("max_iter", max_iter, maximum=_MAX_ITER)
    damping = _validate.damping("damping", damping, tol, _MAX_ITER) if w2 > 0 else \
        _validate.real("damping", damping, minimum=0.0, maximum=1.0, open_min=True)
    if local is None:
        def local(w):
            return continuum_local_green(w, p, q, tol=max(min(tol, 1e-10), 1e-14))
    else:
        local = _validate.function("local", local)
    g0 = complex(local(om))
    born = w2 * g0
    w = om + born
    residual = math.inf
    it = 0
    for it in range(1, max_iter + 1):
        target = om + w2 * complex(local(w))
        residual = abs(target - w)
        if residual <= tol * max(1.0, abs(w)):
            w = target
            break
        w = (1.0 - damping) * w + damping * target
        if w.imag < 0:  # a damped step cannot leave the upper half plane, rounding aside
            w = complex(w.real, 0.0)
    else:
        raise ConvergenceError(f"the SCBA did not converge in {max_iter} iterations (residual {residual:.1e}); "
                               "raise max_iter or lower damping.")
    if not (math.isfinite(w.real) and math.isfinite(w.imag)):
        raise ConvergenceError("the SCBA fixed point is not finite.")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", np.exceptions.ComplexWarning)
        lam = complex(lambda_from_energy(w, p, q))
    return SCBAResult(p=p, q=q, omega=om, variance=w2, self_energy=w - om, omega_shifted=w, lam=lam,
                      born=born, iterations=it, residual=float(residual))


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
