r"""The discrete Gross–Pitaevskii (GP) ground state of a graph and its Bogoliubov spectrum.

The mean-field (coherent-state) energy of the Bose–Hubbard model with N bosons in the condensate
:math:`\psi_i = \langle a_i\rangle`, :math:`\sum_i |\psi_i|^2 = N`, is

.. math:: E[\psi] = -t \sum_{ij} \psi_i^* A_{ij} \psi_j + \frac U2 \sum_i |\psi_i|^4 ,

(:math:`\frac U2 n(n-1) \to \frac U2|\psi|^4` at this level), stationary where

.. math:: -t (A\psi)_i + U |\psi_i|^2 \psi_i = \mu \psi_i

(the discrete GP equation; μ is the Lagrange multiplier, :math:`\mu = \partial E/\partial N`).
For t > 0 the ground state is real and positive. It is found by minimising E over
:math:`\psi = \sqrt N x/\lVert x\rVert` with L-BFGS (scipy; one sparse product per step), polished by
Newton steps on (ψ, μ) through :mod:`hyperlattice.graph.factor`, and checked by the residual of
the GP equation.

Bogoliubov spectrum
-------------------
Around a real ground state, with :math:`\mathcal A = -tA + U\psi^2 - \mu` (positive semidefinite,
:math:`\mathcal A\psi = 0`) and :math:`\mathcal B = -tA + 3U\psi^2 - \mu` (positive definite), the
Bogoliubov–de Gennes frequencies are :math:`\omega = \sqrt{\mathrm{eig}(\mathcal A\mathcal B)}`
(e.g. Pethick and Smith, *Bose–Einstein Condensation in Dilute Gases*, Ch. 8). The Goldstone mode
of the broken U(1) symmetry is :math:`\omega = 0` exactly (:math:`\mathcal A\psi = 0`). The
lowest ω² are found as the generalised symmetric problem :math:`\mathcal A u = \omega^2\mathcal
B^{-1} u` by shift-invert Lanczos with the operator :math:`(\mathcal B\mathcal A - \sigma)^{-1}`
(one sparse LU of :math:`\mathcal B\mathcal A - \sigma`, one factorisation of
:math:`\mathcal B`, both through :mod:`hyperlattice.graph.factor`); small graphs (≤ 3000 sites)
use a dense symmetric eigensolver on :math:`\mathcal B^{1/2}\mathcal A\mathcal B^{1/2}`.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..errors import ConvergenceError, ConvergenceWarning
from ..results import Column, Result
from .meanfield import _adjacency, _system_label

__all__ = ["GPState", "gp_ground_state", "BogoliubovSpectrum", "bogoliubov"]

#: relative GP residual below which the ground state is accepted without a warning
_RESIDUAL_TOL = 1e-8
#: largest U / t accepted (the GP equation is a weak-coupling theory; beyond this the optimiser
#: works with numbers that mean nothing physically)
_MAX_COUPLING = 1e6
#: largest energy scale accepted (float64 ends at 1.8e308; psi^4 and sums need headroom)
_MAX_ENERGY = 1e300
#: U N / sites below this fraction of the hopping scale: the minimisation starts at the U = 0 state
_WEAK = 1e-6
#: sites up to which the Bogoliubov problem is solved densely
_DENSE_SITES = 3000


@dataclasses.dataclass(frozen=True, eq=False)
class GPState(Result):
    r"""A discrete Gross–Pitaevskii ground state.

    Attributes
    ----------
    label : str
        What the graph is (e.g. ``"{7,3} flake, l = 2"``).
    t, U : float
        Hopping and interaction (one energy unit, that of t; :math:`H = -tA` for the hopping).
    particles : float
        :math:`N = \sum_i |\psi_i|^2`.
    psi : ndarray
        Real, non-negative condensate amplitude per site (0-based, the graph's site order).
    mu : float
        Chemical potential μ (same unit), from the GP equation.
    energy : float
        E[ψ].
    residual : float
        :math:`\lVert -tA\psi + U\psi^3 - \mu\psi\rVert / \lVert\mu\psi\rVert`.
    iterations : int
        Iterations of the minimiser.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.gp import gp_ground_state
    >>> state = gp_ground_state(hl.ring_lattice(7, 3, 2), 35.0, 0.5)
    >>> state.label, state.psi.shape
    ('{7,3} flake, l = 2', (35,))
    >>> print(f"{state.mu:.6f} {float(state.density.sum()):.6f}")
    -1.953974 35.000000
    """

    #: one row per site
    COLUMNS = (Column("psi", "psi", "sqrt(bosons)"), Column("density", "density", "bosons"))

    label: str
    t: float
    U: float
    particles: float
    psi: np.ndarray
    mu: float
    energy: float
    residual: float
    iterations: int

    @property
    def density(self) -> np.ndarray:
        r""":math:`|\psi_i|^2`, bosons per site."""
        return self.psi**2

    def summary(self) -> dict:
        return {"label": self.label, "t": self.t, "U": self.U, "particles": self.particles, "mu": self.mu,
                "energy": self.energy, "sites": int(self.psi.shape[0]),
                "max_density": float(np.max(self.psi**2)), "residual": self.residual,
                "iterations": self.iterations}


def gp_ground_state(system, particles: float, U: float, t: float = 1.0, *, tol: float = 1e-10,
                    max_iter: int = 20_000, psi0=None) -> GPState:
    r"""The discrete GP ground state of N bosons on a graph (Lattice, Cluster or adjacency matrix).

    Parameters
    ----------
    system : Lattice, Cluster or sparse matrix
        A flake or line graph, a periodic cluster, or a symmetric adjacency matrix.
    particles : float
        N > 0 (a real number: the condensate's norm).
    U : float
        On-site interaction, >= 0 (U = 0 gives :math:`\sqrt N` times the single-particle ground
        state and μ = E0).
    t : float, optional
        Hopping > 0. Default 1.
    tol : float, optional
        Target relative residual of the GP equation (the optimiser's gradient tolerance is set
        from it); a :class:`~hyperlattice.errors.ConvergenceWarning` states the residual reached
        when it stays above ``max(tol, 1e-8)``. Default 1e-10.
    max_iter : int, optional
        L-BFGS iteration cap. Default 20 000.
    psi0 : array, optional
        Starting amplitudes, one per site, not all zero (default: uniform).

    Returns
    -------
    GPState
        The amplitudes ``psi`` (real, >= 0, :math:`\sum_i\psi_i^2 = N`), the chemical potential
        ``mu`` and ``energy`` (units of t), the GP ``residual`` and ``iterations``.

    Raises
    ------
    ValueError
        For bad input: N <= 0, U < 0 or U > 1e6 t (far outside the weak-coupling regime),
        t <= 0, a zero ``psi0`` or a bad system.

    Warns
    -----
    ConvergenceWarning
        If the residual stays above ``max(tol, 1e-8)``.

    See Also
    --------
    bogoliubov : the excitations of the state.
    hyperlattice.continuum.gp.disk_gp : the continuum counterpart.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.gp import gp_ground_state
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> state = gp_ground_state(lat, 35.0, 0.5)
    >>> print(f"{state.mu:.6f} {float(np.sum(state.psi ** 2)):.6f}")
    -1.953974 35.000000
    >>> print(f"{gp_ground_state(lat, 35.0, 0.0).mu:.6f}")   # U = 0: mu = E0
    -2.636405
    """
    from scipy.optimize import minimize

    a = _adjacency(system)
    n = a.shape[0]
    N = _validate.positive_real("particles", particles)
    U = _validate.real("U", U, minimum=0.0)
    t = _validate.positive_real("t", t)
    if U > _MAX_COUPLING * t:
        raise ValueError(f"U = {U:g} is more than {_MAX_COUPLING:g} t: far outside the weak-coupling regime of the "
                         "Gross-Pitaevskii equation (use exact diagonalisation, hyperlattice.bosons.ed).")
    tol = _validate.solver_tolerance("tol", tol)
    max_iter = _validate.integer("max_iter", max_iter, minimum=1, maximum=10**7)
    _validate.require_memory("the GP minimisation", 8.0 * n * 40 + 12.0 * a.nnz)
    h = (-t) * a
    x0 = None if psi0 is None else _validate.real_array("psi0", psi0, shape=(n,)).copy()
    if x0 is not None and not np.any(x0):
        raise ValueError("psi0 must not be zero.")
    scale = t * max(1.0, float(np.max(np.asarray(a.sum(axis=1))))) if n else t  # an energy scale of H
    # the energy is about N (U N / sites + scale): refused before work when it (or psi^4 on the way)
    # would overflow; at 1e308 bosons it came back as NaN and -inf
    if N * max(U * N / max(n, 1), scale) > _MAX_ENERGY or N * N * U > _MAX_ENERGY:
        raise ValueError(f"particles = {N:g} at U = {U:g}: the energy (about U N^2/(2 sites) + q t N) lies beyond the "
                         f"range of float64 numbers ({_MAX_ENERGY:.0e}); give fewer particles.")

    def energy_and_gradient(x):
        nx = np.linalg.norm(x)
        psi = math.sqrt(N) * x / nx
        hp = h @ psi
        e = float(psi @ hp + 0.5 * U * np.sum(psi**4))
        g_psi = 2.0 * (hp + U * psi**3)
        # chain rule through psi = sqrt(N) x / |x|: project out the radial direction
        g = (math.sqrt(N) / nx) * (g_psi - psi * (psi @ g_psi) / N)
        return e, g

    if U == 0.0:
        # linear: sqrt(N) times the single-particle ground state (positive, Perron-Frobenius)
        return _noninteracting(system, a, h, N, t)
    if x0 is None:
        if U * N / max(n, 1) <= _WEAK * scale:
            # weak interaction (U N / sites << t): the state is the single-particle ground state to
            # O(U N / t). From the uniform start L-BFGS crawled (the energy differences are U-small:
            # U = 1e-14 stopped at a residual of 2e-6) and Newton's Jacobian H + 3U psi^2 - mu is
            # singular to rounding there, so start at the U = 0 state, where the residual is O(U N)
            x0 = _noninteracting(system, a, h, 1.0, t, check=False).psi.copy()
        else:
            x0 = np.ones(n)
    res = minimize(energy_and_gradient, x0, jac=True, method="L-BFGS-B",
                   options={"maxiter": max_iter, "gtol": 1e-6 * scale * math.sqrt(N), "ftol": 0.0,
                            "maxcor": 20})
    psi = np.abs(math.sqrt(N) * res.x / np.linalg.norm(res.x))
    hp = h @ psi
    mu = float((psi @ hp + U * np.sum(psi**4)) / N)
    residual = _relative_residual(h, U, psi, mu, N)
    if residual > 0.1 * tol:
        psi, mu = _newton(h, U, psi, mu, N, tol)
        hp = h @ psi
        residual = _relative_residual(h, U, psi, mu, N)
    if residual > max(tol, _RESIDUAL_TOL):
        warnings.warn(f"GP ground state: relative residual {residual:.1e} after {res.nit} L-BFGS iterations "
                      f"and Newton (target {tol:.0e}).", ConvergenceWarning, stacklevel=2)
    e = float(psi @ hp + 0.5 * U * np.sum(psi**4))
    return GPState(label=_system_label(system), t=t, U=U, particles=N, psi=np.abs(psi), mu=mu, energy=e,
                   residual=residual, iterations=int(res.nit))


def _noninteracting(system, a, h, N: float, t: float, *, check: bool = True) -> GPState:
    n = a.shape[0]
    if hasattr(system, "ring_offsets"):
        from ..graph.spectrum import lowest_levels

        spec = lowest_levels(system, 1, t=t, eigenvectors=True)
        vec = np.asarray(spec.eigenvectors)[:, 0].real
    elif n <= 400:
        vec = np.linalg.eigh(h.toarray())[1][:, 0]
    else:
        import scipy.sparse.linalg as spla

        vec = spla.eigsh(h, k=1, which="SA", v0=np.ones(n), tol=1e-13)[1][:, 0]
    psi = math.sqrt(N) * np.abs(vec) / np.linalg.norm(vec)
    mu = float(psi @ (h @ psi) / N)
    residual = _relative_residual(h, 0.0, psi, mu, N)
    if check and residual > _RESIDUAL_TOL:
        warnings.warn(f"GP ground state at U = 0: relative residual {residual:.1e}.", ConvergenceWarning, stacklevel=3)
    return GPState(label=_system_label(system), t=t, U=0.0, particles=N, psi=psi, mu=mu, energy=mu * N,
                   residual=residual, iterations=0)


def _relative_residual(h, U, psi, mu, N) -> float:
    r = h @ psi + U * psi**3 - mu * psi
    return float(np.linalg.norm(r) / max(abs(mu) * math.sqrt(N), 1e-300))


def _newton(h, U, psi, mu, N, tol, steps: int = 8):
    """Newton on (psi, mu): J = H + 3U psi^2 - mu is positive definite at the ground state, so
    each step is one factorisation (graph.factor, proving J > 0) and two solves."""
    from ..graph.factor import factorize

    n = psi.shape[0]
    for _ in range(steps):
        r = h @ psi + U * psi**3 - mu * psi
        if float(np.linalg.norm(r) / max(abs(mu) * math.sqrt(N), 1e-300)) <= 0.1 * tol:
            break
        jac = (h + sp.diags(3.0 * U * psi**2)).tocsc()
        fac = factorize(jac, mu, positive=True, what="the GP Jacobian")
        if fac.negatives not in (0, None):
            break   # not near the ground state: leave it to the caller's residual check
        a_ = fac.solve(r)
        b_ = fac.solve(psi)
        f2 = 0.5 * (psi @ psi - N)
        dmu = (psi @ a_ - f2) / (psi @ b_)
        psi = psi - a_ + dmu * b_
        mu = mu + float(dmu)
        if n and psi.sum() < 0:
            psi = -psi
    return np.abs(psi), float(mu)


@dataclasses.dataclass(frozen=True, eq=False)
class BogoliubovSpectrum(Result):
    r"""The lowest Bogoliubov frequencies around a GP ground state.

    Attributes
    ----------
    label : str
        What the graph is.
    frequencies : ndarray
        The K lowest ω >= 0 ascending, the Goldstone mode first (ω = 0 to rounding); in the
        energy unit of t and U (:math:`\hbar = 1`).
    zero_mode : float
        The computed Goldstone frequency (its size is the method's error).
    tolerance : float
        The frequency below which a mode counts as zero: a multiple of the problem's rounding
        level :math:`\sqrt{\epsilon\,\lVert\mathcal A\rVert\lVert\mathcal B\rVert\, n}`.
    method : str
        ``"dense"`` or ``"shift-invert"``.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.gp import bogoliubov, gp_ground_state
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> spec = bogoliubov(gp_ground_state(lat, 35.0, 0.5), lat, modes=3)
    >>> spec.method, bool(abs(spec.zero_mode) < spec.tolerance)
    ('dense', True)
    >>> [round(float(w), 4) for w in spec.frequencies[1:]]
    [0.4868, 0.4868]
    """

    label: str
    frequencies: np.ndarray
    zero_mode: float
    tolerance: float
    method: str

    def summary(self) -> dict:
        return {"label": self.label, "frequencies": self.frequencies.tolist(), "zero_mode": self.zero_mode,
                "tolerance": self.tolerance, "method": self.method}


def bogoliubov(state: GPState, system, modes: int = 6) -> BogoliubovSpectrum:
    r"""The ``modes`` lowest Bogoliubov frequencies (Goldstone mode included) of a GP ground state.

    Parameters
    ----------
    state : GPState
        From :func:`gp_ground_state` on the same ``system``.
    system : Lattice, Cluster or sparse matrix
        The graph the state lives on.
    modes : int, optional
        K >= 2. Default 6.

    Returns
    -------
    BogoliubovSpectrum
        The K lowest ``frequencies`` :math:`\omega \ge 0` (units of t), the computed Goldstone
        frequency ``zero_mode``, the ``tolerance`` below which a mode counts as zero, and the
        ``method`` (``"dense"`` up to 3000 sites, else ``"shift-invert"``).

    Raises
    ------
    ValueError
        If ``state`` is not a GPState or has another number of sites than ``system``.
    hyperlattice.errors.ConvergenceError
        If the Bogoliubov matrix :math:`\mathcal B` is not positive definite (the state is not
        a GP ground state).

    References
    ----------
    .. [1] C. J. Pethick and H. Smith, *Bose–Einstein Condensation in Dilute Gases*, Ch. 8.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.bosons.gp import bogoliubov, gp_ground_state
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> spec = bogoliubov(gp_ground_state(lat, 35.0, 0.5), lat, modes=3)
    >>> spec.method, bool(spec.frequencies[0] < spec.tolerance)
    ('dense', True)
    >>> [round(float(w), 4) for w in spec.frequencies[1:]]
    [0.4868, 0.4868]
    """
    if not isinstance(state, GPState):
        raise ValueError(f"state must be a GPState from gp_ground_state(), got {_validate._shown(state)}.")
    a = _adjacency(system)
    n = a.shape[0]
    if n != state.psi.shape[0]:
        raise ValueError(f"state has {state.psi.shape[0]} sites but the system has {n}.")
    k = _validate.integer("modes", modes, minimum=2, maximum=max(2, n - 2))
    psi2 = state.psi**2
    h = (-state.t) * a
    eye = sp.identity(n, format="csr")
    A = (h + sp.diags(state.U * psi2) - state.mu * eye).tocsr()
    B = (h + sp.diags(3.0 * state.U * psi2) - state.mu * eye).tocsr()
    norm = float(abs(A).sum(axis=1).max()) * float(abs(B).sum(axis=1).max())
    tol = 64.0 * math.sqrt(np.finfo(float).eps * norm * n)
    b_error = 16.0 * np.finfo(float).eps * float(abs(B).sum(axis=1).max()) + state.residual * abs(state.mu)
    if n <= _DENSE_SITES:
        bd = B.toarray()
        wb, vb = np.linalg.eigh(bd)
        # B = A + 2U psi^2 > 0, but at tiny U its lowest eigenvalue (~2U psi^2) is below the error
        # of the computed B (rounding, and mu's error from the state's residual), where it cannot
        # be told from 0 (U = 1e-14 was refused as "not a GP ground state"): within that error it
        # counts as 0, which moves omega^2 by at most |A| times the error
        if wb[0] < -b_error:
            raise ConvergenceError("the Bogoliubov matrix B is not positive definite: the state is not a "
                                   "GP ground state (unconverged, or a state of higher energy).")
        root = (vb * np.sqrt(np.clip(wb, 0.0, None))) @ vb.T
        w2 = np.linalg.eigvalsh(root @ A.toarray() @ root)[:k]
        method = "dense"
    else:
        w2 = _shift_invert_bdg(A, B, k, norm, b_error)
        method = "shift-invert"
    if np.any(w2 < -tol**2 * 16):
        warnings.warn(f"Bogoliubov: a negative omega^2 = {w2.min():.2e} beyond rounding: the state is not a "
                      "stable ground state.", ConvergenceWarning, stacklevel=2)
    freqs = np.sqrt(np.clip(w2, 0.0, None))
    return BogoliubovSpectrum(label=state.label, frequencies=freqs, zero_mode=math.sqrt(abs(float(w2[0]))),
                              tolerance=tol,
                              method=method)


def _shift_invert_bdg(A: sp.csr_matrix, B: sp.csr_matrix, k: int, norm: float, b_error: float) -> np.ndarray:
    """ω² nearest a small negative shift: eigsh on the pencil (A, B^-1) with OP = (BA - σ)^-1.
    A B whose lowest eigenvalue is within ``b_error`` of 0 is shifted by it (as in the dense case)."""
    import scipy.sparse.linalg as spla

    from ..graph.factor import factorize

    n = A.shape[0]
    sigma = -1e-6 * math.sqrt(norm)
    fb = factorize(B, 0.0, positive=True, what="the Bogoliubov matrix B")
    if fb.negatives not in (0, None):
        B = (B + b_error * sp.identity(n, format="csr")).tocsr()
        fb = factorize(B, 0.0, positive=True, what="the Bogoliubov matrix B")
    if fb.negatives not in (0, None):
        raise ConvergenceError("the Bogoliubov matrix B is not positive definite: the state is not a GP "
                               "ground state.")
    ba = (B @ A).tocsc()
    fba = factorize(ba, sigma, pivoting=True, what="B A - sigma (Bogoliubov)")
    m_op = spla.LinearOperator((n, n), matvec=lambda v: fb.solve(np.asarray(v).ravel()), dtype=np.float64)
    op_inv = spla.LinearOperator((n, n), matvec=lambda v: fba.solve(B @ np.asarray(v).ravel()), dtype=np.float64)
    vals = spla.eigsh(A, k=k, M=m_op, sigma=sigma, OPinv=op_inv, which="LM", return_eigenvectors=False,
                      v0=np.ones(n), tol=1e-12)
    return np.sort(vals)


# every public function above checks its arguments at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
