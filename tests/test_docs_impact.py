"""docs/impact_figure.py, short: the metro wheel grown to 0.1 and 0.5 mm is rolled at one speed,
both tables print and both figures are drawn; docs/maintenance.md shows them."""

from pathlib import Path

import numpy as np
from helpers import doc_script

DOCS = Path(__file__).resolve().parents[1] / "docs"


def test_the_figure_script_runs_short_and_the_page_shows_its_figures(tmp_path, capsys):
    loads = doc_script("impact_figure.py").main(["--out", str(tmp_path), "--speeds", "70", "--revolutions", "1"])
    printed = capsys.readouterr().out
    assert printed.count("dynamic wheel load of metro") == 2 and "metro-0.5mm.nc" in printed
    for name in ("impact-peak.png", "impact-trace.png"):
        assert (tmp_path / name).stat().st_size > 20_000
        assert f"(figures/{name})" in (DOCS / "maintenance.md").read_text(encoding="utf-8")
    small, grown = (float(loads[k].peak_force.values[0]) for k in (0.1, 0.5))
    assert np.isclose(loads[0.5].attrs["transient_s"], 1.0) and 75e3 < small < grown < 160e3
