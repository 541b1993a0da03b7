"""`hyperlattice reproduce` gives the same tables and report text with one and two BLAS threads.

Different thread counts change the reduction order inside BLAS and so the last bits of every
dense result; nothing the report prints or tabulates may depend on them. Both runs start from an
empty cache, so every number is computed under the thread count being tested.
"""

import pytest
from threadpoolctl import threadpool_limits

from hyperlattice.cache import Cache
from hyperlattice.report import reproduce


@pytest.mark.slow
def test_report_and_tables_identical_with_one_and_two_blas_threads(tmp_path):
    runs = {}
    for threads in (1, 2):
        with threadpool_limits(threads, user_api="blas"):
            reproduce(tmp_path / f"t{threads}", max_rings=4, cache=Cache(tmp_path / f"cache{threads}"))
        runs[threads] = tmp_path / f"t{threads}"
    names = sorted(p.name for p in runs[1].iterdir()
                   if p.suffix in (".csv", ".md") or (p.suffix == ".json" and p.name != "timings.json"))
    assert "report.md" in names and any(n.endswith(".csv") for n in names)
    assert names == sorted(p.name for p in runs[2].iterdir()
                           if p.suffix in (".csv", ".md") or (p.suffix == ".json" and p.name != "timings.json"))
    differ = [n for n in names if (runs[1] / n).read_bytes() != (runs[2] / n).read_bytes()]
    assert differ == [], f"these outputs depend on the BLAS thread count: {differ}"
