"""Checkpoints of the XXZ SSE chain (spins.quantum.xxz_qmc): a stored chain is checked before it is
resumed (checksum, then the operator string, the spin state, the world lines, the counters and the
bins), the directory is locked for the run, and a signal stops the chain cleanly with its state saved.

Each tampered file is written with a recomputed checksum (the checksum alone would catch an
accidental edit): the refusal must come from the consistency checks, in one sentence.
"""

from __future__ import annotations

import signal

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice import _mc_chain
from hyperlattice.spins import quantum
from hyperlattice.spins.quantum import xxz_qmc

# short chains: these tests are about the stored state, not about converged averages
pytestmark = pytest.mark.filterwarnings("ignore::hyperlattice.spins.quantum.XXZWarning")

RING8 = hl.ring_lattice(8, 3, 1)
KW = dict(J=1.0, Delta=1.0, beta=2.0, thermalization=100, seed=3, progress=False)


@pytest.fixture(scope="module")
def stored(tmp_path_factory):
    """A chain of 300 measured sweeps saved in a directory: (meta, arrays)."""
    where = tmp_path_factory.mktemp("xxz")
    xxz_qmc(RING8, sweeps=300, checkpoint=where, **KW)
    return _mc_chain.read(where / "xxz_chain.npz")


def _first(ops, which):
    return int(np.flatnonzero(which(ops))[0])


def _flip_spin(a):
    a["state"][0] ^= 1


def _spin_two(a):
    a["state"][1] = 2


def _bond_out_of_range(a):
    a["ops"][_first(a["ops"], lambda o: o >= 0)] = 4 * 999


def _kind_three(a):
    a["ops"][_first(a["ops"], lambda o: o >= 0)] |= 3


def _hop_made_diagonal(a):
    i = _first(a["ops"], lambda o: (o >= 0) & ((o & 3) != 0))
    a["ops"][i] &= ~3


def _hop_reversed(a):
    i = _first(a["ops"], lambda o: (o >= 0) & ((o & 3) != 0))
    a["ops"][i] ^= 3                     # kind 1 <-> kind 2: the world line runs the other way


def _operator_count(a):
    a["counters"][0] += 1


def _bins_counter(a):
    a["sinfo"][2] += 1


def _negative_string_length_bin(a):
    a["sbins"][0, 0] = -5.0


def _nan_bin(a):
    a["vbins"][0, 0] = np.nan


def _zero_generator(a):
    a["rng"][:] = 0


def _ops_matrix(a):
    a["ops"] = a["ops"].reshape(-1, 2)


TAMPER = [_flip_spin, _spin_two, _bond_out_of_range, _kind_three, _hop_made_diagonal, _hop_reversed,
          _operator_count, _bins_counter, _negative_string_length_bin, _nan_bin, _zero_generator, _ops_matrix]


@pytest.mark.parametrize("tamper", TAMPER, ids=[f.__name__.strip("_") for f in TAMPER])
def test_a_tampered_chain_is_refused_in_one_sentence(tmp_path, stored, tamper):
    meta, arrays = stored
    a = {k: v.copy() for k, v in arrays.items()}
    tamper(a)
    _mc_chain.write(tmp_path / "xxz_chain.npz", {k: v for k, v in meta.items() if k != "format"}, a)
    with pytest.raises(ValueError) as info:
        xxz_qmc(RING8, sweeps=600, checkpoint=tmp_path, **KW)
    msg = str(info.value)
    assert "checkpoint" in msg and ("inconsistent" in msg or "damaged" in msg), msg
    assert msg.count(". ") == 0 and "\n" not in msg


def test_an_untouched_chain_passes_and_an_edit_breaks_the_checksum(tmp_path, stored):
    meta, arrays = stored
    _mc_chain.write(tmp_path / "xxz_chain.npz", {k: v for k, v in meta.items() if k != "format"}, arrays)
    r = xxz_qmc(RING8, sweeps=600, checkpoint=tmp_path, **KW)
    assert r.sweeps == 600
    raw = bytearray((tmp_path / "xxz_chain.npz").read_bytes())
    raw[len(raw) // 2] ^= 0xFF
    (tmp_path / "xxz_chain.npz").write_bytes(bytes(raw))
    with pytest.raises(ValueError, match="checkpoint"):
        xxz_qmc(RING8, sweeps=900, checkpoint=tmp_path, **KW)


def test_the_directory_is_locked_for_the_run(tmp_path):
    with _mc_chain.locked(tmp_path, quantum._LOCK_FILE):
        with pytest.raises(ValueError, match="in use by another run"):
            xxz_qmc(RING8, sweeps=100, checkpoint=tmp_path, **KW)
    assert xxz_qmc(RING8, sweeps=100, checkpoint=tmp_path, **KW).sweeps == 100


def test_a_signal_saves_the_chain_and_the_rerun_resumes_it(tmp_path, monkeypatch):
    real = quantum._run_chain

    def interrupted(chain, model, fp, ckdir, stop, QK, a):
        stop.signum = signal.SIGINT              # as if Ctrl-C arrived during the first kernel call
        return real(chain, model, fp, ckdir, stop, QK, a)

    monkeypatch.setattr(quantum, "_run_chain", interrupted)
    with pytest.raises(KeyboardInterrupt, match="saved"):
        xxz_qmc(RING8, sweeps=400, checkpoint=tmp_path, **KW)
    monkeypatch.setattr(quantum, "_run_chain", real)
    assert (tmp_path / "xxz_chain.npz").exists()
    resumed = xxz_qmc(RING8, sweeps=400, checkpoint=tmp_path, **KW)
    whole = xxz_qmc(RING8, sweeps=400, **KW)
    assert resumed.e == whole.e and resumed.s_pi == whole.s_pi


def test_cli_refuses_a_tampered_checkpoint_in_one_line(tmp_path, stored, capsys):
    from hyperlattice.cli import main

    meta, arrays = stored
    a = {k: v.copy() for k, v in arrays.items()}
    _flip_spin(a)
    _mc_chain.write(tmp_path / "xxz_chain.npz", {k: v for k, v in meta.items() if k != "format"}, a)
    code = main(["spins", "quantum", "--rings", "1", "-p", "8", "-q", "3", "--J", "1", "--beta", "2", "--sweeps",
                 "600", "--thermalization", "100", "--seed", "3", "--checkpoint", str(tmp_path)])
    err = capsys.readouterr().err
    lines = [x for x in err.splitlines() if x.strip()]
    assert code == 2 and len(lines) == 1 and "inconsistent" in lines[0], err


# ----------------------------------------------------------------------------
# the Heisenberg antiferromagnet on {8,3}: what the physics table is built from
# ----------------------------------------------------------------------------

def test_ring_staggered_correlations_add_up_to_the_structure_factor():
    # sum_i mu_i = <M_s^2> / N slice by slice, so the ring means weighted by the ring sizes give
    # s_pi / N to rounding when the scalar and the site bins cover the same sweeps (2048 = 32 x 64)
    lat = hl.ring_lattice(8, 3, 2)
    r = xxz_qmc(lat, J=1.0, Delta=1.0, beta=2.0, sweeps=2048, thermalization=200, seed=5, progress=False)
    sizes = np.array([np.sum(r.ring == k + 1) for k in range(r.ring_stag.size)])
    assert r.ring_stag.size == 2 and sizes.sum() == r.sites == 48
    assert abs(float(sizes @ r.ring_stag) / r.sites - r.s_pi / r.sites) < 1e-9 * r.s_pi
    assert np.all(r.ring_stag > 0)


def _heisenberg_ground_energy(system) -> float:
    """Lowest eigenvalue of the S = 1/2 Heisenberg model (J = 1) in the S^z = 0 block (Lanczos)."""
    import itertools

    import scipy.sparse as sp
    from scipy.sparse.linalg import eigsh

    a = sp.triu(sp.csr_matrix(system.adjacency()), k=1).tocoo()
    n = system.adjacency().shape[0]
    states = np.array([sum(1 << i for i in c) for c in itertools.combinations(range(n), n // 2)], dtype=np.int64)
    states.sort()
    rows, cols, vals = [], [], []
    diag = np.zeros(states.size)
    for i, j in zip(a.row, a.col):
        si, sj = (states >> i) & 1, (states >> j) & 1
        diag += np.where(si == sj, 0.25, -0.25)
        flip = np.flatnonzero(si != sj)
        rows.append(np.searchsorted(states, states[flip] ^ ((1 << i) | (1 << j))))
        cols.append(flip)
        vals.append(np.full(flip.size, 0.5))
    h = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(states.size, states.size)) + sp.diags(diag)
    return float(eigsh(h, k=1, which="SA", tol=1e-12)[0][0])


@pytest.mark.slow
def test_bolza_ground_state_energy_at_large_beta():
    from hyperlattice.graph.clusters import pbc_cluster

    bolza = pbc_cluster(8, 3, "bolza")
    e0 = _heisenberg_ground_energy(bolza) / 16
    assert abs(e0 - (-0.564593)) < 1e-6
    r = xxz_qmc(bolza, J=1.0, Delta=1.0, beta=48.0, sweeps=20000, thermalization=2000, seed=2, progress=False)
    assert abs(r.e - e0) < 4 * r.e_err, (r.e, r.e_err, e0)
