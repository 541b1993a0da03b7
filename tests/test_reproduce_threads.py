"""`hyperlattice reproduce` gives the same report with one and two BLAS threads.

Different thread counts change the reduction order inside BLAS and so the last bits of every
dense result; nothing the report prints or tabulates may depend on them (issue 28 item 3: the
band-bottom fit table printed 12 decimals of a least-squares fit, which moved in the 12th digit).
Both runs start from an empty cache, so every number is computed under the thread count being
tested. Compared: every table (CSV, JSON), ``report.md`` and the whole text of ``report.html``
(the embedded PNG figures are left out: their pixels are drawn from the same numbers, and a
one-pixel antialiasing difference is not a printed digit). The report is built with
``max_rings = 10``, as ``make run`` builds it.
"""

import re

import pytest
from threadpoolctl import threadpool_limits

from hyperlattice.cache import Cache
from hyperlattice.report import reproduce


def _text_outputs(out):
    names = sorted(p.name for p in out.iterdir()
                   if p.suffix in (".csv", ".md", ".html") or (p.suffix == ".json" and p.name != "timings.json"))
    texts = {}
    for name in names:
        text = (out / name).read_text(encoding="utf-8")
        if name.endswith(".html"):
            text = re.sub(r"data:image/png;base64,[A-Za-z0-9+/=]+", "data:image/png;base64,…", text)
        if name == "_report.json":
            # the report's manifest holds a SHA-256 of every file it wrote: those of the figures and of
            # timings.json (left out above, for the reasons above) are masked, the others must agree
            text = re.sub(r'("[^"]+\.(?:png|svg)"|"timings\.json"): "[0-9a-f]{64}"', r'\1: "…"', text)
        texts[name] = text
    return texts


@pytest.mark.slow
def test_report_and_tables_identical_with_one_and_two_blas_threads(tmp_path):
    runs = {}
    for threads in (1, 2):
        with threadpool_limits(threads, user_api="blas"):
            reproduce(tmp_path / f"t{threads}", max_rings=10, cache=Cache(tmp_path / f"cache{threads}"))
        runs[threads] = _text_outputs(tmp_path / f"t{threads}")
    assert {"report.md", "report.html", "table_band_fit.csv", "table_paper_table4.csv"} <= set(runs[1])
    assert sorted(runs[1]) == sorted(runs[2])
    differ = {}
    for name in runs[1]:
        a, b = runs[1][name].splitlines(), runs[2][name].splitlines()
        lines = [(x, y) for x, y in zip(a, b) if x != y]
        if lines or len(a) != len(b):
            differ[name] = lines[:3]
    assert differ == {}, f"these outputs depend on the BLAS thread count: {differ}"
