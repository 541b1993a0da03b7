"""The bad-input harness, shared by ``test_bad_input.py`` and each topic's ``test_bad_input_*.py``.

A topic file lists its public functions as ``CASES`` (id, function, working keyword arguments,
{argument: tags it legitimately accepts}) and its CLI flags as ``CLI_FLAGS`` (subcommand words,
flag, values of :data:`BAD_CLI` that are legitimate), then parametrizes::

    @pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
    def test_api(func, good, arg, value):
        check_api(func, good, arg, value)

    @pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
    def test_cli(words, flag, value, capsys, tmp_path, monkeypatch):
        check_cli(words, flag, value, capsys, tmp_path, monkeypatch)

The contract (README, "Conventions"): bad input gives a ``ValueError`` with one plain sentence
from the API, and one line on stderr with exit code 2 from the CLI, never a traceback.
"""

from __future__ import annotations

import math

import pytest

# the bad values, by tag
BAD = {
    "none": None,
    "nan": math.nan,
    "inf": math.inf,
    "bool": True,
    "str": "seven",
    "ragged": [[1, 2], [3]],
    "object": object(),
    "complex": 1 + 2j,
}

#: bad strings for every numeric CLI flag
BAD_CLI = ["nan", "inf", "abc", "", "1e400", "-1", "0", "1e22", "3.5"]


def api_cases(cases):
    """Yield one pytest.param per (function, argument, bad value) not legitimately accepted."""
    for name, func, good, allowed in cases:
        for arg in good:
            for tag, value in BAD.items():
                if tag in allowed.get(arg, set()):
                    continue
                if tag == "str" and arg in ("path",):
                    continue  # a string is a path; a missing one is tested by the working call
                yield pytest.param(func, good, arg, value, id=f"{name}-{arg}-{tag}")


def check_api(func, good, arg, value) -> None:
    """``func(**good)`` with ``arg`` spoiled must raise a ValueError with one plain sentence."""
    kwargs = dict(good)
    kwargs[arg] = value
    with pytest.raises(ValueError) as info:
        func(**kwargs)
    msg = str(info.value)
    assert msg and "\n" not in msg.strip(), "the message is one plain sentence"
    assert "Traceback" not in msg


def cli_cases(flags):
    """Yield one pytest.param per (subcommand, flag, bad string) not legitimately accepted."""
    for words, flag, ok in flags:
        for value in BAD_CLI:
            if value in ok:
                continue
            yield pytest.param(words, flag, value, id=f"{'-'.join(words[:2])}{flag}={value or 'empty'}")


def check_cli(words, flag, value, capsys, tmp_path, monkeypatch) -> None:
    """``hyperlattice WORDS FLAG=VALUE`` must exit 2 with exactly one line on stderr."""
    from hyperlattice.cli import main

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HYPERLATTICE_CACHE", str(tmp_path / "cache"))
    try:
        code = main(words + [f"{flag}={value}"])
    except SystemExit as exc:  # argparse rejects the value itself
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2, err
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1, err
    assert "Traceback" not in err
