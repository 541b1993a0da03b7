"""``hyperlattice bosons lobe``: a lobe scan for any {p,q} written where the user says, resumed by a
rerun, with a flag on boundaries whose chains did not converge."""

from __future__ import annotations

import json

import pytest

import hyperlattice as hl
from hyperlattice.cli import _bosons_lobe, main
from hyperlattice.compare import qmc_lobe as ql

OCTAGON = ["bosons", "lobe", "--rings", "1", "-p", "8", "-q", "3", "--beta", "2", "--nmax", "2",
           "--sweeps", "300", "--thermalization", "100", "--iterations", "1"]


def test_the_stored_scan_is_never_the_target(capsys):
    # fuzz of 0.5.0: "its default --out overwrites the package's stored scan"
    where = str(_bosons_lobe._stored_scan().parent)
    before = _bosons_lobe._stored_scan().read_bytes()
    code = main([*OCTAGON, "--t-over-U", "0.05", "--out", where])
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and "stored scan" in err and err.count("\n") == 1
    assert _bosons_lobe._stored_scan().read_bytes() == before


@pytest.mark.filterwarnings("ignore::hyperlattice.bosons.sse.QMCWarning")
def test_qmc_boundary_flags_chains_that_did_not_converge():
    # fuzz of 0.5.0: "qmc_boundary returns mu+- without a flag"
    b = ql.qmc_boundary(hl.ring_lattice(7, 3, 1), 0.05, "plus", beta_t=2.0, sweeps=20, nmax=2, iterations=1,
                        thermalization=20)
    assert b["converged"] is False and b["notes"] and all("plateau" in n or "thermal" in n or "string" in n
                                                          for n in b["notes"])


def test_an_8_3_scan_is_written_where_asked_and_a_rerun_resumes(tmp_path, capsys, monkeypatch):
    argv = [*OCTAGON, "--t-over-U", "0.05", "--out", str(tmp_path / "scan"), "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    rows = out["boundaries"]
    assert [r["side"] for r in rows] == ["plus", "minus"] and all(r["system"] == "{8,3}:flake:1" for r in rows)
    assert all(isinstance(r["converged"], bool) for r in rows) and rows[0]["sites"] == 8
    plus, minus = rows[0]["mu"], rows[1]["mu"]
    assert 0 < minus < plus < 1                                        # the n = 1 lobe, in units of U
    assert abs(plus - rows[0]["mu_strong_coupling"]) < 0.05            # t/U = 0.05: strong coupling is close
    stored = json.loads((tmp_path / "scan" / "qmc_lobe_scan.json").read_text())
    assert len(stored["boundaries"]) == 2 and stored["boundaries"][0]["system"] == "{8,3}:flake:1"
    # the scan reads back through the {7,3} analysis, the {8,3} graph rebuilt from its name
    lobe = ql.qmc_lobe(ql.load_scan(tmp_path / "scan" / "qmc_lobe_scan.json"))
    assert lobe.systems[0]["sites"] == 8
    # a rerun computes nothing
    monkeypatch.setattr(ql, "qmc_boundary", lambda *a, **k: pytest.fail("recomputed a stored boundary"))
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["boundaries"] == rows


def test_an_interrupted_scan_keeps_its_boundaries(tmp_path, capsys, monkeypatch):
    calls = []
    real = ql.qmc_boundary

    def boundary(*a, **k):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(*a, **k)

    monkeypatch.setattr(ql, "qmc_boundary", boundary)
    code = main([*OCTAGON, "--t-over-U", "0.05", "--out", str(tmp_path)])
    out, err = capsys.readouterr()
    assert code == 130 and err.count("\n") == 1 and "1 of 2 boundaries kept" in err and "rerun" in err
    assert len(json.loads((tmp_path / "qmc_lobe_scan.json").read_text())["boundaries"]) == 1


def test_system_spec_round_trip():
    assert ql.system_spec(7, 3, rings=2) == "flake:2"
    assert ql.system_spec(8, 3, cluster="bolza") == "{8,3}:cluster:bolza"
    assert ql._system("{8,3}:flake:1").sites == 8
    with pytest.raises(ValueError, match="exactly one"):
        ql.system_spec(8, 3)
