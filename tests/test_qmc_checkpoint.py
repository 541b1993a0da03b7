"""QMC runs that survive: checkpoints that cannot hurt, resume as documented, clean stops on
SIGINT/SIGTERM, and defaults that run. The cases quoted are those a fuzz of version 0.5.0 found."""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

import hyperlattice as hl
from hyperlattice.bosons import QMCWarning, merge_chains, qmc, qmc_seconds
from hyperlattice.bosons import _checkpoint, sse
from hyperlattice.cli import main

# short chains: what is tested is the plumbing, not the physics (the QMCWarning of a short chain)
pytestmark = pytest.mark.filterwarnings("ignore::hyperlattice.bosons.sse.QMCWarning")

HEPTAGON = hl.ring_lattice(7, 3, 1)
KW = dict(U=4.0, mu=1.0, beta=1.0, nmax=2, progress=False)
CLI = ["bosons", "qmc", "--rings", "1", "-p", "7", "-q", "3", "--nmax", "2", "--U", "4", "--mu", "1", "--beta", "1"]


def _ring(n: int, weights=None) -> sp.csr_matrix:
    w = np.ones(n) if weights is None else np.asarray(weights, dtype=float)
    i = np.arange(n)
    a = sp.coo_matrix((w, (i, (i + 1) % n)), shape=(n, n))
    return (a + a.T).tocsr()


def _same(a, b) -> bool:
    da, db = a.as_dict(), b.as_dict()
    da.pop("seconds"), db.pop("seconds")
    return json.dumps(da, sort_keys=True, default=str) == json.dumps(db, sort_keys=True, default=str)


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """A finished 300-sweep chain's checkpoint (read back as arrays) and its result."""
    where = tmp_path_factory.mktemp("ck")
    r = qmc(HEPTAGON, sweeps=300, thermalization=100, seed=4, checkpoint=where, **KW)
    meta, arrays = _checkpoint.read(where / "qmc_chain.npz")
    return where, meta, arrays, r


def _write(where: Path, meta: dict, arrays: dict, *, checksum: bool) -> Path:
    """The checkpoint with edited arrays: its checksum recomputed (a careful forger) or kept stale."""
    path = where / "qmc_chain.npz"
    if checksum:
        _checkpoint.write(path, meta, arrays)
    else:
        text = json.dumps({**meta, "format": _checkpoint.FORMAT}, sort_keys=True)
        np.savez(path, __meta__=np.array(text), __sha256__=np.array("0" * 64), **arrays)
    return path


def _cli(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


# ----------------------------------------------------------------------------
# checkpoints that cannot hurt
# ----------------------------------------------------------------------------

def test_truncated_checkpoint_is_one_sentence_exit_2(saved, tmp_path, capsys):
    # fuzz of 0.5.0: "a truncated checkpoint gives internal error (BadZipFile)"
    where = saved[0]
    data = (where / "qmc_chain.npz").read_bytes()
    (tmp_path / "qmc_chain.npz").write_bytes(data[: len(data) // 2])
    code, out, err = _cli([*CLI, "--sweeps", "300", "--thermalization", "100", "--seed", "4",
                           "--checkpoint", str(tmp_path)], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "damaged or truncated" in err and "internal error" not in err


@pytest.mark.parametrize("field, edit", [
    ("state", lambda a: a.__setitem__(0, 40)),                        # fuzz: a segfault
    ("sinfo", lambda a: a.__setitem__(0, 5000)),                      # fuzz: a heap abort
    ("sbins", lambda a: a.__setitem__((slice(None), 3), 0.0)),        # fuzz: kappa = -9.6 with exit 0
])
def test_edited_fields_fail_the_checksum(saved, tmp_path, field, edit, capsys):
    # fuzz of 0.5.0: "editing the chain's state, sinfo or sbins gives a segfault, a heap abort, or
    # kappa = -9.6 with exit 0 (those fields are not under the checksum)"
    _, meta, arrays, _ = saved
    arrays = {k: v.copy() for k, v in arrays.items()}
    edit(arrays[field])
    _write(tmp_path, meta, arrays, checksum=False)
    code, out, err = _cli([*CLI, "--sweeps", "300", "--thermalization", "100", "--seed", "4",
                           "--checkpoint", str(tmp_path)], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1 and "checksum" in err


def _bad_ops(a):
    a["ops"][np.flatnonzero(a["ops"] >= 0)[0]] = 4 * 10_000        # a bond that does not exist


def _offdiag_flip(a):
    k = np.flatnonzero((a["ops"] >= 0) & (a["ops"] & 3 != 0))
    a["ops"][k[0]] ^= 3                                             # 1 <-> 2: world lines broken


@pytest.mark.parametrize("edit, needle", [
    (lambda a: a["state"].__setitem__(0, 40), "occupation"),
    (lambda a: a["state"].__setitem__(0, -1), "occupation"),
    (_bad_ops, "operator"),
    (_offdiag_flip, "world lines"),
    (lambda a: a["sinfo"].__setitem__(0, 5000), "bin counters"),
    (lambda a: a["sinfo"].__setitem__(2, 1), "bin counters"),
    (lambda a: a["sbins"].__setitem__((slice(None), 3), 0.0), "scalar bins"),
    (lambda a: a["counters"].__setitem__(1, 10**9), "counters"),
    (lambda a: a["rng"].__setitem__(slice(None), 0), "generator"),
    (lambda a: a["loopstat"].__setitem__(0, np.nan), "non-finite"),
    (lambda a: a.__setitem__("ops", a["ops"][:8]), "string"),
    (lambda a: a.__setitem__("vbins", a["vbins"][:3]), "vbins"),
])
def test_edited_but_checksummed_arrays_never_reach_a_kernel(saved, tmp_path, edit, needle):
    # a forger who recomputes the checksum still cannot crash a kernel: shapes, ranges and the
    # world-line picture are checked before any array is used
    _, meta, arrays, _ = saved
    arrays = {k: v.copy() for k, v in arrays.items()}
    edit(arrays)
    _write(tmp_path, meta, arrays, checksum=True)
    with pytest.raises(ValueError, match=needle) as exc:
        qmc(HEPTAGON, sweeps=300, thermalization=100, seed=4, checkpoint=tmp_path, **KW)
    assert "\n" not in str(exc.value) and "inconsistent" in str(exc.value)


def test_a_checkpoint_that_is_intact_resumes_to_the_same_result(saved):
    where, _, _, first = saved
    again = qmc(HEPTAGON, sweeps=300, thermalization=100, seed=4, checkpoint=where, **KW)
    assert _same(first, again)


def test_another_run_into_the_same_directory_is_refused(tmp_path, capsys):
    # fuzz of 0.5.0: "two runs with different parameters into one --checkpoint directory both exit 0
    # and the second silently overwrites the first"
    args = ["--sweeps", "200", "--thermalization", "50", "--seed", "1", "--checkpoint", str(tmp_path)]
    assert _cli([*CLI, *args], capsys)[0] == 0
    before = (tmp_path / "qmc_chain.npz").read_bytes()
    other = [w if w != "4" else "5" for w in CLI]                    # --U 5
    code, out, err = _cli([*other, *args], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "other parameters" in err and "U = 4.0 there, 5.0 here" in err
    assert (tmp_path / "qmc_chain.npz").read_bytes() == before


def test_a_directory_in_use_is_refused(tmp_path):
    from filelock import FileLock

    with FileLock(str(tmp_path / ".qmc_chain.lock")):
        with pytest.raises(ValueError, match="in use by another run"):
            qmc(HEPTAGON, sweeps=50, thermalization=20, seed=1, checkpoint=tmp_path, **KW)
    assert not (tmp_path / "qmc_chain.npz").exists()


def test_atomic_write_leaves_no_temporary_file(saved):
    where = saved[0]
    assert sorted(p.name for p in where.iterdir()) == [".qmc_chain.lock", "qmc_chain.npz"]


# ----------------------------------------------------------------------------
# resume as documented
# ----------------------------------------------------------------------------

def test_rerun_with_more_sweeps_resumes_with_the_default_thermalisation(tmp_path, capsys):
    # fuzz of 0.5.0: "'rerun with more --sweeps' is refused as 'other parameters' because the default
    # thermalisation (sweeps/5) enters the fingerprint"
    ck = ["--seed", "8", "--checkpoint", str(tmp_path), "--json", "--no-windings"]
    code, out, _ = _cli([*CLI, "--sweeps", "300", *ck], capsys)
    assert code == 0 and json.loads(out)["thermalization"] == 200
    code, out, err = _cli([*CLI, "--sweeps", "600", *ck], capsys)
    assert code == 0, err
    resumed = json.loads(out)
    straight = qmc(HEPTAGON, sweeps=600, thermalization=200, seed=8, **KW)
    assert resumed["sweeps"] == 600 and resumed["thermalization"] == 200
    assert resumed["energy"] == straight.energy and resumed["energy_err"] == straight.energy_err
    # an explicit thermalisation other than the one done is refused in one sentence
    code, _, err = _cli([*CLI, "--sweeps", "900", "--thermalization", "500", *ck], capsys)
    assert code == 2 and "thermalised for 200 sweeps" in err and err.count("\n") == 1


def test_a_run_without_seed_resumes(tmp_path):
    # fuzz of 0.5.0: "without --seed a run can never resume"
    first = qmc(HEPTAGON, sweeps=200, thermalization=50, checkpoint=tmp_path, **KW)
    again = qmc(HEPTAGON, sweeps=400, thermalization=50, checkpoint=tmp_path, **KW)
    straight = qmc(HEPTAGON, sweeps=400, thermalization=50, seed=first.seed, **KW)
    assert again.seed == first.seed and _same(again, straight)


def test_thermalization_zero_is_refused_unless_resuming(tmp_path, capsys):
    # fuzz of 0.5.0: "--thermalization 0 returns E = -3.95 +- 0.20 against the exact -12.717 with exit 0"
    code, out, err = _cli([*CLI, "--sweeps", "100", "--thermalization", "0"], capsys)
    assert code == 2 and out == "" and "thermalization 0" in err and err.count("\n") == 1
    first = qmc(HEPTAGON, sweeps=200, thermalization=50, seed=2, checkpoint=tmp_path, **KW)
    more = qmc(HEPTAGON, sweeps=400, thermalization=0, seed=2, checkpoint=tmp_path, **KW)
    assert first.thermalization == more.thermalization == 50 and more.sweeps == 400


# ----------------------------------------------------------------------------
# defaults that run
# ----------------------------------------------------------------------------

def test_merge_chains_refuses_equal_bonds_with_other_couplings():
    # fuzz of 0.5.0: "merge_chains accepts chains of graphs with equal bonds and different weights"
    kw = dict(U=2.0, mu=0.7, beta=1.0, nmax=1, sweeps=300, thermalization=50, progress=False)
    with pytest.warns(QMCWarning):
        a = qmc(_ring(5), seed=1, **kw)
        b = qmc(_ring(5, [1, 1, 1, 1, 2]), seed=2, **kw)
    with pytest.raises(ValueError, match="couplings t_ij differ"):
        merge_chains([a, b])
    back = type(a).from_dict(a.as_dict())
    assert np.array_equal(back.bond_hopping, a.bond_hopping)


def test_self_loop_in_adjacency_is_refused(tmp_path, capsys):
    # fuzz of 0.5.0: "a self-loop in --adjacency is dropped silently"
    a = _ring(5).tolil()
    a[1, 1] = 1.0
    sp.save_npz(tmp_path / "loop.npz", a.tocsr())
    code, out, err = _cli(["bosons", "qmc", "--adjacency", str(tmp_path / "loop.npz"), "--nmax", "1", "--U", "0",
                           "--mu", "0", "--beta", "1", "--sweeps", "100"], capsys)
    assert code == 2 and out == "" and "self-loop" in err and err.count("\n") == 1


def test_winding_components_beyond_64_are_skipped_with_one_warning():
    # fuzz of 0.5.0: "--cluster 'PSL(2,17)' -p 8 -q 3 (816 sites) stops with 'at most 64 winding
    # components are measured, got 104'": an optional observable must not fail a default run.
    # The same path on a 6-ring with 104 (arbitrary integer) winding components:
    a = _ring(6)
    edges = np.array([[i, (i + 1) % 6] for i in range(6)])
    w = np.random.default_rng(0).integers(-1, 2, size=(6, 104))
    with pytest.warns(QMCWarning, match="first 64 of the 104 winding components") as rec:
        r = qmc(a, U=0.0, mu=0.2, beta=0.5, nmax=1, sweeps=200, thermalization=20, seed=1, windings=(edges, w),
                progress=False, measure_green=False)
    assert sum("winding components" in str(x.message) for x in rec) == 1
    assert r.stiffness.shape == (64, 64) and "components 65-104 skipped" in r.stiffness_note


@pytest.mark.slow
def test_the_816_site_psl_2_17_cluster_runs_by_default(capsys):
    # the fuzz case itself (about 10 CPU s: the cluster's construction and 104 windings)
    code, out, err = _cli(["bosons", "qmc", "--cluster", "PSL(2,17)", "-p", "8", "-q", "3", "--nmax", "1", "--U", "0",
                           "--mu", "0", "--beta", "0.5", "--sweeps", "20", "--thermalization", "10", "--seed", "1",
                           "--json"], capsys)
    assert code == 0, err
    res = json.loads(out)
    assert res["sites"] == 816 and len(res["stiffness"]) == 64 and "components 65-104 skipped" in res["stiffness_note"]
    assert sum("winding components" in line for line in err.splitlines()) == 1


def test_long_runs_are_estimated_and_refused_up_front(capsys):
    # fuzz of 0.5.0: "--beta 1e4 / 1e6 run for minutes with no estimate"
    code, out, err = _cli([*CLI[:-2], "--beta", "1e6"], capsys)
    assert code == 2 and out == "" and "days" in err and "--max-seconds" in err and err.count("\n") == 1
    code, out, err = _cli([*CLI[:-2], "--beta", "1e4", "--sweeps", "100", "--max-seconds", "10"], capsys)
    assert code == 2 and "more than --max-seconds 10" in err
    small = qmc_seconds(HEPTAGON, U=4.0, mu=1.0, beta=1.0, nmax=2, sweeps=1000)
    assert small < qmc_seconds(HEPTAGON, U=4.0, mu=1.0, beta=2.0, nmax=2, sweeps=1000) < 1.0
    # --nmax 1000: the string alone is refused (memory) or the time estimate is (a day by default)
    code, _, err = _cli([*CLI[:8], "--nmax", "1000", *CLI[10:]], capsys)
    assert code == 2 and ("--max-seconds" in err or "allocate" in err)


def test_int32_loop_arrays_are_guarded_before_allocating():
    with pytest.raises(ValueError, match="32-bit"):
        sse._check_int32(1e9, 1e6)
    sse._check_int32(1e7, 10.0)


# ----------------------------------------------------------------------------
# signals: a clean stop between kernel calls, the rerun resumes (subprocesses: slow tier)
# ----------------------------------------------------------------------------

def _stop_and_resume(tmp_path, sig, code_wanted):
    env = {**os.environ, "PYTHONPATH": str(Path(hl.__file__).parents[1])}
    argv = [sys.executable, "-m", "hyperlattice", *CLI[:-2], "--beta", "8", "--sweeps", "40000",
            "--thermalization", "1000", "--seed", "21", "--no-progress", "--json", "--checkpoint", str(tmp_path)]
    # a background job of a non-interactive shell starts with SIGINT ignored (and the chain then
    # rightly leaves it ignored): the child gets the default disposition back
    proc = subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 120
    while not (tmp_path / "qmc_chain.npz").exists() and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.02)
    time.sleep(0.3)
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=120)
    # fuzz of 0.5.0: "SIGINT or SIGTERM during a run gives internal error (SystemError: CPUDispatcher ...)"
    assert proc.returncode == code_wanted, err
    assert out == "" and err.count("\n") == 1 and "interrupted: stopped after" in err and "saved" in err
    assert "SystemError" not in err and "internal error" not in err
    done = subprocess.run(argv, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    resumed = json.loads(done.stdout)
    straight = qmc(HEPTAGON, U=4.0, mu=1.0, beta=8.0, nmax=2, sweeps=40000, thermalization=1000, seed=21,
                   progress=False)
    assert resumed["energy"] == straight.energy and resumed["density"] == straight.density
    assert resumed["energy_err"] == straight.energy_err


@pytest.mark.slow
def test_sigterm_stops_cleanly_and_the_rerun_resumes(tmp_path):
    _stop_and_resume(tmp_path, signal.SIGTERM, 143)


@pytest.mark.slow
def test_sigint_stops_cleanly_and_the_rerun_resumes(tmp_path):
    _stop_and_resume(tmp_path, signal.SIGINT, 130)


def test_a_signal_in_the_api_saves_and_raises_keyboard_interrupt(tmp_path, monkeypatch):
    # the stop is checked between kernel calls: simulate a signal recorded during the first chunk
    real = sse._Chain.advance

    def advance(self, *a, **k):
        real(self, *a, **k)
        signal.raise_signal(signal.SIGINT)

    monkeypatch.setattr(sse._Chain, "advance", advance)
    # Python's own Ctrl-C handler (a pytest-xdist worker may start with SIGINT ignored)
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt, match="stopped after 1 of 150 sweeps; the chain is saved"):
            qmc(HEPTAGON, sweeps=100, thermalization=50, seed=6, checkpoint=tmp_path, **KW)
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, before)
    monkeypatch.setattr(sse._Chain, "advance", real)
    resumed = qmc(HEPTAGON, sweeps=100, thermalization=50, seed=6, checkpoint=tmp_path, **KW)
    assert _same(resumed, qmc(HEPTAGON, sweeps=100, thermalization=50, seed=6, **KW))
