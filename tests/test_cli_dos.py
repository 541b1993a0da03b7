"""``hyperlattice dos``: flake interiors and periodic clusters, CSV, figure, JSON."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.graph.kpm import bulk_dos, kpm_dos, local_dos
from hyperlattice.graph.lattice import ring_lattice

KEYS = {"method", "label", "p", "q", "sites", "traced_sites", "moments", "vectors", "vector_kind", "seed", "site",
        "scale", "bound", "exact_moments", "excluded_rings", "deflated", "mu", "mu_err", "time"}


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_flake_json_matches_api(capsys):
    code, out, _ = run(capsys, "dos", "-p", "7", "-q", "3", "--rings", "5", "--vectors", "3", "--seed", "2", "--json")
    assert code == 0
    d = json.loads(out)
    assert set(d) == KEYS and d["method"] == "bulk" and d["excluded_rings"] == 2
    ref = bulk_dos(ring_lattice(7, 3, 5), vectors=3, seed=2)
    assert d["moments"] == ref.exact_moments == ref.moments
    np.testing.assert_allclose(d["mu"], ref.mu[:8], rtol=0, atol=1e-14)


def test_cluster_csv_and_plot(capsys, tmp_path):
    out, fig = tmp_path / "dos.csv", tmp_path / "dos.png"
    code, text, _ = run(capsys, "dos", "--cluster", "klein", "--moments", "64", "--vectors", "4",
                        "--out", str(out), "--plot", str(fig), "--points", "41")
    assert code == 0 and "left out of the trace: 1 state" in text
    with out.open() as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["energy", "dos", "error", "integrated"] and len(rows) == 42
    e = np.array([float(r[0]) for r in rows[1:]])
    n = np.array([float(r[3]) for r in rows[1:]])
    from hyperlattice.graph.clusters import pbc_cluster

    ref = kpm_dos(pbc_cluster(7, 3, "klein"), 64, vectors=4, deflate=True)
    # the uniform state is out of the trace: the total weight is |(1 - P) r|^2 / N, 55/56 on average
    assert e[0] == -3.0 and e[-1] == 3.0 and n[-1] == pytest.approx(ref.mu[0], abs=1e-4)  # kernel tails beyond |E| = q
    assert abs(ref.mu[0] - 55 / 56) < 4 * ref.mu_err[0]
    assert fig.stat().st_size > 1000
    _, rho, _ = ref.density(e)
    np.testing.assert_allclose([float(r[1]) for r in rows[1:]], rho, rtol=1e-12, atol=1e-14)


def test_keep_uniform_and_local(capsys):
    code, out, _ = run(capsys, "dos", "--cluster", "klein", "--moments", "16", "--vectors", "2", "--keep-uniform",
                       "--json")
    assert code == 0 and json.loads(out)["deflated"] == 0
    code, out, _ = run(capsys, "dos", "--rings", "4", "--site", "3", "--moments", "20", "--json")
    d = json.loads(out)
    ref = local_dos(ring_lattice(7, 3, 4), 3, 20)
    assert d["method"] == "local" and d["site"] == 3 and d["exact_moments"] == ref.exact_moments
    np.testing.assert_allclose(d["mu"], ref.mu[:8], rtol=0, atol=1e-15)


def test_contradictory_flags_exit_2(capsys):
    for argv in (["dos", "--cluster", "klein", "--exclude", "2"], ["dos", "--rings", "3", "--keep-uniform"],
                 ["dos", "--rings", "3", "--cluster", "klein"], ["dos", "--rings", "3", "--out", "x.txt"]):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = exc.code
        err = capsys.readouterr().err
        assert code == 2 and len([ln for ln in err.splitlines() if ln.strip()]) == 1, argv
