"""Bad values for the magnetic-flux CLI flags (harness in tests/badinput.py)."""

import pytest
from badinput import check_cli, cli_cases

CLI_FLAGS = [
    (["fluxmap", "--rings", "2"], "--fluxes", set()),
    (["fluxmap", "--rings", "2"], "--fmax", {"0"}),
    (["fluxmap", "--rings", "2"], "--levels", set()),
    (["fluxmap"], "--rings", set()),
    (["butterfly", "--rings", "2"], "--fluxes", set()),
    (["butterfly"], "--rings", set()),
]


@pytest.mark.parametrize("words,flag,value", list(cli_cases(CLI_FLAGS)))
def test_cli_bad_value_exits_2_with_one_line(words, flag, value, capsys, tmp_path, monkeypatch):
    check_cli(words, flag, value, capsys, tmp_path, monkeypatch)
