import json
import os
import subprocess
import sys

import numpy as np
import pytest

# Keep BLAS single-threaded in tests: the machine has 2 cores and pytest may share them.
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MPLBACKEND", "Agg")

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
