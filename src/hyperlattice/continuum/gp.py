r"""The Gross–Pitaevskii equation on the Poincaré disk: ground state, vortices, Bogoliubov spectrum.

The mean-field limit of the paper's continuum Hamiltonian (Boettcher et al., PRA 102, 032208,
Eq. 12, with the interaction written :math:`\frac{U'}2|\alpha|^4` to match
:math:`\frac U2 n(n-1)` on the lattice) on the disk :math:`|z| \le L` with a Dirichlet boundary:

.. math::

    E[\varphi] = \int dV_g \Bigl[ t' |\nabla_g\varphi|^2 + \frac{U'}{2} |\varphi|^4 \Bigr], \qquad
    N = \int dV_g\, |\varphi|^2, \qquad
    -t'\Delta_g\varphi + U'|\varphi|^2\varphi = \mu_c\varphi ,

with :math:`dV_g = d^2z/(1-|z|^2)^2`, :math:`\Delta_g = (1-|z|^2)^2(\partial_x^2+\partial_y^2)`
(curvature −4). Through the dictionary (:func:`hyperlattice.continuum_parameters`)
:math:`t' = \frac q4 h^2 t`, :math:`U' = \mathcal A U` and the lattice chemical potential is
:math:`\mu = \mu_c - q t`; :math:`|\varphi|^2` is a density per unit area, :math:`\mathcal
A|\varphi|^2` bosons per site.

Radial form
-----------
In the geodesic radius ρ (:math:`|z| = \tanh\rho`) the metric is :math:`d\rho^2 + S^2 d\theta^2`,
:math:`S(\rho) = \frac12\sinh 2\rho`, and a state of winding m is :math:`f(\rho)e^{im\theta}` with
:math:`\Delta_g \to S^{-1}(S f')' - m^2 f/S^2` on :math:`0 \le \rho \le R = \operatorname{artanh} L`.

Two independent discretisations:

* ``"fv"``: cell-centred finite volumes (exact cell volumes, second order), the energy minimised by
  L-BFGS at fixed N and polished by Newton on (f, μ_c), checked by the residual of the discrete
  equation; Bogoliubov frequencies per
  angular momentum j from the dense symmetric form of :math:`\mathcal A_j\mathcal B_j`;
* ``"shooting"``: the radial ODE integrated from the centre (scipy ``solve_ivp``, DOP853) with the
  centre amplitude and μ found by a two-dimensional root search on f(R) = 0 and the norm.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from .. import _validate
from ..errors import ConvergenceError, ConvergenceWarning
from ..results import Column, Result

__all__ = ["DiskGPState", "disk_gp", "disk_gp_shooting", "DiskBogoliubov", "disk_bogoliubov", "healing_length"]


def _S(rho):
    return 0.5 * np.sinh(2.0 * rho)


def _grid(R: float, cells: int):
    h = R / cells
    edges = np.arange(cells + 1) * h
    centres = edges[:-1] + 0.5 * h
    vol = 0.5 * math.pi * (np.cosh(2.0 * edges[1:]) - np.cosh(2.0 * edges[:-1]))   # 2π ∫ S dρ per cell
    return h, edges, centres, vol


def _stiffness(R: float, cells: int, m: int):
    """Tridiagonal (diag, off) of the quadratic form 2π ∫ (f'^2 + m^2 f^2/S^2) S dρ with f(R) = 0."""
    h, edges, centres, vol = _grid(R, cells)
    s_face = _S(edges[1:-1])                    # interior faces
    w = 2.0 * math.pi * s_face / h
    diag = np.zeros(cells)
    diag[:-1] += w
    diag[1:] += w
    diag[-1] += 2.0 * math.pi * _S(R) / (0.5 * h)     # the Dirichlet face (ghost value -f)
    if m:
        diag += 2.0 * math.pi * m * m * h / _S(centres)
    return diag, -w, vol, centres


@dataclasses.dataclass(frozen=True, eq=False)
class DiskGPState(Result):
    r"""A GP state of winding m on the Dirichlet disk.

    Attributes
    ----------
    radius : float
        L (Euclidean radius in the Poincaré disk).
    rho_max : float
        artanh L, the geodesic radius of the disk in the paper's metric.
    t_prime, U_prime : float
        Continuum hopping and interaction of the dictionary (:math:`t' = \frac q4 h^2 t`,
        :math:`U' = \mathcal A U`); they fix the energy unit (that of t).
    particles : float
        :math:`N = \int |\varphi|^2 dV_g`.
    winding : int
        m.
    rho, f : ndarray
        Geodesic radius of the grid and the real radial amplitude (per unit area: :math:`|\varphi|^2 = f^2`).
    mu_c : float
        Continuum chemical potential μ_c (the lattice's μ is μ_c − q t).
    energy : float
        The GP energy of the state, in the energy unit of t' and U'.
    residual : float
        Relative residual of the discrete equation (``"fv"``) or of the boundary and norm
        conditions (``"shooting"``).
    method : str
        ``"fv"`` (finite volumes, :func:`disk_gp`) or ``"shooting"`` (:func:`disk_gp_shooting`).

    Examples
    --------
    >>> from hyperlattice.continuum.gp import disk_gp
    >>> s = disk_gp(0.75, 0.057, 0.112, 20.0, cells=100)
    >>> s.method, s.winding, s.rho.shape, round(s.rho_max, 6)
    ('fv', 0, (100,), 0.972955)
    >>> print(f"{s.mu_c:.4f} {s.energy:.4f} {float(s.density[0]):.3f}")
    1.4624 19.6241 12.528
    """

    #: one row per radial grid point
    COLUMNS = (Column("rho", "rho", "1 (geodesic radius)"), Column("f", "f", "1/sqrt(unit area)"),
               Column("density", "density", "1/unit area"))

    radius: float
    rho_max: float
    t_prime: float
    U_prime: float
    particles: float
    winding: int
    rho: np.ndarray
    f: np.ndarray
    mu_c: float
    energy: float
    residual: float
    method: str

    @property
    def density(self) -> np.ndarray:
        r""":math:`|\varphi|^2` per unit area at ``rho``."""
        return self.f**2

    def summary(self) -> dict:
        return {"radius": self.radius, "rho_max": self.rho_max, "t_prime": self.t_prime, "U_prime": self.U_prime,
                "particles": self.particles, "winding": self.winding, "mu_c": self.mu_c, "energy": self.energy,
                "central_density": float(self.f[0] ** 2), "residual": self.residual, "method": self.method}


def _check(radius, t_prime, U_prime, particles, winding):
    L = _validate.real("radius", radius)
    if not 0.0 < L < 1.0:
        raise ValueError(f"radius must lie in (0, 1) (a disk inside the Poincaré disk), got {L!r}.")
    tp = _validate.positive_real("t_prime", t_prime)
    up = _validate.real("U_prime", U_prime, minimum=0.0)
    N = _validate.positive_real("particles", particles)
    m = _validate.integer("winding", winding, minimum=-1000, maximum=1000)
    if up > 1e8 * tp:
        raise ValueError(f"U_prime = {up:g} is more than 1e8 t_prime: far outside the weak-coupling regime of the "
                         "Gross-Pitaevskii equation.")
    return L, tp, up, N, m


def disk_gp(radius: float, t_prime: float, U_prime: float, particles: float, *, winding: int = 0,
            cells: int = 800, tol: float = 1e-10) -> DiskGPState:
    r"""The lowest GP state of winding m on the Dirichlet disk of radius L (finite volumes + L-BFGS).

    Minimises :math:`E[\varphi] = \int dV_g [t'|\nabla_g\varphi|^2 + \frac{U'}2|\varphi|^4]` at fixed
    N (module docstring), then polishes (f, μ_c) by Newton on the discrete equation.

    Parameters
    ----------
    radius : float
        Euclidean disk radius L in (0, 1); for a flake of ℓ rings use
        :func:`hyperlattice.dictionary.disk_radius_for_rings`.
    t_prime : float
        Continuum hopping :math:`t' > 0` of the dictionary (:math:`\frac q4 h^2 t`).
    U_prime : float
        Continuum interaction :math:`U' \ge 0` (:math:`\mathcal A U`), at most :math:`10^8 t'`.
    particles : float
        Particle number :math:`N = \int |\varphi|^2 dV_g > 0`.
    winding : int, optional
        Winding number m, :math:`|m| \le 1000` (default 0: the rotationally symmetric ground
        state; m ≠ 0: a vortex at the centre).
    cells : int, optional
        Radial cells, 20 to :math:`10^6` (default 800; error ~ cells⁻²).
    tol : float, optional
        Target relative residual (default 1e-10); a ConvergenceWarning states the one reached if
        above it (or 1e-8).

    Returns
    -------
    DiskGPState
        Frozen result with ``rho`` and ``f`` (geodesic radii of the cell centres and the real
        radial amplitude, :math:`|\varphi|^2 = f^2` per unit area), ``mu_c`` (continuum chemical
        potential; the lattice μ is :math:`\mu_c - qt`), ``energy``, ``particles``, ``winding``,
        ``residual`` and ``method = "fv"``.

    Raises
    ------
    ValueError
        If the radius is outside (0, 1), :math:`t' \le 0`, :math:`U' < 0` or
        :math:`U' > 10^8 t'`, :math:`N \le 0`, or ``winding``, ``cells`` or ``tol`` is invalid.

    Warns
    -----
    ConvergenceWarning
        If the relative residual reached is above ``tol`` (or 1e-8).

    See Also
    --------
    disk_gp_shooting : an independent check.
    disk_bogoliubov, healing_length, hyperlattice.dictionary.continuum_parameters

    References
    ----------
    Boettcher et al., Phys. Rev. A 102, 032208 (2020), Eq. (12) (mean-field limit).

    Examples
    --------
    >>> from hyperlattice.continuum.gp import disk_gp
    >>> s = disk_gp(0.75, 0.057, 0.112, 20.0, cells=100)
    >>> print(s.method, f"{s.mu_c:.4f}", f"{s.energy:.4f}", s.rho.shape)
    fv 1.4624 19.6241 (100,)
    """
    from scipy.optimize import minimize

    L, tp, up, N, m = _check(radius, t_prime, U_prime, particles, winding)
    cells = _validate.integer("cells", cells, minimum=20, maximum=10**6)
    tol = _validate.positive_real("tol", tol)
    R = math.atanh(L)
    diag, off, vol, centres = _stiffness(R, cells, m)
    # g = sqrt(vol) f: the quadratic form becomes the symmetric tridiagonal K~
    sv = np.sqrt(vol)
    kd = diag / vol
    ko = off / (sv[:-1] * sv[1:])

    def kmul(g):
        out = kd * g
        out[:-1] += ko * g[1:]
        out[1:] += ko * g[:-1]
        return tp * out

    def eg(x):
        nx = np.linalg.norm(x)
        g = math.sqrt(N) * x / nx
        kg = kmul(g)
        e = float(g @ kg + 0.5 * up * np.sum(g**4 / vol))
        dg = 2.0 * (kg + up * g**3 / vol)
        return e, (math.sqrt(N) / nx) * (dg - g * (g @ dg) / N)

    # start: the lowest eigenvector of K~ (the U' = 0 state)
    from scipy.linalg import eigh_tridiagonal

    _, v = eigh_tridiagonal(kd, ko, select="i", select_range=(0, 0))
    x0 = np.abs(v[:, 0]) + 1e-300
    scale = tp * float(np.max(np.abs(kd)))
    res = minimize(eg, x0, jac=True, method="L-BFGS-B",
                   options={"maxiter": 5_000, "gtol": 1e-5 * scale * math.sqrt(N), "ftol": 0.0, "maxcor": 30})
    g = np.abs(math.sqrt(N) * res.x / np.linalg.norm(res.x))
    mu = float((g @ kmul(g) + up * np.sum(g**4 / vol)) / N)
    # Newton on (g, mu) from the L-BFGS point: the exponential cell volumes make the energy
    # ill-conditioned for a first-order method; J = K~ + 3U'g^2/vol - mu is positive definite at
    # the ground state (K~ + U'g^2/vol - mu >= 0 with null vector g), so each step is two
    # tridiagonal solves (LAPACK banded) and a bordered update of mu
    from scipy.linalg import solve_banded

    def residual_of(g, mu):
        return kmul(g) + up * g**3 / vol - mu * g

    for _ in range(30):
        r = residual_of(g, mu)
        rel = float(np.linalg.norm(r) / max(abs(mu) * math.sqrt(N), 1e-300))
        if rel <= 0.1 * tol:
            break
        band = np.zeros((3, cells))
        band[0, 1:] = tp * ko
        band[1] = tp * kd + 3.0 * up * g**2 / vol - mu
        band[2, :-1] = tp * ko
        try:
            a_ = solve_banded((1, 1), band, r)
            b_ = solve_banded((1, 1), band, g)
        except np.linalg.LinAlgError:   # pragma: no cover - J singular: not near the ground state
            break
        f2 = 0.5 * (g @ g - N)
        dmu = (g @ a_ - f2) / (g @ b_)
        g = g - a_ + dmu * b_
        mu = mu + dmu
    kg = kmul(g)
    r = kg + up * g**3 / vol - mu * g
    residual = float(np.linalg.norm(r) / max(abs(mu) * math.sqrt(N), 1e-300))
    if residual > max(tol, 1e-8):
        warnings.warn(f"disk GP: relative residual {residual:.1e} after {res.nit} L-BFGS iterations and Newton.",
                      ConvergenceWarning, stacklevel=2)
    energy = float(g @ kg + 0.5 * up * np.sum(g**4 / vol))
    return DiskGPState(radius=L, rho_max=R, t_prime=tp, U_prime=up, particles=N, winding=m, rho=centres,
                       f=g / sv, mu_c=mu, energy=energy, residual=residual, method="fv")


def disk_gp_shooting(radius: float, t_prime: float, U_prime: float, particles: float, *, winding: int = 0,
                     guess: DiskGPState | None = None, points: int = 400) -> DiskGPState:
    r"""The same GP state by shooting: the radial ODE from the centre, (amplitude, μ_c) by a root search.

    An independent check of :func:`disk_gp` (no shared discretisation). Suited to disks with
    artanh L ≲ 4 (the outward integration grows like :math:`e^{2\rho}` away from the solution).

    Parameters
    ----------
    radius : float
        Euclidean disk radius L in (0, 1); for a flake of ℓ rings use
        :func:`hyperlattice.dictionary.disk_radius_for_rings`.
    t_prime : float
        Continuum hopping :math:`t' > 0` of the dictionary (:math:`\frac q4 h^2 t`).
    U_prime : float
        Continuum interaction :math:`U' \ge 0` (:math:`\mathcal A U`), at most :math:`10^8 t'`.
    particles : float
        Particle number :math:`N = \int |\varphi|^2 dV_g > 0`.
    winding : int, optional
        Winding number m, :math:`|m| \le 1000` (default 0: the rotationally symmetric ground
        state; m ≠ 0: a vortex at the centre).
    guess : DiskGPState, optional
        Starting point of the root search (default: a :func:`disk_gp` run with 200 cells).
    points : int, optional
        Number of radii at which the result holds f (10 to :math:`10^6`, default 400).

    Returns
    -------
    DiskGPState
        As for :func:`disk_gp`, with ``method = "shooting"`` and ``residual`` that of the boundary
        and norm conditions.

    Raises
    ------
    ValueError
        If an argument is invalid (as for :func:`disk_gp`) or ``guess`` is not a
        :class:`DiskGPState`.
    ConvergenceError
        If the root search does not converge.

    Examples
    --------
    >>> from hyperlattice.continuum.gp import disk_gp, disk_gp_shooting
    >>> s = disk_gp(0.75, 0.057, 0.112, 20.0, cells=100)
    >>> s2 = disk_gp_shooting(0.75, 0.057, 0.112, 20.0, guess=s, points=100)
    >>> print(s2.method, f"{s2.mu_c:.3f}", f"{s2.energy:.3f}")
    shooting 1.462 19.623
    """
    from scipy.integrate import solve_ivp
    from scipy.optimize import root

    L, tp, up, N, m = _check(radius, t_prime, U_prime, particles, winding)
    points = _validate.integer("points", points, minimum=10, maximum=10**6)
    R = math.atanh(L)
    am = abs(m)
    if guess is None:
        guess = disk_gp(L, tp, up, N, winding=m, cells=200)
    if not isinstance(guess, DiskGPState):
        raise ValueError(f"guess must be a DiskGPState, got {_validate._shown(guess)}.")
    eps = 1e-6 * R
    grid = np.linspace(eps, R, points)

    def rhs(rho, y, mu):
        f, fp, nrm = y
        s = _S(rho)
        fpp = -2.0 / np.tanh(2.0 * rho) * fp + (m * m / (s * s)) * f + (up * f**3 - mu * f) / tp
        return [fp, fpp, 2.0 * math.pi * s * f * f]

    def start(c, mu):
        if am == 0:
            return [c, eps * c * (up * c * c - mu) / (2.0 * tp), 0.0]
        return [c * eps**am, c * am * eps ** (am - 1), 0.0]

    def shoot(c, mu, dense=False):
        return solve_ivp(rhs, (eps, R), start(c, mu), args=(mu,), method="DOP853", rtol=1e-12, atol=1e-14,
                         t_eval=grid if dense else None)

    # the guess: centre amplitude (or slope coefficient) and mu
    if am == 0:
        c0 = float(guess.f[0])
    else:
        c0 = float(guess.f[0] / guess.rho[0] ** am)
    scale_f = max(abs(c0), 1e-300)

    def equations(x):
        c, mu = x[0] * scale_f, x[1]
        sol = shoot(c, mu)
        f_end, _, nrm = sol.y[:, -1]
        return [f_end / scale_f, nrm / N - 1.0]

    out = root(equations, [1.0, guess.mu_c], method="hybr", options={"xtol": 1e-13})
    if not out.success:
        raise ConvergenceError(f"disk GP shooting did not converge ({out.message}).")
    c, mu = out.x[0] * scale_f, float(out.x[1])
    sol = shoot(c, mu, dense=True)
    residual = float(np.max(np.abs(equations(out.x))))
    f = sol.y[0]
    s = _S(grid)
    fp = sol.y[1]
    kinetic = 2.0 * math.pi * np.trapezoid(tp * (fp**2 + (m * m) * f**2 / s**2) * s, grid)
    inter = 2.0 * math.pi * np.trapezoid(0.5 * up * f**4 * s, grid)
    return DiskGPState(radius=L, rho_max=R, t_prime=tp, U_prime=up, particles=N, winding=m, rho=grid, f=f,
                       mu_c=mu, energy=float(kinetic + inter), residual=residual, method="shooting")


def healing_length(state: DiskGPState) -> float:
    r"""The healing length :math:`\xi = \sqrt{t'/(U' n_0)}` of a GP state, a geodesic length.

    :math:`n_0` is the largest density of the state. The continuum description of the lattice
    needs ξ ≫ d0 (the lattice spacing); the curvature radius is 1/2 in the paper's metric.

    Parameters
    ----------
    state : DiskGPState
        A state from :func:`disk_gp` or :func:`disk_gp_shooting`.

    Returns
    -------
    float
        ξ in the paper's metric; ``inf`` for U' = 0.

    Raises
    ------
    ValueError
        If ``state`` is not a :class:`DiskGPState`.

    Examples
    --------
    >>> from hyperlattice.continuum.gp import disk_gp, healing_length
    >>> s = disk_gp(0.75, 0.057, 0.112, 20.0, cells=100)
    >>> print(f"{healing_length(s):.4f}")
    0.2016
    """
    if not isinstance(state, DiskGPState):
        raise ValueError(f"state must be a DiskGPState, got {_validate._shown(state)}.")
    n0 = float(np.max(state.f**2))
    if state.U_prime == 0 or n0 == 0:
        return math.inf
    return math.sqrt(state.t_prime / (state.U_prime * n0))


@dataclasses.dataclass(frozen=True, eq=False)
class DiskBogoliubov(Result):
    r"""Bogoliubov frequencies of a rotationally symmetric disk GP state, by angular momentum.

    Attributes
    ----------
    frequencies : ndarray
        The K lowest ω >= 0 ascending, each j ≠ 0 mode listed twice (±j), Goldstone mode first;
        in the energy unit of t' and U' (:math:`\hbar = 1`).
    angular_momenta : ndarray
        :math:`|j|` of each frequency.
    zero_mode : float
        The computed Goldstone frequency (j = 0), zero up to the discretisation.

    Examples
    --------
    >>> from hyperlattice.continuum.gp import disk_gp, disk_bogoliubov
    >>> b = disk_bogoliubov(disk_gp(0.75, 0.057, 0.112, 20.0, cells=100), 4)
    >>> [round(float(w), 4) for w in b.frequencies[1:]], b.angular_momenta.tolist()
    ([0.7306, 0.7306, 1.1985], [0, 1, 1, 2])
    >>> abs(b.zero_mode) < 1e-3
    True
    """

    COLUMNS = (Column("frequency", "frequencies", "t"), Column("abs_j", "angular_momenta", "1"))

    frequencies: np.ndarray
    angular_momenta: np.ndarray
    zero_mode: float

    def summary(self) -> dict:
        return {"frequencies": self.frequencies.tolist(), "angular_momenta": self.angular_momenta.tolist(),
                "zero_mode": self.zero_mode}


def disk_bogoliubov(state: DiskGPState, modes: int = 6, *, max_j: int | None = None) -> DiskBogoliubov:
    r"""The ``modes`` lowest Bogoliubov frequencies around a ``"fv"`` ground state (winding 0).

    For each angular momentum j the radial operators :math:`\mathcal A_j = -t'\Delta_j +
    U'f^2 - \mu_c` and :math:`\mathcal B_j = -t'\Delta_j + 3U'f^2 - \mu_c` on the state's own
    grid; :math:`\omega^2 = \mathrm{eig}(U\mathcal A_jU^T)` with :math:`\mathcal B_j = U^TU` (a
    bidiagonal Cholesky factor, so the matrix is pentadiagonal: LAPACK's banded eigensolver).
    j runs until its lowest frequency exceeds the K-th found (or up to ``max_j``).

    Parameters
    ----------
    state : DiskGPState
        A winding-0 state from :func:`disk_gp` (finite volumes).
    modes : int, optional
        Number K of frequencies, at least 2 (default 6); each j ≠ 0 mode counts twice (±j).
    max_j : int, optional
        Largest angular momentum scanned (default: the number of cells).

    Returns
    -------
    DiskBogoliubov
        Frozen result with ``frequencies`` (the K lowest ω ≥ 0 ascending, in the units of
        t' and U', Goldstone mode first), ``angular_momenta`` (:math:`|j|` of each) and
        ``zero_mode`` (the computed Goldstone frequency, close to 0).

    Raises
    ------
    ValueError
        If ``state`` is not a winding-0 finite-volume :class:`DiskGPState`, or ``modes`` or
        ``max_j`` is invalid.
    ConvergenceError
        If :math:`\mathcal B_j` is not positive definite (the state is not the GP ground state).

    Examples
    --------
    >>> from hyperlattice.continuum.gp import disk_gp, disk_bogoliubov
    >>> s = disk_gp(0.75, 0.057, 0.112, 20.0, cells=100)
    >>> b = disk_bogoliubov(s, 4)
    >>> [round(float(w), 4) for w in b.frequencies[1:]], b.angular_momenta.tolist()
    ([0.7306, 0.7306, 1.1985], [0, 1, 1, 2])
    """
    if not isinstance(state, DiskGPState) or state.method != "fv" or state.winding != 0:
        raise ValueError("state must be a winding-0 DiskGPState from disk_gp() (finite volumes).")
    from scipy.linalg import cholesky_banded, eigvals_banded
    import scipy.sparse as sp

    k = _validate.integer("modes", modes, minimum=2, maximum=10_000)
    cells = state.rho.shape[0]
    jmax = cells if max_j is None else _validate.integer("max_j", max_j, minimum=0, maximum=10**5)
    found_w, found_j = [], []
    zero = math.nan
    for j in range(0, jmax + 1):
        diag, off, vol, _ = _stiffness(state.rho_max, cells, j)
        sv = np.sqrt(vol)
        kd = state.t_prime * diag / vol
        ko = state.t_prime * off / (sv[:-1] * sv[1:])
        dens = state.f**2
        a_diag = kd + state.U_prime * dens - state.mu_c
        b_diag = kd + 3.0 * state.U_prime * dens - state.mu_c
        # omega^2 = eig(A B) = eig(L^T A L) with B = L L^T (tridiagonal Cholesky: L is bidiagonal),
        # so L^T A L is a symmetric pentadiagonal matrix: LAPACK's banded solver gives its lowest k
        try:
            chol = cholesky_banded(np.vstack([np.concatenate([[0.0], ko]), b_diag]), lower=False)
        except np.linalg.LinAlgError:
            # B_j = A_j + 2U' f^2 with A_0 >= 0 (its zero mode is the Goldstone mode): at tiny U' its
            # lowest eigenvalue is below the rounding of B (and the error of mu_c, the state's
            # residual), where it cannot be told from 0; shifted by that error it must factor, and
            # omega^2 moves by at most |A| times the shift (U = 1e-14 was refused as "not the GP state")
            delta = _rounding(b_diag, ko, state)
            try:
                chol = cholesky_banded(np.vstack([np.concatenate([[0.0], ko]), b_diag + delta]), lower=False)
            except np.linalg.LinAlgError:
                raise ConvergenceError("B_j is not positive definite: the state is not the GP ground state."
                                       ) from None
        upper = sp.diags([chol[1], chol[0, 1:]], [0, 1], format="csr")      # B = U^T U, U upper bidiagonal
        amat = sp.diags([ko, a_diag, ko], [-1, 0, 1], format="csr")
        c = (upper @ amat @ upper.T).todia()                                  # U A U^T ~ A B
        bands = np.zeros((3, cells))
        for off_, data in zip(c.offsets, c.data):
            if off_ >= 0:
                bands[2 - off_, off_:] = data[off_:]
        w2 = eigvals_banded(bands, lower=False, select="i", select_range=(0, min(k, cells) - 1))
        if j == 0:
            zero = math.sqrt(abs(float(w2[0])))
        w = np.sqrt(np.clip(w2, 0.0, None))
        for x in w:
            found_w.extend([x] if j == 0 else [x, x])
            found_j.extend([j] if j == 0 else [j, j])
        if len(found_w) >= k and w[0] > np.sort(found_w)[k - 1]:
            break
    order = np.argsort(found_w, kind="stable")[:k]
    return DiskBogoliubov(frequencies=np.asarray(found_w)[order], angular_momenta=np.asarray(found_j)[order],
                          zero_mode=zero)


def _rounding(b_diag: np.ndarray, ko: np.ndarray, state) -> float:
    """The error of the lowest eigenvalue of a tridiagonal B_j (diagonal ``b_diag``, off-diagonal
    ``ko``): its rounding, 16 eps |B|, plus the error of mu_c (the state's relative residual)."""
    norm = float(np.max(np.abs(b_diag))) + 2.0 * (float(np.max(np.abs(ko))) if ko.size else 0.0)
    return 16.0 * np.finfo(float).eps * norm + float(state.residual) * abs(float(state.mu_c))


# every public function above checks its arguments at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
