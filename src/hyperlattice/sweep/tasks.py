"""The tasks a sweep can run, by name: each is a pure function of its parameters returning one row.

A task maps keyword parameters (int, float, str, bool or None) to a dict of outputs (numbers,
strings or 1-d numeric arrays). Tasks must be deterministic: the same parameters give the same bits
on any worker, which is what makes the task keys idempotent and resumed tables identical. Dense
linear algebra therefore runs on one BLAS thread (:func:`blas_one_thread`).

Registered tasks:

``disorder``
    One disorder realization (:func:`hyperlattice.compare.disorder.realization_observables`):
    parameters ``p, q, rings, line_graph, model, W, seed, realization, omega0, ipr``.
``levels``
    The lowest levels of a flake with flux (:func:`hyperlattice.graph.spectrum.lowest_levels`):
    ``p, q, rings, line_graph, flux, levels``; outputs ``E`` (array) and ``E0``, ``E1``.
``qmc``
    One Markov chain of the Bose–Hubbard quantum Monte Carlo (:func:`hyperlattice.bosons.qmc`):
    ``p, q, rings, cluster, nmax, U, t, mu, beta, sweeps, thermalization, seed`` (``cluster``
    None: the flake of ``rings`` rings; a name: that periodic cluster, ``rings`` unused). Outputs
    the scalar observables with errors and ``tau_*``, ``converged``, ``notes``,
    ``thermalization_sweeps``, the site densities, bond kinetic energies, the equal-time Green
    function by distance class and the condensate fraction (not the full G matrix), and on a
    periodic cluster the superfluid stiffness from the winding numbers (``rho_s``,
    ``stiffness_geometric``, their ``_err``, ``tau_stiffness``, the D x D tensor ``stiffness`` and
    ``stiffness_err`` flattened row by row with ``stiffness_dim`` = D; nan, empty and 0 on a flake,
    ``stiffness_note`` says why; the columns: docs/qmc.md); a grid over ``seed`` gives independent chains, merged per point by
    :func:`hyperlattice.sweep.qmc.merge_qmc` (:func:`hyperlattice.bosons.merge_chains`). A chain's wall-clock time is
    not stored (rows are pure functions of the parameters).
``spins_quantum``
    One Markov chain of the spin-1/2 XXZ SSE (:func:`hyperlattice.spins.quantum.xxz_qmc`):
    ``p, q, rings, cluster, J, Delta, h, beta, sweeps, thermalization, seed`` (``cluster`` as for
    ``qmc``). Outputs ``e, c, chi_u, mz, s_pi, binder, rho_s`` with ``_err``, ``tau_*``,
    ``converged``, ``notes``, ``energy_estimator``, the site arrays ``site_sz``, ``site_stag``
    (with ``_err``) and on a flake ``ring_stag`` and ``ring_stag_err`` (empty otherwise); a grid
    over ``seed`` gives independent chains.
``device``
    One fabricated device (:func:`hyperlattice.device.resonator_device` with drawn disorder, then
    :func:`hyperlattice.device.transmission`): ``p, q, rings, line_graph, omega0, J, kappa_int, ports``
    (``"RES:KAPPA,RES:KAPPA"``, or ``"RES@KAPPA+RES@KAPPA"`` on the sweep command's ``--grid``), ``sigma_omega, sigma_J, seed, omega_min, omega_max, points``; outputs
    ``omega``, ``s21_abs2`` (arrays), ``levels`` (the disordered device's eigenvalues: the resonance
    positions) and ``method``. A grid over ``seed`` is an ensemble, merged by
    :func:`hyperlattice.sweep.device.merge_device` (mean and spread).
``topology``
    One disorder realization of the hyperbolic local Chern marker at a flake's centre
    (:func:`hyperlattice.topology.kpm_marker.centre_marker`, Chebyshev projector, E_F = 0):
    ``p, q, rings, model, M, t2, phi, W, seed, moments``; outputs ``marker``, ``marker_error``,
    ``kitaev``, ``gap``. A grid over ``seed`` gives the ensemble (the topological Anderson
    insulator: the averaged marker against W).
``probe``
    ``x -> x**2`` after sleeping ``sleep`` seconds: measures the engine's own overhead and
    exercises its fault handling; no physics.
"""

from __future__ import annotations

import contextlib
import functools
import inspect
import math
import threading
import time
from dataclasses import dataclass
from typing import Callable, Iterator

import numpy as np

from .. import _validate

__all__ = ["Task", "TASKS", "get_task", "blas_one_thread"]

_LOCK = threading.Lock()
_DEPTH = 0
_SAVED: list = []


def _blas_controls() -> tuple:
    """(setter, getter) of every OpenBLAS loaded in this process (the solvers' list, found once)."""
    import numpy.linalg  # noqa: F401 - load numpy's and scipy's OpenBLAS before looking for them
    import scipy.linalg  # noqa: F401

    from ..graph.solvers import blas_thread_controls

    return blas_thread_controls()


@contextlib.contextmanager
def blas_one_thread() -> Iterator[None]:
    """One BLAS thread while any sweep task runs in this process (thread-safe, nestable).

    Dense LAPACK results may depend on the thread count in the last bits; a task must give the
    same bits on every worker. The solvers' own guard saves and restores the count per call,
    which races when two worker threads of one process interleave; this process-wide count held
    by every running task sets it once and restores it when the last task ends.

    Yields
    ------
    None
        The body runs with every OpenBLAS of the process on one thread; the previous counts
        come back when the outermost block ends.

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.sweep.tasks import blas_one_thread
    >>> with blas_one_thread():
    ...     print(float(np.linalg.eigvalsh(np.eye(2))[0]))
    1.0
    """
    global _DEPTH
    with _LOCK:
        if _DEPTH == 0:
            _SAVED[:] = [(setter, int(getter())) for setter, getter in _blas_controls()]
            for setter, _ in _SAVED:
                setter(1)
        _DEPTH += 1
    try:
        yield
    finally:
        with _LOCK:
            _DEPTH -= 1
            if _DEPTH == 0:
                for setter, old in _SAVED:
                    setter(old)
                _SAVED.clear()


@functools.lru_cache(maxsize=8)
def _lattice(p: int, q: int, rings: int, line: bool):
    from ..graph.lattice import line_graph, ring_lattice

    lat = ring_lattice(p, q, rings)
    return line_graph(lat) if line else lat


def _sites(p, q, rings, line) -> int:
    from ..graph.lattice import edge_count, site_count

    return edge_count(p, q, rings) if line else site_count(p, q, rings)


def _check_geometry(params: dict, dense_max: int) -> None:
    p, q = _validate.pq(params["p"], params["q"])
    rings = _validate.positive_int("rings", params["rings"], maximum=40)
    line = _validate.flag("line_graph", params["line_graph"])
    n = _sites(p, q, rings, line)
    if n > dense_max:
        raise ValueError(f"the {{{p},{q}}} {'line graph' if line else 'flake'} of {rings} rings has {n:,} sites; "
                         f"this task is a dense computation limited to {dense_max:,}.")


def _disorder(p: int = 7, q: int = 3, rings: int = 4, line_graph: bool = False, model: str = "box", W: float = 1.0,
              seed: int = 0, realization: int = 0, omega0: float | None = None, ipr: bool = False) -> dict:
    from ..compare.disorder import realization_observables

    lat = _lattice(p, q, rings, line_graph)
    return realization_observables(lat, model, W, seed=seed, realization=realization, omega0=omega0, ipr=ipr)


def _check_disorder(params: dict) -> None:
    from ..compare.disorder import DENSE_MAX
    from ..graph.disorder import MODELS, _realization, _seed, _strength

    _check_geometry(params, DENSE_MAX)
    model = _validate.choice("model", params["model"], MODELS)
    _strength(model, params["W"])
    _seed(params["seed"])
    _realization(params["realization"])
    if params["omega0"] is not None:
        _validate.positive_real("omega0", params["omega0"])
    _validate.flag("ipr", params["ipr"])


def _levels(p: int = 7, q: int = 3, rings: int = 4, line_graph: bool = False, flux: float = 0.0,
            levels: int = 2) -> dict:
    from ..graph.spectrum import lowest_levels

    spec = lowest_levels(_lattice(p, q, rings, line_graph), levels, flux=flux)
    e = np.asarray(spec.energies, float)
    return {"E": e, "E0": float(e[0]), "E1": float(e[1]) if e.size > 1 else math.nan, "method": spec.method}


def _check_levels(params: dict) -> None:
    _check_geometry(params, 5_000_000)
    _validate.real("flux", params["flux"])
    _validate.positive_int("levels", params["levels"], maximum=1000)


#: the fields of a QMCResult a ``qmc`` row stores under their own names (the rest: see _qmc)
_QMC_SCALARS = ("system", "sites", "energy", "energy_err", "density", "density_err",
                "compressibility", "compressibility_err", "bins", "bin_size", "mean_operators", "string_length",
                "loops_per_sweep", "condensate_fraction", "condensate_fraction_err", "distance_kind")
#: the 1-d arrays of the equal-time Green function by distance class (empty when not measured)
_QMC_GREEN = ("green_distance", "green", "green_err", "green_pairs")
_QMC_TAUS = ("energy", "density", "compressibility")
#: the stiffness scalars of a ``qmc`` row (nan without winding numbers: an open flake)
_QMC_STIFFNESS = ("rho_s", "rho_s_err", "stiffness_geometric", "stiffness_geometric_err")
#: separates the notes of a chain in the ``notes`` column
_NOTES_SEP = " | "


def _qmc_system(p: int, q: int, rings: int, cluster):
    if cluster is None:
        return _lattice(p, q, rings, False)
    from ..graph.clusters import pbc_cluster

    return pbc_cluster(p, q, cluster)


def _check_chain_graph(params: dict) -> tuple[int, int]:
    """(p, q) of a Monte Carlo task's graph: a flake of ``rings`` or a known periodic ``cluster``."""
    p, q = _validate.pq(params["p"], params["q"])
    if params["cluster"] is None:
        _validate.positive_int("rings", params["rings"], maximum=40)
    else:
        from ..graph.clusters import pbc_cluster

        pbc_cluster(p, q, params["cluster"])        # refuses an unknown name in one sentence
    return p, q


def _check_chain_length(params: dict, couplings: tuple = (), positive_beta: bool = False) -> float | None:
    """A Monte Carlo task's real ``couplings``, its beta (> 0, returned) when ``positive_beta``, its sweeps,
    thermalisation sweeps and seed."""
    for name in couplings:
        _validate.real(name, params[name])
    beta = None
    if positive_beta:
        beta = _validate.real("beta", params["beta"])
        if not beta > 0:
            raise ValueError(f"beta must be positive, got {beta!r}.")
    _validate.positive_int("sweeps", params["sweeps"])
    if params["thermalization"] is not None:
        _validate.integer("thermalization", params["thermalization"], minimum=0)
    _validate.integer("seed", params["seed"], minimum=0)
    return beta


def _quietly(warning: type, chain, *args, **kwargs):
    """``chain(*args, **kwargs)`` with its warnings of class ``warning`` silenced: the row keeps what a
    warning says (``converged`` and ``notes``)."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", warning)
        return chain(*args, **kwargs)


def _qmc(p: int = 7, q: int = 3, rings: int = 3, cluster: str | None = None, nmax: int = 2, U: float = 10.0,
         t: float = 1.0, mu: float = 5.0, beta: float = 4.0, sweeps: int = 5000, thermalization: int | None = None,
         seed: int = 0) -> dict:
    from ..bosons import QMCWarning, qmc

    r = _quietly(QMCWarning, qmc, _qmc_system(p, q, rings, cluster), U=U, mu=mu, beta=beta, nmax=nmax, t=t,
                 sweeps=sweeps, thermalization=thermalization, seed=seed, progress=False)
    row = {k: getattr(r, k) for k in _QMC_SCALARS}
    # an output never reuses a parameter's name (the table holds both): the thermalisation actually run
    row["thermalization_sweeps"] = int(r.thermalization)
    row.update({f"tau_{k}": float(r.tau_int.get(k, math.nan)) for k in _QMC_TAUS})
    row["converged"] = bool(r.converged)
    row["notes"] = _NOTES_SEP.join(r.notes)
    row["site_density"] = np.asarray(r.site_density, float)
    row["site_density_err"] = np.asarray(r.site_density_err, float)
    row["bond_i"] = np.asarray(r.bonds, np.int64)[:, 0]
    row["bond_j"] = np.asarray(r.bonds, np.int64)[:, 1]
    row["bond_kinetic"] = np.asarray(r.bond_kinetic, float)
    row["bond_kinetic_err"] = np.asarray(r.bond_kinetic_err, float)
    for k in _QMC_GREEN:     # G(d) by distance class; the full matrix (2-d) is not a table column
        v = getattr(r, k)
        row[k] = np.zeros(0) if v is None else np.asarray(v, float)
    # the superfluid stiffness from the winding numbers (a periodic cluster): the D x D tensor row by
    # row (a column holds 1-d arrays), D in ``stiffness_dim``; empty, 0 and nan on a flake
    row.update({k: float(getattr(r, k)) for k in _QMC_STIFFNESS})
    row["tau_stiffness"] = float(r.tau_int.get("stiffness", math.nan))
    row["stiffness_dim"] = 0 if r.stiffness is None else int(r.stiffness.shape[0])
    for k in ("stiffness", "stiffness_err"):
        v = getattr(r, k)
        row[k] = np.zeros(0) if v is None else np.asarray(v, float).ravel()
    row["stiffness_note"] = r.stiffness_note
    return row


def _check_qmc(params: dict) -> None:
    p, q = _check_chain_graph(params)
    _validate.positive_int("nmax", params["nmax"], maximum=1000)
    beta = _check_chain_length(params, ("U", "t", "mu"), positive_beta=True)
    if params["t"] == 0:
        raise ValueError("t = 0 leaves no bond term; the sites are independent.")
    # the operator string grows with beta * bonds: the engine's own estimate refuses a point that will
    # not fit, before the grid runs
    from ..bosons.sse import qmc_memory

    need = qmc_memory(_qmc_system(p, q, params["rings"], params["cluster"]), U=float(params["U"]),
                      mu=float(params["mu"]), beta=beta, nmax=int(params["nmax"]), t=float(params["t"]))
    try:
        _validate.require_memory(f"the SSE operator string at beta = {beta:g}", need)
    except MemoryError as exc:
        raise ValueError(str(exc)) from None


#: the scalar observables of a ``spins`` row, each with its ``_err``
_SPINS_SCALARS = ("e", "c", "m", "m2", "m_abs", "U4", "chi", "m2_s", "m_abs_s", "U4_s", "chi_s")


def _spins(p: int = 7, q: int = 3, rings: int = 3, cluster: str | None = None, model: str = "ising",
           J: float = 1.0, h: float = 0.0, T: float = 2.0, sweeps: int = 5000, thermalization: int | None = None,
           seed: int = 0, update: str = "auto") -> dict:
    from ..spins.classical import SpinWarning, classical_mc

    r = _quietly(SpinWarning, classical_mc, _qmc_system(p, q, rings, cluster), model=model, T=T, J=J, h=h,
                 sweeps=sweeps, thermalization=thermalization, seed=seed, update=update, measure_correlation=False,
                 progress=False)
    row = {"sites": int(r.sites), "update_used": r.update}
    for k in _SPINS_SCALARS:
        row[k] = float(getattr(r, k))
        row[k + "_err"] = float(getattr(r, k + "_err"))
    row.update({f"tau_{k}": float(r.tau_int.get(k, math.nan)) for k in ("e", "m2")})
    row["converged"] = bool(r.converged)
    row["notes"] = _NOTES_SEP.join(r.notes)
    for k in ("ring_energy", "ring_alignment", "ring_alignment_err", "ring_m"):     # bulk against boundary
        v = getattr(r, k)
        row[k] = np.zeros(0) if v is None else np.asarray(v, float)
    return row


def _check_spins(params: dict) -> None:
    p, q = _check_chain_graph(params)
    from ..spins.classical import MODELS, classical_mc_memory

    _validate.choice("model", params["model"], tuple(MODELS))
    _validate.choice("update", params["update"], ("auto", "wolff", "swendsen-wang", "local"))
    T = _validate.real("T", params["T"])
    if not T > 0:
        raise ValueError(f"T must be positive, got {T!r}.")
    _check_chain_length(params, ("J", "h"))
    need = classical_mc_memory(_qmc_system(p, q, params["rings"], params["cluster"]), model=params["model"],
                               measure_correlation=False)
    try:
        _validate.require_memory("the classical spin chain", need)
    except MemoryError as exc:
        raise ValueError(str(exc)) from None


#: the scalars of an XXZResult a ``spins_quantum`` row stores under their own names
_XXZ_SCALARS = ("system", "sites", "bipartite", "e", "e_err", "c", "c_err", "chi_u", "chi_u_err", "mz", "mz_err",
                "s_pi", "s_pi_err", "binder", "binder_err", "rho_s", "rho_s_err", "bins", "bin_size",
                "mean_operators", "energy_estimator")


def _spins_quantum(p: int = 8, q: int = 3, rings: int = 2, cluster: str | None = None, J: float = 1.0,
                   Delta: float = 1.0, h: float = 0.0, beta: float = 4.0, sweeps: int = 5000,
                   thermalization: int | None = None, seed: int = 0) -> dict:
    from ..spins.quantum import XXZWarning, xxz_qmc

    r = _quietly(XXZWarning, xxz_qmc, _qmc_system(p, q, rings, cluster), J=J, Delta=Delta, h=h, beta=beta,
                 sweeps=sweeps, thermalization=thermalization, seed=seed, progress=False)
    row = {k: getattr(r, k) for k in _XXZ_SCALARS}
    row["thermalization_sweeps"] = int(r.thermalization)
    row.update({f"tau_{k}": float(r.tau_int.get(k, math.nan)) for k in ("energy", "chi_u", "s_pi", "stiffness")})
    row["converged"] = bool(r.converged)
    row["notes"] = _NOTES_SEP.join(r.notes)
    for k in ("site_sz", "site_sz_err", "site_stag", "site_stag_err", "ring_stag", "ring_stag_err"):
        v = getattr(r, k)
        row[k] = np.zeros(0) if v is None else np.asarray(v, float)
    return row


def _check_spins_quantum(params: dict) -> None:
    p, q = _check_chain_graph(params)
    _check_chain_length(params, ("J", "Delta", "h"), positive_beta=True)
    if params["J"] == 0:
        raise ValueError("J = 0 leaves free spins in a field (no bond term); use a nonzero J.")
    if params["J"] > 0 and params["cluster"] is None and p % 2:
        raise ValueError(f"an antiferromagnet (J > 0) on a graph with an odd cycle is frustrated and gives the "
                         f"quantum Monte Carlo a sign problem (the {{{p},{q}}} flake has {p}-gons).")


#: largest device of the ``device`` task (its levels come from a dense eigensolver)
DEVICE_MAX = 5000


def _device_ports(text) -> dict:
    if not isinstance(text, str) or not text.strip():
        raise ValueError(f"ports must be a string 'RES:KAPPA,RES:KAPPA', got {_validate._shown(text)}.")
    import re

    out = {}
    # "0-1:0.1,30-31:0.1", or without the characters the sweep command's --grid reserves: "0-1@0.1+30-31@0.1"
    for item in re.split(r"[,+;]", text):
        name, sep, kappa = item.strip().replace("@", ":").rpartition(":")
        if not sep or not name:
            raise ValueError(f"each port is RES:KAPPA, got {item.strip()!r}.")
        try:
            out[name] = float(kappa)
        except ValueError:
            raise ValueError(f"the kappa of port {item.strip()!r} is not a number.") from None
    return out


def _device_of(params: dict):
    from ..device import resonator_device

    lat = _lattice(params["p"], params["q"], params["rings"], False)
    return resonator_device(lat, line_graph=params["line_graph"], omega0=params["omega0"], J=params["J"],
                            kappa_int=params["kappa_int"], ports=_device_ports(params["ports"]),
                            sigma_omega=params["sigma_omega"], sigma_J=params["sigma_J"], seed=params["seed"])


def _device(p: int = 7, q: int = 3, rings: int = 3, line_graph: bool = True, omega0: float = 0.0, J: float = 1.0,
            kappa_int: float = 0.05, ports: str = "0-1:0.1,110-111:0.1", sigma_omega: float = 0.0,
            sigma_J: float = 0.0, seed: int = 0, omega_min: float = -4.5, omega_max: float = 2.5,
            points: int = 701) -> dict:
    from ..device import transmission

    params = dict(p=p, q=q, rings=rings, line_graph=line_graph, omega0=omega0, J=J, kappa_int=kappa_int,
                  ports=ports, sigma_omega=sigma_omega, sigma_J=sigma_J, seed=seed)
    dev = _device_of(params)
    tr = transmission(dev, np.linspace(omega_min, omega_max, points))
    levels = tr.levels if tr.levels is not None and len(tr.levels) else np.linalg.eigvalsh(dev.hamiltonian().toarray())
    return {"omega": np.asarray(tr.omega, float), "s21_abs2": np.asarray(tr.power, float),
            "levels": np.asarray(levels, float), "method": tr.method}


def _check_device(params: dict) -> None:
    _check_geometry(params, DEVICE_MAX)
    for name in ("omega_min", "omega_max"):
        _validate.real(name, params[name])
    if not params["omega_max"] > params["omega_min"]:
        raise ValueError(f"omega_max {params['omega_max']!r} must exceed omega_min {params['omega_min']!r}.")
    _validate.positive_int("points", params["points"], maximum=1_000_000)
    _device_of(params)          # refuses bad ports, rates and seeds in one sentence


def _topology(p: int = 8, q: int = 3, rings: int = 4, model: str = "qwz", M: float = 1.0, t2: float = 0.2,
              phi: float = 1.5707963267948966, W: float = 0.0, seed: int = 0, moments: int = 256) -> dict:
    import warnings

    from ..errors import ConvergenceWarning
    from ..topology.kpm_marker import centre_marker

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)   # the row carries marker_error instead
        r = centre_marker(_lattice(p, q, rings, False), model, M=M, t2=t2, phi=phi, disorder=W, seed=seed,
                          moments=moments)
    return {"marker": r.marker, "marker_error": r.marker_error, "kitaev": r.kitaev, "gap": r.gap}


def _check_topology(params: dict) -> None:
    _check_geometry(dict(params, line_graph=False), 200_000)
    _validate.choice("model", params["model"], ("qwz", "haldane"))
    for name in ("M", "t2", "phi"):
        _validate.real(name, params[name], minimum=-1e6, maximum=1e6)
    _validate.real("W", params["W"], minimum=0.0, maximum=1e6)
    _validate.integer("seed", params["seed"], minimum=0, maximum=2**63 - 1)
    _validate.integer("moments", params["moments"], minimum=16, maximum=100_000)


def _point_value(v):
    """A hashable, exact stand-in of a parameter value (floats by repr)."""
    return repr(v) if isinstance(v, float) else v


def _probe(x: float = 0.0, sleep: float = 0.0) -> dict:
    if sleep:
        time.sleep(sleep)
    return {"y": x * x}


def _check_probe(params: dict) -> None:
    _validate.real("x", params["x"])
    _validate.real("sleep", params["sleep"], minimum=0.0, maximum=3600.0)


@dataclass(frozen=True)
class Task:
    """A named sweep task: ``run(**params) -> dict`` and ``check(params)`` (raises ValueError).

    Attributes
    ----------
    name : str
        The task's name in :data:`TASKS` and on the command line.
    run : callable
        ``run(**params) -> dict``: one point of the sweep (energies in units of t for the
        physics tasks); every parameter has a default (:attr:`defaults`).
    check : callable
        ``check(params)``: raises ValueError, with one sentence, for a parameter set the task
        refuses (checked for the whole grid before anything runs).

    Examples
    --------
    >>> from hyperlattice.sweep.tasks import get_task
    >>> probe = get_task("probe")
    >>> probe.name, probe.defaults, probe.run(x=2.0)
    ('probe', {'x': 0.0, 'sleep': 0.0}, {'y': 4.0})
    >>> probe.check({"x": 1.0, "sleep": -1.0})
    Traceback (most recent call last):
    ...
    ValueError: sleep must be at least 0, got -1.
    """

    name: str
    run: Callable[..., dict]
    check: Callable[[dict], None]

    @property
    def defaults(self) -> dict:
        """Every parameter with its default value (a grid overrides some of them)."""
        return {k: v.default for k, v in inspect.signature(self.run).parameters.items()}


TASKS = {t.name: t for t in (Task("disorder", _disorder, _check_disorder), Task("levels", _levels, _check_levels),
                             Task("qmc", _qmc, _check_qmc), Task("spins", _spins, _check_spins),
                             Task("spins_quantum", _spins_quantum, _check_spins_quantum),
                             Task("device", _device, _check_device), Task("topology", _topology, _check_topology),
                             Task("probe", _probe, _check_probe))}


def get_task(name) -> Task:
    """The registered task called ``name`` (ValueError listing the names otherwise).

    Parameters
    ----------
    name : str
        ``"disorder"``, ``"levels"``, ``"qmc"``, ``"spins"``, ``"spins_quantum"``, ``"device"``, ``"topology"`` or ``"probe"`` (the keys of :data:`TASKS`).

    Returns
    -------
    Task
        ``name``, ``run(**params) -> dict``, ``check(params)`` and ``defaults`` (every
        parameter with its default value).

    Raises
    ------
    ValueError
        If no task has that name (the message lists them).

    Examples
    --------
    >>> from hyperlattice.sweep.tasks import get_task
    >>> get_task("probe").defaults
    {'x': 0.0, 'sleep': 0.0}
    >>> get_task("levels").defaults
    {'p': 7, 'q': 3, 'rings': 4, 'line_graph': False, 'flux': 0.0, 'levels': 2}
    """
    return TASKS[_validate.choice("task", name, tuple(TASKS))]


def execute(name: str, params: dict) -> dict:
    """Run task ``name`` on ``params`` on one BLAS thread, without progress bars (this is what a worker calls)."""
    import inspect

    task = get_task(name)
    if not isinstance(params, dict):
        raise ValueError(f"params must be a dict of the task's parameters, got {type(params).__name__}.")
    try:
        inspect.signature(task.run).bind(**params)
    except TypeError as exc:
        raise ValueError(f"params do not fit task {name!r}: {exc}.") from None
    from .._progress import default as progress_default

    # no bars from inside a task: a worker process shares the terminal with the sweep's own bar
    with blas_one_thread(), progress_default(False):
        return task.run(**params)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
