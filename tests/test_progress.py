"""Progress bars and interruption (issue 21, item 4): one mechanism, quiet off a terminal, resume.

* :mod:`hyperlattice._progress` decides once whether a bar is drawn: True/False, None (a terminal,
  ``HYPERLATTICE_PROGRESS``, ``--progress``/``--no-progress``), never inside another bar; a function
  still receives messages.
* Bars go to stderr; stdout (JSON, tables) stays clean.
* ``--checkpoint DIR`` keeps every finished point of fluxmap and butterfly; after Ctrl-C the same
  command computes only the missing points and writes the same table, byte for byte.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from hyperlattice import _progress
from hyperlattice.cli import build_parser, main


@pytest.fixture
def no_delay(monkeypatch):
    """Bars draw at once (the default waits a second, longer than these small runs)."""
    monkeypatch.setattr(_progress, "DELAY", 0.0)


class _Tty:
    """A stderr that claims to be a terminal and records what is written."""

    def __init__(self) -> None:
        self.parts: list[str] = []

    def write(self, text: str) -> int:
        self.parts.append(text)
        return len(text)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return True

    @property
    def text(self) -> str:
        return "".join(self.parts)


# ---------------------------------------------------------------------------------------------
# the mechanism
# ---------------------------------------------------------------------------------------------

def test_auto_follows_the_terminal_the_environment_and_the_command_line(monkeypatch):
    monkeypatch.delenv(_progress.ENV, raising=False)
    assert _progress.enabled(None) is False          # pytest captures stderr: not a terminal
    monkeypatch.setattr(sys, "stderr", _Tty())
    assert _progress.enabled(None) is True
    monkeypatch.setenv(_progress.ENV, "0")
    assert _progress.enabled(None) is False
    assert _progress.enabled(True) is True             # an explicit argument wins over the environment
    monkeypatch.setenv(_progress.ENV, "1")
    with _progress.default(False):                     # --no-progress wins over the environment
        assert _progress.enabled(None) is False
        assert _progress.enabled(True) is True
    assert _progress.enabled(None) is True


def test_an_auto_bar_inside_another_bar_stays_off(monkeypatch):
    monkeypatch.setattr(sys, "stderr", _Tty())
    monkeypatch.delenv(_progress.ENV, raising=False)
    with _progress.progress_bar(3, "outer", progress=False):
        # the outer loop owns the line, even when it draws nothing (--no-progress)
        assert _progress.enabled(None) is False
    assert _progress.enabled(None) is True


def test_a_function_receives_messages_and_no_bar_is_drawn(monkeypatch):
    tty = _Tty()
    monkeypatch.setattr(sys, "stderr", tty)
    seen = []
    with _progress.progress_bar(2, "points", progress=seen.append) as bar:
        assert not bar.drawn
        bar.note("l=3")
        bar.update()
        bar.update()
    assert seen == ["l=3", "points: 1/2", "points: 2/2"]
    assert tty.text == ""


@pytest.mark.parametrize("bad", ["yes", 1, 0.5, object(), [True]])
def test_a_progress_argument_that_is_not_a_flag_or_function_is_refused(bad):
    with pytest.raises(ValueError, match="progress must be True, False, None or a function"):
        _progress.progress_bar(3, "x", progress=bad)


def test_a_forced_bar_writes_to_stderr_only(no_delay, capsys):
    with _progress.progress_bar(4, "work", unit="point", progress=True) as bar:
        for _ in range(4):
            bar.update()
    out, err = capsys.readouterr()
    assert out == ""
    assert "work" in err and "4/4" in err


# ---------------------------------------------------------------------------------------------
# the command line
# ---------------------------------------------------------------------------------------------

def _commands(parser, words=()):
    """Every (words, parser) of the command line, nested subcommands (``bosons ed``) included."""
    import argparse

    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield words + (name,), sub
                yield from _commands(sub, words + (name,))


def test_every_command_takes_progress_and_no_progress():
    found = list(_commands(build_parser()))
    assert len(found) > 20 and ("bosons", "ed") in [w for w, _ in found]
    for words, sub in found:
        for flag in ("--progress", "--no-progress"):
            assert flag in sub._option_string_actions, (words, flag)
        assert sub._option_string_actions["--no-progress"].dest == "progress", words


@pytest.mark.parametrize("tail,expected", [([], None), (["--no-progress"], False), (["--progress"], True)])
def test_the_flag_counts_after_a_nested_subcommand(tail, expected):
    args = build_parser().parse_args(["scaling", "angles", "--rings", "2"] + tail)
    assert args.progress is expected
    args = build_parser().parse_args(["scaling", "--progress", "angles", "--rings", "2"] + tail)
    assert args.progress is (True if expected is None else expected)


def test_no_bar_when_stderr_is_not_a_terminal(no_delay, capsys, tmp_path, monkeypatch):
    monkeypatch.delenv(_progress.ENV, raising=False)
    code = main(["butterfly", "--rings", "2", "--fluxes", "4", "--json"])
    out, err = capsys.readouterr()
    assert code == 0 and err == ""
    json.loads(out)


def test_forced_progress_goes_to_stderr_and_the_json_stays_clean(no_delay, capsys):
    code = main(["butterfly", "--rings", "2", "--fluxes", "4", "--json", "--progress"])
    out, err = capsys.readouterr()
    assert code == 0
    assert json.loads(out)["fluxes"] == 4              # stdout is exactly one JSON object
    assert "butterfly" in err and "4/4" in err


def test_no_progress_silences_a_terminal(no_delay, monkeypatch, capsys):
    tty = _Tty()
    monkeypatch.setattr(sys, "stderr", tty)
    assert main(["fluxmap", "--rings", "2", "--fluxes", "2", "--levels", "1", "--json", "--no-progress"]) == 0
    assert tty.text == ""
    assert main(["fluxmap", "--rings", "2", "--fluxes", "2", "--levels", "1", "--json"]) == 0
    assert "fluxmap" in tty.text and "2/2" in tty.text


# ---------------------------------------------------------------------------------------------
# checkpoints: interrupt after k points, rerun, compare with an uninterrupted run
# ---------------------------------------------------------------------------------------------

def _interrupt_after(monkeypatch, module, name: str, calls: int) -> list:
    """Replace ``module.name`` by a wrapper that raises KeyboardInterrupt on call number ``calls + 1``."""
    real = getattr(module, name)
    count = []

    def wrapper(*args, **kwargs):
        if len(count) >= calls:
            raise KeyboardInterrupt
        count.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(module, name, wrapper)
    return count


def _one_line(err: str) -> str:
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


FLUXMAP = ["fluxmap", "--rings", "2-3", "--fluxes", "3", "--levels", "2"]


def test_fluxmap_resumes_to_the_same_table(tmp_path, monkeypatch, capsys):
    from hyperlattice.compare import magnetic

    plain = tmp_path / "plain.csv"
    assert main(FLUXMAP + ["--table", str(plain)]) == 0
    capsys.readouterr()

    ck, table = tmp_path / "ck", tmp_path / "resumed.csv"
    with monkeypatch.context() as mp:
        _interrupt_after(mp, magnetic, "_point", 4)
        code = main(FLUXMAP + ["--table", str(table), "--checkpoint", str(ck)])
    line = _one_line(capsys.readouterr().err)
    assert code == 130
    assert line == f"hyperlattice fluxmap: interrupted: 4 of 6 points kept in {ck}; rerun the same command to resume"
    assert len(list(ck.glob("*/fluxmap-point-*.json"))) == 4
    assert not table.exists()

    computed = []
    real = magnetic._point
    monkeypatch.setattr(magnetic, "_point", lambda *a, **k: computed.append(a[2:5:2]) or real(*a, **k))
    assert main(FLUXMAP + ["--table", str(table), "--checkpoint", str(ck)]) == 0
    assert len(computed) == 2                          # only the missing points
    assert table.read_bytes() == plain.read_bytes()


def test_butterfly_resumes_to_the_same_table(tmp_path, monkeypatch, capsys):
    from hyperlattice.graph import butterfly as symmetry   # the module whose sector_table the butterfly calls

    words = ["butterfly", "--rings", "3", "--fluxes", "6"]
    plain = tmp_path / "plain.csv"
    assert main(words + ["--table", str(plain)]) == 0
    capsys.readouterr()

    ck, table = tmp_path / "ck", tmp_path / "resumed.csv"
    with monkeypatch.context() as mp:
        # p = 7 sector blocks per flux value: stop inside the fourth flux value
        _interrupt_after(mp, symmetry, "sector_table", 3 * 7 + 2)
        code = main(words + ["--table", str(table), "--checkpoint", str(ck)])
    line = _one_line(capsys.readouterr().err)
    assert code == 130
    assert line.endswith(f"interrupted: 3 of 6 flux values kept in {ck}; rerun the same command to resume")
    assert len(list(ck.glob("*/butterfly-point-*.json"))) == 3

    count = _interrupt_after(monkeypatch, symmetry, "sector_table", 10**6)
    assert main(words + ["--table", str(table), "--checkpoint", str(ck)]) == 0
    assert len(count) == 3 * 7                         # three flux values left, seven blocks each
    assert table.read_bytes() == plain.read_bytes()


def test_interrupt_without_checkpoint_says_nothing_was_kept(monkeypatch, capsys):
    from hyperlattice.compare import magnetic

    _interrupt_after(monkeypatch, magnetic, "_point", 1)
    assert main(FLUXMAP) == 130
    line = _one_line(capsys.readouterr().err)
    assert line.startswith("hyperlattice fluxmap: interrupted: nothing kept of 6 points (--checkpoint DIR")


def test_a_checkpoint_serves_only_its_own_lattice(tmp_path):
    from hyperlattice.graph.butterfly import butterfly
    from hyperlattice.graph.lattice import line_graph, ring_lattice

    lat = ring_lattice(7, 3, 2)
    f = np.linspace(0.0, 1.0, 3)
    a = butterfly(lat, f, checkpoint=tmp_path)
    b = butterfly(line_graph(lat), f, checkpoint=tmp_path)   # another operator: its own entries
    assert len(list(tmp_path.glob("*/butterfly-point-*.json"))) == 6
    assert np.array_equal(a.energies, butterfly(lat, f).energies)
    assert np.array_equal(b.energies, butterfly(line_graph(lat), f).energies)


def test_a_checkpoint_that_is_a_file_is_refused_in_one_line(tmp_path, capsys):
    afile = tmp_path / "afile"
    afile.write_text("not a directory")
    for words in (FLUXMAP, ["butterfly", "--rings", "2", "--fluxes", "2"]):
        assert main(words + ["--checkpoint", str(afile)]) == 2
        _one_line(capsys.readouterr().err)


# ---------------------------------------------------------------------------------------------
# a real signal, in a real process
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("sig,code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_stops_the_command_with_one_line_and_keeps_the_points(tmp_path, sig, code):
    ck = tmp_path / "ck"
    env = dict(os.environ, HYPERLATTICE_CACHE=str(tmp_path / "cache"))
    cmd = [sys.executable, "-m", "hyperlattice", "butterfly", "--rings", "5", "--fluxes", "5000",
           "--checkpoint", str(ck), "--max-seconds", "1e5"]
    # a shell starts a background job (`make test &`, some CI runners) with SIGINT ignored, and the
    # children inherit that: Python then installs no KeyboardInterrupt handler and the command ran to
    # its end (exit 0). Ctrl-C reaches a foreground command with the default action, as here.
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 120
        while not list(ck.glob("*/butterfly-point-*.json")):
            assert proc.poll() is None, proc.communicate()
            assert time.monotonic() < deadline, "no point was kept within two minutes"
            time.sleep(0.05)
        proc.send_signal(sig)
        out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    assert proc.returncode == code, err
    # l = 5 and 5,000 fluxes (about a minute of work): the run cannot finish between the first kept
    # point and the signal, however loaded the machine; a run that long announces its estimate
    # first, one note line
    note, _, rest = err.partition("\n")
    assert note.startswith("hyperlattice butterfly: note: about ") and " s of work " in note, err
    line = _one_line(rest)
    head, _, tail = line.partition(" of 5000 flux values kept in ")
    assert head.startswith("hyperlattice butterfly: interrupted: ")
    assert tail == f"{ck}; rerun the same command to resume"
    said = int(head.rsplit(" ", 1)[1])
    kept = len(list(Path(ck).glob("*/butterfly-point-*.json")))
    # a point is counted once its file is in place: the signal can land between the two (then the
    # file is there and the count one short), never the other way round
    assert 1 <= said <= kept <= said + 1 < 5000
    assert out == ""


def test_reproduce_counts_its_stages_on_stderr(no_delay, tmp_path, monkeypatch, capsys):
    import hyperlattice.report as report

    def fake(out_dir, max_rings, *, cache, progress):
        for stage in ("Fig1", "Fig2", "Fig3"):  # the report announces each stage as it starts
            progress(stage)
        return {"out_dir": str(out_dir), "sections": [], "seconds": 0.0, "cache_hits": 0, "cache_misses": 0,
                "cache_reused": 0}

    monkeypatch.setattr(report, "reproduce", fake)  # the bar, not the paper, is under test
    args = ["reproduce", "--out", str(tmp_path / "r"), "--max-rings", "2", "--no-cache"]
    assert main(args + ["--progress"]) == 0
    out, err = capsys.readouterr()
    assert "reproduce" in err and "3stage" in err.replace(" ", "") and "Fig3" in err
    assert "reproduce" not in out.split("wrote")[0]
    assert main(args) == 0
    assert capsys.readouterr().err == ""


def test_a_read_only_checkpoint_is_refused_before_any_work(tmp_path, monkeypatch, capsys):
    from hyperlattice.compare import magnetic

    if os.geteuid() == 0:
        pytest.skip("root can write into read-only folders")
    locked = tmp_path / "locked"
    locked.mkdir()
    locked.chmod(0o500)
    count = _interrupt_after(monkeypatch, magnetic, "_point", 10**6)
    assert main(FLUXMAP + ["--checkpoint", str(locked)]) == 2
    assert "not writable" in _one_line(capsys.readouterr().err)
    assert count == []


def test_a_sweep_task_draws_no_bar_even_on_a_terminal(no_delay, monkeypatch):
    from hyperlattice.sweep import tasks

    tty = _Tty()
    monkeypatch.setattr(sys, "stderr", tty)
    monkeypatch.delenv(_progress.ENV, raising=False)
    seen = []
    import dataclasses

    task = dataclasses.replace(tasks.TASKS["probe"], run=lambda **kw: seen.append(_progress.enabled()) or {})
    monkeypatch.setitem(tasks.TASKS, "probe", task)
    tasks.execute("probe", {})
    assert seen == [False] and tty.text == ""


def test_an_interrupted_sweep_says_where_its_rows_are(tmp_path, monkeypatch, capsys):
    import dataclasses

    from hyperlattice.sweep import tasks

    calls, stop = [], [True]

    def probe(x=0.0, sleep=0.0):
        if stop[0] and len(calls) == 2:  # Ctrl-C during the third task
            raise KeyboardInterrupt
        calls.append(x)
        return {"y": x * x}

    monkeypatch.setitem(tasks.TASKS, "probe", dataclasses.replace(tasks.TASKS["probe"], run=probe))
    out = tmp_path / "sw"
    words = ["sweep", "--task", "probe", "--grid", "x=1,2,3,4", "--out", str(out), "--scheduler", "serial"]
    assert main(words) == 130
    assert _one_line(capsys.readouterr().err) == (f"hyperlattice sweep: interrupted: the finished tasks are kept in "
                                                  f"{out}; rerun the same command to resume")
    stop[0] = False
    assert main(words + ["--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["skipped"], summary["completed"]) == (2, 2)


DOS = ["dos", "--rings", "6", "--vectors", "20", "--moments", "64"]


def test_dos_resumes_to_the_same_table(tmp_path, monkeypatch, capsys):
    from hyperlattice.graph import kpm
    from hyperlattice.graph.lattice import ring_lattice

    assert kpm.block_width(ring_lattice(7, 3, 6).sites, 20) == 8
    plain = tmp_path / "plain.csv"
    assert main(DOS + ["--out", str(plain)]) == 0
    capsys.readouterr()

    ck, table = tmp_path / "ck", tmp_path / "resumed.csv"
    with monkeypatch.context() as mp:
        _interrupt_after(mp, kpm, "_chebyshev_moments_block", 2)   # blocks of 8, 8, 4 vectors
        code = main(DOS + ["--out", str(table), "--checkpoint", str(ck)])
    line = _one_line(capsys.readouterr().err)
    assert code == 130
    assert line == (f"hyperlattice dos: interrupted: 2 of 3 blocks of random vectors kept in {ck}; "
                    "rerun the same command to resume")
    assert len(list(ck.glob("*/kpm-block-*.json"))) == 2

    count = _interrupt_after(monkeypatch, kpm, "_chebyshev_moments_block", 10**6)
    assert main(DOS + ["--out", str(table), "--checkpoint", str(ck)]) == 0
    assert len(count) == 1                             # only the last block
    assert table.read_bytes() == plain.read_bytes()


def test_a_dos_checkpoint_serves_only_its_own_operator(tmp_path):
    from hyperlattice.graph.kpm import bulk_dos, kpm_dos
    from hyperlattice.graph.lattice import ring_lattice

    a = bulk_dos(ring_lattice(7, 3, 5), 32, vectors=3, checkpoint=tmp_path)
    b = kpm_dos(ring_lattice(7, 3, 5), 32, vectors=3, checkpoint=tmp_path)   # all sites: another trace
    c = bulk_dos(ring_lattice(7, 3, 5), 32, vectors=3, seed=1, checkpoint=tmp_path)
    assert len(list(tmp_path.glob("*/kpm-block-*.json"))) == 3
    assert np.array_equal(b.mu, kpm_dos(ring_lattice(7, 3, 5), 32, vectors=3).mu)
    assert not np.array_equal(a.mu, b.mu) and not np.array_equal(a.mu, c.mu)


def test_dos_site_takes_no_checkpoint(tmp_path, capsys):
    assert main(["dos", "--rings", "4", "--site", "0", "--checkpoint", str(tmp_path)]) == 2
    assert "--checkpoint" in _one_line(capsys.readouterr().err)


def test_a_serial_sweep_draws_its_bar_when_its_first_task_starts(tmp_path, monkeypatch):
    """``sweep --progress`` in the serial fallback (no Dask): the bar is drawn as the first task starts
    and names the running task, without waiting for the task to end."""
    from hyperlattice.sweep import engine, run_sweep

    tty = _Tty()
    monkeypatch.setattr(engine, "have_dask", lambda: False)
    monkeypatch.setattr(sys, "stderr", tty)
    rep = run_sweep("probe", {"x": [1.0, 2.0]}, tmp_path / "s", progress=True)
    assert rep.scheduler == "serial"
    assert any("0/2" in part and "x=1.0" in part for part in tty.text.split("\r")), tty.text
    assert "2/2" in tty.text


def test_sweep_help_lists_every_task(capsys):
    from hyperlattice.sweep.tasks import TASKS

    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert all(name in text.split("--task TASK")[-1].split("--grid")[0] for name in TASKS), text
    assert "qmc" in text.split("positional arguments")[0]
