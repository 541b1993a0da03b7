"""The QMC Mott-lobe comparison (compare/qmc_lobe.py, plots/qmc_lobe.py) on tiny fast scans.

The stored scan (src/hyperlattice/report/qmc_lobe_scan.json, from benchmarks/qmc_lobe_scan.py) is read and checked for
consistency; the QMC runs here are a few hundred sweeps on the heptagon, compared with exact
thermal averages of the same graph (bosons.exact_thermal), so the boundary finder is checked
against the number it estimates.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import hyperlattice as hl
from hyperlattice.compare import qmc_lobe as ql

SCAN = Path(ql.__file__).resolve().parent.parent / "report" / "qmc_lobe_scan.json"


def test_square_lattice_builder():
    A = ql.square_lattice(5)
    assert A.shape == (25, 25) and (A != A.T).nnz == 0
    assert np.all(np.asarray(A.sum(axis=1)).ravel() == 4)
    # translation invariant: the spectrum of the torus is 2cos(2pi a/L) + 2cos(2pi b/L)
    k = 2 * np.pi * np.arange(5) / 5
    ref = np.sort((2 * np.cos(k)[:, None] + 2 * np.cos(k)[None, :]).ravel())
    assert np.allclose(np.linalg.eigvalsh(A.toarray()), ref)
    with pytest.raises(ValueError, match="L"):
        ql.square_lattice(2)


def test_mean_field_boundaries_meet_at_the_tip():
    from hyperlattice.bosons.meanfield import lobe_boundary, lobe_tip

    lam = 2.9
    x_tip = lobe_tip(lam)[1]
    mp, mm = ql.mean_field_boundaries(lam, [0.5 * x_tip, x_tip * (1 - 1e-9), 1.1 * x_tip])
    assert mp[0] > mm[0] and abs(mp[1] - mm[1]) < 1e-3 and math.isnan(mp[2])
    # the roots are the mean-field boundary of bosons.meanfield read the other way
    assert lobe_boundary(lam, mp[0]) == pytest.approx(0.5 * x_tip, rel=1e-10)
    assert lobe_boundary(lam, mm[0]) == pytest.approx(0.5 * x_tip, rel=1e-10)
    assert ql.SQUARE_TIP_MEAN_FIELD == pytest.approx(lobe_tip(4.0)[1])


@pytest.mark.slow          # QMC kernels compile; minutes on a loaded machine
def test_heptagon_boundary_against_exact_thermal():
    # the Newton finder on <N>(mu) = M + 1/2: at the QMC estimate the exact thermal <N> of the same
    # graph, beta and cutoff must be M + 1/2 within the estimate's error (times the exact slope)
    lat = hl.ring_lattice(7, 3, 1)
    x, beta = 0.08, 5.0
    U = 1 / x
    b = ql.qmc_boundary(lat, x, "plus", beta_t=beta, sweeps=600, iterations=2, seed=5)
    assert b["sites"] == 7 and len(b["steps"]) == 2 and b["mu_err"] > 0
    ex = hl.bosons.exact_thermal(lat, U=U, mu=b["mu"] * U, beta=beta, nmax=3)
    slope = ex.compressibility * 7 * U          # d<N>/d(mu/U)
    assert abs(ex.density * 7 - 7.5) < slope * (4 * b["mu_err"] + 1e-3)


def test_finite_temperature_offset_statement():
    off = ql.boundary_offset(hl.ring_lattice(7, 3, 1), 5.0)
    # heptagon: lambda_1 = 2, lambda_2 = 2 cos(2 pi/7)
    assert off["splitting_over_t"] == pytest.approx(2 * (2 - 2 * math.cos(2 * math.pi / 7)))
    assert off["beta_splitting"] == pytest.approx(5 * off["splitting_over_t"])


def _tiny_scan():
    return {"meta": {"beta_t": 5.0}, "boundaries": [
        {"system": "flake:1", "sites": 7, "t_over_U": 0.08, "beta_t": 5.0, "side": "plus", "mu": 0.69, "mu_err": 0.01},
        {"system": "flake:1", "sites": 7, "t_over_U": 0.08, "beta_t": 5.0, "side": "minus", "mu": 0.13,
         "mu_err": 0.01},
        {"system": "square:4", "sites": 16, "t_over_U": 0.04, "beta_t": 5.0, "side": "plus", "mu": 0.8,
         "mu_err": float("nan")},
    ]}


def test_lobe_assembly_and_figure(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from hyperlattice.plots.qmc_lobe import plot_qmc_lobe_system, qmc_lobe_figure

    lobe = ql.qmc_lobe(_tiny_scan(), points=11)
    assert [s["system"] for s in lobe.systems] == ["flake:1", "square:4"]
    hept = lobe.systems[0]
    assert hept["lambda_max"] == pytest.approx(2.0) and hept["tip_mean_field"] == pytest.approx(0.1715729 / 2, rel=1e-6)
    assert hept["tip_strong_coupling"] == pytest.approx(0.2152504, rel=1e-6)
    assert lobe.square["strong_coupling"] == pytest.approx(0.0679604, rel=1e-6)
    assert lobe.infinite_tip_mean_field == pytest.approx(0.058335, abs=2e-6)
    row = next(r for r in lobe.rows if r["system"] == "flake:1" and r["side"] == "plus")
    assert row["mu_strong_coupling"] == pytest.approx(0.689472, abs=1e-6)
    assert [r["side"] for r in lobe.rows[:2]] == ["minus", "plus"]
    ax = plot_qmc_lobe_system(lobe, "flake:1")
    assert len(ax.lines) >= 4 and ax.get_xlabel() == "t/U"
    fig = qmc_lobe_figure(lobe, tmp_path / "lobe.png")
    assert (tmp_path / "lobe.png").stat().st_size > 1000 and len(fig.axes) == 2
    assert lobe.plot() is not None
    plt.close("all")
    with pytest.raises(ValueError, match="not in this lobe"):
        plot_qmc_lobe_system(lobe, "flake:9")


def test_stored_scan_is_consistent():
    if not SCAN.exists():
        pytest.skip("no stored scan")
    data = ql.load_scan(SCAN)
    assert data["meta"]["beta_t"] > 0 and data["boundaries"]
    for b in data["boundaries"]:
        assert b["side"] in ("plus", "minus") and b["steps"]
        last = b["steps"][-1]
        # the estimate is one Newton step from the last run, within a few temperatures of it
        assert abs(b["mu"] - last["mu"]) <= 3.0 * b["t_over_U"] / b["beta_t"] + 1e-12
        assert 0.0 < b["mu"] < 1.0


@pytest.mark.slow
def test_xy_qubits_against_exact():
    out = ql.xy_qubit_check(rings=2, ring=1, beta_J=10.0, sweeps=3000, seed=11)
    assert out["qubits"] == 7 and out["lamb_shift_spread"] < 1e-9
    for key, dev in out["deviation_sigma"].items():
        assert dev < 4.0, (key, out)


@pytest.mark.slow          # strong-coupling tips and rho of every graph of the stored scan
def test_report_section(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from hyperlattice.report.qmc_lobe import qmc_lobe_section

    from hyperlattice.report.qmc_lobe import extrapolation_rows, headline, stored_scan, tip_rows

    sec = qmc_lobe_section(tmp_path, lambda msg: None)
    assert sec.anchor == "qmc-lobe" and len(sec.tables) == 3 and len(sec.figures) == 2
    assert (tmp_path / "fig_qmc_lobe.png").exists() and (tmp_path / "fig_qmc_tip.png").exists()
    assert "0.058335" in " ".join(sec.text) and "stored scan" in sec.provenance[0]
    # the section's tables and verdict are the analysis of the committed scan
    lobe = ql.qmc_lobe(stored_scan())
    assert sec.tables[1].rows == tip_rows(lobe) and sec.tables[2].rows == extrapolation_rows(lobe)
    h = headline(lobe)
    assert h["cluster"] is not None and f"{h['cluster']['tip']:.4f}" in " ".join(sec.text)
    # mean field, which drops the fluctuations that stabilise the Mott state, ends the lobe earlier than the QMC
    assert h["cluster"]["tip"] > h["cluster"]["mean_field"]
    # three periodic cluster sizes (Klein quartic, Macbeath surface, PSL(2,13)) test the 1/M form
    f = h["infinite"]
    assert f["sites"] == [56, 168, 364] and f["dof"] == 1 and math.isfinite(f["chi2"])
    assert f"χ² = {f['chi2']:.2f}" in " ".join(sec.text)
    row = next(r for r in sec.tables[2].rows if r[0] == "clusters" and r[1] == f"{f['beta_t']:g}")
    assert row[2] == "56 + 168 + 364" and row[6] == f"{f['chi2']:.2f}/1"


def test_extrapolation_rows_state_chi2():
    # two sizes: the line is not tested (—); three sizes: χ²/dof of each form
    from hyperlattice.report.qmc_lobe import EXTRAPOLATION_HEADER, extrapolation_rows

    lobe = ql.qmc_lobe(_tiny_scan(), points=11)
    base = {"kind": "cluster", "beta_t": 8.0, "tip": 0.09, "tip_err": 0.001, "tip_sqrt_form": 0.089,
            "tip_sqrt_form_err": 0.002, "systematic": 0.001, "slope": 0.1, "slope_sqrt_form": 0.01}
    two = dict(base, sites=[56, 364], chi2=0.0, chi2_sqrt_form=0.0, dof=0)
    three = dict(base, sites=[56, 168, 364], chi2=0.5, chi2_sqrt_form=1.25, dof=1)
    lobe2 = dataclasses.replace(lobe, finite_size=[two, three])
    rows = extrapolation_rows(lobe2)
    assert all(len(r) == len(EXTRAPOLATION_HEADER) for r in rows)
    assert rows[0][-2:] == ["—", "—"] and rows[1][-2:] == ["0.50/1", "1.25/1"]


# ---------------------------------------------------------------------------------------------
# the tip analysis (gap extrapolation, size extrapolation, Newton-run combination) on synthetic data
# ---------------------------------------------------------------------------------------------

def test_gap_lines_bracket_the_mean_field_tip():
    # Gutzwiller's gap on a 3-regular graph closes as a square root (z nu = 1/2): the Delta^2 line
    # through three points below the tip lands within 1 % of it (from below: Delta^2 is convex), the
    # Delta line overshoots; the midpoint's error covers the true tip
    from hyperlattice.bosons.meanfield import lobe_tip

    lam = 3.0
    xc = lobe_tip(lam)[1]
    x = xc * np.array([0.80, 0.87, 0.94])
    mp, mm = ql.mean_field_boundaries(lam, x)
    gap, err = mp - mm, np.full(3, 1e-4)
    sq = ql.gap_tip(x, gap, err, form="sqrt")
    li = ql.gap_tip(x, gap, err, form="linear")
    assert sq["tip"] < xc < li["tip"]
    assert abs(sq["tip"] / xc - 1) < 0.01
    mid = 0.5 * (sq["tip"] + li["tip"])
    assert abs(mid - xc) < 0.5 * (li["tip"] - sq["tip"])
    # with four points the free power law finds the mean-field exponent
    x4 = xc * np.array([0.80, 0.85, 0.90, 0.95])
    mp, mm = ql.mean_field_boundaries(lam, x4)
    pw = ql.gap_tip(x4, mp - mm, np.full(4, 1e-4), form="power")
    assert pw["exponent"] == pytest.approx(0.5, abs=0.05) and pw["tip"] == pytest.approx(xc, rel=0.01)


def test_gap_tip_error_bars_cover():
    # straight-line gaps with Gaussian noise: the stated 1-sigma interval holds the true tip about
    # 68 % of the time (400 synthetic data sets, fixed seed), 2 sigma about 95 %
    rng = np.random.default_rng(7)
    x = np.array([0.06, 0.07, 0.08, 0.09])
    true = 0.1
    g0 = 12.0 * (true - x)
    err = np.full(4, 0.01)
    z = []
    for _ in range(400):
        r = ql.gap_tip(x, g0 + err * rng.standard_normal(4), err, form="linear")
        z.append((r["tip"] - true) / r["tip_err"])
    z = np.abs(np.array(z))
    assert 0.60 < np.mean(z < 1) < 0.78
    assert 0.90 < np.mean(z < 2) < 0.99


def test_gap_tip_refuses_bad_input():
    with pytest.raises(ValueError, match="two points"):
        ql.gap_tip([0.05], [0.1], [0.01])
    with pytest.raises(ValueError, match="one length"):
        ql.gap_tip([0.05, 0.06], [0.1], [0.01])
    with pytest.raises(ValueError, match="four points"):
        ql.gap_tip([0.05, 0.06, 0.07], [0.3, 0.2, 0.1], [0.01] * 3, form="power")
    # a gap that grows with t/U has no tip
    assert math.isnan(ql.gap_tip([0.05, 0.06], [0.1, 0.2], [0.01, 0.01])["tip"])


def test_size_extrapolation_is_a_weighted_line():
    m = np.array([56, 364, 2000])
    tips = 0.07 + 0.9 / m
    r = ql.size_extrapolation(m, tips, [0.001] * 3)
    assert r["tip"] == pytest.approx(0.07, abs=1e-12) and r["slope"] == pytest.approx(0.9) and r["chi2"] < 1e-20
    # two sizes: the error is the propagated one, x_inf = (M2 x2 - M1 x1)/(M2 - M1)
    r2 = ql.size_extrapolation([100, 400], [0.07, 0.064], [0.001, 0.001])
    assert r2["tip"] == pytest.approx((400 * 0.064 - 100 * 0.07) / 300)
    assert r2["tip_err"] == pytest.approx(math.hypot(400 / 300, 100 / 300) * 0.001)
    r3 = ql.size_extrapolation([100, 400], [0.07, 0.064], [0.001, 0.001], power=0.5)
    assert r3["tip"] == pytest.approx((20 * 0.064 - 10 * 0.07) / 10)
    with pytest.raises(ValueError, match="two sizes"):
        ql.size_extrapolation([100, 100], [0.07, 0.06], [0.001, 0.001])


def test_combine_steps_window_and_scatter():
    M, x, beta = 20, 0.1, 5.0
    U = 1 / x
    kap = 0.1          # slope dN/d(mu/U) = kappa M U = 20

    def run(mu, N):
        return {"mu": mu, "N": N, "N_err": 0.02, "kappa": kap, "kappa_err": 0.0}

    # a run far from M + 1/2 is left out; the two inside agree on 0.50
    steps = [run(0.40, 19.0), run(0.50 + 0.05 / 20, 20.55), run(0.50 - 0.05 / 20, 20.45)]
    mu, err, used = ql.combine_steps(steps, "plus", M, x, beta)
    assert used == 2 and mu == pytest.approx(0.50) and err == pytest.approx(0.001 / math.sqrt(2))
    # two runs that disagree by 10 sigma: the error grows with the scatter (Birge ratio)
    steps = [run(0.50, 20.5), run(0.52, 20.5)]
    mu, err, used = ql.combine_steps(steps, "plus", M, x, beta)
    assert mu == pytest.approx(0.51) and err == pytest.approx(0.01, rel=1e-6)
    assert math.isnan(ql.combine_steps([run(0.4, 19.0)], "plus", M, x, beta)[0])


def test_stored_scan_matches_its_analysis():
    # every stored boundary is the combination of its own Newton runs (the analysis the report reads),
    # and every graph/temperature of the tip scan has both sides at each t/U
    from hyperlattice.report.qmc_lobe import SCAN_COMMAND

    data = ql.load_scan(SCAN)
    assert data["meta"]["command"] == SCAN_COMMAND
    pairs: dict = {}
    for b in data["boundaries"]:
        mu, err, used = ql.combine_steps(b["steps"], b["side"], b["sites"], b["t_over_U"], b["beta_t"])
        if "steps_used" in b:
            # no run inside the window: the boundary is the last Newton estimate, as in the analysis
            assert used == b["steps_used"] and (used == 0 or mu == pytest.approx(b["mu"], abs=1e-12))
        elif used:        # scans stored before the combination: within 3 errors of the last Newton step
            assert abs(mu - b["mu"]) < 3 * math.hypot(err, b["mu_err"]) + 1e-3
        pairs.setdefault((b["system"], b["beta_t"], b.get("nmax", 3), b["t_over_U"]), set()).add(b["side"])
    tip_graphs = {k for k in pairs if k[1] in (4.0, 8.0)}
    assert tip_graphs and all(pairs[k] == {"plus", "minus"} for k in tip_graphs)
