import json
import os
import subprocess
import sys

import numpy as np
import pytest

os.environ.setdefault("MPLBACKEND", "Agg")


# ----------------------------------------------------------------------------------------------
# machine independence: the same answers with 1 and 2 BLAS threads, with numba's parallel
# loops on one thread. Different thread counts give different reduction orders and so different
# last bits; a test that passes with both asserts nothing that depends on them. The counts are
# set inside the run with threadpoolctl (and numba.set_num_threads), not by environment
# variables read at library load; subprocesses the tests start (the CLI) get the same counts
# through their environment (BLAS only). OPENBLAS_CORETYPE / OPENBLAS_L2_SIZE are never touched.
# ----------------------------------------------------------------------------------------------

def pytest_addoption(parser):
    group = parser.getgroup("hyperlattice")
    group.addoption("--blas-threads", type=int, default=None, metavar="N",
                    help="run the session with N BLAS threads (threadpoolctl); default: leave as loaded")
    group.addoption("--numba-serial", action="store_true", default=False,
                    help="run numba's parallel loops on one thread")
    group.addoption("--rounding-noise", type=int, default=None, metavar="SEED",
                    help="simulate another machine's rounding: every eigenvalue the eigensolvers return moves by "
                         "up to 8 ulps of the spectrum's norm and every eigenvector gets a random sign or phase, "
                         "deterministically per input and SEED (tests/rounding_noise.py; this process only)")
    group.addoption("--superlu-only", action="store_true", default=False,
                    help="hide CHOLMOD (HYPERLATTICE_FACTOR_BACKEND=superlu, inherited by CLI subprocesses): "
                         "every factorisation runs SciPy's SuperLU, the CHOLMOD-only tests skip")
    group.addoption("--run-heavy", action="store_true", default=False,
                    help="also run the tests marked heavy (docs examples of minutes or GBs: ell = 16/17 "
                         "flakes, 10^7-site clusters); deselected by default")


def pytest_configure(config):
    n = config.getoption("--blas-threads")
    if n is not None:
        if n < 1:
            raise pytest.UsageError("--blas-threads must be a positive integer.")
        from threadpoolctl import threadpool_limits

        # kept for the whole session (the object restores the old limits when collected, so hold it)
        config._hl_blas_limits = threadpool_limits(n, user_api="blas")
        for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
            os.environ[var] = str(n)
    if config.getoption("--rounding-noise") is not None:
        from rounding_noise import install

        config._hl_rounding_noise = install(config.getoption("--rounding-noise"))
    if config.getoption("--superlu-only"):
        # graph/factor reads the variable at every call: the fallback configuration of an install
        # without scikit-sparse, for this process and the CLI subprocesses the tests start
        os.environ["HYPERLATTICE_FACTOR_BACKEND"] = "superlu"
    if config.getoption("--numba-serial"):
        import numba

        # in this process only: numba re-reads NUMBA_NUM_THREADS at every compilation and refuses
        # a change once its threads run, so the environment of CLI subprocesses is left alone
        numba.set_num_threads(1)


#: test files that assert counts, labels, orderings or report text: the machine-independence pass
#: of .ci/run runs them again with one BLAS thread and numba's parallel loops serial (the main
#: run uses two BLAS threads). Listed here, in one place, rather than marked file by file.
MACHINE_INDEPENDENCE_FILES = frozenset({
    "test_ties.py",               # zero modes, thresholds, degenerate orderings
    "test_compare_levels.py",     # levels below 0, partition functions (the 146 vs 148 defect)
    "test_reproduce.py",          # the report's text and tables
    "test_spectrum.py",           # (n, m) labels of degenerate levels, dense/sparse/sector agreement
    "test_sectors.py",            # E0/E1 from sector blocks, inertia counts
    "test_symmetry.py",           # rotation sectors
    "test_continuum_spectrum.py",  # (n, m) labels and the K-lowest cut through +-m pairs
    "test_continuum_magnetic.py",  # level order under a field
    "test_flux.py",               # labels with flux
    "test_clusters.py",           # counts of sites, edges and levels of periodic clusters
    "test_bands.py",              # band structure = cover spectrum
    "test_cli_spectrum.py",       # the CLI's JSON labels
    "test_cli_spectrum_pair.py",
    "test_kpm.py",                # parallel kernel = serial kernel
})


def pytest_collection_modifyitems(config, items):
    mark = pytest.mark.machine_independence
    for item in items:
        if item.path.name in MACHINE_INDEPENDENCE_FILES:
            item.add_marker(mark)
    if not config.getoption("--run-heavy"):
        heavy = [item for item in items if item.get_closest_marker("heavy") is not None]
        if heavy:
            config.hook.pytest_deselected(items=heavy)
            items[:] = [item for item in items if item.get_closest_marker("heavy") is None]


def pytest_report_header(config):
    from threadpoolctl import threadpool_info

    blas = sorted({f"{i['internal_api']}:{i['num_threads']}" for i in threadpool_info() if i["user_api"] == "blas"})
    serial = " numba serial" if config.getoption("--numba-serial") else ""
    if config.getoption("--rounding-noise") is not None:
        serial += f"; simulated rounding noise, seed {config.getoption('--rounding-noise')}"
    from hyperlattice.graph.factor import resolve_backend

    return (f"hyperlattice: BLAS threads {', '.join(blas) or 'none found'}{serial}; "
            f"factorisation backend {resolve_backend('auto')}")

#: layers of hypertiling's {3,7} tilings compared with our {7,3} ring lattices
HYPERTILING_RINGS = (3, 5, 7)

_HYPERTILING_SCRIPT = r"""
import json, sys
import numpy as np
from hypertiling import HyperbolicTiling

out = {}
for rings in json.loads(sys.argv[2]):
    tiling = HyperbolicTiling(3, 7, rings, kernel="SRS", center="vertex")
    z = np.array([complex(tiling.get_center(i)) for i in range(len(tiling))])
    pairs = np.array([(i, j) for i, ns in enumerate(tiling.get_nbrs_list()) for j in ns], dtype=np.int64)
    out[f"z{rings}"], out[f"pairs{rings}"] = z, pairs.reshape(-1, 2)
np.savez(sys.argv[1], **out)
"""


@pytest.fixture(scope="session")
def hypertiling_73(tmp_path_factory):
    """hypertiling's {3,7} SRS tilings centred on a vertex: ``{rings: (centres, neighbour pairs)}``.

    Importing hypertiling compiles dozens of numba kernels eagerly (about 40 s on a cold
    numba cache, i.e. in every fresh CI environment), and that cost used to land inside the
    first comparison test. The tilings here are small (at most 5,887 cells), so they are
    computed once per session in a subprocess with numba's JIT switched off: the same
    hypertiling code, run as Python, in about 2 s, with or without a warm cache. A subprocess,
    because NUMBA_DISABLE_JIT must not reach our own numba kernels in this process.
    """
    path = tmp_path_factory.mktemp("hypertiling") / "tilings.npz"
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    res = subprocess.run([sys.executable, "-c", _HYPERTILING_SCRIPT, str(path), json.dumps(HYPERTILING_RINGS)],
                         env=env, capture_output=True, text=True, timeout=600)
    if res.returncode != 0:
        raise RuntimeError(f"hypertiling failed in the subprocess:\n{res.stderr}")
    with np.load(path) as f:
        return {r: (f[f"z{r}"], f[f"pairs{r}"]) for r in HYPERTILING_RINGS}
