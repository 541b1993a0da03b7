r"""Disorder on hyperbolic flakes and line graphs: Anderson, hopping and circuit-QED models.

.. math:: H = -\sum_{\langle ij\rangle} t_{ij}\,(c_i^\dagger c_j + \mathrm{h.c.}) + \sum_i V_i\,c_i^\dagger c_i

Models (``strength`` is W, or the relative spread :math:`\sigma` for ``"resonator"``):

* ``"box"``: Anderson on-site disorder, :math:`V_i` uniform in :math:`[-W/2, W/2]`
  (variance :math:`W^2/12`);
* ``"gaussian"``: on-site :math:`V_i` normal with standard deviation :math:`W/\sqrt{12}`, i.e. the
  *same variance* as the box of width W, so that the two models agree to second order in W (and
  in the self-consistent Born approximation, which sees only the variance);
* ``"hopping"``: off-diagonal disorder :math:`t_{ij} = t(1 + \delta_{ij})`, :math:`\delta_{ij}`
  uniform in :math:`[-W/2, W/2]`, one value per edge;
* ``"resonator"``: the circuit-QED lattice of coplanar-waveguide resonators (sites of the *line
  graph*), whose frequencies :math:`\omega_e = \omega_0(1 + \sigma\xi_e)`, :math:`\xi_e` standard
  normal, spread by fabrication. In the frame rotating at :math:`\omega_0` and in units of the
  photon hopping t, :math:`V_e = (\omega_0/t)\,\sigma\,\xi_e`: a relative spread of
  :math:`10^{-3}` at :math:`\omega_0/t = 100` is Gaussian disorder of standard deviation
  :math:`0.1\,t`. ``omega0`` (:math:`\omega_0/t`) depends on the device and has no default.

Reproducibility: realization ``r`` of seed ``s`` draws from
``numpy.random.default_rng(SeedSequence(s, spawn_key=(r,)))``, which is the r-th child of
``SeedSequence(s).spawn(...)``: any realization can be recomputed alone, on any machine or worker,
in any order, and different realizations are statistically independent streams.

Which solvers apply
-------------------
Disorder breaks the p-fold rotation, so the angular-momentum sectors of
:mod:`hyperlattice.graph.symmetry` no longer decouple: :func:`~hyperlattice.graph.spectrum.full_spectrum`
detects this (``rotation_invariant`` is False) and diagonalises the full dense :math:`N\times N`
matrix (:math:`O(N^3)`, about p² times the clean cost); ``lowest_levels`` must use its ``dense``
or ``sparse`` method (the ``sector`` method refuses a non-invariant on-site term); Green functions
use :class:`~hyperlattice.graph.green.GraphResolvent` (sparse LU) unchanged. Hopping disorder is
passed as a matrix (:func:`disordered_hamiltonian`), which every matrix-taking solver accepts.
Flakes, line graphs and periodic clusters (:class:`~hyperlattice.graph.clusters.Cluster`, no
boundary) all take every model but ``resonator``, which needs a line graph.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .. import _validate
from ..results import Result
from .lattice import Lattice

__all__ = ["MODELS", "Disorder", "disorder", "disordered_hamiltonian", "realization_rng",
           "onsite_variance"]

MODELS = ("box", "gaussian", "hopping", "resonator")
#: largest seed accepted (SeedSequence takes any non-negative integer; 2**63 keeps JSON/Parquet int64)
_MAX_SEED = 2**63 - 1
_MAX_REALIZATION = 2**31 - 1
#: |V| or |t_ij| beyond this is refused: W^2 sums overflow long before, and no physics lives there
_MAX_STRENGTH = 1e150


def _seed(seed) -> int:
    return _validate.integer("seed", seed, minimum=0, maximum=_MAX_SEED)


def _realization(realization) -> int:
    return _validate.integer("realization", realization, minimum=0, maximum=_MAX_REALIZATION)


def _strength(model: str, value) -> float:
    name = "sigma" if model == "resonator" else "W"
    v = _validate.real(name, value, minimum=0.0)
    if v > _MAX_STRENGTH:
        raise ValueError(f"{name} = {v:g} is too large (at most {_MAX_STRENGTH:g}).")
    return v


def _system(value):
    """A flake or line graph (:class:`Lattice`) or a periodic cluster (:class:`~hyperlattice.graph.clusters.Cluster`)."""
    from .clusters import Cluster  # lazy: clusters are optional for flakes

    if isinstance(value, Cluster):
        return value
    return _validate.lattice(value)


def realization_rng(seed: int, realization: int) -> np.random.Generator:
    """The random generator of realization ``realization`` of ``seed`` (independent of any other draw).

    It is ``numpy.random.default_rng(SeedSequence(seed, spawn_key=(realization,)))``, the
    ``realization``-th child of ``SeedSequence(seed)``: any realization can be recomputed alone,
    on any machine, in any order.

    Parameters
    ----------
    seed : int
        Non-negative seed.
    realization : int
        Non-negative realization index.

    Returns
    -------
    numpy.random.Generator
        A fresh generator.

    Raises
    ------
    ValueError
        If ``seed`` or ``realization`` is negative, too large or not an integer.

    See Also
    --------
    disorder

    Examples
    --------
    >>> from hyperlattice.graph.disorder import realization_rng
    >>> round(realization_rng(1, 3).random(), 6) == round(realization_rng(1, 3).random(), 6)
    True
    """
    return np.random.default_rng(np.random.SeedSequence(_seed(seed), spawn_key=(_realization(realization),)))


def onsite_variance(model: str, strength: float, *, omega0: float | None = None) -> float:
    r"""Variance :math:`\langle V_i^2\rangle` of the on-site term of a model (what the SCBA sees).

    :math:`W^2/12` for ``box`` and ``gaussian``, :math:`(\omega_0\sigma)^2` for ``resonator``.

    Parameters
    ----------
    model : {"box", "gaussian", "resonator"}
        The disorder model (``"hopping"`` has no on-site term).
    strength : float
        W >= 0 in units of t, or the relative spread sigma of ``"resonator"``.
    omega0 : float, optional
        :math:`\omega_0/t`, required for ``"resonator"``.

    Returns
    -------
    float
        The variance in units of :math:`t^2`.

    Raises
    ------
    ValueError
        For ``hopping`` (off-diagonal disorder has no on-site variance), a resonator without
        omega0, an unknown model or an invalid strength.

    See Also
    --------
    disorder, hyperlattice.continuum.scba.scba

    Examples
    --------
    >>> from hyperlattice.graph.disorder import onsite_variance
    >>> round(onsite_variance("box", 2.0), 6)
    0.333333
    >>> round(onsite_variance("resonator", 1e-3, omega0=100.0), 6)
    0.01
    """
    model = _validate.choice("model", model, MODELS)
    s = _strength(model, strength)
    if model == "hopping":
        raise ValueError("hopping disorder has no on-site variance; the SCBA here treats on-site disorder.")
    if model == "resonator":
        return (_omega0(omega0) * s) ** 2
    return s * s / 12.0


def _omega0(omega0) -> float:
    if omega0 is None:
        raise ValueError("the resonator model needs omega0, the bare resonator frequency in units of t.")
    return _validate.positive_real("omega0", omega0)


@dataclass(frozen=True, eq=False, kw_only=True)
class Disorder(Result):
    """One disorder realization on one lattice (a :class:`~hyperlattice.results.Result`).

    Attributes
    ----------
    model : str
        One of :data:`MODELS`.
    strength : float
        W (box, gaussian, hopping) or the relative spread sigma (resonator).
    seed, realization : int
        Reproduce it with :func:`disorder`.
    onsite : ndarray of float, shape (N,)
        On-site energies :math:`V_i` (zeros for hopping disorder).
    hopping : ndarray of float, shape (E,)
        Hopping amplitude of each edge of ``lattice.edges`` in units of t (ones for on-site models).
    omega0 : float or None
        :math:`\\omega_0/t` of the resonator model.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.disorder import disorder
    >>> d = disorder(hl.ring_lattice(7, 3, 2), "box", 2.0, seed=1)
    >>> d.model, d.strength, d.onsite.shape, d.hopping.shape
    ('box', 2.0, (35,), (42,))
    >>> bool(abs(d.onsite).max() <= 1.0), bool((d.hopping == 1.0).all())   # V_i in [-W/2, W/2]
    (True, True)
    """

    model: str
    strength: float
    seed: int
    realization: int
    onsite: np.ndarray = field(repr=False)
    hopping: np.ndarray = field(repr=False)
    omega0: float | None = None

    def summary(self) -> dict:
        """model, strength, seed, realization, the sample mean and standard deviation of V and t_ij."""
        return {"model": self.model, "strength": self.strength, "seed": self.seed,
                "realization": self.realization, "omega0": self.omega0,
                "onsite_mean": float(np.mean(self.onsite)) if self.onsite.size else 0.0,
                "onsite_std": float(np.std(self.onsite)) if self.onsite.size else 0.0,
                "hopping_mean": float(np.mean(self.hopping)) if self.hopping.size else 1.0,
                "hopping_std": float(np.std(self.hopping)) if self.hopping.size else 0.0}


def disorder(lattice: Lattice, model: str = "box", strength: float = 1.0, *, seed: int = 0,
             realization: int = 0, omega0: float | None = None) -> Disorder:
    r"""Draw realization ``realization`` of a disorder model on ``lattice``.

    The models (module docstring): ``"box"`` on-site :math:`V_i` uniform in
    :math:`[-W/2, W/2]`; ``"gaussian"`` on-site with the same variance :math:`W^2/12`;
    ``"hopping"`` :math:`t_{ij} = t(1 + \delta_{ij})`, :math:`\delta_{ij}` uniform in
    :math:`[-W/2, W/2]`; ``"resonator"`` :math:`V_e = (\omega_0/t)\,\sigma\,\xi_e` on the line
    graph, :math:`\xi_e` standard normal.

    Parameters
    ----------
    lattice : Lattice or Cluster
        A flake, a periodic cluster (:mod:`hyperlattice.graph.clusters`) or (required for
        ``"resonator"``) a line graph.
    model : {"box", "gaussian", "hopping", "resonator"}, optional
        See the module docstring; default ``"box"``.
    strength : float, optional
        W >= 0 in units of t (box width; Gaussian of the same variance; relative hopping
        spread), or the relative frequency spread sigma >= 0 of the resonator model. 0 gives the
        clean lattice exactly. Default 1.
    seed, realization : int, optional
        Non-negative; the draw is a pure function of ``(seed, realization)`` (SeedSequence
        spawn key, see :func:`realization_rng`). Defaults 0.
    omega0 : float, optional
        :math:`\omega_0/t`, required by the resonator model only (no default: it depends on
        the device).

    Returns
    -------
    Disorder
        ``model``, ``strength``, ``seed``, ``realization``, ``onsite`` (N,) the potentials
        :math:`V_i` in units of t, ``hopping`` (E,) the relative hoppings :math:`t_{ij}/t` of
        ``lattice.edges``, and ``omega0``.

    Raises
    ------
    ValueError
        For an unknown model, a negative or too large strength, a negative seed or
        realization, ``"resonator"`` without ``omega0`` or on a lattice that is not a line
        graph, or ``omega0`` given to another model.

    See Also
    --------
    disordered_hamiltonian, onsite_variance, hyperlattice.compare.disorder.disorder_ensemble

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.disorder import disorder
    >>> d = disorder(hl.ring_lattice(7, 3, 2), "box", 2.0, seed=1, realization=3)
    >>> d.onsite.shape, round(float(d.onsite[0]), 6), d.hopping[:2].tolist()
    ((35,), -0.771751, [1.0, 1.0])
    """
    lattice = _system(lattice)
    model = _validate.choice("model", model, MODELS)
    s = _strength(model, strength)
    seed, realization = _seed(seed), _realization(realization)
    if model == "resonator":
        w0 = _omega0(omega0)
        if getattr(lattice, "kind", "cluster") != "line_graph":
            raise ValueError("the resonator model lives on the line graph (resonators are its sites); "
                             "pass line_graph(lattice).")
    elif omega0 is not None:
        raise ValueError("omega0 applies to the resonator model only.")
    rng = realization_rng(seed, realization)
    n, n_e = lattice.sites, lattice.edges.shape[0]
    onsite = np.zeros(n)
    hopping = np.ones(n_e)
    # always draw with the same call for a model, so that W -> 0 is continuous in every realization
    if model == "box":
        onsite = s * (rng.random(n) - 0.5)
    elif model == "gaussian":
        onsite = (s / math.sqrt(12.0)) * rng.standard_normal(n)
    elif model == "hopping":
        hopping = 1.0 + s * (rng.random(n_e) - 0.5)
    else:
        onsite = (w0 * s) * rng.standard_normal(n)
    return Disorder(model=model, strength=s, seed=seed, realization=realization, onsite=onsite,
                    hopping=hopping, omega0=omega0 if model == "resonator" else None)


def disordered_hamiltonian(lattice: Lattice, dis: Disorder, *, t: float = 1.0) -> sp.csr_matrix:
    r""":math:`H = -\sum t\,t_{ij}(|i\rangle\langle j| + \mathrm{h.c.}) + \mathrm{diag}(V)` as sorted CSR (float64).

    With ``strength = 0`` this is exactly :func:`~hyperlattice.graph.operators.hamiltonian` of the
    clean lattice (same entries, same order). Disorder breaks the p-fold rotation: pass the
    matrix to a solver that does not use sectors (module docstring).

    Parameters
    ----------
    lattice : Lattice or Cluster
        The lattice ``dis`` was drawn for.
    dis : Disorder
        A realization from :func:`disorder`.
    t : float, optional
        Hopping amplitude, the energy unit; default 1.

    Returns
    -------
    scipy.sparse.csr_matrix
        The N x N real symmetric Hamiltonian, float64, sorted indices.

    Raises
    ------
    ValueError
        If ``dis`` is not a Disorder, was drawn for a lattice of other sizes, or ``t`` is not
        a finite real number.

    See Also
    --------
    disorder, hyperlattice.graph.operators.hamiltonian

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.graph.disorder import disorder
    >>> lat = hl.ring_lattice(7, 3, 2)
    >>> H = hl.disordered_hamiltonian(lat, disorder(lat, "box", 2.0, seed=1, realization=3))
    >>> H.shape, round(float(H[0, 0]), 6), float(H[0, 1])
    ((35, 35), -0.771751, -1.0)
    >>> (hl.disordered_hamiltonian(lat, disorder(lat, "box", 0.0)) != hl.hamiltonian(lat)).nnz
    0
    """
    lattice = _system(lattice)
    if not isinstance(dis, Disorder):
        raise ValueError(f"dis must be a Disorder (from hyperlattice.graph.disorder.disorder), got {type(dis).__name__}.")
    t = _validate.real("the hopping t", t)
    n = lattice.sites
    if dis.onsite.shape != (n,) or dis.hopping.shape != (lattice.edges.shape[0],):
        raise ValueError("this disorder realization was drawn for another lattice (sizes differ).")
    e = lattice.edges.astype(np.int64)
    hop = -t * dis.hopping
    rows = np.concatenate([e[:, 0], e[:, 1], np.arange(n)])
    cols = np.concatenate([e[:, 1], e[:, 0], np.arange(n)])
    vals = np.concatenate([hop, hop, dis.onsite])
    h = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
    # the clean Hamiltonian stores no diagonal: drop the explicit zeros so W = 0 is the same matrix
    h.eliminate_zeros()
    h.sort_indices()
    return h


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
