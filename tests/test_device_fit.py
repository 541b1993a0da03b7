"""Fitting a measured trace: known parameters recovered from synthetic noisy data (within their stated
errors), the count of parameters the data support, and refusals of traces that cannot be fitted."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.device import fit_transmission, read_trace, resonator_device, transmission
from hyperlattice.graph.lattice import ring_lattice

PORTS = {"0-1": 1.0, "30-31": 1.0}
TRUE = {"omega0": 7000.0, "J": -66.0, "kappa_int": 0.7}


def _trace(seed=5, noise=2e-4, points=1601):
    lat = ring_lattice(7, 3, 2)
    dev = resonator_device(lat, line_graph=True, ports=PORTS, **TRUE)
    w = np.linspace(6800.0, 7300.0, points)
    mag = np.abs(transmission(dev, w).s21)
    return lat, w, np.abs(mag + noise * np.random.default_rng(seed).standard_normal(w.size))


@pytest.mark.slow
def test_fit_recovers_known_parameters_within_errors():
    lat, w, mag = _trace()
    f = fit_transmission(lat, w, mag, ports=PORTS, line_graph=True)
    for name, value in TRUE.items():
        err = getattr(f, name + "_err")
        assert 0 < err < 1e-2 * max(abs(value), 1)
        assert abs(getattr(f, name) - value) < 5 * err, (name, getattr(f, name), err)
    assert f.supported == 3
    assert f.residual_rms == pytest.approx(2e-4, rel=0.1)
    assert list(f.to_dataframe().columns) == ["omega", "data", "fit"]


def test_a_single_resonator_does_not_fix_j():
    w = np.linspace(4.0, 6.0, 201)
    s = np.abs(-1j * 0.1 / (w - 5.0 + 0.5j * 0.25))
    f = fit_transmission(np.zeros((1, 1)), w, s, ports=[("0", 0.1), ("0", 0.1)], shared_ports=True)
    assert f.supported == 2 and np.isinf(f.J_err)
    assert f.omega0 == pytest.approx(5.0, abs=1e-9) and f.kappa_int == pytest.approx(0.05, abs=1e-9)


def test_read_trace_forms(tmp_path):
    w = np.linspace(1, 2, 10)
    s = np.exp(1j * w) * 0.1
    a = tmp_path / "db.csv"
    a.write_text("omega,mag_db\n" + "".join(f"{x},{20 * np.log10(abs(v))}\n" for x, v in zip(w, s)))
    b = tmp_path / "ri.csv"
    b.write_text("omega,re,im\n" + "".join(f"{x},{v.real},{v.imag}\n" for x, v in zip(w, s)))
    for p in (a, b):
        ww, mag = read_trace(p)
        assert np.allclose(ww, w) and np.allclose(mag, 0.1, rtol=1e-12)


@pytest.mark.parametrize("text, message", [
    ("freq,db\n" + "1,2\n" * 9, "columns omega,mag_db or omega,re,im"),
    ("omega,mag_db\n" + "".join(f"{k},nan\n" for k in range(9)), "NaN"),
    ("omega,mag_db\n" + "".join(f"{k},-3\n" for k in range(9)), "flat"),
    ("omega,mag_db\n1,2\n", "at least 8"),
    ("omega,re,im\n" + "1,2\n" * 9, "must have 3 values"),
    ("omega,mag_db\n" + "".join(f"{k},x\n" for k in range(9)), "not a number"),
])
def test_bad_traces_are_refused_in_one_line(text, message, tmp_path, capsys):
    p = tmp_path / "t.csv"
    p.write_text(text)
    code = main(["device", "fit", "--rings", "2", "--line-graph", "--port", "0-1:1", "--port", "30-31:1",
                 "--measured", str(p)])
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1


@pytest.mark.slow
def test_cli_fit_keys(tmp_path, capsys):
    lat, w, mag = _trace(points=401)
    p = tmp_path / "m.csv"
    p.write_text("omega,mag_db\n" + "".join(f"{float(x)!r},{float(20 * np.log10(v))!r}\n" for x, v in zip(w, mag)))
    assert main(["device", "fit", "--rings", "2", "--line-graph", "--port", "0-1:1", "--port", "30-31:1",
                 "--measured", str(p), "--plot", str(tmp_path / "f.png"), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert {"omega0", "J", "kappa_int", "omega0_err", "J_err", "kappa_int_err"} <= set(d)
    assert abs(d["J"] - TRUE["J"]) < 5 * d["J_err"]
    assert (tmp_path / "f.png").stat().st_size > 0
