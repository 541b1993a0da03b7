"""A QMC under an address-space limit (``ulimit -v``, RLIMIT_AS): refused in one sentence before
it allocates when its memory estimate does not fit, and run to the end when it fits (issue 27,
item 3: "refuse sizes that will not fit, in one sentence").

Each case runs in a fresh interpreter whose RLIMIT_AS is set in ``preexec_fn``: the limit is
the probe's address space once numba is loaded (what :func:`hyperlattice.bosons.qmc` sees at its
check) plus a multiple of the estimate ``qmc_memory + _RUNTIME_BYTES``. Without the kernels
loaded before the check, the process died under such a limit with llvmlite's "Could not
find/load shared object file" or OpenBLAS's "Memory allocation still failed" instead.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

resource = pytest.importorskip("resource")

pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs /proc (Linux)")]

SRC = str(Path(__file__).resolve().parents[1] / "src")

#: loads the kernels, prints its address space and the estimate, then (sweeps > 0) runs the chain
DRIVER = r"""
import json, sys, warnings
import hyperlattice as hl
from hyperlattice import _validate
from hyperlattice.bosons import qmc, qmc_memory, sse

sse._load_kernels()
rings, beta, sweeps = int(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3])
lat = hl.ring_lattice(7, 3, rings)
need = qmc_memory(lat, U=6.0, mu=3.0, beta=beta, nmax=3) + sse._RUNTIME_BYTES
print(json.dumps({"vmsize": _validate._proc_status_bytes("VmSize"), "need": need}), flush=True)
if sweeps:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = qmc(lat, U=6.0, mu=3.0, beta=beta, nmax=3, sweeps=sweeps, thermalization=100, seed=1, progress=False)
    print(json.dumps({"energy": r.energy, "energy_err": r.energy_err}), flush=True)
"""


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = SRC + os.pathsep + env.get("PYTHONPATH", "")
    # one BLAS thread and few malloc arenas: the address space of the probe and of the limited run agree
    env.update(OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1", MALLOC_ARENA_MAX="2")
    return env


def _run(argv: list[str], limit: int | None) -> subprocess.CompletedProcess:
    def cap():
        if limit is not None:
            resource.setrlimit(resource.RLIMIT_AS, (limit, resource.getrlimit(resource.RLIMIT_AS)[1]))

    return subprocess.run([sys.executable, *argv], capture_output=True, text=True, env=_env(), preexec_fn=cap,
                          timeout=600)


def _probe(rings: int, beta: float) -> dict:
    res = _run(["-c", DRIVER, str(rings), str(beta), "0"], None)
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout.splitlines()[0])


@pytest.fixture(scope="module", autouse=True)
def _unlimited():
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    if hard != resource.RLIM_INFINITY and hard < 4 * 2**30:
        pytest.skip("the hard address-space limit is already below 4 GiB")


def test_a_run_whose_estimate_does_not_fit_is_refused_in_one_sentence():
    # l = 3 at beta = 20000: an estimate of about 3.3 GB; the limit leaves 150 MB once numba is in
    probe = _probe(3, 20000.0)
    assert probe["need"] > 10**9
    limit = probe["vmsize"] + 150 * 2**20
    cli = _run(["-m", "hyperlattice", "bosons", "qmc", "--rings", "3", "--nmax", "3", "--U", "6", "--mu", "3",
                "--beta", "20000", "--sweeps", "100", "--seed", "1", "--json"], limit)
    err = cli.stderr.strip()
    assert cli.returncode == 2, err
    assert cli.stdout == ""
    assert "\n" not in err and "Traceback" not in err, err
    assert "the SSE chain" in err and "may still allocate" in err, err
    for backend in ("numba", "llvmlite", "OpenBLAS", "MemoryError"):
        assert backend not in err, err
    # the API says the same sentence as a MemoryError, before allocating: the driver's process
    api = _run(["-c", DRIVER, "3", "20000", "100"], limit)
    assert api.returncode == 1 and "MemoryError: the SSE chain" in api.stderr
    assert "may still allocate" in api.stderr.strip().splitlines()[-1]


@pytest.mark.parametrize("rings, beta", [(3, 8.0), (5, 1.0)])     # l = 5: 847 sites, the full G measured
def test_just_under_the_limit_runs_and_just_over_is_refused(rings, beta):
    probe = _probe(rings, beta)
    room = probe["need"]
    # the estimate is 80 % of what the limit leaves: the chain runs to the end
    fits = _run(["-c", DRIVER, str(rings), str(beta), "200"], probe["vmsize"] + int(1.25 * room))
    assert fits.returncode == 0, fits.stderr
    out = json.loads(fits.stdout.splitlines()[-1])
    assert out["energy_err"] > 0
    # the estimate is 125 % of it: refused with the sentence, nothing run
    over = _run(["-c", DRIVER, str(rings), str(beta), "200"], probe["vmsize"] + int(0.8 * room))
    assert over.returncode == 1
    last = over.stderr.strip().splitlines()[-1]
    assert last.startswith("MemoryError: the SSE chain") and "may still allocate" in last, over.stderr
    assert len(over.stdout.splitlines()) == 1          # the probe line only: no result
