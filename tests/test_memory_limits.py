"""Big paths under an address-space limit (RLIMIT_AS): one sentence (API) or one line and exit 2 (CLI).

Each case runs in a subprocess that lowers its own RLIMIT_AS after the imports, so that the
limit is known relative to what the interpreter already maps. SuperLU is forced in the cases that
must be refused (CHOLMOD fits where SuperLU does not: SuperLU reserves its workspace up front).
"""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS and /proc are Linux")

SRC = str(Path(__file__).resolve().parents[1] / "src")

PRELUDE = textwrap.dedent("""
    import os, resource, sys
    import numpy, scipy.sparse.linalg
    import hyperlattice.graph.factor as F
    from hyperlattice.graph.sectors import lowest_pair
    from hyperlattice.cli import main
    if __SUPERLU__:
        F._cholmod = lambda: None
    mapped = int(open("/proc/self/statm").read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    limit = __LIMIT__ if __LIMIT__ > 0 else mapped + __EXTRA__
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
""")


def _run(body: str, *, limit: int = 0, extra: int = 0, superlu: bool = True, timeout: float = 300):
    code = (PRELUDE.replace("__SUPERLU__", str(superlu)).replace("__LIMIT__", str(limit))
            .replace("__EXTRA__", str(extra)))
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    return subprocess.run([sys.executable, "-c", code + textwrap.dedent(body)], capture_output=True, text=True,
                          timeout=timeout, env=env)


def test_api_refusal_is_one_sentence_with_needed_and_available():
    # l = 12: the sector build (~0.1 GB) fits in 250 MB more address space, SuperLU's workspace for
    # the 103,680-row m = 1 block (~0.37 GB reserved) does not: refused before its numeric work
    proc = _run("""
        try:
            lowest_pair(7, 3, 12)
        except MemoryError as exc:
            print(type(exc).__name__, isinstance(exc, F.HyperlatticeError), repr(str(exc)))
            sys.exit(0)
        print("no refusal")
        sys.exit(1)
    """, extra=250 * 1024**2)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = proc.stdout.strip()
    assert out.startswith("FactorMemoryError True"), out
    assert "needs about" in out and "more than the" in out and "address" in out
    assert "SUPERLU" not in out and "\\n" not in out


def test_cli_refusal_is_one_line_and_exit_2():
    proc = _run("""
        sys.exit(main(["spectrum", "--rings", "12", "--method", "pair", "--json"]))
    """, extra=250 * 1024**2)
    assert proc.returncode == 2, proc.stderr
    err = proc.stderr.strip().splitlines()
    assert len(err) == 1 and "needs about" in err[0], proc.stderr
    assert "internal error" not in proc.stderr and "Traceback" not in proc.stderr and proc.stdout == ""


def test_a_backend_allocation_failure_becomes_the_sentence(monkeypatch):
    # what SuperLU raises when its malloc fails: a RuntimeError the user must never see raw
    import scipy.sparse.linalg as spla

    from hyperlattice.graph import factor as F
    from hyperlattice.graph.lattice import ring_lattice
    from hyperlattice.graph.operators import hamiltonian

    def failing(*args, **kwargs):
        raise RuntimeError("SUPERLU_MALLOC fails for buf in intSpace()")

    monkeypatch.setattr(spla, "splu", failing)
    with pytest.raises(F.FactorMemoryError, match="ran out of memory") as info:
        F.factorize(hamiltonian(ring_lattice(7, 3, 3)), -3.5, backend="superlu")
    assert "SUPERLU" not in str(info.value)


@pytest.mark.slow
@pytest.mark.parametrize("rings", [15, 16])
def test_big_flakes_under_six_gigabytes_never_end_in_a_raw_error(rings):
    # issue 19/20: l = 15 and 16 under a 6 GB address-space limit ended in "internal error
    # (RuntimeError: SUPERLU_MALLOC fails ...)", exit 1. With SuperLU they are now refused before
    # the numeric work of the block that does not fit: one line, exit 2.
    proc = _run(f"""
        sys.exit(main(["spectrum", "--rings", "{rings}", "--method", "pair", "--json"]))
    """, limit=6 * 1024**3, timeout=600)
    assert proc.returncode == 2, proc.stdout + proc.stderr
    err = proc.stderr.strip().splitlines()
    assert len(err) == 1 and "needs about" in err[0] and "SUPERLU" not in err[0], proc.stderr
