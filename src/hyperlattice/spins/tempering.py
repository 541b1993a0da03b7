r"""Parallel tempering (replica exchange) of the classical spin models over a set of temperatures.

R copies of the chain of :func:`hyperlattice.spins.classical_mc` run at inverse temperatures
:math:`\beta_1 < \dots < \beta_R` with the update of :func:`~hyperlattice.spins.classical_mc`
(heat-bath with over-relaxation on frustrated or mixed-sign couplings, Wolff clusters where a gauge
makes every coupling ferromagnetic). Every ``exchange_every`` sweeps the configurations of
neighbouring temperatures are offered an exchange, accepted with probability
:math:`\min\{1, e^{(\beta_{k+1}-\beta_k)(E_{k+1}-E_k)}\}` (Hukushima and Nemoto, J. Phys. Soc. Jpn.
65, 1604 (1996)); the even pairs (1,2), (3,4), ... and the odd pairs (2,3), (4,5), ... take turns.
Each temperature keeps its own measurement bins, so its observables (with binning errors and
:math:`\tau_{\mathrm{int}}` in sweeps, exchanges included) are those of a :class:`ClassicalResult`.
Reported besides: the acceptance rate of each neighbouring pair and the completed round trips of
the replicas (a configuration walking from the highest temperature to the lowest and back), the
measure of whether the temperature set lets the cold chains forget their state.

Whether it pays is measured in ``benchmarks/spins_tempering.py`` and stated in ``docs/spins.md``.
A run may be checkpointed and resumed bit-identically, like a single chain.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import _validate
from .._progress import progress_bar
from ..bosons import _checkpoint
from ..results import Column, Result, to_jsonable
from . import classical as _cl

__all__ = ["TemperingResult", "tempering_mc"]

#: most temperatures of one tempering run
MAX_REPLICAS = 256
#: the lock file a run holds in its checkpoint directory
_LOCK_FILE = ".spins_tempering.lock"


@dataclass(frozen=True, eq=False, kw_only=True)
class TemperingResult(Result):
    r"""Parallel tempering of a classical spin model: one chain per temperature, with exchanges.

    Attributes
    ----------
    system, model : str
        What was simulated and the spins (``"ising"``, ``"xy"``, ``"heisenberg"``).
    sites : int
        Number of sites N.
    J, h : float
        Coupling scale and field.
    beta : ndarray
        The inverse temperatures, ascending (hottest first).
    update : str
        The update each chain ran between exchanges.
    sweeps, thermalization, exchange_every : int
        Measured and thermalisation sweeps per temperature, sweeps between exchange attempts.
    seed : int
        The seed of the run (the chains' and the exchanges' streams derive from it).
    acceptance : ndarray, shape (R - 1,)
        Accepted fraction of the exchanges offered to the pair (beta[k], beta[k + 1]).
    attempts : ndarray of int, shape (R - 1,)
        Exchanges offered to each pair.
    round_trips : int
        Completed round trips of the replicas (hottest to coldest and back to the hottest).
    chains : tuple of ClassicalResult
        The observables at each temperature (errors and tau_int in sweeps, exchanges included).
    seconds : float
        Wall-clock seconds of the whole run.

    Examples
    --------
    >>> import hyperlattice as hl
    >>> from hyperlattice.spins import tempering_mc
    >>> r = tempering_mc(hl.ring_lattice(7, 3, 2), model="ising", J=-1.0, beta=[0.5, 0.8, 1.2], sweeps=2000,
    ...                  seed=1, progress=False)
    >>> r.update, len(r.chains), bool(r.acceptance.min() > 0.1)
    ('heat-bath', 3, True)
    """

    COLUMNS = (Column("T", "T", "J"), Column("beta", "beta", "1/J"), Column("e", "e", "J"),
               Column("e_err", "e_err", "J"), Column("c", "c", "1"), Column("c_err", "c_err", "1"),
               Column("m2", "m2", "1"), Column("m2_err", "m2_err", "1"), Column("U4", "U4", "1"),
               Column("U4_err", "U4_err", "1"), Column("chi", "chi", "1/J"), Column("chi_err", "chi_err", "1/J"),
               Column("tau_e", "tau_e", "sweeps"), Column("tau_m2", "tau_m2", "sweeps"))

    system: str
    model: str
    sites: int
    J: float
    h: float
    beta: np.ndarray
    update: str
    sweeps: int
    thermalization: int
    exchange_every: int
    seed: int
    acceptance: np.ndarray
    attempts: np.ndarray
    round_trips: int
    chains: tuple
    seconds: float

    @property
    def T(self) -> np.ndarray:
        """The temperatures 1/beta."""
        return 1.0 / self.beta

    def _col(self, name: str) -> np.ndarray:
        return np.array([float(getattr(r, name)) for r in self.chains])

    @property
    def e(self) -> np.ndarray:
        """Energy per site at each temperature."""
        return self._col("e")

    @property
    def e_err(self) -> np.ndarray:
        """Its binning error."""
        return self._col("e_err")

    @property
    def c(self) -> np.ndarray:
        """Specific heat per site."""
        return self._col("c")

    @property
    def c_err(self) -> np.ndarray:
        """Its jackknife error."""
        return self._col("c_err")

    @property
    def m2(self) -> np.ndarray:
        r""":math:`\langle|m|^2\rangle` at each temperature."""
        return self._col("m2")

    @property
    def m2_err(self) -> np.ndarray:
        """Its binning error."""
        return self._col("m2_err")

    @property
    def U4(self) -> np.ndarray:
        """The Binder cumulant at each temperature."""
        return self._col("U4")

    @property
    def U4_err(self) -> np.ndarray:
        """Its jackknife error."""
        return self._col("U4_err")

    @property
    def chi(self) -> np.ndarray:
        r""":math:`\chi = \beta N\langle|m|^2\rangle`."""
        return self._col("chi")

    @property
    def chi_err(self) -> np.ndarray:
        """Its error."""
        return self._col("chi_err")

    @property
    def tau_e(self) -> np.ndarray:
        """Integrated autocorrelation time of the energy (sweeps)."""
        return np.array([float(r.tau_int["e"]) for r in self.chains])

    @property
    def tau_m2(self) -> np.ndarray:
        r"""Integrated autocorrelation time of :math:`|m|^2` (sweeps)."""
        return np.array([float(r.tau_int["m2"]) for r in self.chains])

    def _check_loaded(self) -> str | None:
        why = super()._check_loaded()
        if why is not None:
            return why
        R = self.beta.shape[0]
        if self.beta.ndim != 1 or R < 2 or not np.all(self.beta > 0) or not np.all(np.diff(self.beta) > 0):
            return "beta must hold at least two positive inverse temperatures, ascending"
        if self.acceptance.shape != (R - 1,) or self.attempts.shape != (R - 1,):
            return "acceptance and attempts need one entry per neighbouring pair"
        if np.any((self.acceptance < 0) | (self.acceptance > 1)) or np.any(self.attempts < 0):
            return "acceptance rates lie in [0, 1] and attempts are counts"
        if len(self.chains) != R or not all(isinstance(r, _cl.ClassicalResult) for r in self.chains):
            return "chains must hold one ClassicalResult per temperature"
        return None

    def summary(self) -> dict:
        """The JSON view: the parameters, the exchange statistics and each temperature's observables."""
        out = {"type": self.TYPE, "sites": self.sites, "model": self.model, "system": self.system, "J": self.J,
               "h": self.h, "update": self.update, "sweeps": self.sweeps, "thermalization": self.thermalization,
               "exchange_every": self.exchange_every, "seed": self.seed, "beta": to_jsonable(self.beta),
               "acceptance": to_jsonable(self.acceptance), "attempts": to_jsonable(self.attempts),
               "round_trips": self.round_trips, "seconds": self.seconds}
        out["temperatures"] = [r.summary() for r in self.chains]
        return out

    def __str__(self) -> str:
        lines = [f"parallel tempering, classical {self.model} model, {self.system}: J = {self.J:g}, h = {self.h:g}, "
                 f"{self.beta.size} temperatures, update {self.update}, {self.sweeps} sweeps each, exchange every "
                 f"{self.exchange_every}, {self.round_trips} round trips"]
        lines.append("  T         e                    U4                  tau_e   accept (to next)")
        for k, r in enumerate(self.chains):
            acc = f"{self.acceptance[k]:.3f}" if k < self.acceptance.size else ""
            lines.append(f"  {r.T:<8.4g} {r.e: .6f} +- {r.e_err:.6f}  {r.U4: .4f} +- {r.U4_err:.4f}  "
                         f"{r.tau_int['e']:6.2f}   {acc}")
        return "\n".join(lines)


class _State:
    """The exchanges' bookkeeping: who sits where, the replicas' labels for round trips, the counts."""

    def __init__(self, R: int):
        self.who = np.arange(R, dtype=np.int64)        # which replica sits at each temperature
        self.label = np.zeros(R, dtype=np.int64)       # 1: last seen at the hottest, -1: at the coldest
        self.label[0] = 1
        self.accepted = np.zeros(R - 1, dtype=np.int64)
        self.attempts = np.zeros(R - 1, dtype=np.int64)
        self.trips = 0
        self.parity = 0
        self.done = 0

    def exchange(self, chains, energies, betas, gen) -> None:
        R = len(chains)
        for k in range(self.parity, R - 1, 2):
            self.attempts[k] += 1
            x = (betas[k + 1] - betas[k]) * (energies[k + 1] - energies[k])
            if x >= 0 or gen.random() < math.exp(x):
                self.accepted[k] += 1
                chains[k].spins, chains[k + 1].spins = chains[k + 1].spins, chains[k].spins
                energies[k], energies[k + 1] = energies[k + 1], energies[k]
                self.who[k], self.who[k + 1] = self.who[k + 1], self.who[k]
        self.parity ^= 1
        if self.label[self.who[R - 1]] == 1:
            self.label[self.who[R - 1]] = -1
        if self.label[self.who[0]] == -1:
            self.trips += 1
        self.label[self.who[0]] = 1

    def save(self, path: Path, fingerprint: str, chains, gen) -> None:
        arrays = {f"c{k}_{f}": getattr(ch, f) for k, ch in enumerate(chains) for f in _cl._Chain.FIELDS}
        arrays.update(who=self.who, label=self.label, accepted=self.accepted, attempts=self.attempts,
                      counts=np.array([self.trips, self.parity, self.done], dtype=np.int64))
        _checkpoint.write(path, {"fingerprint": fingerprint, "generator": gen.bit_generator.state}, arrays)

    def load(self, path: Path, fingerprint: str, chains, gen) -> None:
        meta, data = _checkpoint.read(path)
        shown = repr(str(path))
        if meta.get("fingerprint") != fingerprint:
            raise ValueError(f"the checkpoint {shown} belongs to a run with other parameters (system, model, J, h, "
                             "temperatures, update, seed, thermalization or exchange_every); use another directory.")
        R = len(chains)
        for name, want in (("who", self.who), ("label", self.label), ("accepted", self.accepted),
                           ("attempts", self.attempts)):
            got = data.get(name)
            if got is None or got.dtype != want.dtype or got.shape != want.shape:
                raise ValueError(f"the checkpoint {shown} is damaged (field {name}); delete it to start afresh.")
        counts = data.get("counts")
        ok = (counts is not None and counts.shape == (3,) and counts.dtype == np.int64 and np.all(counts >= 0)
              and counts[1] in (0, 1) and np.array_equal(np.sort(data["who"]), np.arange(R))
              and np.all(np.isin(data["label"], (-1, 0, 1))) and np.all(data["attempts"] >= 0)
              and np.all((data["accepted"] >= 0) & (data["accepted"] <= data["attempts"])))
        if not ok:
            raise ValueError(f"the checkpoint {shown} holds exchange counters out of range; delete it to start afresh.")
        for k, ch in enumerate(chains):
            part = {f: data.get(f"c{k}_{f}") for f in _cl._Chain.FIELDS}
            for f, got in part.items():
                want = getattr(ch, f)
                if got is None or got.dtype != want.dtype or got.shape != want.shape:
                    raise ValueError(f"the checkpoint {shown} is damaged (chain {k}, field {f}); delete it to start "
                                     "afresh.")
            ch._check_ranges(path, part)
        try:
            gen.bit_generator.state = meta["generator"]
        except (KeyError, TypeError, ValueError):
            raise ValueError(f"the checkpoint {shown} holds no valid state of the exchanges' random numbers; delete "
                             "it to start afresh.") from None
        for k, ch in enumerate(chains):
            for f in _cl._Chain.FIELDS:
                setattr(ch, f, data[f"c{k}_{f}"])
        self.who, self.label = data["who"], data["label"]
        self.accepted, self.attempts = data["accepted"], data["attempts"]
        self.trips, self.parity, self.done = (int(x) for x in counts)


def _fingerprint(mdl, name, J, h, betas, mode, overrelax, seed, thermalization, exchange_every, cevery) -> str:
    hsh = hashlib.sha256()
    for a in (mdl.indptr, mdl.indices, mdl.J, np.asarray(betas, dtype=float)):
        hsh.update(np.ascontiguousarray(a).tobytes())
    hsh.update(json.dumps([mdl.sites, name, J, h, mode, overrelax, seed, thermalization, exchange_every, cevery,
                           _cl._RULES, "tempering-1"]).encode())
    return hsh.hexdigest()


def _temperatures(beta, T) -> np.ndarray:
    if (beta is None) == (T is None):
        raise ValueError("give the temperatures as exactly one of beta and T (a list of at least two).")
    name, vals = ("beta", beta) if beta is not None else ("T", T)
    arr = _validate.real_array(name, vals, ndim=1)
    arr = np.asarray(arr, dtype=float)
    if arr.ndim != 1 or arr.size < 2:
        raise ValueError(f"{name} must be a list of at least two temperatures, got {_validate._shown(vals)}.")
    if arr.size > MAX_REPLICAS:
        raise ValueError(f"parallel tempering takes at most {MAX_REPLICAS} temperatures, got {arr.size}.")
    if not np.all(np.isfinite(arr)) or not np.all(arr > 0):
        raise ValueError(f"every {name} must be positive and finite.")
    betas = arr if name == "beta" else 1.0 / arr
    if not np.all(np.isfinite(betas)):
        raise ValueError("a temperature is too small: beta = 1/T overflows.")
    betas = np.sort(betas)
    if np.any(np.diff(betas) <= 0):
        raise ValueError("the temperatures of parallel tempering must be distinct.")
    return betas


def tempering_mc(system, *, model: str, beta=None, T=None, J: float = 1.0, h: float = 0.0, sweeps: int = 10000,
                 thermalization: int | None = None, seed: int | None = None, update: str = "auto",
                 exchange_every: int = 1, measure_correlation=None, checkpoint=None, progress=None) -> TemperingResult:
    r"""Parallel tempering of the classical Ising, XY or Heisenberg model over a set of temperatures.

    Parameters
    ----------
    system : Lattice, Cluster or matrix
        As for :func:`~hyperlattice.spins.classical_mc`.
    model : {"ising", "xy", "heisenberg"}
        The spins.
    beta, T : sequence of float
        The inverse temperatures or the temperatures (exactly one; at least two, distinct, > 0;
        sorted internally, hottest first).
    J, h : float, optional
        Coupling scale (J < 0 antiferromagnetic) and field.
    sweeps : int, optional
        Measured sweeps per temperature (default 10000).
    thermalization : int, optional
        Thermalisation sweeps per temperature, exchanges included (default ``max(100, sweeps // 10)``).
    seed : int, optional
        Seed of the run (None draws one, stored in the result).
    update : {"auto", "wolff", "swendsen-wang", "local"}, optional
        The update of every chain between exchanges (as in :func:`~hyperlattice.spins.classical_mc`).
    exchange_every : int, optional
        Sweeps between exchange attempts (default 1).
    measure_correlation : bool, optional
        Measure the spin correlation by distance at every temperature (default: up to 3000 sites).
    checkpoint : str or path, optional
        A directory, locked for the run: every chain and the exchanges' state are saved there every
        minute, at the end and when interrupted (atomically, with a checksum); a rerun with the same
        arguments (``sweeps`` may grow) resumes bit-identically. A checkpoint of other parameters is
        refused.
    progress : bool, optional
        Progress bar on stderr (default: when a terminal watches).

    Returns
    -------
    TemperingResult

    Raises
    ------
    ValueError
        On bad input or an impossible update.
    MemoryError
        When the R chains will not fit (said before allocating).

    Examples
    --------
    >>> import numpy as np
    >>> from hyperlattice.spins import tempering_mc
    >>> tri = np.ones((3, 3)) - np.eye(3)          # a frustrated triangle
    >>> r = tempering_mc(tri, model="ising", J=-1.0, T=[1.0, 1.5, 2.0], sweeps=3000, seed=3, progress=False)
    >>> E = np.array([3.0, 3.0] + [-1.0] * 6)      # every state: 2 aligned, 6 with one bond satisfied
    >>> w = np.exp(-1.0 * E)                       # the coldest chain, T = 1
    >>> bool(abs(r.chains[-1].e - (w @ E) / w.sum() / 3) < 4 * r.chains[-1].e_err)
    True
    """
    name, _, J, h = _cl._inputs(model, 1.0, None, J, h)
    betas = _temperatures(beta, T)
    ncomp = _cl.MODELS[name]
    sweeps = _validate.integer("sweeps", sweeps, minimum=1)
    if thermalization is None:
        thermalization = max(100, sweeps // 10)
    thermalization = _validate.integer("thermalization", thermalization, minimum=0)
    exchange_every = _validate.integer("exchange_every", exchange_every, minimum=1)
    if seed is None:
        seed = int(np.random.SeedSequence().entropy % (2**63))
    seed = _validate.integer("seed", seed, minimum=0)
    if measure_correlation is not None:
        measure_correlation = _validate.flag("measure_correlation", measure_correlation)
    mdl = _cl._model(system, J)
    mode, label, _reason = _cl._choose(mdl, name, h, update)
    R = betas.size
    corr_on = measure_correlation is not False and mdl.sites <= _cl.CORRELATION_MAX
    K = _cl._load_kernels()
    one = _cl._memory_need(mdl.sites, mdl.indices.size, ncomp, corr_on)
    table = mdl.sites * mdl.sites * 48.0 if corr_on else 0.0          # the class table is shared
    _validate.require_memory(f"parallel tempering of {R} chains on {mdl.sites:,} sites (spins, couplings, per-site "
                             "bins" + (", the N x N distance classes" if corr_on else "") + " and 64 MiB for the "
                             "compiled kernels)", R * (one - table) + table + _cl._RUNTIME_BYTES)
    corr = _cl._corr_setup(mdl, measure_correlation, "all")
    group, ngroups = _cl._groups(mdl)
    kerns = [_cl._kern(mdl, mode, ncomp, h, float(b), corr, group) for b in betas]
    streams = np.random.SeedSequence(seed).generate_state(R + 1, dtype=np.uint64)
    seeds = [int(s) % (2**63) for s in streams[:R]]
    chains = [_cl._Chain(mdl, ncomp, s, corr.pairs.size, ngroups) for s in seeds]
    gen = np.random.default_rng(int(streams[R]))
    Jg, hs = kerns[0].Jg, kerns[0].hsite         # the gauged couplings and field (the same at every beta)

    def energy(spins):
        return float(K.energy(spins, mdl.indptr, mdl.indices, Jg, hs))

    state = _State(R)
    fp = _fingerprint(mdl, name, J, h, betas, mode, kerns[0].overrelax, seed, thermalization, exchange_every,
                      corr.every)
    ckdir = None if checkpoint is None else _validate.directory("checkpoint", checkpoint)
    total = thermalization + sweeps
    with contextlib.ExitStack() as stack:
        ckpt = None
        if ckdir is not None:
            stack.enter_context(_checkpoint.locked(ckdir, _LOCK_FILE))
            ckpt = ckdir / "spins_tempering.npz"
            if ckpt.exists():
                state.load(ckpt, fp, chains, gen)
                if chains[0].counters[1] > sweeps:
                    raise ValueError(f"the checkpoint already holds {int(chains[0].counters[1])} measured sweeps per "
                                     f"temperature, more than the {sweeps} asked for.")
        start = time.perf_counter()
        last_save = start
        try:
            with progress_bar(total, f"tempering {name}", unit="sweep", progress=progress) as bar:
                bar.update(state.done)
                while state.done < total:
                    therm = state.done < thermalization
                    n = min(exchange_every, (thermalization - state.done) if therm else (total - state.done))
                    for kern, ch in zip(kerns, chains):
                        kern.run(K, ch, mdl, n, therm)
                    state.done += n
                    bar.update(n)
                    state.exchange(chains, [energy(ch.spins) for ch in chains], betas, gen)
                    if ckpt is not None and time.perf_counter() - last_save > _cl._CHECKPOINT_SECONDS:
                        state.save(ckpt, fp, chains, gen)
                        last_save = time.perf_counter()
        except KeyboardInterrupt:
            if ckpt is not None:
                state.save(ckpt, fp, chains, gen)
            raise
        if ckpt is not None:
            state.save(ckpt, fp, chains, gen)
    accepted, attempts, trips = state.accepted, state.attempts, state.trips
    seconds = time.perf_counter() - start
    results = []
    for kern, ch, s in zip(kerns, chains, seeds):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", _cl.SpinWarning)
            results.append(_cl._analyse(ch, mdl, corr, name=name, ncomp=ncomp, J=J, h=h, beta=kern.beta,
                                        sweeps=sweeps, thermalization=thermalization, seed=s, update=label,
                                        reason=f"parallel tempering over {R} temperatures; between exchanges: "
                                        + _reason, seconds=seconds / R))
        for w in caught:        # said once, with the temperature it concerns
            warnings.warn(f"at T = {1.0 / kern.beta:.6g}: {w.message}", _cl.SpinWarning, stacklevel=3)
    with np.errstate(invalid="ignore", divide="ignore"):
        acc = np.where(attempts > 0, accepted / np.maximum(attempts, 1), np.nan)
    return TemperingResult(system=mdl.label, model=name, sites=mdl.sites, J=J, h=h, beta=betas, update=label,
                           sweeps=sweeps, thermalization=thermalization, exchange_every=exchange_every, seed=seed,
                           acceptance=acc, attempts=attempts, round_trips=int(trips), chains=tuple(results),
                           seconds=float(seconds))


_validate.guard_public(globals())
