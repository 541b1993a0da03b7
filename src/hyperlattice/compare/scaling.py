r"""From adjacency to Laplacian: local frame angles, the formal operator :math:`\hat A_h`
and its small-h expansion (paper, App. ``AppAdj`` and ``AppFS``).

For a site :math:`z_i` with full coordination q the automorphism of ``adj2``,
:math:`w(z) = (z_i - z)/(1 - z\bar z_i)`, maps :math:`z_i` to the origin and its neighbours
onto a regular star :math:`w_a = h e^{i\chi_i}\omega^a`, :math:`\omega = e^{2\pi i/q}`,
:math:`h = \tanh d_0` (``adj7``–``adj9`` for q = 3). The angle :math:`\chi_i` is defined
modulo :math:`2\pi/q` (the neighbours carry no labels); only :math:`e^{iq\chi_i}` enters
the expansion. The formal operator of ``adj34``, generalised to q,

.. math:: (\hat A_h f)_i = \sum_{a=0}^{q-1} f\Bigl(\frac{z_i - w_a}{1 - w_a\bar z_i}\Bigr),
          \qquad w_a = h e^{i\chi_i} e^{2\pi i a/q},

can be evaluated for any :math:`0 < h \le \tanh d_0`.

Expansion for general q (derived here, it reduces to ``adj26``, ``adj28``, (adj32) for q=3).
Write :math:`F(w) = f(z(w))` with the inverse map (adj3); its Taylor coefficients
:math:`c_{mn}` of :math:`w^m\bar w^n` are summed against
:math:`\sum_a w_a^m \bar w_a^n = q h^{m+n} e^{i(m-n)\chi_i}` if :math:`q \mid (m-n)`, else 0.
Hence at order :math:`h^k` only the terms with :math:`m+n = k`, :math:`m-n \in q\mathbb Z`
survive:

* even k always has the isotropic term m = n (independent of :math:`\chi_i`);
* odd k needs m - n an odd multiple of q, so **every odd order vanishes for even q**, and for
  odd q the first odd order is :math:`h^q`;
* the first anisotropic term (m, n) = (q, 0), (0, q) appears at :math:`h^q`.

With the identity :math:`\frac{d^n}{dw^n} f(z(w))|_{w=0} = (-1)^n \mathcal D_n f(z_i)`,
:math:`\mathcal D_n = \partial_z^{n-1}(1-|z|^2)^n\partial_z` (:math:`\mathcal D_3 = \mathcal D`
of ``adj33``), and :math:`\partial_w^2\bar\partial_w^2 F(0) = \Delta_g^2 f/16 + \Delta_g f/2`
(the metric is flat to first order at the origin; :math:`\Delta_g` is invariant), the
expansion through :math:`h^4` is complete for every q >= 3:

.. math::
   \hat A_h f = q f + \frac{q}{4}h^2\Delta_g f
   + \frac{(-1)^q h^q}{(q-1)!}\bigl[e^{iq\chi}\mathcal D_q f + e^{-iq\chi}\bar{\mathcal D}_q f\bigr]_{q\le 4}
   + q h^4\Bigl(\frac{\Delta_g^2 f}{64} + \frac{\Delta_g f}{8}\Bigr) + O(h^5).

For q = 3 the anisotropic term is :math:`-\tfrac{h^3}{2}[e^{3i\chi}\mathcal Df + \mathrm{c.c.}]`,
``adj32``. For q >= 4 there is **no** :math:`h^3` term: the quadratic approximation
(adj35) is already correct to :math:`O(h^4)`, and the "cubic" approximation (adj36)
coincides with it. For q = 4 the anisotropic :math:`e^{\pm 4i\chi}` term joins the isotropic
:math:`h^4` term; for q >= 5 the :math:`h^4` term is purely isotropic. The error of the
order-k approximation therefore shrinks like :math:`h^{k'}`, k' the next non-vanishing order
(:func:`expected_error_order`): q = 3: 3, 4, 5 for k = 2, 3, 4; q = 4: 4, 4, 6; q = 5: 4, 4, 5;
q >= 6: 4, 4, 6.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from .. import _validate
from .. import geometry
from ..dictionary import laplacian_coefficient
from ..errors import ConvergenceWarning
from ..graph.lattice import Lattice
from ..results import Column, Result


__all__ = [
    "FrameAngles",
    "frame_angles",
    "RadialProfile",
    "radial_profile",
    "angle_profile",
    "OperatorProfile",
    "operator_profile",
    "SmoothFunction",
    "formal_operator",
    "expansion",
    "expected_error_order",
    "ConvergenceStudy",
    "convergence_study",
    "MAX_H_VALUES",
]

#: Tolerance for the ideal-star check of ``adj7``–``adj9``; the lattice coordinates are
#: accurate to a few ulp, so anything above this means a wrong lattice, not round-off.
STAR_TOL = 1e-10

#: Most values of h in one :func:`convergence_study` (each costs one evaluation of
#: :math:`\hat A_h` and three expansions on every site; a fit needs about ten).
MAX_H_VALUES = 1000


# ----------------------------------------------------------------------------
# local frame angles chi_i and delta_i
# ----------------------------------------------------------------------------

@dataclass(frozen=True, eq=False, kw_only=True)
class FrameAngles(Result):
    r"""The local frame of every site: ``adj7``–``adj9``, generalised to {p,q}.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    h : float
        :math:`\tanh d_0` of the lattice.
    z : ndarray of complex, shape (N,)
        Site coordinates.
    chi : ndarray of float, shape (N,)
        :math:`\chi_i \in [0, 2\pi/q)`; NaN for isolated sites.
    delta : ndarray of float, shape (N,)
        :math:`\delta_i = \chi_i - \phi_i` reduced to :math:`[0, 2\pi/q)`.
    full : ndarray of bool, shape (N,)
        Sites with full coordination q (the ones ``adj34`` applies to as an identity).
    residual : ndarray of float, shape (N,)
        Largest distance of a mapped neighbour :math:`w(z_j)` from the ideal star point
        :math:`h e^{i\chi_i}\omega^a` (covers radius and mutual angles at once).

    Notes
    -----
    Coordinates are those of the paper's Poincaré disk; angles are in radians; site indices
    follow the lattice (0-based, ring by ring).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> fa = hl.frame_angles(hl.ring_lattice(7, 3, 3))
    >>> fa.chi.shape, int(fa.full.sum()), f"{fa.h:.6f} {fa.chi[0]:.6f}"
    ((112,), 56, '0.275798 1.047198')
    >>> bool(np.max(fa.residual) < 1e-12)
    True
    """

    #: one row per site
    COLUMNS = (Column("r", "r", "1 (Poincare-disk radius)"), Column("phi", "phi", "rad"), Column("chi", "chi", "rad"),
               Column("delta", "delta", "rad"), Column("full", "full", "true/false"),
               Column("residual", "residual", "1 (Poincare-disk distance)"))

    p: int
    q: int
    h: float
    z: np.ndarray
    chi: np.ndarray
    delta: np.ndarray
    full: np.ndarray
    residual: np.ndarray

    @property
    def r(self) -> np.ndarray:
        """Site radii :math:`r_i = |z_i|`."""
        return np.abs(self.z)

    @property
    def phi(self) -> np.ndarray:
        r"""Polar angles :math:`\phi_i \in [0, 2\pi)`."""
        return np.mod(np.angle(self.z), 2 * np.pi)

    @property
    def phase(self) -> np.ndarray:
        r""":math:`e^{iq\chi_i}`, the only combination of :math:`\chi_i` that enters ``adj36``."""
        return np.exp(1j * self.q * self.chi)

    @property
    def max_residual(self) -> float:
        """Largest star residual over the fully coordinated sites."""
        return float(np.max(self.residual[self.full])) if np.any(self.full) else 0.0


def _mapped_neighbours(lattice: Lattice) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For every directed edge (i, j): owner i and w = w_i(z_j) of ``adj2``."""
    indptr, nbr = lattice.neighbours()
    owner = np.repeat(np.arange(lattice.sites), np.diff(indptr))
    zi = lattice.z[owner]
    zj = lattice.z[nbr]
    dz = zi - zj
    # 1 - z_j conj(z_i) = (1-|z_i|^2) + conj(z_i)(z_i - z_j): the first term with compensated
    # arithmetic and the second from the (accurate) small difference. Forming 1 - z_j conj(z_i)
    # directly loses ~1e-16/(1-r^2) relative accuracy near the rim of large lattices.
    den = geometry.one_minus_abs2(zi) + np.conj(zi) * dz
    return owner, dz / den, indptr


def frame_angles(lattice: Lattice, *, tol: float = STAR_TOL) -> FrameAngles:
    r"""Local frame angles :math:`\chi_i` and :math:`\delta_i = \chi_i - \phi_i`.

    Implements ``adj2``, ``adj7``-(adj9): map :math:`z_i` to the origin with
    :math:`w(z) = (z_i - z)/(1 - z\bar z_i)`; the q neighbours land on
    :math:`h e^{i\chi_i} e^{2\pi i a/q}`. Since :math:`\sum_a w_a^q = q h^q e^{iq\chi_i}` for an
    ideal star, :math:`\chi_i = \arg(\sum_j w_j^q)/q \bmod 2\pi/q`; this uses every neighbour
    and also works for boundary sites with fewer than q neighbours (their missing neighbours
    belong to the tessellation and sit on the same star).

    Parameters
    ----------
    lattice : Lattice
        A {p,q} lattice of ``kind == "sites"`` (the line graph has no regular star).
    tol : float, optional
        Largest accepted distance of a mapped neighbour from its ideal star point (Euclidean, in
        the Poincaré disk). Default :data:`STAR_TOL` (1e-10).

    Returns
    -------
    FrameAngles
        Per site: ``chi`` :math:`\chi_i \in [0, 2\pi/q)` (NaN for isolated sites), ``delta``
        :math:`\delta_i`, ``full`` (full coordination q) and the star ``residual``; with the
        lattice's ``h`` = tanh(d0) and the coordinates ``z``.

    Raises
    ------
    ValueError
        If ``lattice`` is not a site lattice or ``tol`` is out of range.

    Warns
    -----
    ConvergenceWarning
        If some fully coordinated site misses the ideal star by more than ``tol``.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eq. (7)
       and corrections" (source labels ``adj2``, ``adj7``--``adj9``).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> fa = hl.frame_angles(hl.ring_lattice(7, 3, 3))
    >>> fa.chi.shape, int(fa.full.sum())
    ((112,), 56)
    >>> print(f"{fa.h:.6f} {fa.chi[0]:.6f}")
    0.275798 1.047198
    >>> bool(np.max(fa.residual) < 1e-12)
    True
    """
    if not isinstance(lattice, Lattice):
        raise ValueError("frame_angles needs a Lattice from ring_lattice().")
    if lattice.kind != "sites":
        raise ValueError("frame angles are defined for the {p,q} lattice itself, not its line graph.")
    tol = _validate.positive_real("tol", tol)
    q = lattice.q
    h = lattice.h
    owner, w, indptr = _mapped_neighbours(lattice)
    n = lattice.sites
    deg = np.diff(indptr)
    s = np.bincount(owner, weights=(w ** q).real, minlength=n) + 1j * np.bincount(
        owner, weights=(w ** q).imag, minlength=n)
    chi = np.full(n, np.nan)
    has = deg > 0
    chi[has] = np.mod(np.angle(s[has]) / q, 2 * np.pi / q)
    # distance of each mapped neighbour from the nearest ideal star point
    rel = w * np.exp(-1j * chi[owner])
    k = np.round(np.angle(rel) * q / (2 * np.pi))
    dev = np.abs(rel - h * np.exp(2j * np.pi * k / q))
    residual = np.full(n, np.nan)
    residual[has] = 0.0
    np.maximum.at(residual, owner, dev)
    phi = np.mod(np.angle(lattice.z), 2 * np.pi)
    delta = np.mod(chi - phi, 2 * np.pi / q)
    full = deg == q
    out = FrameAngles(p=lattice.p, q=q, h=h, z=lattice.z, chi=chi, delta=delta, full=full,
                      residual=residual)
    if out.max_residual > tol:
        warnings.warn(f"mapped neighbours miss the ideal star by up to {out.max_residual:.2e} "
                      f"(tolerance {tol:.1e}): the lattice coordinates are inaccurate.",
                      ConvergenceWarning, stacklevel=2)
    return out


@dataclass(frozen=True, eq=False, kw_only=True)
class RadialProfile(Result):
    """Site values grouped at equal radius: mean, min and max per distinct radius.

    ``unique`` is False where the sites at one radius do not share one value (the
    red "error bars" of Fig. FigScos3delta).

    Attributes
    ----------
    r : ndarray
        The distinct Euclidean radii :math:`|z|` in the paper's Poincaré disk, ascending.
    mean, min, max : ndarray
        Mean, smallest and largest value at each radius (in the unit of the values).
    count : ndarray of int
        Number of sites at each radius.
    unique : ndarray of bool
        Whether all sites at that radius share one value (within the tolerance).

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.compare.scaling import radial_profile
    >>> prof = radial_profile(np.array([0.5, -0.5, 0.5j, 0.8]), np.array([1.0, 1.0, 2.0, 3.0]))
    >>> prof.r.tolist(), prof.min.tolist(), prof.max.tolist(), prof.unique.tolist()
    ([0.5, 0.8], [1.0, 3.0], [2.0, 3.0], [False, True])
    """

    COLUMNS = (Column("r", "r", "1 (Poincare-disk radius)"), Column("mean", "mean", "of the values"),
               Column("min", "min", "of the values"), Column("max", "max", "of the values"),
               Column("count", "count", "1"), Column("unique", "unique", "1"))

    r: np.ndarray
    mean: np.ndarray
    min: np.ndarray
    max: np.ndarray
    count: np.ndarray
    unique: np.ndarray

    @property
    def distance(self) -> np.ndarray:
        """Hyperbolic distance :math:`d(r, 0) = \\mathrm{artanh}\\, r` of each radius."""
        return np.arctanh(self.r)


def radial_profile(z: np.ndarray, values: np.ndarray, *, rtol: float = 1e-9,
                   value_tol: float = 1e-8) -> RadialProfile:
    """Average ``values`` over sites of equal radius ``|z|`` (radii equal to ``rtol``).

    ``value_tol`` decides when the sites of one radius disagree (non-unique map r -> value).

    Parameters
    ----------
    z : ndarray of complex, shape (N,)
        Site positions in the Poincaré disk, not empty.
    values : ndarray of float, shape (N,)
        One real value per site.
    rtol : float, optional
        Relative tolerance (>= 0) below which two radii count as one. Default 1e-9.
    value_tol : float, optional
        Largest spread (>= 0) of the values at one radius that still counts as one value.
        Default 1e-8.

    Returns
    -------
    RadialProfile
        Per distinct radius (increasing): ``r``, ``mean``, ``min``, ``max``, ``count`` and
        ``unique`` (spread at most ``value_tol``); ``distance`` gives :math:`d(r, 0)`.

    Raises
    ------
    ValueError
        If the arrays are empty, of different lengths or not finite, or a tolerance is negative.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.compare.scaling import radial_profile
    >>> prof = radial_profile(np.array([0.5, -0.5, 0.5j, 0.8]), np.array([1.0, 1.0, 2.0, 3.0]))
    >>> prof.r.tolist(), prof.count.tolist(), prof.unique.tolist()
    ([0.5, 0.8], [3, 1], [False, True])
    >>> [round(float(v), 6) for v in prof.mean]
    [1.333333, 3.0]
    """
    z = _validate.complex_array("z", z, ndim=1)
    values = _validate.real_array("values", values, ndim=1)
    rtol = _validate.real("rtol", rtol, minimum=0.0)
    value_tol = _validate.real("value_tol", value_tol, minimum=0.0)
    if z.shape != values.shape or z.size == 0:
        raise ValueError("z and values must be non-empty 1-d arrays of the same length.")
    r = np.abs(z)
    order = np.argsort(r, kind="stable")
    rs, vs = r[order], values[order]
    new = np.r_[True, np.diff(rs) > rtol * np.maximum(rs[1:], 1.0)]
    gid = np.cumsum(new) - 1
    count = np.bincount(gid)
    mean = np.bincount(gid, vs) / count
    vmin = np.full(count.size, np.inf)
    vmax = np.full(count.size, -np.inf)
    np.minimum.at(vmin, gid, vs)
    np.maximum.at(vmax, gid, vs)
    rmean = np.bincount(gid, rs) / count
    return RadialProfile(r=rmean, mean=mean, min=vmin, max=vmax, count=count,
                         unique=(vmax - vmin) <= value_tol)


def angle_profile(lattice: Lattice | FrameAngles) -> RadialProfile:
    r""":math:`\cos(q\delta_i)` averaged over the sites of equal radius (Fig. ``FigScos3delta``).

    :math:`\delta_i` is defined modulo :math:`2\pi/q`, so :math:`\cos(q\delta_i)` (the
    combination entering ``adj36``) is the quantity with a meaning; sites without neighbours
    (undefined :math:`\delta_i`) are left out. The one place the CLI and the figure get it from.

    Parameters
    ----------
    lattice : Lattice or FrameAngles
        A {p,q} site lattice, or its :func:`frame_angles`.

    Returns
    -------
    RadialProfile
        :math:`\cos(q\delta_i)` per distinct radius: ``mean``, ``min``, ``max``, ``count``,
        ``unique``.

    Raises
    ------
    ValueError
        If ``lattice`` is neither a Lattice nor FrameAngles, or is not a site lattice.

    See Also
    --------
    frame_angles

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eq. (7)
       and corrections" and App. "Finite-size scaling limit" (source labels ``adj14``,
       ``adj26``--``adj36``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import angle_profile
    >>> prof = angle_profile(hl.ring_lattice(7, 3, 3))
    >>> prof.r.size, [round(float(c), 4) for c in prof.mean[:3]]
    (10, [-1.0, 1.0, -0.189])
    """
    angles = _angles(lattice)
    sel = np.isfinite(angles.delta)
    return radial_profile(angles.z[sel], np.cos(angles.q * angles.delta[sel]))


# ----------------------------------------------------------------------------
# test functions with exact derivatives
# ----------------------------------------------------------------------------

class SmoothFunction:
    r"""A test function :math:`f(z,\bar z)` with exact (symbolic) derivatives.

    The expression is a sympy expression in the independent symbols ``z`` and ``zb``
    (:math:`\bar z`); derivatives are Wirtinger derivatives (``adj18``, ``adj18b``) taken by
    sympy, then compiled with ``lambdify``. No finite differences are involved, so the
    :math:`h^3` and :math:`h^4` terms are not swamped by differencing error.

    Radial functions written through :math:`\sqrt{z\bar z}` have removable singularities
    at z = 0 in their derivatives; ring lattices have no site at the origin.

    Parameters
    ----------
    expr : sympy.Expr
        Expression in ``SmoothFunction.symbols()``.
    name : str, optional
        Label for plots and output (default: the expression as text).

    Raises
    ------
    ValueError
        If the expression depends on symbols other than ``z`` and ``zb``.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.compare.scaling import SmoothFunction
    >>> z, zb = SmoothFunction.symbols()
    >>> f = SmoothFunction(z * zb, name="|z|^2")
    >>> round(float(f.laplacian(np.array([0.5]))[0].real), 6)    # 4 (1 - 1/4)^2
    2.25
    >>> SmoothFunction.cos_distance().name, SmoothFunction.preset("exp-x").name
    ('cos(pi d(z,0))', 'exp(x)')
    """

    def __init__(self, expr, name: str | None = None) -> None:
        import sympy as sp

        z, zb = self.symbols()
        expr = sp.sympify(expr)
        extra = expr.free_symbols - {z, zb}
        if extra:
            raise ValueError(f"the test function may depend only on z and zb, not on {sorted(map(str, extra))}.")
        self.expr = expr
        self.name = name or str(expr)
        self._cache: dict = {}

    @staticmethod
    def symbols() -> tuple:
        """The sympy symbols ``(z, zb)`` test functions are written in."""
        import sympy as sp

        return sp.Symbol("z"), sp.Symbol("zb")

    def __repr__(self) -> str:
        return f"SmoothFunction({self.name})"

    # -- presets -------------------------------------------------------------
    @classmethod
    def cos_distance(cls, k: float = math.pi) -> "SmoothFunction":
        r""":math:`f = \cos[k\, d(z,0)]`, :math:`d(z,0) = \mathrm{artanh}|z|` (Fig. FigSh uses k = pi).

        Parameters
        ----------
        k : float, optional
            Wave number per unit distance of the paper's metric; default :math:`\pi`.

        Returns
        -------
        SmoothFunction
        """
        import sympy as sp

        z, zb = cls.symbols()
        kk = sp.pi if k == math.pi else sp.Float(k)
        return cls(sp.cos(kk * sp.atanh(sp.sqrt(z * zb))), name=f"cos({'pi' if k == math.pi else k} d(z,0))")

    @classmethod
    def gaussian(cls, width: float = 1.0) -> "SmoothFunction":
        r""":math:`f = \exp[-d(z,0)^2/w^2]`.

        Parameters
        ----------
        width : float, optional
            w, in the paper's metric; default 1.

        Returns
        -------
        SmoothFunction
        """
        import sympy as sp

        z, zb = cls.symbols()
        return cls(sp.exp(-sp.atanh(sp.sqrt(z * zb)) ** 2 / sp.Float(width) ** 2),
                   name=f"exp(-d^2/{width:g}^2)")

    @classmethod
    def inverse_rho_squared(cls) -> "SmoothFunction":
        r""":math:`f = \rho^{-2} = [(1-|z|^2)/(1+|z|^2)]^2` (``sum3``); integrable over the disk."""
        z, zb = cls.symbols()
        return cls(((1 - z * zb) / (1 + z * zb)) ** 2, name="rho^-2")

    @classmethod
    def anisotropic(cls) -> "SmoothFunction":
        r""":math:`f = (1 + x^2)\rho^{-2}`, x = Re z: a non-radial, integrable test function."""
        z, zb = cls.symbols()
        x = (z + zb) / 2
        return cls((1 + x ** 2) * ((1 - z * zb) / (1 + z * zb)) ** 2, name="(1+x^2) rho^-2")

    @classmethod
    def exp_x(cls) -> "SmoothFunction":
        r""":math:`f = e^{x}`, x = Re z: non-radial, so :math:`e^{iq\chi_i}` terms do not average out."""
        import sympy as sp

        z, zb = cls.symbols()
        return cls(sp.exp((z + zb) / 2), name="exp(x)")

    @classmethod
    def preset(cls, name: str) -> "SmoothFunction":
        """A preset by name: one of :data:`PRESETS`.

        Parameters
        ----------
        name : str
            ``"cos-distance"``, ``"gaussian"``, ``"inverse-rho-squared"``, ``"anisotropic"`` or
            ``"exp-x"``.

        Returns
        -------
        SmoothFunction
            The preset with its default parameters.

        Raises
        ------
        ValueError
            For an unknown name.
        """
        try:
            return PRESETS[name]()
        except KeyError:
            raise ValueError(f"unknown test function {name!r}: choose one of {', '.join(PRESETS)}.") from None

    # -- derivatives ---------------------------------------------------------
    def _compiled(self, key):
        if key in self._cache:
            return self._cache[key]
        import sympy as sp

        z, zb = self.symbols()
        s = 1 - z * zb
        kind, n = key
        if kind == "f":
            e = self.expr
        elif kind == "lap":
            e = 4 * s ** 2 * sp.diff(self.expr, z, zb)
        elif kind == "bilap":
            lap = 4 * s ** 2 * sp.diff(self.expr, z, zb)
            e = 4 * s ** 2 * sp.diff(lap, z, zb)
        elif kind == "D":
            e = sp.diff(s ** n * sp.diff(self.expr, z), z, n - 1)
        elif kind == "Dbar":
            e = sp.diff(s ** n * sp.diff(self.expr, zb), zb, n - 1)
        else:  # pragma: no cover - internal keys only
            raise KeyError(key)
        fn = sp.lambdify((z, zb), e, modules="numpy")
        self._cache[key] = fn
        return fn

    def _eval(self, key, z) -> np.ndarray:
        z = np.asarray(z, dtype=complex)
        if not np.all(np.isfinite(z)):
            raise ValueError("z contains NaN or infinite values.")
        if np.any(np.abs(z) >= 1):
            raise ValueError("test functions are evaluated inside the unit disk |z| < 1 only.")
        with np.errstate(all="ignore"):
            out = self._compiled(key)(z, np.conj(z))
        return np.broadcast_to(np.asarray(out, dtype=complex), z.shape).copy()

    def __call__(self, z) -> np.ndarray:
        """f(z), complex array."""
        return self._eval(("f", 0), z)

    def laplacian(self, z) -> np.ndarray:
        r""":math:`\Delta_g f = 4(1-|z|^2)^2\partial_z\bar\partial_z f`, ``eq7``.

        Parameters
        ----------
        z : array_like of complex
            Points of the Poincaré disk.

        Returns
        -------
        numpy.ndarray of complex
            :math:`\Delta_g f` at each point.
        """
        return self._eval(("lap", 0), z)

    def bilaplacian(self, z) -> np.ndarray:
        r""":math:`\Delta_g^2 f`.

        Parameters
        ----------
        z : array_like of complex
            Points of the Poincaré disk.

        Returns
        -------
        numpy.ndarray of complex
            :math:`\Delta_g^2 f` at each point.
        """
        return self._eval(("bilap", 0), z)

    def D(self, z, n: int = 3) -> np.ndarray:
        r""":math:`\mathcal D_n f = \partial_z^{n-1}(1-|z|^2)^n\partial_z f`; n = 3 is ``adj33``.

        Parameters
        ----------
        z : array_like of complex
            Points of the Poincaré disk.
        n : int, optional
            The order n >= 1; default 3.

        Returns
        -------
        numpy.ndarray of complex
            :math:`\mathcal D_n f` at each point.
        """
        return self._eval(("D", _order(n)), z)

    def Dbar(self, z, n: int = 3) -> np.ndarray:
        r""":math:`\bar{\mathcal D}_n f = \bar\partial_z^{n-1}(1-|z|^2)^n\bar\partial_z f`.

        Parameters
        ----------
        z : array_like of complex
            Points of the Poincaré disk.
        n : int, optional
            The order n >= 1; default 3.

        Returns
        -------
        numpy.ndarray of complex
            :math:`\bar{\mathcal D}_n f` at each point.
        """
        return self._eval(("Dbar", _order(n)), z)


def _order(n) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"the order n of D_n must be a positive integer, got {n!r}.")
    return int(n)


#: Named test functions (used by the CLI; no user expression is ever evaluated).
PRESETS = {
    "cos-distance": SmoothFunction.cos_distance,
    "gaussian": SmoothFunction.gaussian,
    "inverse-rho-squared": SmoothFunction.inverse_rho_squared,
    "anisotropic": SmoothFunction.anisotropic,
    "exp-x": SmoothFunction.exp_x,
}


# ----------------------------------------------------------------------------
# the formal operator and its expansion
# ----------------------------------------------------------------------------

def _smooth(f) -> SmoothFunction:
    if not isinstance(f, SmoothFunction):
        raise ValueError("f must be a SmoothFunction (the expansion needs its exact derivatives).")
    return f


def _angles(obj) -> FrameAngles:
    if isinstance(obj, FrameAngles):
        return obj
    if isinstance(obj, Lattice):
        return frame_angles(obj)
    raise ValueError("expected a Lattice or the FrameAngles of one.")


def _check_h(h, angles: FrameAngles) -> float:
    if h is None:
        return angles.h
    h = _validate.real("h", h)
    if h <= 0:
        raise ValueError(f"h must be positive, got {h}.")
    # 1e-12 slack so that the printed lattice value 0.275798 and lattice.h both pass
    if h > angles.h * (1 + 1e-12) and not math.isclose(h, round(angles.h, 6), abs_tol=5e-7):
        raise ValueError(f"h = {h} exceeds the lattice value tanh(d0) = {angles.h:.6f} of "
                         f"{{{angles.p},{angles.q}}}; the formal operator is defined for h <= tanh(d0).")
    return h


def _selection(angles: FrameAngles, sites) -> np.ndarray:
    if sites is None or isinstance(sites, str):
        sites = _validate.choice("sites", "full" if sites is None else sites, ("full", "all"))
        return np.flatnonzero(angles.full if sites == "full" else np.isfinite(angles.chi))
    mask = np.asarray(sites) if isinstance(sites, (np.ndarray, list, tuple)) else None
    if mask is not None and mask.dtype == bool:
        if mask.shape != angles.z.shape:
            raise ValueError(f"a boolean mask of sites must have shape {angles.z.shape}, got {mask.shape}.")
        idx = np.flatnonzero(mask)
    else:
        idx = _validate.site_indices("sites", sites, angles.z.size)
    if idx.size and np.any(~np.isfinite(angles.chi[idx])):
        raise ValueError("some selected sites have no neighbours, so chi_i is undefined there.")
    return idx


def formal_operator(lattice: Lattice | FrameAngles, f: SmoothFunction, h: float | None = None,
                    *, sites="full") -> np.ndarray:
    r"""The formal operator :math:`(\hat A_h f)_i` of ``adj34``, generalised to q neighbours.

    .. math:: (\hat A_h f)_i = \sum_{a=0}^{q-1}
              f\Bigl(\frac{z_i - h e^{i\chi_i}\omega^a}{1 - h e^{i\chi_i}\omega^a\bar z_i}\Bigr)

    At :math:`h = \tanh d_0` it equals :math:`(Af)_i` on fully coordinated sites (``adj14``).

    Parameters
    ----------
    lattice : Lattice or FrameAngles
        The lattice (its frame angles are computed) or precomputed :func:`frame_angles`.
    f : SmoothFunction
        Test function.
    h : float, optional
        :math:`0 < h \le \tanh d_0`; default the lattice value.
    sites : {"full", "all"}, bool mask or index array, optional
        Where to evaluate; default the fully coordinated sites.

    Returns
    -------
    ndarray of complex
        One value per selected site.

    Raises
    ------
    ValueError
        If h is not in :math:`(0, \tanh d_0]`, ``f`` is not callable, or the selection is
        malformed or holds sites without neighbours.

    See Also
    --------
    expansion : its small-h approximations.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eq. (7)
       and corrections" and App. "Finite-size scaling limit" (source labels ``adj14``,
       ``adj26``--``adj36``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import SmoothFunction, formal_operator
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> values = formal_operator(lat, SmoothFunction.cos_distance())
    >>> values.shape
    (56,)
    >>> print(f"{values[0].real:.6f}")
    0.832996
    """
    angles = _angles(lattice)
    f = _validate.function("f", f)
    h = _check_h(h, angles)
    idx = _selection(angles, sites)
    q = angles.q
    zi = angles.z[idx][:, None]
    w = h * np.exp(1j * angles.chi[idx])[:, None] * np.exp(2j * np.pi * np.arange(q) / q)[None, :]
    pts = (zi - w) / (1.0 - w * np.conj(zi))
    return f(pts).sum(axis=1)


def expansion(lattice: Lattice | FrameAngles, f: SmoothFunction, h: float | None = None,
              order: int = 2, *, sites="full") -> np.ndarray:
    r"""Small-h approximation of :math:`\hat A_h f` truncated after :math:`h^{\rm order}`.

    * order 2: ``adj35``, :math:`q f + \frac q4 h^2 \Delta_g f`;
    * order 3: ``adj36``; adds :math:`-\frac{h^3}{2}[e^{3i\chi}\mathcal Df + e^{-3i\chi}\bar{\mathcal D}f]`
      for q = 3 and nothing for q >= 4 (all odd orders below q vanish);
    * order 4: adds :math:`q h^4(\Delta_g^2 f/64 + \Delta_g f/8)` and, for q = 4 only,
      :math:`\frac{h^4}{6}[e^{4i\chi}\mathcal D_4 f + e^{-4i\chi}\bar{\mathcal D}_4 f]`.

    Every derivative is exact (:class:`SmoothFunction`). See the module docstring for the
    derivation.

    Parameters
    ----------
    lattice : Lattice or FrameAngles
        The lattice (its frame angles are computed) or precomputed :func:`frame_angles`.
    f : SmoothFunction
        Test function with exact derivatives.
    h : float, optional
        :math:`0 < h \le \tanh d_0`; default the lattice value.
    order : {2, 3, 4}, optional
        Last power of h kept. Default 2.
    sites : {"full", "all"}, bool mask or index array, optional
        Where to evaluate; default the fully coordinated sites.

    Returns
    -------
    ndarray of complex
        One value per selected site.

    Raises
    ------
    ValueError
        If ``order`` is not 2, 3 or 4, ``f`` is not a SmoothFunction, h is out of range or the
        selection is malformed.

    See Also
    --------
    formal_operator : the exact operator.
    expected_error_order : how fast the difference vanishes.

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eq. (7)
       and corrections" and App. "Finite-size scaling limit" (source labels ``adj14``,
       ``adj26``--``adj36``).

    Examples
    --------
    >>> import numpy as np
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import SmoothFunction, expansion, formal_operator
    >>> lat = hl.ring_lattice(7, 3, 3)
    >>> f = SmoothFunction.cos_distance()
    >>> exact = formal_operator(lat, f)
    >>> [f"{np.max(np.abs(exact - expansion(lat, f, order=k))):.2e}" for k in (2, 3)]
    ['1.36e-01', '2.04e-02']
    """
    if isinstance(order, bool) or not isinstance(order, (int, np.integer)) or order not in (2, 3, 4):
        raise ValueError(f"order must be 2, 3 or 4 (the expansion is derived through h^4), got {order!r}.")
    angles = _angles(lattice)
    _smooth(f)
    h = _check_h(h, angles)
    idx = _selection(angles, sites)
    q = angles.q
    z = angles.z[idx]
    lap = f.laplacian(z)
    out = q * f(z) + laplacian_coefficient(q, h) * lap
    for k in range(3, order + 1):
        if k % 2 == 0:
            out = out + q * h ** k * (f.bilaplacian(z) / 64.0 + lap / 8.0)
        if k == q:
            ph = np.exp(1j * q * angles.chi[idx])
            coef = (-1) ** q * h ** q / math.factorial(q - 1)
            out = out + coef * (ph * f.D(z, q) + np.conj(ph) * f.Dbar(z, q))
    return out


@dataclass(frozen=True, eq=False, kw_only=True)
class OperatorProfile(Result):
    r""":math:`\hat A_h f - qf` and its approximations at one h, averaged at equal radius (Fig. ``FigSh``).

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    h : float
        The h of :math:`\hat A_h`.
    function : str
        Name of the test function f.
    exact, quadratic, cubic : RadialProfile
        Real parts of :math:`\hat A_h f - qf` (``adj34``), :math:`\hat A^{(2)}_h f - qf` (``adj35``)
        and :math:`\hat A^{(3)}_h f - qf` (``adj36``) on the fully coordinated sites, grouped by radius.
    max_error_quadratic, max_error_cubic : float
        :math:`\max_i |\hat A_h f - \hat A^{(k)}_h f|` over those sites (complex values).
    curve_distance, curve_quadratic : ndarray or None
        For a radial f the quadratic approximation depends on r alone (it has no :math:`\chi_i`):
        its real part on a fine grid of :math:`d(r, 0)` up to the outermost site. None otherwise.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import operator_profile
    >>> prof = operator_profile(hl.ring_lattice(7, 3, 3))
    >>> prof.function, round(prof.h, 6), int(prof.exact.count.sum())
    ('cos(pi d(z,0))', 0.275798, 56)
    >>> print(f"{prof.max_error_quadratic:.2e} {prof.max_error_cubic:.2e}")
    1.36e-01 2.04e-02
    """

    NOT_TABULAR = ("its data are three RadialProfile tables (exact, quadratic, cubic: each exports "
                   "its own) and an optional fine curve, not one table")

    p: int
    q: int
    h: float
    function: str
    exact: RadialProfile
    quadratic: RadialProfile
    cubic: RadialProfile
    max_error_quadratic: float
    max_error_cubic: float
    curve_distance: np.ndarray | None = None
    curve_quadratic: np.ndarray | None = None

    def summary(self) -> dict:
        """One row of ``hyperlattice scaling operator --json``."""
        return {"h": self.h, "max_error_quadratic": self.max_error_quadratic,
                "max_error_cubic": self.max_error_cubic, "distance": self.exact.distance,
                "A_h_minus_qf": self.exact.mean, "quadratic_minus_qf": self.quadratic.mean,
                "cubic_minus_qf": self.cubic.mean}


def _is_radial(f: SmoothFunction, z: np.ndarray) -> bool:
    """True if f takes equal values on the sites' radii rotated to the real axis."""
    r = np.abs(z[:50]) + 0j
    return bool(np.allclose(f(z[:50]), f(r), rtol=1e-12, atol=1e-12))


def operator_profile(lattice: Lattice | FrameAngles, f: SmoothFunction | None = None,
                     h: float | None = None) -> OperatorProfile:
    r"""The radial profile of :math:`\hat A_h f - qf` and of its quadratic and cubic approximations.

    The one computation behind ``hyperlattice scaling operator`` and Fig. ``FigSh``
    (:func:`hyperlattice.plots.scaling.plot_formal_operator`).

    Parameters
    ----------
    lattice : Lattice or FrameAngles
        The lattice, or its :func:`frame_angles`.
    f : SmoothFunction, optional
        Test function; default :math:`\cos[\pi d(z, 0)]` (the paper's).
    h : float, optional
        :math:`0 < h \le \tanh d_0`; default the lattice value.

    Returns
    -------
    OperatorProfile
        ``exact``, ``quadratic`` and ``cubic`` :class:`RadialProfile` of the real parts,
        ``max_error_quadratic``, ``max_error_cubic``, and for a radial f the fine curve
        ``curve_distance``, ``curve_quadratic``.

    Raises
    ------
    ValueError
        If ``f`` is not a SmoothFunction, h is out of range, or the lattice has no fully
        coordinated site (one ring).

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eq. (7)
       and corrections" and App. "Finite-size scaling limit" (source labels ``adj14``,
       ``adj26``--``adj36``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import operator_profile
    >>> prof = operator_profile(hl.ring_lattice(7, 3, 3))
    >>> prof.function
    'cos(pi d(z,0))'
    >>> print(f"{prof.max_error_quadratic:.2e} {prof.max_error_cubic:.2e}")
    1.36e-01 2.04e-02
    """
    angles = _angles(lattice)
    f = _smooth(f if f is not None else SmoothFunction.cos_distance())
    h = _check_h(h, angles)
    if not np.any(angles.full):
        raise ValueError("the lattice has no fully coordinated site: use at least 2 rings.")
    z = angles.z[angles.full]
    base = angles.q * f(z)
    ex = formal_operator(angles, f, h)
    a2, a3 = expansion(angles, f, h, 2), expansion(angles, f, h, 3)
    pe, p2, p3 = (radial_profile(z, (v - base).real) for v in (ex, a2, a3))
    curve_d = curve_v = None
    if _is_radial(f, z):
        grid = np.linspace(0.0, np.abs(z).max(), 400)[1:] + 0j
        curve_d = np.arctanh(grid.real)
        curve_v = (laplacian_coefficient(angles.q, h) * f.laplacian(grid)).real
    return OperatorProfile(p=angles.p, q=angles.q, h=float(h), function=f.name, exact=pe, quadratic=p2,
                           cubic=p3, max_error_quadratic=float(np.max(np.abs(ex - a2))),
                           max_error_cubic=float(np.max(np.abs(ex - a3))),
                           curve_distance=curve_d, curve_quadratic=curve_v)


def expected_error_order(q: int, order: int) -> int:
    r"""Power of h with which :math:`\hat A_h f - \hat A_h^{(\rm order)} f` vanishes.

    The next non-vanishing order k > ``order``: even k always (isotropic m = n term), odd k
    only for odd q with q <= k (an anisotropic term with m - n = +-q). Generic f assumed.

    Parameters
    ----------
    q : int
        Coordination number, >= 3.
    order : int
        Last power of h kept in the approximation, >= 1.

    Returns
    -------
    int
        The power k of the leading error term :math:`O(h^k)`.

    Raises
    ------
    ValueError
        If q < 3 or ``order`` < 1 (or either is not an integer).

    Examples
    --------
    >>> from hyperlattice.compare.scaling import expected_error_order
    >>> [expected_error_order(3, k) for k in (2, 3, 4)]
    [3, 4, 5]
    >>> [expected_error_order(4, k) for k in (2, 3, 4)]
    [4, 4, 6]
    """
    q = _validate.integer("q", q, minimum=3)
    k = _validate.integer("order", order, minimum=1) + 1
    while True:
        if k % 2 == 0 or (q % 2 == 1 and q <= k):
            return k
        k += 1


@dataclass(frozen=True, eq=False, kw_only=True)
class ConvergenceStudy(Result):
    r"""Errors :math:`\max_i|\hat A_h f - \hat A_h^{(k)} f|` against h and their fitted powers.

    ``errors[k]`` and ``exponents[k]`` for each order k; ``expected[k]`` from
    :func:`expected_error_order`. ``fit_rms[k]`` is the rms residual of the log-log fit.

    Attributes
    ----------
    p, q : int
        Schläfli symbol.
    function : str
        Name of the test function f.
    h : ndarray
        The values of h (:math:`\tanh` of an edge length in the paper's metric) studied.
    errors : dict of int to ndarray
        For each order k, the error at each h.
    exponents : dict of int to float
        Fitted power of h for each k.
    expected : dict of int to int
        The expected power (:func:`expected_error_order`).
    fit_rms : dict of int to float
        Rms residual of each log-log fit.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import SmoothFunction, convergence_study
    >>> study = convergence_study(hl.ring_lattice(7, 3, 3), SmoothFunction.exp_x())
    >>> study.function, {k: round(v, 1) for k, v in study.exponents.items()}, study.expected
    ('exp(x)', {2: 3.0, 3: 4.0, 4: 5.0}, {2: 3, 3: 4, 4: 5})
    """

    p: int
    q: int
    function: str
    h: np.ndarray
    errors: dict
    exponents: dict
    expected: dict
    fit_rms: dict

    def summary(self) -> dict:
        """The JSON printed by ``hyperlattice scaling convergence --json`` (without ``rings``)."""
        return {"p": self.p, "q": self.q, "function": self.function, "h": self.h,
                "orders": {str(k): {"errors": self.errors[k], "exponent": self.exponents[k],
                                    "expected": self.expected[k], "fit_rms": self.fit_rms[k]}
                           for k in self.errors}}


def convergence_study(lattice: Lattice | FrameAngles, f: SmoothFunction, hs=None,
                      orders=(2, 3, 4), *, tol: float = 0.2) -> ConvergenceStudy:
    r"""Fit the power of h in the error of the order-k approximations (App. ``AppFS``).

    The error is the largest :math:`|\hat A_h f - \hat A_h^{(k)} f|` over fully coordinated
    sites, at geometrically spaced h (default 8 values in [0.01, 0.08]: small enough for the
    asymptotic regime, large enough that the :math:`h^6` errors of order 4 stay 1000x above
    round-off). The exponent is the slope of a least-squares line in log-log.

    Parameters
    ----------
    lattice : Lattice or FrameAngles
        A {p,q} site lattice with at least 2 rings, or its :func:`frame_angles`.
    f : SmoothFunction
        Test function (its higher derivatives must not vanish).
    hs : array_like of float, optional
        3 to :data:`MAX_H_VALUES` values :math:`0 < h \le \tanh d_0`; default
        ``geomspace(0.01, 0.08, 8)``.
    orders : sequence of int, optional
        Orders k among 2, 3, 4. Default ``(2, 3, 4)``.
    tol : float, optional
        Largest accepted deviation (> 0) of a fitted exponent from the expected one before a
        warning. Default 0.2.

    Returns
    -------
    ConvergenceStudy
        ``h``, and per order k: ``errors[k]`` (one per h), the fitted ``exponents[k]``, the
        ``expected[k]`` power and the fit's ``fit_rms[k]``.

    Raises
    ------
    ValueError
        For bad input, fewer than 3 or too many h, an h out of range, bad ``orders``, a lattice
        without fully coordinated sites, or an error that vanishes identically.

    Warns
    -----
    ConvergenceWarning
        If a fitted exponent differs from :func:`expected_error_order` by more than ``tol``
        or the log-log fit is not straight (rms residual > 0.05).

    See Also
    --------
    expected_error_order, formal_operator, expansion

    References
    ----------
    .. [1] I. Boettcher et al., Phys. Rev. A 102, 032208 (2020), App. "Derivation of Eq. (7)
       and corrections" and App. "Finite-size scaling limit" (source labels ``adj14``,
       ``adj26``--``adj36``).

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.compare.scaling import SmoothFunction, convergence_study
    >>> study = convergence_study(hl.ring_lattice(7, 3, 3), SmoothFunction.exp_x())
    >>> {k: round(v, 1) for k, v in study.exponents.items()}
    {2: 3.0, 3: 4.0, 4: 5.0}
    >>> study.expected
    {2: 3, 3: 4, 4: 5}
    """
    angles = _angles(lattice)
    _smooth(f)
    tol = _validate.positive_real("tol", tol)
    if hs is None:
        hs = np.geomspace(0.01, 0.08, 8)
    hs = _validate.real_array("hs", hs, ndim=1)
    if hs.size < 3:
        raise ValueError("need at least three values of h for a convergence fit.")
    if hs.size > MAX_H_VALUES:
        raise ValueError(f"at most {MAX_H_VALUES} values of h (a fit needs about ten), got {hs.size}.")
    for h in hs:
        _check_h(h, angles)
    if isinstance(orders, (str, bytes)) or not isinstance(orders, (list, tuple, np.ndarray)):
        raise ValueError(f"orders must be a list of 2, 3 and/or 4, got {orders!r}.")
    orders = tuple(_validate.integer("orders", k, minimum=2, maximum=4) for k in orders)
    if not orders:
        raise ValueError("orders must name at least one of 2, 3, 4.")
    if not np.any(angles.full):
        raise ValueError("the lattice has no fully coordinated site: use at least 2 rings.")
    errors = {k: np.empty(hs.size) for k in orders}
    for n, h in enumerate(hs):
        exact = formal_operator(angles, f, h)
        for k in orders:
            errors[k][n] = np.max(np.abs(exact - expansion(angles, f, h, k)))
    exponents, expected, rms = {}, {}, {}
    for k in orders:
        if np.any(errors[k] <= 0):
            raise ValueError(f"the order-{k} error vanishes identically for {f.name}: "
                             "choose a test function with nonzero higher derivatives.")
        x, y = np.log(hs), np.log(errors[k])
        slope, icpt = np.polyfit(x, y, 1)
        exponents[k] = float(slope)
        rms[k] = float(np.sqrt(np.mean((y - (slope * x + icpt)) ** 2)))
        expected[k] = expected_error_order(angles.q, k)
        if abs(slope - expected[k]) > tol or rms[k] > 0.05:
            warnings.warn(f"order-{k} error of A_h scales as h^{slope:.2f} (fit rms {rms[k]:.3f}), "
                          f"expected h^{expected[k]}.", ConvergenceWarning, stacklevel=2)
    return ConvergenceStudy(p=angles.p, q=angles.q, function=f.name, h=hs, errors=errors,
                            exponents=exponents, expected=expected, fit_rms=rms)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
