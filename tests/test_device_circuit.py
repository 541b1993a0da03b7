"""Electric circuits on the package's graphs: admittance, impedances against a dense inverse, resonances
from the Laplacian spectrum, voltage profiles, bad element specs."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.device import (circuit_resonances, element_admittance, impedance, node_voltages,
                                 parse_elements)
from hyperlattice.graph.lattice import ring_lattice
from hyperlattice.graph.operators import adjacency


def _dense_y(lat, w, ye, yg):
    a = adjacency(lat).toarray()
    lap = np.diag(a.sum(axis=1)) - a
    return ye * lap + yg * np.eye(len(a))


def test_admittance_of_parallel_elements():
    w = np.array([0.5, 2.0])
    y = element_admittance(parse_elements("C:2,L:3,R:4"), w)
    assert np.allclose(y, 1j * w * 2 + 1 / (1j * w * 3) + 0.25, rtol=1e-15)


@pytest.mark.parametrize("edge, ground", [("C:1", "L:1,R:100"), ("L:2", "C:0.5"), ("R:3,C:1", "R:7")])
def test_impedances_match_a_dense_inverse(edge, ground):
    lat = ring_lattice(7, 3, 2)
    w = np.array([0.3, 0.77, 1.9])
    zab = impedance(lat, w, edge=edge, ground=ground, between=("0", "20"))
    za = impedance(lat, w, edge=edge, ground=ground, to_ground="5")
    ye = element_admittance(parse_elements(edge), w)
    yg = element_admittance(parse_elements(ground), w)
    for k in range(w.size):
        yi = np.linalg.inv(_dense_y(lat, w[k], ye[k], yg[k]))
        e = np.zeros(lat.sites)
        e[0], e[20] = 1, -1
        assert abs(e @ yi @ e - zab.z[k]) < 1e-10 * abs(zab.z[k])
        assert abs(yi[5, 5] - za.z[k]) < 1e-10 * abs(za.z[k])


def test_resonances_are_where_the_lossless_impedance_diverges():
    lat = ring_lattice(7, 3, 2)
    res = circuit_resonances(lat, edge="C:1", ground="L:1")
    a = adjacency(lat).toarray()
    mu = np.linalg.eigvalsh(np.diag(a.sum(axis=1)) - a)
    assert np.allclose(res, np.sort(1 / np.sqrt(mu[mu > 1e-9])), rtol=1e-10)
    # the lossless circuit at a resonance: Y is singular, refused in one sentence
    with pytest.raises(ValueError, match="resonance"):
        impedance(lat, [res[3]], edge="C:1", ground="L:1", to_ground="0")


def test_voltage_profile_solves_kirchhoff():
    lat = ring_lattice(7, 3, 2)
    nv = node_voltages(lat, 1.3, edge="C:1", ground="L:1,R:50", drive="3", sink="17")
    y = _dense_y(lat, 1.3, 1.3j, 1 / 1.3j + 1 / 50)
    cur = y @ nv.v
    e = np.zeros(lat.sites)
    e[3], e[17] = 1, -1
    assert np.max(np.abs(cur - e)) < 1e-12
    assert list(nv.to_dataframe().columns) == ["node", "v_re", "v_im", "v_abs"]


@pytest.mark.parametrize("spec, message", [("C:nan", "positive and finite"), ("L:-1", "positive and finite"),
                                           ("X:1", "unknown element"), ("C", "LETTER:VALUE"), ("C:1,C:2", "twice"),
                                           ("C:abc", "not a number"), (3, "string")])
def test_bad_element_specs(spec, message):
    with pytest.raises(ValueError, match=message):
        impedance(ring_lattice(7, 3, 1), [1.0], edge=spec, ground="R:1", to_ground="0")


def test_cli_impedance_keys_and_errors(tmp_path, capsys):
    argv = ["device", "impedance", "--rings", "2", "--edge", "C:1", "--ground", "L:1,R:100", "--between", "0", "20",
            "--omega-min", "0.5", "--omega-max", "2", "--points", "4", "--json"]
    assert main(argv) == 0
    d = json.loads(capsys.readouterr().out)
    assert {"omega", "z_re", "z_im"} <= set(d) and len(d["z_re"]) == 4
    ref = impedance(ring_lattice(7, 3, 2), np.linspace(0.5, 2, 4), edge="C:1", ground="L:1,R:100",
                    between=("0", "20"))
    assert np.allclose(d["z_re"], ref.z_re, rtol=1e-15, atol=0)
    for bad in (["--edge", "C:-1"], ["--between", "0", "999"]):
        args = list(argv)
        k = args.index(bad[0])
        args[k:k + len(bad)] = bad
        assert main(args) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err


def test_large_circuits_take_the_factor_layer(monkeypatch):
    import hyperlattice.device.circuit as circuit

    lat = ring_lattice(7, 3, 2)
    w = np.array([0.4, 1.3])
    ref = impedance(lat, w, edge="C:1", ground="L:1,R:100", between=("0", "20"))
    monkeypatch.setattr(circuit, "EIGEN_MAX", 10)
    big = impedance(lat, w, edge="C:1", ground="L:1,R:100", between=("0", "20"))
    assert ref.method == "eigen" and big.method == "direct" and big.resonances.size == 0
    assert np.allclose(big.z, ref.z, rtol=1e-11, atol=0)
