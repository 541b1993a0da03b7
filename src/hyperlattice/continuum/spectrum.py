r"""Dirichlet spectrum of the hyperbolic Laplacian on a disk of radius :math:`L<1`.

Continuum approximation of the hopping Hamiltonian :math:`H=-A` of a {p,q} lattice
(``eq10``/``adj26`` generalised to any coordination number :math:`q`, see
:func:`level_energy`):

.. math:: H^{(\rm cont)} = -q - \frac{q}{4}h^2\Delta_g,\qquad
          E_{nm} = -q + \frac{q}{4}h^2\,(1 + k_{nm}^2),

with :math:`k_{nm}` the :math:`n`-th positive root of the Dirichlet condition ``spec2``

.. math:: P^{m}_{\frac12(-1+\mathrm{i}k)}\Bigl(\frac{1+L^2}{1-L^2}\Bigr) = 0 .

Roots are bracketed on a grid fine enough to separate neighbouring roots (a sign-change count
from :math:`k=0`, so the :math:`n`-th bracket holds the :math:`n`-th root), refined by a vectorized
Chandrupatla iteration (:func:`scipy.optimize.elementwise.find_root`) and verified (residual at
the root relative to the bracket values, strict ordering in :math:`n` and :math:`|m|`, and on
request the number :math:`n-1` of radial nodes of the eigenfunction).

Also here: the asymptotic formulas ``spec10``/``spec16`` and ``eq19``/``spec11``/``spec17``,
:math:`E_\infty = -q + \frac{q}{4}h^2`, the eigenfunctions ``eig12`` and the radial functions
``eig17``/``eig19``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import elementwise as _elementwise

from .. import _validate
from ..dictionary import energy_from_k, hopping_scale
from ..errors import ConvergenceError
from ..geometry import lattice_h, one_minus_abs2, radius_constant
from .special import _check_m, _log_p_parts, _guarded, legendre_p

__all__ = [
    "disk_argument",
    "dirichlet_roots",
    "dirichlet_levels",
    "DirichletTable",
    "continuum_levels",
    "ContinuumSpectrum",
    "level_energy",
    "energy_infinity",
    "asymptotic_k0",
    "asymptotic_k1",
    "asymptotic_energies",
    "psi_K",
    "radial_g",
]

GOLDEN = (1.0 + math.sqrt(5.0)) / 2.0


# ----------------------------------------------------------------------------
# the disk
# ----------------------------------------------------------------------------

def _check_radius(radius) -> float:
    try:
        r = float(radius)
    except (TypeError, ValueError):
        raise ValueError(f"the disk radius must be a number in (0, 1), got {radius!r}.") from None
    if not math.isfinite(r) or not 0.0 < r < 1.0:
        raise ValueError(f"the disk radius L must lie strictly between 0 and 1, got {radius!r}.")
    return r


def disk_argument(radius=None, *, p=7, q=3, rings=None) -> tuple[float, float]:
    r"""Return ``(L, x_L)`` with :math:`x_L = (1+L^2)/(1-L^2)` (the argument in ``spec2``).

    Either ``radius`` (:math:`0<L<1`) or ``rings`` (the {p,q} ring lattice with
    :math:`N` = :func:`hyperlattice.lattice.site_count` sites, :math:`L=\sqrt{N/(N+c_{pq})}`,
    ``eq12``). For rings, :math:`x_L = (2N + c_{pq})/c_{pq}` exactly, which keeps full relative
    precision even when :math:`1-L \sim 10^{-9}` would lose digits in :math:`L` itself.
    """
    if (radius is None) == (rings is None):
        raise ValueError("give exactly one of radius or rings.")
    if rings is not None:
        from ..graph.lattice import site_count

        if isinstance(rings, bool) or int(rings) != rings or rings < 1:
            raise ValueError(f"rings must be a positive integer, got {rings!r}.")
        p, q = _validate.pq(p, q)
        n_sites = site_count(p, q, int(rings))
        c = radius_constant(p, q)
        return math.sqrt(n_sites / (n_sites + c)), (2.0 * n_sites + c) / c
    r = _check_radius(radius)
    return r, (1.0 + r * r) / ((1.0 - r) * (1.0 + r))


# ----------------------------------------------------------------------------
# energies and asymptotics
# ----------------------------------------------------------------------------

def level_energy(k, p=7, q=3):
    r"""Continuum energy :math:`E = -q + \frac{q}{4}h^2(1+k^2)` of a Dirichlet level.

    Derivation of the :math:`q`-dependence (generalising ``eq10``/``adj15``–``adj26``): move
    site :math:`i` to the origin by a Möbius map; its :math:`q` neighbours sit at
    :math:`w_a = h e^{\mathrm{i}(\chi+2\pi a/q)}`, :math:`a=0..q-1`, with :math:`h=\tanh d_0`.
    Expanding :math:`\sum_a f(z(w_a))` to second order in :math:`h` gives
    :math:`q f + (\text{first order}) \sum_a w_a + (\text{holomorphic 2nd order}) \sum_a w_a^2
    + (1-|z|^2)^2 \sum_a |w_a|^2\,\partial\bar\partial f`. For :math:`q \ge 3`,
    :math:`\sum_a w_a = \sum_a w_a^2 = 0` and :math:`\sum_a|w_a|^2 = q h^2`, so
    :math:`A f = q f + q h^2 (1-|z|^2)^2\partial\bar\partial f + O(h^3)
    = q f + \frac{q}{4}h^2\Delta_g f + O(h^3)` (using :math:`\Delta_g = 4(1-|z|^2)^2
    \partial\bar\partial`). Hence :math:`H=-A \approx -q - \frac{q}{4}h^2\Delta_g` and an
    eigenvalue :math:`-(1+k^2)` of :math:`\Delta_g` gives the energy above; for :math:`q=3` this
    is ``spec1``, :math:`-3 + \frac34 h^2(1+k^2)`.
    """
    _validate.pq(p, q)
    out = energy_from_k(np.asarray(k, dtype=float), p, q)
    return float(out) if np.ndim(out) == 0 else out


def energy_infinity(p=7, q=3) -> float:
    r""":math:`E_\infty = -q + \frac{q}{4}h^2`, the :math:`k\to 0` limit (main text after ``eq19``;
    :math:`-2.94295` for {7,3})."""
    return level_energy(0.0, p, q)


def asymptotic_k0(x):
    r"""``spec10``: :math:`k_0 \sim 2\pi/\ln(8x)` for :math:`x = (1+L^2)/(1-L^2)\to\infty`."""
    return 2.0 * np.pi / np.log(8.0 * np.asarray(x, dtype=float))


def asymptotic_k1(x):
    r"""``spec16``: :math:`k_1 \sim 2\pi/\ln(8x/e^2)` for :math:`x\to\infty`."""
    return 2.0 * np.pi / (np.log(8.0 * np.asarray(x, dtype=float)) - 2.0)


def asymptotic_energies(p=7, q=3, *, radius=None, rings=None, form="auto") -> dict:
    r"""Large-disk asymptotics of the two lowest continuum levels.

    ``form="rings"`` (only {7,3} with ``rings``): ``eq19`` with ``spec11``/``spec17``,
    :math:`E_{0,1} \sim E_\infty + \frac{3\pi^2h^2}{4}[\ln\varphi\,\ell + c_{0,1}]^{-2}`,
    :math:`c_0=\ln 2`, :math:`c_1 = \ln 2 - 1` — the paper's "asymptotic" rows of ``SuppTab1``
    (they use :math:`N\sim 7\varphi^{2\ell}`). ``form="radius"`` (any {p,q}): ``spec10`` and
    ``spec16`` inserted in :func:`level_energy`, i.e. with the exact :math:`x_L`;
    ``"auto"`` picks ``"rings"`` for {7,3} with rings and ``"radius"`` otherwise.

    Returns
    -------
    dict
        ``{"E0", "E1", "E_inf"}`` (floats).
    """
    p, q = _validate.pq(p, q)
    e_inf = energy_infinity(p, q)
    if form == "auto":
        form = "rings" if (rings is not None and (p, q) == (7, 3)) else "radius"
    if form == "rings":
        if rings is None or (p, q) != (7, 3):
            raise ValueError("the ring form of eq19 is defined for {7,3} with a number of rings.")
        lnphi = math.log(GOLDEN)
        pref = math.pi**2 * hopping_scale(p, q)
        e0 = e_inf + pref / (lnphi * rings + math.log(2.0)) ** 2
        e1 = e_inf + pref / (lnphi * rings + math.log(2.0) - 1.0) ** 2
        return {"E0": e0, "E1": e1, "E_inf": e_inf}
    if form != "radius":
        raise ValueError(f"form must be 'auto', 'rings' or 'radius', got {form!r}.")
    _, x = disk_argument(radius, p=p, q=q, rings=rings)
    return {"E0": level_energy(float(asymptotic_k0(x)), p, q),
            "E1": level_energy(float(asymptotic_k1(x)), p, q), "E_inf": e_inf}


# ----------------------------------------------------------------------------
# Dirichlet roots
# ----------------------------------------------------------------------------

def _prod_abs_log(nu, m):
    """log prod_{n<m} |nu - n|: the eig19 normalisation, which makes P^m/prod ~ J_m of size 1."""
    out = np.zeros(nu.shape)
    for j in range(int(m.max()) if m.size else 0):
        out = np.where(j < m, out + np.log(np.abs(nu - j)), out)
    return out


def _dirichlet_function(k, m, x):
    """Real f(k) = P^m_nu(x)/|prod_{n<m}(nu-n)|, nu = (-1+ik)/2 (sign carries the roots)."""
    k = np.asarray(k, dtype=float)
    k, m, x = np.broadcast_arrays(k, m, x)
    nu = (-0.5 + 0.5j * k).ravel()
    mm = m.ravel().astype(np.int64)
    s, mt, _ = _guarded(_log_p_parts, nu, mm, x.ravel().astype(float), warn=False)
    with np.errstate(over="ignore", under="ignore"):
        val = mt.real * np.exp(s - _prod_abs_log(nu, mm))
    return val.reshape(k.shape)


def _roots_at_x(ms, x, n_roots: int, *, check_nodes: bool = False, radius=None):
    """k_{n,m} for n = 1..n_roots and each m in ``ms`` at argument x; array (len(ms), n_roots)."""
    ms = np.asarray(ms, dtype=np.int64)
    t = math.acosh(x) if x < 1e8 else math.log(2.0 * x)
    # spacing of consecutive roots in k is about 2 pi / ln(8x) (spec9) <= 2 pi / t; take 6
    # grid points per spacing so that no bracket can hold two roots
    dk = 2.0 * math.pi / (t + math.log(8.0)) / 6.0
    # upper end: Bessel/WKB estimate k ~ 2 (n + m/2 + 1) pi / t, enlarged until enough roots
    kmax = 2.0 * math.pi * (n_roots + 0.5 * ms.max() + 1.0) / t + 4.0 * ms.max() / t + 1.0
    for _attempt in range(8):
        grid = np.arange(0.0, kmax + dk, dk)
        vals = _dirichlet_function(grid[None, :], ms[:, None], x)
        sgn = np.sign(vals)
        change = sgn[:, :-1] * sgn[:, 1:] < 0
        exact = sgn[:, :-1] == 0
        counts = (change | exact).sum(axis=1)
        if np.all(counts >= n_roots):
            break
        kmax *= 2.0
    else:
        raise ConvergenceError(f"could not bracket {n_roots} Dirichlet roots below k = {kmax:.3g}.")
    lo = np.empty((ms.size, n_roots))
    hi = np.empty((ms.size, n_roots))
    flo = np.empty((ms.size, n_roots))
    fhi = np.empty((ms.size, n_roots))
    for a in range(ms.size):
        idx = np.nonzero(change[a] | exact[a])[0][:n_roots]
        lo[a], hi[a] = grid[idx], grid[idx + 1]
        flo[a], fhi[a] = vals[a, idx], vals[a, idx + 1]
    mgrid = np.broadcast_to(ms[:, None], lo.shape)
    res = _elementwise.find_root(
        lambda kk, mm: _dirichlet_function(kk, mm, x), (lo, hi), args=(mgrid,),
        tolerances={"xatol": 1e-15, "xrtol": 4.0 * np.finfo(float).eps, "fatol": 0.0, "frtol": 0.0},
    )
    if not np.all(res.success):
        raise ConvergenceError("the Dirichlet root refinement did not converge "
                               f"(status {np.unique(res.status)}).")
    k = np.asarray(res.x, dtype=float)
    # verification 1: residual at the root is at rounding level relative to the bracket values
    fk = _dirichlet_function(k, mgrid, x)
    scale = np.maximum(np.abs(flo), np.abs(fhi))
    if np.any(np.abs(fk) > 1e-8 * scale):
        raise ConvergenceError("a Dirichlet root failed its residual check.")
    # verification 2: strict ordering in n (simple roots) and in |m| (Dirichlet monotonicity)
    if np.any(np.diff(k, axis=1) <= 0):
        raise ConvergenceError("Dirichlet roots are not strictly increasing in n.")
    order = np.argsort(ms)
    if ms.size > 1 and np.any(np.diff(k[order, 0]) <= 0):
        raise ConvergenceError("lowest Dirichlet roots are not increasing with |m|.")
    if check_nodes:
        _check_radial_nodes(k, ms, x)
    return k


def _check_radial_nodes(k, ms, x, npts: int = 600):
    """The n-th root's radial function P^m_nu(rho(r)) has n-1 sign changes on 0 < r < L."""
    t_l = math.acosh(x)
    tt = np.linspace(0.0, t_l, npts + 2)[1:-1]
    rho = np.cosh(tt)
    kk = k[:, :, None]
    mm = np.broadcast_to(ms[:, None, None], k.shape + (1,))
    vals = _dirichlet_function(kk, mm, rho[None, None, :])
    sgn = np.sign(vals)
    nodes = (sgn[..., :-1] * sgn[..., 1:] < 0).sum(axis=-1)
    expected = np.arange(k.shape[1])[None, :]
    if np.any(nodes != expected):
        raise ConvergenceError("a Dirichlet eigenfunction has the wrong number of radial nodes.")


def dirichlet_roots(m, radius=None, n_roots: int = 5, *, x=None, check_nodes: bool = False):
    r"""The first ``n_roots`` positive roots :math:`k_{nm}` of ``spec2`` for one or more orders.

    Parameters
    ----------
    m : int or sequence of int
        Azimuthal quantum number(s); the roots depend on :math:`|m|` only.
    radius : float
        Disk radius :math:`L \in (0,1)`. Alternatively pass ``x`` :math:`=(1+L^2)/(1-L^2)`.
    n_roots : int
        Number of roots per order (n = 1..n_roots).
    check_nodes : bool
        Also verify that the n-th eigenfunction has n-1 radial nodes (costs one extra
        evaluation on a radial grid).

    Returns
    -------
    ndarray
        Shape ``(n_roots,)`` for scalar ``m``, else ``(len(m), n_roots)``.

    Raises
    ------
    ValueError
        Radius outside (0, 1), negative ``n_roots``.
    ConvergenceError
        If bracketing, refinement or verification fails.
    """
    if x is None:
        _, x = disk_argument(radius)
    else:
        x = float(x)
        if not math.isfinite(x) or x <= 1.0:
            raise ValueError("x = (1+L^2)/(1-L^2) must be a finite number > 1.")
    if isinstance(n_roots, bool) or int(n_roots) != n_roots or n_roots < 1:
        raise ValueError(f"n_roots must be a positive integer, got {n_roots!r}.")
    m_arr = np.abs(np.asarray(m))
    scalar = m_arr.ndim == 0
    ms = _check_m(np.atleast_1d(m_arr))
    k = _roots_at_x(ms, x, int(n_roots), check_nodes=check_nodes)
    return k[0] if scalar else k


@dataclass(frozen=True)
class DirichletTable:
    """Roots :math:`k_{nm}` and energies :math:`E_{nm}` on a grid n = 1..n_max, m = 0..m_max."""

    p: int
    q: int
    radius: float
    x: float
    h: float
    k: np.ndarray = field(repr=False)        # shape (n_max, m_max+1): k[n-1, m]
    energies: np.ndarray = field(repr=False)


def dirichlet_levels(p=7, q=3, radius=None, rings=None, n_max: int = 5, m_max: int = 10,
                     *, check_nodes: bool = False) -> DirichletTable:
    r"""Table of Dirichlet roots :math:`k_{nm}` (``spec2``) and energies
    :math:`E_{nm} = -q + \frac{q}{4}h^2(1+k_{nm}^2)` for n = 1..n_max, m = 0..m_max."""
    p, q = _validate.pq(p, q)
    radius, x = disk_argument(radius, p=p, q=q, rings=rings)
    if isinstance(m_max, bool) or int(m_max) != m_max or m_max < 0:
        raise ValueError(f"m_max must be a non-negative integer, got {m_max!r}.")
    k = dirichlet_roots(np.arange(int(m_max) + 1), x=x, n_roots=n_max, check_nodes=check_nodes).T
    return DirichletTable(p=p, q=q, radius=radius, x=x, h=lattice_h(p, q), k=k,
                          energies=level_energy(k, p, q))


@dataclass(frozen=True)
class ContinuumSpectrum:
    r"""The lowest continuum levels, one row per state, ascending in energy.

    Labels follow the graph ``spectrum`` command: ``n`` is the radial index within
    :math:`|m|`, ``m`` is signed and a level with :math:`m\ne0` appears twice, first as
    :math:`+m`, then as :math:`-m`.
    """

    p: int
    q: int
    rings: int | None
    radius: float
    x: float
    h: float
    energies: np.ndarray
    n: np.ndarray
    m: np.ndarray
    k: np.ndarray
    asymptotic: dict
    method: str = "spec2 roots: grid bracketing + Chandrupatla (scipy.optimize.elementwise)"

    def summary(self) -> dict:
        """The CLI contract: keys p, q, rings, radius, h, energies, n, m, k, asymptotic."""
        return {"p": self.p, "q": self.q, "rings": self.rings, "radius": self.radius,
                "h": self.h, "energies": self.energies.tolist(), "n": self.n.tolist(),
                "m": self.m.tolist(), "k": self.k.tolist(), "asymptotic": dict(self.asymptotic)}


def continuum_levels(p=7, q=3, radius=None, rings=None, levels: int = 4,
                     *, check_nodes: bool = False) -> ContinuumSpectrum:
    r"""The ``levels`` lowest states of :math:`H^{(\rm cont)} = -q - \frac q4 h^2\Delta_g` on a disk.

    Parameters
    ----------
    p, q : int
        Schläfli symbol (hyperbolic: :math:`(p-2)(q-2) > 4`).
    radius : float, optional
        Disk radius :math:`L\in(0,1)`.
    rings : int, optional
        Number of rings of the {p,q} lattice; :math:`L` from ``eq12`` with its exact site count.
    levels : int
        Number of states (degenerate :math:`\pm m` levels count twice).

    Notes
    -----
    Because :math:`k_{nm}` increases with :math:`n` and with :math:`|m|`, the state
    :math:`(n, m)` has at least :math:`n-1 + 2\cdot\#\{0<|m'|<|m|\} + \dots` states below it;
    so the ``levels`` lowest states have :math:`|m| \le \lfloor K/2\rfloor` and
    :math:`n \le K` (m = 0) or :math:`n \le \lceil K/2 \rceil` (m != 0), which are the
    roots computed.
    """
    p, q = _validate.pq(p, q)
    if isinstance(levels, bool) or int(levels) != levels or levels < 1:
        raise ValueError(f"levels must be a positive integer, got {levels!r}.")
    K = int(levels)
    radius, x = disk_argument(radius, p=p, q=q, rings=rings)
    m_max = K // 2
    n0 = K
    n1 = (K + 1) // 2
    k0 = dirichlet_roots(0, x=x, n_roots=n0, check_nodes=check_nodes)
    ks, ns, ms_ = list(k0), list(range(1, n0 + 1)), [0] * n0
    if m_max >= 1:
        k1 = dirichlet_roots(np.arange(1, m_max + 1), x=x, n_roots=n1, check_nodes=check_nodes)
        for a, mval in enumerate(range(1, m_max + 1)):
            for b in range(n1):
                for sgn in (1, -1):
                    ks.append(k1[a, b])
                    ns.append(b + 1)
                    ms_.append(sgn * mval)
    ks = np.array(ks)
    ns = np.array(ns)
    ms_ = np.array(ms_)
    # ascending k; ties (the +-m pairs) keep +m first; lexsort's last key is primary
    order = np.lexsort((ms_ < 0, np.abs(ms_), ks))[:K]
    ks, ns, ms_ = ks[order], ns[order], ms_[order]
    return ContinuumSpectrum(p=p, q=q, rings=None if rings is None else int(rings), radius=radius,
                             x=x, h=lattice_h(p, q), energies=level_energy(ks, p, q), n=ns, m=ms_,
                             k=ks, asymptotic=asymptotic_energies(p, q, radius=None if rings is not None else radius,
                                                                  rings=rings))


# ----------------------------------------------------------------------------
# eigenfunctions
# ----------------------------------------------------------------------------

def psi_K(z, k, beta=0.0):
    r"""Eigenfunction ``eig12`` (= ``eq16a``) of :math:`\Delta_g` with eigenvalue :math:`-(1+k^2)`.

    .. math:: \psi_K(z) = \Bigl(\frac{1-|z|^2}{|1-z e^{-\mathrm{i}\beta}|^2}\Bigr)^{\frac12(1+\mathrm{i}k)},
              \quad K = k e^{\mathrm{i}\beta}.

    ``z`` is an array of points with :math:`|z|<1` (ValueError otherwise).
    """
    z = np.asarray(z, dtype=complex)
    if np.any(~np.isfinite(z)) or np.any(np.abs(z) >= 1.0):
        raise ValueError("psi_K needs finite points inside the unit disk, |z| < 1.")
    base = one_minus_abs2(z) / np.abs(1.0 - z * np.exp(-1j * beta)) ** 2
    return np.exp(0.5 * (1.0 + 1j * k) * np.log(base))


def radial_g(k, m, r, method: str = "closed"):
    r"""Radial function :math:`g_{km}(r)` of the partial-wave expansion ``eig15``.

    ``method="integral"``: the Fourier integral ``eig17``,
    :math:`g_{km}(r) = \mathrm{i}^{-m}\int_0^{2\pi}\frac{d\phi}{2\pi}e^{-\mathrm{i}m\phi}
    \psi_{k}(re^{\mathrm{i}\phi})`, by the trapezoidal rule (exponentially convergent for this
    periodic analytic integrand; the node count is doubled until two rules agree to 1e-13).

    ``method="closed"``: the Legendre form of ``eig18``/``eig19``,
    :math:`g_{km}(r) = \mathrm{i}^{-m}\,P^{|m|}_\nu(\rho)/\prod_{n=0}^{|m|-1}(\nu-n)`,
    :math:`\nu=\frac12(-1+\mathrm{i}k)`, :math:`\rho = (1+r^2)/(1-r^2)`.

    Note on ``eig19``: the paper's closed form omits the factor :math:`\mathrm{i}^{-m}`; as
    printed it equals the Fourier coefficient :math:`\mathrm{i}^m g_{km}` of ``eig15``, not
    :math:`g_{km}` itself, so it disagrees with ``eig17`` by :math:`\mathrm{i}^{|m|}` (its
    :math:`m<0` rule :math:`g_{k,-m} = (-1)^m g_{k,m}` is consistent with both). With the factor
    included, both methods agree and :math:`g_{km}(r)\to J_m(kr)` in the Euclidean limit, as the
    paper states. The tests check this numerically.
    """
    k = float(k)
    if not math.isfinite(k):
        raise ValueError("k must be a finite real number.")
    m = int(m)
    r = np.asarray(r, dtype=float)
    if np.any(~np.isfinite(r)) or np.any(r < 0) or np.any(r >= 1):
        raise ValueError("the radius r must satisfy 0 <= r < 1.")
    phase = (1j) ** (-m % 4)
    if method == "closed":
        am = abs(m)
        nu = -0.5 + 0.5j * k
        rho = (1.0 + r * r) / ((1.0 - r) * (1.0 + r))
        prod = np.prod([nu - n for n in range(am)]) if am else 1.0
        return phase * legendre_p(nu, am, rho) / prod
    if method != "integral":
        raise ValueError(f"method must be 'closed' or 'integral', got {method!r}.")
    rr = np.atleast_1d(r)
    out = np.empty(rr.shape, complex)
    for i, rv in enumerate(rr.ravel()):
        n = 64
        n = max(n, int(2 ** math.ceil(math.log2(8 * abs(m) + 4 * abs(k) + 40.0 / max(1e-12, 1 - rv)))))
        prev = None
        for _ in range(12):
            phi = 2.0 * np.pi * np.arange(n) / n
            vals = psi_K(rv * np.exp(1j * phi), k)
            cur = np.mean(vals * np.exp(-1j * m * phi))
            if prev is not None and abs(cur - prev) <= 1e-13 * max(1.0, abs(cur)):
                break
            prev = cur
            n *= 2
        else:
            raise ConvergenceError("the eig17 quadrature did not converge.")
        out.ravel()[i] = phase * cur
    out = out.reshape(rr.shape)
    return out.reshape(r.shape)[()] if r.ndim == 0 else out
