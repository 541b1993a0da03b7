"""``hyperlattice device``: the contract's flags and JSON keys, and bad input as one line with exit code 2."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hyperlattice.cli import main
from hyperlattice.device import resonator_device, transmission
from hyperlattice.graph.lattice import ring_lattice

BASE = ["device", "transmission", "--rings", "2", "--line-graph", "--omega0", "7000", "--J", "-66",
        "--kappa-int", "0.7", "--port", "0-1:1", "--port", "30-31:1"]


def test_transmission_json_keys_and_values(tmp_path, capsys):
    om = tmp_path / "om.txt"
    om.write_text("6900\n7000.5\n7100\n")
    assert main(BASE + ["--omegas", str(om), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert {"omega", "s_re", "s_im", "resonators", "flat_band_degeneracy"} <= set(d)
    lat = ring_lattice(7, 3, 2)
    assert d["flat_band_degeneracy"] == len(lat.edges) - lat.sites
    s = np.array(d["s_re"]) + 1j * np.array(d["s_im"])
    assert s.shape == (3, 2, 2)
    dev = resonator_device(lat, line_graph=True, omega0=7000.0, J=-66.0, kappa_int=0.7,
                           ports={"0-1": 1.0, "30-31": 1.0})
    assert np.max(np.abs(s - transmission(dev, [6900, 7000.5, 7100]).s)) < 1e-12
    assert d["resonators"] == list(dev.resonators)


def test_json_list_omegas_and_disorder_files(tmp_path, capsys):
    om = tmp_path / "om.json"
    om.write_text("[6950, 7050]")
    fr = tmp_path / "f.json"
    fr.write_text(json.dumps({"0-1": 7001.0}))
    hop = tmp_path / "h.json"
    hop.write_text(json.dumps({"0-1|1-2": -60.0}))
    assert main(BASE + ["--omegas", str(om), "--frequencies", str(fr), "--hoppings", str(hop), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["omega"] == [6950.0, 7050.0]


@pytest.mark.parametrize("extra, files, message", [
    (["--port", "99-100:1"], {}, "names no resonator"),
    (["--port", "0-1:2"], {}, "two ports"),
    (["--port", "5-6:0"], {}, "must be a positive number"),
    (["--port", "5-6:nan"], {}, "must be a positive number"),
    (["--omegas", "{om}"], {"om": "1\nnan\n"}, "NaN"),
    (["--omegas", "{om}"], {"om": "1\nabc\n"}, "not a number"),
    (["--omegas", "{om}", "--frequencies", "{fr}"], {"om": "1\n", "fr": '{"3-77": 1.0}'}, "names no resonator"),
    (["--omegas", "{om}", "--hoppings", "{fr}"], {"om": "1\n", "fr": '{"0-1|30-31": 1.0}'}, "not coupled"),
    (["--omegas", "{om}", "--frequencies", "{fr}"], {"om": "1\n", "fr": '{"0-1": "x"}'}, "finite number"),
    (["--omega-min", "1", "--omega-max", "2", "--points", "3", "--sigma-omega", "1"], {}, "--seed"),
    (["--omega-min", "2", "--omega-max", "1", "--points", "3"], {}, "must exceed"),
])
def test_bad_input_is_one_line_exit_2(extra, files, message, tmp_path, capsys):
    paths = {}
    for key, text in files.items():
        p = tmp_path / (key + (".json" if key == "fr" else ".txt"))
        p.write_text(text)
        paths[key] = str(p)
    extra = [e.format(**paths) for e in extra]
    if not any(e.startswith("--omega") for e in extra):
        extra = extra + ["--omega-min", "6900", "--omega-max", "7100", "--points", "3"]
    try:
        code = main(BASE + extra)
    except SystemExit as exc:          # argparse's own refusals
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
