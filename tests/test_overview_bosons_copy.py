"""The bosons paragraph of docs/overview.md (once the README's) quotes numbers that docs/bosons.md checks
(its tables are printed by that page's examples): hold the overview's copy to those tables."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _rows(page: str, first_cell: str) -> list[list[str]]:
    """The cells of the Markdown table rows of ``page`` whose first cell starts with ``first_cell``."""
    return [[c.strip().replace("−", "-") for c in line.strip().strip("|").split("|")]
            for line in page.splitlines() if line.startswith(f"| {first_cell}")]


def _readme_bosons() -> str:
    text = (ROOT / "docs" / "overview.md").read_text(encoding="utf-8")
    return text[text.index("## Interacting bosons"):text.index("**Exact diagonalisation**")]


def test_readme_bosons_numbers_are_the_checked_ones_of_docs_bosons():
    page = (ROOT / "docs" / "bosons.md").read_text(encoding="utf-8")
    readme = " ".join(_readme_bosons().split())
    # rho: the infinite-lattice row of the Mott-lobe table, to the overview's 4 decimals
    (inf,) = _rows(page, "infinite lattice")
    assert f"ρ = {float(inf[1]):.4f}" in readme
    # "to 0.1 % from l = 5 on": every flake/continuum pair of the lobe table from l = 5
    tips = {tuple(r[0].split(" ℓ = ")): float(r[2]) for r in _rows(page, "flake") + _rows(page, "continuum")}
    rings = sorted({int(k[1]) for k in tips if int(k[1]) >= 5})
    assert rings and "to 0.1 % from ℓ = 5 on" in readme
    assert all(abs(tips["continuum", str(n)] / tips["flake", str(n)] - 1) < 1e-3 for n in rings)
    # the GP table's largest flake at U = 0.05 t and 0.5 t: mu within 1 % at xi ~ 1.6 d0, 9 % at xi ~ 0.8 d0
    gp = {(r[0], r[1]): r for r in _rows(page, "0.05 |") + _rows(page, "0.5 |")}
    weak, strong = gp["0.05", "6"], gp["0.5", "6"]
    weak_pct, strong_pct = (float(r[5].rstrip(" %")) for r in (weak, strong))
    m = re.search(r"to (\d+) % while .*?ξ ≈ ([\d.]+) d0 at U = 0\.05 t.*?drifts to (\d+) % at ξ ≈ ([\d.]+) d0 "
                  r"\(U = 0\.5 t\)", readme)
    assert m, "the overview's sentence on the condensate's mu changed: update this test"
    assert abs(weak_pct) <= float(m.group(1)) and f"{float(weak[6]):.1f}" == m.group(2)
    assert f"{abs(strong_pct):.0f}" == m.group(3) and f"{float(strong[6]):.1f}" == m.group(4)
