"""CLI: ``hyperlattice scaling ...`` and ``hyperlattice dictionary``."""

import json
import math

import pytest

from hyperlattice.cli import main
from hyperlattice.paper_values import paper_value


def run_json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_angles_json(capsys):
    out = run_json(capsys, ["scaling", "angles", "--rings", "4", "--json"])
    assert out["sites"] == 315 and out["max_star_residual"] < 1e-10
    assert len(out["profile"]["r"]) == out["distinct_radii"]


def test_counting_json(capsys):
    out = run_json(capsys, ["scaling", "counting", "--json"])
    assert abs(out["intercept"] - paper_value("b_counting", 4).value) < 1e-3 and out["window"] == "all"


def test_convergence_json(capsys):
    out = run_json(capsys, ["scaling", "convergence", "--rings", "3", "--json"])
    for k, power in {"2": 3, "3": 4}.items():
        assert abs(out["orders"][k]["exponent"] - power) < 0.2


def test_operator_and_sums_text(capsys, tmp_path):
    png = tmp_path / "sh.png"
    assert main(["scaling", "operator", "--rings", "3", "--h", "0.1", "--plot", str(png)]) == 0
    assert "0.100000" in capsys.readouterr().out and png.stat().st_size > 1000
    assert main(["scaling", "sums", "--rings", "4", "--function", "gaussian"]) == 0
    assert "exp(-d^2" in capsys.readouterr().out


def test_dictionary_json(capsys):
    out = run_json(capsys, ["dictionary", "--t", "1", "--mu", "0.5", "--U", "2", "--json"])
    assert out["continuum"]["mu_prime"] == 3.5
    assert out["continuum"]["U_prime"] == pytest.approx(2 * math.pi / 28)
    assert out["field_scale"] == pytest.approx(math.sqrt(28 / math.pi))


@pytest.mark.parametrize("argv", [
    ["scaling", "operator", "--h", "0.5"],
    ["scaling", "counting", "--rings", "1"],
    ["scaling", "convergence", "--h-min", "0.1", "--h-max", "0.05"],
    ["dictionary", "-p", "6"],
])
def test_bad_input_exit_2(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "error" in err


def test_argparse_rejects_nan(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["dictionary", "--t", "nan"])
    assert exc.value.code == 2


# ---------------------------------------------------------------------------------------------
# output paths, size bounds, non-finite results, never a traceback
# ---------------------------------------------------------------------------------------------

def _one_line_exit_2(capsys, argv):
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse
        code = exc.code
    captured = capsys.readouterr()
    assert code == 2, captured.err
    assert captured.err.count("\n") == 1 and "Traceback" not in captured.err, captured.err
    return captured


@pytest.mark.parametrize("task", [["angles"], ["counting"], ["operator", "--h", "0.1"]])
def test_plot_into_directory_refused(task, tmp_path, capsys):
    """--plot DIR silently wrote DIR.png."""
    err = _one_line_exit_2(capsys, ["scaling", *task, "--rings", "3", "--plot", str(tmp_path)]).err
    assert "directory" in err and not (tmp_path.parent / (tmp_path.name + ".png")).exists()


def test_plot_without_format_suffix_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    err = _one_line_exit_2(capsys, ["scaling", "angles", "--rings", "3", "--plot", "figure"]).err
    assert ".png" in err and not (tmp_path / "figure.png").exists()


def test_plot_missing_folder_refused_before_computing(tmp_path, capsys, monkeypatch):
    import hyperlattice.cli.cmd_scaling as cmd

    def fail(*args, **kwargs):
        raise AssertionError("computed before checking --plot")

    monkeypatch.setattr(cmd, "ring_lattice", fail)
    _one_line_exit_2(capsys, ["scaling", "counting", "--plot", str(tmp_path / "no" / "f.png")])


def test_plot_other_format(tmp_path, capsys):
    assert main(["scaling", "counting", "--plot", str(tmp_path / "s1.svg")]) == 0
    assert (tmp_path / "s1.svg").read_text().lstrip().startswith("<?xml")
    capsys.readouterr()


def test_points_bounded_before_allocating(capsys):
    """--rings 3 --points 100000000 still ran after 50 minutes."""
    err = _one_line_exit_2(capsys, ["scaling", "convergence", "--rings", "3", "--points", "100000000"]).err
    assert "--points" in err and "1000" in err


@pytest.mark.parametrize("argv", [
    ["scaling", "operator", "--rings", "3", "--h", *["0.1"] * 51],
    ["scaling", "sums", "--rings", *["4"] * 51],
])
def test_list_lengths_bounded(argv, capsys):
    _one_line_exit_2(capsys, argv)


@pytest.mark.parametrize("slope", ["1e308", "-1e308", "1e22"])
def test_huge_slope_refused(slope, capsys):
    """--slope 1e308 printed b = -inf and eight RuntimeWarning lines."""
    captured = _one_line_exit_2(capsys, ["scaling", "counting", f"--slope={slope}"])
    assert "--slope" in captured.err and captured.out == ""


@pytest.mark.parametrize("argv", [["dictionary", "--t", "1e308"], ["dictionary", "--U", "1e308", "-p", "3", "-q", "20"],
                                  ["dictionary", "--inverse", "--t", "1e308"]])
def test_dictionary_overflow_exit_2(argv, capsys):
    """dictionary --t 1e308 printed mu' = inf with exit 0."""
    err = _one_line_exit_2(capsys, argv).err
    assert "overflows" in err


def test_warnings_are_one_line(capsys, monkeypatch):
    import warnings

    import hyperlattice.cli.cmd_dictionary as cmd
    from hyperlattice.errors import ConvergenceWarning

    def warn_then_succeed(args):
        warnings.warn("tolerance only nearly met", ConvergenceWarning)
        return 0

    monkeypatch.setattr(cmd, "run", warn_then_succeed)
    assert main(["dictionary"]) == 0
    err = capsys.readouterr().err
    assert err == "hyperlattice dictionary: warning: tolerance only nearly met (ConvergenceWarning)\n"


@pytest.mark.parametrize("exc, code, text", [
    (OSError(13, "Permission denied", "/x/f.png"), 2, "/x/f.png: Permission denied"),
    (MemoryError(), 2, "out of memory"),
    (TypeError("a bug"), 1, "internal error (TypeError: a bug)"),
])
def test_never_a_traceback(exc, code, text, capsys, monkeypatch):
    import hyperlattice.cli.cmd_dictionary as cmd

    def boom(args):
        raise exc

    monkeypatch.setattr(cmd, "run", boom)
    monkeypatch.delenv("HYPERLATTICE_TRACEBACK", raising=False)
    assert main(["dictionary"]) == code
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and text in err


def test_operator_json_is_operator_profile(capsys):
    from hyperlattice.compare.scaling import SmoothFunction, frame_angles, operator_profile
    from hyperlattice.graph.lattice import ring_lattice

    out = run_json(capsys, ["scaling", "operator", "--rings", "3", "--h", "0.1", "--json"])
    prof = operator_profile(frame_angles(ring_lattice(7, 3, 3)), SmoothFunction.cos_distance(), 0.1)
    row = out["results"][0]
    assert row["h"] == 0.1 and row["max_error_cubic"] == prof.max_error_cubic
    assert row["A_h_minus_qf"] == prof.exact.mean.tolist() and row["distance"] == prof.exact.distance.tolist()
    assert set(row) == {"h", "max_error_quadratic", "max_error_cubic", "distance", "A_h_minus_qf",
                        "quadratic_minus_qf", "cubic_minus_qf"}
