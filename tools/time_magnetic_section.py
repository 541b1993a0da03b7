"""Time the report's magnetic section alone: once on an empty cache (cold), once on the warm one.

    python tools/time_magnetic_section.py [--keep DIR]

prints the two wall times in seconds and writes the section's figures (``fig_butterfly.png``,
``fig_magnetic_error.png``) to DIR (default: a temporary directory, deleted afterwards).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from hyperlattice.cache import Cache  # noqa: E402
from hyperlattice.report.sections import magnetic_section  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", type=Path, help="write the figures here and keep them")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out = args.keep or Path(tmp) / "out"
        out.mkdir(parents=True, exist_ok=True)
        cache = Cache(Path(tmp) / "cache")
        for label in ("cold", "warm"):
            t0 = time.perf_counter()
            magnetic_section(out, lambda msg: None, cache)
            print(f"{label}: {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
