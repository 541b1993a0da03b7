r"""The scattering matrix of a device: input–output theory, swept over thousands of frequencies.

Convention (Clerk et al., Rev. Mod. Phys. 82, 1155 (2010), Sec. E; the e^{−iωt} time dependence):
with :math:`\Gamma = \kappa_{int}\,1 + \sum_p \kappa_p e_{r_p} e_{r_p}^T` and
:math:`G(\omega) = (\omega - H + \tfrac{i}{2}\Gamma)^{-1}`,

.. math::

    S_{qp}(\omega) = \delta_{qp} - i\sqrt{\kappa_p \kappa_q}\; G_{r_q r_p}(\omega).

Without loss (:math:`\kappa_{int} = 0`) S is unitary; S is symmetric (reciprocity) because H is
real. For weak port coupling (:math:`\kappa_p \ll` level spacing) G is the resolvent of H broadened
by :math:`\kappa_{int}`, and :math:`S_{21} = -i\sqrt{\kappa_1\kappa_2}\sum_n
\langle r_2|\psi_n\rangle\langle\psi_n|r_1\rangle / (\omega - E_n + i\kappa_{int}/2)`, the sum of
Lorentzians experimental groups fit with.

Only the P × P port block of G is needed. Write :math:`z = \omega + i\kappa_{int}/2` (a scalar,
because the internal loss is uniform), :math:`g_0(z) = U^T (z - H)^{-1} U` with U the port
columns, D = diag(iκ_p/2): then :math:`G_{PP} = (1 + g_0 D)^{-1} g_0` (Woodbury, exact). Three
routes compute :math:`g_0`:

``"eigen"``
    One dense eigendecomposition :math:`H = V\Lambda V^T`, then
    :math:`g_0 = W (z - \Lambda)^{-1} W^T`, W the port rows of V: O(N P) per frequency. Devices up
    to :data:`EIGEN_MAX` resonators.
``"chebyshev"``
    For large devices with loss: the Chebyshev series of the resolvent,
    :math:`1/(z - x) = s^{-1}(1 + 2\sum_{n\ge1}\rho^n T_n(x))` with :math:`s = \sqrt{z^2-1}`,
    :math:`\rho = z - s`, :math:`|\rho| < 1` (H scaled into [−1, 1] by its Gershgorin bounds). The
    moments :math:`\mu_n = U^T T_n(\tilde H) U` cost M/2 sparse products with the P port vectors
    (:math:`\mu_{2k} = 2 v_k^T v_k - \mu_0`, :math:`\mu_{2k+1} = 2 v_{k+1}^T v_k - \mu_1`), once
    for all frequencies. Since :math:`|\mu_n| \le 1`, the tail after M terms is at most
    :math:`2|\rho|^M / (|s|(1-|\rho|))` (a proof, not an estimate); it is propagated to S to first
    order through the Woodbury step and reported per frequency (``error_bound``, with the rounding
    of the recurrence); M is doubled until the bound meets ``tol``.
``"direct"``
    One sparse LU of :math:`H - z` per frequency through the package's factor layer
    (:mod:`hyperlattice.graph.factor`, SuperLU with its column order kept), P solves, then the
    same Woodbury step: the fallback for large lossless devices.

``"auto"`` takes eigen up to :data:`EIGEN_MAX` resonators, else Chebyshev when its moments cost less
than :data:`_CHEB_PER_FREQUENCY` sparse products per frequency (κ_int large enough), else direct.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..errors import ConvergenceWarning
from ..results import Column, Result
from .resonators import Device

__all__ = ["Transmission", "transmission", "METHODS", "EIGEN_MAX"]

METHODS = ("auto", "eigen", "chebyshev", "direct")
#: largest device of the eigen route (dense eigh of N x N: 2500^3 flops ~ 15 s, 150 MB)
EIGEN_MAX = 2500
#: most frequencies one call takes
MAX_FREQUENCIES = 10_000_000
#: "auto" prefers Chebyshev while its moments (M P sparse products) stay below this many per frequency
#: (one SuperLU of these graphs costs ~100-300 sparse products, measured on l = 6-8 line graphs)
_CHEB_PER_FREQUENCY = 50
#: most Chebyshev moments a call computes
MAX_MOMENTS = 20_000_000
_EPS = np.finfo(float).eps
#: a level closer than this (relative to the spectral scale) to z is kept out of g0 (eigen: bordered system;
#: direct without loss: the mean of z +- this distance)
_NEAR_LEVEL = 1e-6
#: levels whose port amplitudes are all below this are dark: they do not couple to any port
_DARK = 1e-12


@dataclass(frozen=True, eq=False, kw_only=True)
class Transmission(Result):
    r"""The scattering matrix S(ω) of a device at every frequency.

    Attributes
    ----------
    omega : ndarray
        Frequencies (the user's units).
    s : ndarray, shape (F, P, P)
        :math:`S_{qp}(\omega)`: ``s[f, out, in]``.
    resonators : tuple of str
        Resonator names in the order used.
    ports : tuple of str
        The resonator of each port, in port order.
    port_kappa : ndarray
        κ_p of each port.
    kappa_int : float
        Internal loss rate.
    method : str
        ``"eigen"``, ``"chebyshev"`` or ``"direct"``.
    error_bound : ndarray
        Per frequency, a bound on max ``|δS|`` (Chebyshev: truncation proved, rounding estimated);
        NaN for the direct routes (rounding only).
    flat_band : int or None
        Line graph: multiplicity of the eigenvalue −2 of its adjacency.
    levels : ndarray
        Eigenvalues of H when the eigen route ran (else empty): the resonances' positions.
    moments : int
        Chebyshev moments used (0 otherwise).
    description : str
        The device.

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.device import resonator_device, transmission
    >>> dev = resonator_device(hl.ring_lattice(7, 3, 1), omega0=5.0, J=0.1, kappa_int=0.0,
    ...                        ports={"0": 0.05, "3": 0.05})
    >>> tr = transmission(dev, np.linspace(4.7, 5.3, 5))
    >>> tr.method, tr.s.shape
    ('eigen', (5, 2, 2))
    >>> s = tr.s[2]; bool(np.allclose(s.conj().T @ s, np.eye(2)))      # lossless: unitary
    True
    """

    COLUMNS: ClassVar[tuple] = (Column("omega", "omega", "user's frequency unit"),
                                Column("s21_re", "s21_re", "1"), Column("s21_im", "s21_im", "1"),
                                Column("s21_abs2", "power", "1"), Column("error_bound", "error_bound", "1"))

    omega: np.ndarray
    s: np.ndarray
    resonators: tuple
    ports: tuple
    port_kappa: np.ndarray
    kappa_int: float
    method: str
    error_bound: np.ndarray
    flat_band: int | None = None
    levels: np.ndarray | None = None
    moments: int = 0
    description: str = ""

    def __post_init__(self) -> None:
        super().__post_init__()
        s, w = np.asarray(self.s), np.asarray(self.omega)
        if w.ndim != 1 or s.ndim != 3 or s.shape[0] != w.size or s.shape[1] != s.shape[2] or s.shape[1] == 0:
            raise ValueError(f"a Transmission holds s of shape (frequencies, ports, ports) = ({w.size}, P, P), "
                             f"got {s.shape}.")
        if len(self.ports) != s.shape[1]:
            raise ValueError(f"a Transmission names {len(self.ports)} ports for an S matrix of {s.shape[1]}.")

    @property
    def s21(self) -> np.ndarray:
        """S from port 1 to port 2 (``s[:, 1, 0]``; the reflection ``s[:, 0, 0]`` with one port)."""
        s = np.asarray(self.s)
        return s[:, 1, 0] if s.shape[1] > 1 else s[:, 0, 0]

    @property
    def s21_re(self) -> np.ndarray:
        """Re S21."""
        return self.s21.real

    @property
    def s21_im(self) -> np.ndarray:
        """Im S21."""
        return self.s21.imag

    @property
    def power(self) -> np.ndarray:
        """``|S21|²``, the transmitted power fraction."""
        return np.abs(self.s21) ** 2



def _omegas(omegas) -> np.ndarray:
    if isinstance(omegas, (str, bytes, bool)) or omegas is None:
        raise ValueError(f"omegas must be a list of real frequencies, got {_validate._shown(omegas)}.")
    try:
        w = np.atleast_1d(np.asarray(omegas))
    except (TypeError, ValueError):
        raise ValueError("omegas must be a flat list of real frequencies (a ragged list is not).") from None
    if w.ndim != 1 or w.dtype.kind not in "iuf" or w.size == 0:
        raise ValueError(f"omegas must be a non-empty 1-d list of real frequencies, got {_validate._shown(omegas)}.")
    w = w.astype(float)
    if not np.all(np.isfinite(w)):
        raise ValueError("omegas holds NaN or infinite values.")
    if w.size > MAX_FREQUENCIES:
        raise ValueError(f"at most {MAX_FREQUENCIES:,} frequencies per call, got {w.size:,}.")
    return w


def _scale(dev: Device) -> tuple[float, float]:
    """(centre, half width) of an interval holding the spectrum of H (Gershgorin, proved)."""
    h = dev.hamiltonian()
    d = h.diagonal()
    r = np.asarray(abs(h).sum(axis=1)).ravel() - np.abs(d)
    lo, hi = float(np.min(d - r)), float(np.max(d + r))
    half = 0.5 * (hi - lo)
    # a margin for the rounding of the bounds themselves; a single resonator has zero width
    half = half * (1 + 1e-12) + 1e-12 * max(abs(lo), abs(hi), 1e-300) + (1e-300 if half == 0 else 0)
    if half == 0 or not math.isfinite(half):
        half = max(abs(lo), 1.0)
    return 0.5 * (hi + lo), half


def _woodbury(g0: np.ndarray, kap: np.ndarray) -> np.ndarray:
    """S from g0 (F, P, P): G = (1 + g0 D)^-1 g0, S = 1 - i sqrt(k k) G."""
    P = kap.size
    dmat = 0.5j * kap
    a = np.eye(P)[None] + g0 * dmat[None, None, :]
    g = np.linalg.solve(a, g0)
    root = np.sqrt(kap)
    return np.eye(P)[None] - 1j * root[None, :, None] * g * root[None, None, :]


def _bordered(r: np.ndarray, wn: np.ndarray, delta: np.ndarray, kap: np.ndarray) -> np.ndarray:
    """S at a frequency next to levels n (g0 = r + wn diag(1/delta) wn^T with delta tiny, even 0).

    G = (1 + g0 D)^-1 g0 solves the bordered system [[1 + r D, wn], [wn^T D, -diag(delta)]] [X; Y] = [r; wn^T],
    whose entries are all of order one: the pole is never divided out.
    """
    P, K = r.shape[0], wn.shape[1]
    dmat = np.diag(0.5j * kap)
    big = np.zeros((P + K, P + K), np.complex128)
    big[:P, :P] = np.eye(P) + r @ dmat
    big[:P, P:] = wn
    big[P:, :P] = wn.T @ dmat
    big[P:, P:] = -np.diag(delta)
    rhs = np.vstack([r, wn.T]).astype(np.complex128)
    g = np.linalg.solve(big, rhs)[:P]
    root = np.sqrt(kap)
    return np.eye(P) - 1j * root[:, None] * g * root[None, :]


def _direct(dev: Device, omegas: np.ndarray, analysis=None):
    """S by one sparse LU of H − z per frequency (the factor layer), then the port Woodbury step;
    returns (S, analysis)."""
    from ..graph.factor import FactorizationError, analyze

    n = dev.size
    idx = np.asarray(dev.port_index)
    kap = np.asarray(dev.port_kappa, float)
    if analysis is None:
        analysis = analyze(dev.hamiltonian().tocsc(), backend="superlu", what="H − ω of the device")
    rhs = np.zeros((n, idx.size))
    rhs[idx, np.arange(idx.size)] = 1.0
    g0 = np.empty((omegas.size, idx.size, idx.size), np.complex128)
    scale = max(float(abs(analysis.matrix).max()), 1e-300)
    for f, w in enumerate(omegas):
        z = complex(w, 0.5 * dev.kappa_int)
        try:
            fac = analysis.factor(z, pivoting=True)
            g = -fac.solve(rhs)[idx]
            singular = dev.kappa_int <= 0 and float(np.max(np.abs(g))) * _NEAR_LEVEL * scale > 1.0
        except FactorizationError:
            singular = True
        if singular:
            raise ValueError(f"omega = {w:.12g} lies within 1e-6 of the spectral scale of a level of this lossless "
                             "device, where the direct route would lose its digits; move the frequency, add "
                             "kappa_int > 0, or use method='eigen' (devices up to "
                             f"{EIGEN_MAX:,} resonators).")
        g0[f] = g
    return _woodbury(g0, kap), analysis


def _eigen(dev: Device, omegas: np.ndarray):
    import scipy.linalg as sla

    n = dev.size
    _validate.require_memory(f"the dense eigendecomposition of {n:,} resonators", 4.0 * 8 * n * n)
    lam, vec = sla.eigh(dev.hamiltonian().toarray())
    idx = np.asarray(dev.port_index)
    w = vec[idx, :]                              # (P, N)
    kap = np.asarray(dev.port_kappa, float)
    P = idx.size
    scale = max(float(np.max(np.abs(lam))), float(np.ptp(lam)), 1e-300)
    near_d = _NEAR_LEVEL * scale
    z = omegas + 0.5j * dev.kappa_int
    out = np.empty((omegas.size, P, P), np.complex128)
    chunk = max(1, int(2_000_000 // max(n, 1)))
    pairs = (w[:, None, :] * w[None, :, :]).reshape(P * P, n).T      # (N, P*P): w_p w_q per level
    bright = np.linalg.norm(w, axis=0) > _DARK
    lam_bright = lam[bright]
    eta = 0.5 * dev.kappa_int
    for a in range(0, omegas.size, chunk):
        zz = z[a:a + chunk]
        # only the bright levels next to each frequency can be near it: a search, not a scan of N x F
        hit = np.zeros(zz.size, bool)
        if lam_bright.size:
            k = np.searchsorted(lam_bright, zz.real)
            lo = np.abs(zz - lam_bright[np.maximum(k - 1, 0)])
            hi = np.abs(zz - lam_bright[np.minimum(k, lam_bright.size - 1)])
            hit = np.minimum(lo, hi) < near_d
        # 1/(z - lam) = (x - i eta)/(x^2 + eta^2): real arithmetic (numpy's complex division is slower)
        x = zz.real[:, None] - lam[None, :]
        den = x * x + eta * eta
        hits = np.flatnonzero(hit)
        for f in hits:
            near = np.abs(zz[f] - lam) < near_d
            x[f, near] = 0.0                     # bright ones enter the bordered system below, dark ones
            den[f, near] = 1.0                   # couple to no port
        zero = den == 0                          # a lossless frequency exactly on a dark level
        if zero.any():
            x[zero], den[zero] = 0.0, 1.0
        g0 = ((x / den) @ pairs - 1j * (eta / den) @ pairs).reshape(zz.size, P, P)
        out[a:a + chunk] = _woodbury(g0, kap)
        for f in hits:
            near = (np.abs(zz[f] - lam) < near_d) & bright
            out[a + f] = _bordered(g0[f], w[:, near], zz[f] - lam[near], kap)
    return out, lam, "eigen"


def _cheb_moments_needed(zs: np.ndarray, tail_tol: np.ndarray) -> int:
    s = np.sqrt(zs - 1) * np.sqrt(zs + 1)
    rho = np.abs(1.0 / (zs + s))
    # 2 rho^M / (|s| (1 - rho)) <= tail_tol
    with np.errstate(divide="ignore"):
        m = np.log(tail_tol * np.abs(s) * (1 - rho) / 2) / np.log(rho)
    return int(np.ceil(np.max(np.maximum(m, 2))))


_KERNELS: dict = {}


def _kernels() -> dict:
    """Numba kernels of the Chebyshev route, compiled on first use (never at import)."""
    if _KERNELS:
        return _KERNELS
    import numba

    @numba.njit(cache=True)
    def steps(indptr, indices, data, vp, v, nsteps, mu0, mu1, out):     # pragma: no cover - compiled
        # nsteps of v_{k+1} = 2 H v_k - v_{k-1} (vectors as rows: v[p] is port p's), with
        # mu_{2k} = 2 v_k.v_k - mu_0 and mu_{2k+1} = 2 v_{k+1}.v_k - mu_1
        P, n = v.shape
        vn = np.empty_like(v)
        for s in range(nsteps):
            for p in range(P):
                vrow = v[p]
                prow = vp[p]
                nrow = vn[p]
                for i in range(n):
                    acc = 0.0
                    for j in range(indptr[i], indptr[i + 1]):
                        acc += data[j] * vrow[indices[j]]
                    nrow[i] = 2.0 * acc - prow[i]
            for p in range(P):
                for q in range(P):
                    a = 0.0
                    b = 0.0
                    for i in range(n):
                        a += v[p, i] * v[q, i]
                        b += vn[p, i] * v[q, i]
                    out[2 * s, p, q] = 2.0 * a - mu0[p, q]
                    out[2 * s + 1, p, q] = 2.0 * b - mu1[p, q]
            tmp = vp
            vp = v
            v = vn
            vn = tmp
        return vp, v

    @numba.njit(cache=True)
    def horner(mu_t, rho, out):                                          # pragma: no cover - compiled
        # out[p, q, f] = sum_{n >= 1} rho_f^n mu_n[p, q], by Horner's rule from the highest moment,
        # every frequency at once (independent accumulators)
        P = mu_t.shape[0]
        m = mu_t.shape[2]
        nf = rho.shape[0]
        for p in range(P):
            for q in range(P):
                acc = out[p, q]
                for f in range(nf):
                    acc[f] = 0j
                for k in range(m - 1, 0, -1):
                    c = mu_t[p, q, k]
                    for f in range(nf):
                        acc[f] = (acc[f] + c) * rho[f]

    _KERNELS.update(steps=steps, horner=horner)
    return _KERNELS


class _Moments:
    """Chebyshev moments mu_n = U^T T_n(H~) U of the port vectors, extended on demand (doubling)."""

    def __init__(self, hs: sp.csr_matrix, idx: np.ndarray):
        n, P = hs.shape[0], idx.size
        self.hs = hs
        u = np.zeros((n, P))
        u[idx, np.arange(P)] = 1.0
        v1 = hs @ u
        self.mu0 = u.T @ u
        self.mu1 = u.T @ v1
        self.v_prev, self.v = np.ascontiguousarray(u.T), np.ascontiguousarray(v1.T)     # v_0, v_1 as rows
        self.mu = np.concatenate([self.mu0[None], self.mu1[None]])

    def extend(self, m: int) -> np.ndarray:
        have = self.mu.shape[0]
        if have < m:
            nsteps = (m - have + 1) // 2
            out = np.empty((2 * nsteps,) + self.mu0.shape)
            hs = self.hs
            self.v_prev, self.v = _kernels()["steps"](hs.indptr, hs.indices, hs.data, self.v_prev, self.v, nsteps,
                                                      self.mu0, self.mu1, out)
            self.mu = np.concatenate([self.mu, out])
        return self.mu[:m]


def _chebyshev(dev: Device, omegas: np.ndarray, tol: float, m_start: int):
    c, half = _scale(dev)
    h = dev.hamiltonian()
    n = dev.size
    hs = ((h - c * sp.identity(n, format="csr")) / half).tocsr()
    idx = np.asarray(dev.port_index)
    kap = np.asarray(dev.port_kappa, float)
    P = idx.size
    zs = (omegas + 0.5j * dev.kappa_int - c) / half
    s = np.sqrt(zs - 1) * np.sqrt(zs + 1)
    rho = 1.0 / (zs + s)                       # = z - s without its cancellation at large |z|
    arho = np.abs(rho)
    mom = _Moments(hs, idx)
    m = m_start
    while True:
        mu = mom.extend(m)                        # (m, P, P), real
        # Horner in rho: sum_{n>=1} rho^n mu_n
        acc_t = np.empty((P, P, omegas.size), np.complex128)
        _kernels()["horner"](np.ascontiguousarray(mu.transpose(1, 2, 0)), rho, acc_t)
        acc = acc_t.transpose(2, 0, 1)
        g0 = (mu[0][None] + 2.0 * acc) / (s[:, None, None] * half)
        out = _woodbury(g0, kap)
        # the bound: Chebyshev tail (proved: |mu_n| <= 1) + rounding of the recurrence and the sum
        # (an estimate: random-walk growth sqrt(m) eps per moment; checked by direct solves below)
        tail = 2.0 * arho ** m / (np.abs(s) * (1 - arho)) / half
        rounding = 2.0 * _EPS * (math.sqrt(m) + P) / (np.abs(s) * (1 - arho)) / half
        dg = P * (tail + rounding)               # ||delta g0||_2 <= P max entry
        dmat = 0.5j * kap
        a_inv = np.linalg.inv(np.eye(P)[None] + g0 * dmat[None, None, :])
        b_inv = np.linalg.inv(np.eye(P)[None] + dmat[None, :, None] * g0)
        amp = np.linalg.norm(a_inv, 2, axis=(1, 2)) * np.linalg.norm(b_inv, 2, axis=(1, 2))
        bound = float(np.max(kap)) * amp * dg
        if np.max(bound) <= tol or m >= MAX_MOMENTS // 2 or not np.any(tail * P * amp * np.max(kap) > tol / 2):
            break
        m = min(2 * m, MAX_MOMENTS)
    # check the bound where it is largest and where S is most peaked: direct solves there
    spots = np.unique(np.concatenate([np.argsort(bound)[-2:], [int(np.argmax(np.abs(g0).sum(axis=(1, 2))))]]))
    exact, _ = _direct(dev, omegas[spots])
    seen = np.max(np.abs(exact - out[spots]), axis=(1, 2))
    if np.any(seen > bound[spots]):
        factor = float(np.max(seen / bound[spots])) * 2.0
        warnings.warn(f"the Chebyshev route's error estimate was {factor / 2:.3g} times too small at a checked "
                      "frequency; every bound is raised by that factor (x2).", ConvergenceWarning, stacklevel=3)
        bound = bound * factor
    if np.max(bound) > tol:
        warnings.warn(f"the Chebyshev route reached an error bound of {float(np.max(bound)):.2g} on S, above "
                      f"tol = {tol:g} ({m:,} moments); method='direct' solves each frequency exactly.",
                      ConvergenceWarning, stacklevel=3)
    return out, bound, m


def _moments_for(dev: Device, omegas: np.ndarray, tol: float) -> int:
    if dev.kappa_int <= 0:
        return MAX_MOMENTS + 1
    c, half = _scale(dev)
    zs = (omegas + 0.5j * dev.kappa_int - c) / half
    kmax = float(np.max(dev.port_kappa))
    P = len(dev.ports)
    return _cheb_moments_needed(zs, np.full(zs.shape, tol / (4.0 * kmax * P)))


def transmission(device: Device, omegas, *, method: str = "auto", tol: float = 1e-10) -> Transmission:
    r"""S(ω) of a device at every frequency of ``omegas`` (see the module docstring for the routes).

    Parameters
    ----------
    device : Device
        From :func:`resonator_device`.
    omegas : array_like
        Frequencies, in the units of the device.
    method : {"auto", "eigen", "chebyshev", "direct"}, optional
        The route; default ``"auto"``.
    tol : float, optional
        Target of the Chebyshev route's error bound on S (absolute); default 1e-10.

    Returns
    -------
    Transmission
        ``s[f, out, in]``, ``power`` (``|S21|²``), ``error_bound``, ``method``.

    Raises
    ------
    ValueError
        NaN or infinite frequencies, an unknown method, ``"chebyshev"`` without internal loss
        (the series needs Im z > 0), ``"eigen"`` on a device above :data:`EIGEN_MAX`.
    MemoryError
        A device whose route will not fit (refused before allocating).

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.device import resonator_device, transmission
    >>> one = resonator_device(np.zeros((1, 1)), omega0=5.0, kappa_int=0.1, ports={"0": 0.3})
    >>> s = transmission(one, [5.0]).s[0, 0, 0]        # (κ_int − κ)/(κ_int + κ) on resonance
    >>> round(float(s.real), 6)
    -0.5
    """
    if not isinstance(device, Device):
        raise ValueError(f"device must be a Device from resonator_device(), got {type(device).__name__}.")
    w = _omegas(omegas)
    method = _validate.choice("method", method, METHODS)
    tol = _validate.real("tol", tol, minimum=1e-15, maximum=1.0)
    from ..graph.solvers import single_threaded_blas

    with single_threaded_blas():
        # small dense blocks and many small BLAS calls: threads cost more than they save (and on a
        # loaded machine a 140 x 140 eigh waited seconds for a descheduled thread)
        return _transmission(device, w, method, tol)


def _transmission(device: Device, w: np.ndarray, method: str, tol: float) -> Transmission:
    n = device.size
    P = len(device.ports)
    # the result (and the batched Woodbury step) hold a few F x P x P complex arrays
    _validate.require_memory(f"S at {w.size:,} frequencies and {P} ports", 4.0 * 16 * w.size * P * P)
    moments = 0
    levels = np.zeros(0)
    if method == "auto":
        if n <= EIGEN_MAX:
            method = "eigen"
        else:
            m = _moments_for(device, w, tol)
            method = "chebyshev" if m * len(device.ports) <= _CHEB_PER_FREQUENCY * w.size and m <= MAX_MOMENTS \
                else "direct"
    if method == "eigen":
        if n > EIGEN_MAX:
            raise ValueError(f"the eigen route takes devices of at most {EIGEN_MAX:,} resonators, this one has {n:,}; "
                             "use method='chebyshev' (with internal loss) or 'direct'.")
        s, levels, used = _eigen(device, w)
        bound = np.full(w.size, np.nan)
    elif method == "chebyshev":
        if not device.kappa_int > 0:
            raise ValueError("the Chebyshev route needs internal loss (kappa_int > 0): the series of the resolvent "
                             "converges only off the real axis; use method='direct' or 'eigen'.")
        m = _moments_for(device, w, tol)
        if m > MAX_MOMENTS:
            raise ValueError(f"the Chebyshev route would need about {m:,} moments (kappa_int is tiny against the "
                             f"band width); use method='direct'.")
        _validate.require_memory("the Chebyshev moments", 8.0 * (4 * n + 2 * m) * len(device.ports) ** 2 + 4e7)
        s, bound, moments = _chebyshev(device, w, tol, max(m, 4))
        used = "chebyshev"
    else:
        s, _ = _direct(device, w)
        bound = np.full(w.size, np.nan)
        used = "direct"
    return Transmission(omega=w, s=s, resonators=device.resonators, ports=device.ports,
                        port_kappa=np.asarray(device.port_kappa), kappa_int=float(device.kappa_int), method=used,
                        error_bound=bound, flat_band=device.flat_band, levels=levels, moments=int(moments),
                        description=device.description)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
