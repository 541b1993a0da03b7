"""The tasks a sweep can run, by name: each is a pure function of its parameters returning one row.

A task maps keyword parameters (int, float, str, bool or None) to a dict of outputs (numbers,
strings or 1-d numeric arrays). Tasks must be deterministic: the same parameters give the same bits
on any worker, which is what makes the task keys idempotent and resumed tables identical. Dense
linear algebra therefore runs on one BLAS thread (:func:`blas_one_thread`).

The registry (:data:`TASKS`, :func:`get_task`, :func:`execute`) lives here; each task family's
``run`` and ``check`` live in a module of their own (``disorder``, ``levels``, ``qmc``, ``spins``,
``spins_quantum``, ``device``, ``topology`` (with ``conductance``), ``probe``; shared helpers in ``_common``). A new task
is a new module with its ``run(**params) -> dict`` (every parameter with a default) and
``check(params)``, and one :class:`Task` entry in :data:`TASKS`.

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
``spins``
    One Markov chain of a classical spin model (:func:`hyperlattice.spins.classical.classical_mc`):
    ``p, q, rings, cluster, model, J, h, T, sweeps, thermalization, seed, update`` (``cluster`` as
    for ``qmc``). Outputs ``e, c, m, m2, m_abs, U4, chi`` and their staggered forms with ``_err``,
    ``tau_e``, ``tau_m2``, ``converged``, ``notes``, ``update_used`` and the ring profiles
    ``ring_energy``, ``ring_alignment``, ``ring_m``.
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
``conductance``
    One disorder realization of the two-terminal conductance at one energy
    (:func:`hyperlattice.topology.transport.conductance`, wide-band leads on two opposite arcs of
    the edge): ``p, q, rings, model, M, t2, phi, W, seed, energy, coupling, arc``; outputs
    ``conductance`` (e²/h) and ``error`` (its current-conservation check). A grid over ``seed``
    gives the ensemble (the plateau of the topological Anderson insulator and its boundaries).
``probe``
    ``x -> x**2`` after sleeping ``sleep`` seconds: measures the engine's own overhead and
    exercises its fault handling; no physics.
"""

from __future__ import annotations

import contextlib
import inspect
import threading
from dataclasses import dataclass
from typing import Callable, Iterator

from ... import _validate
# the shared helpers and every task family's run and check, under the names they had when this was one module
from ._common import _NOTES_SEP, _check_geometry, _lattice, _point_value, _qmc_system, _sites  # noqa: F401
from .device import DEVICE_MAX, _check_device, _device, _device_of, _device_ports  # noqa: F401
from .disorder import _check_disorder, _disorder
from .levels import _check_levels, _levels
from .probe import _check_probe, _probe
from .qmc import _QMC_GREEN, _QMC_SCALARS, _QMC_STIFFNESS, _QMC_TAUS, _check_qmc, _qmc  # noqa: F401
from .spins import _SPINS_SCALARS, _check_spins, _spins  # noqa: F401
from .spins_quantum import _XXZ_SCALARS, _check_spins_quantum, _spins_quantum  # noqa: F401
from .topology import _check_conductance, _check_topology, _conductance, _topology

__all__ = ["Task", "TASKS", "get_task", "blas_one_thread"]

_LOCK = threading.Lock()
_DEPTH = 0
_SAVED: list = []


def _blas_controls() -> tuple:
    """(setter, getter) of every OpenBLAS loaded in this process (the solvers' list, found once)."""
    import numpy.linalg  # noqa: F401 - load numpy's and scipy's OpenBLAS before looking for them
    import scipy.linalg  # noqa: F401

    from ...graph.solvers import blas_thread_controls

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
                             Task("conductance", _conductance, _check_conductance),
                             Task("probe", _probe, _check_probe))}


def get_task(name) -> Task:
    """The registered task called ``name`` (ValueError listing the names otherwise).

    Parameters
    ----------
    name : str
        ``"disorder"``, ``"levels"``, ``"qmc"``, ``"spins"``, ``"spins_quantum"``, ``"device"``, ``"topology"``, ``"conductance"`` or ``"probe"`` (the keys of :data:`TASKS`).

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
    from ..._progress import default as progress_default

    # no bars from inside a task: a worker process shares the terminal with the sweep's own bar
    with blas_one_thread(), progress_default(False):
        return task.run(**params)


# every public function above checks its annotated argument types at the door
from hyperlattice._validate import guard_public as _guard_public  # noqa: E402

_guard_public(globals())
