"""Bad input for the sector-only flakes (graph/sectors.py): one plain ValueError sentence each."""

import pytest

from badinput import api_cases, check_api
from hyperlattice.graph.sectors import flake_memory, lowest_pair, lowest_sector_levels, sector_block, sector_lattice

_SLAT = sector_lattice(7, 3, 3)

CASES = [
    ("sector_lattice", sector_lattice, {"p": 7, "q": 3, "rings": 3, "coordinates": False, "max_bytes": 10**9}, {"coordinates": {"bool"}, "max_bytes": {"none"}}),
    ("sector_block", sector_block, {"slat": _SLAT, "m": 1, "mirror": "real", "t": 1.0, "shift": 0.0},
     {"mirror": {"none"}}),
    ("lowest_pair", lowest_pair, {"p": 7, "q": 3, "rings": 3, "t": 1.0, "tol": 1e-10, "backend": "auto",
                                  "max_bytes": 10**9}, {"max_bytes": {"none"}}),
    ("lowest_sector_levels", lowest_sector_levels, {"p": 7, "q": 3, "rings": 3, "levels": 3, "t": 1.0,
                                                    "tol": 1e-10, "backend": "auto", "max_bytes": 10**9},
     {"max_bytes": {"none"}}),
    ("flake_memory", flake_memory, {"p": 7, "q": 3, "rings": 3}, {}),
]


@pytest.mark.parametrize("func,good,arg,value", list(api_cases(CASES)))
def test_api(func, good, arg, value):
    check_api(func, good, arg, value)


@pytest.mark.parametrize("kwargs", [{"m": 1, "mirror": "even"}, {"m": 9}, {"m": 0, "mirror": "sideways"}])
def test_sector_block_refuses_wrong_sector_or_mirror(kwargs):
    with pytest.raises(ValueError):
        sector_block(_SLAT, **kwargs)


def test_lowest_pair_refuses_a_non_sector_lattice_and_a_negative_hopping():
    with pytest.raises(ValueError, match="SectorLattice"):
        lowest_pair(sectors="not a lattice")
    with pytest.raises(ValueError):
        lowest_pair(7, 3, 3, t=-1.0)
