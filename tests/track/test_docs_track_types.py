"""docs/track.md, Track types: the figure script runs and the table states what it computes."""

import math

from helpers import DOCS, doc_script

ROWS = {  # the figure script's label: how the row of the table in docs/track.md starts
    "ballast, single layer (default)": "| ballast, single layer",
    "ballast on subgrade, two layers (zhai-2004)": "| ballast on subgrade",
    "slab, CA 60 MN/m (crts-slab-2019)": "| slab, CA 60",
    "slab, CA 240 MN/m (crts-slab-2021)": "| slab, CA 240",
    "pads on a rigid base": "| pads on a rigid base",
}


def test_figure_script_runs_and_the_table_says_what_it_computes(tmp_path):
    out = tmp_path / "track-types.png"
    results = doc_script("track_types_figure.py").main(out)
    assert out.stat().st_size > 10_000 and set(results) == set(ROWS)
    lines = (DOCS / "track.md").read_text(encoding="utf-8").splitlines()
    for label, r in results.items():
        (row,) = [line for line in lines if line.startswith(ROWS[label])]
        cells = [c.strip() for c in row.split("|")[1:-1]]
        assert cells[2] == f"{r['p2']:.2f}", label
        others = ", ".join(f"{x:.2f}" for x in r["resonances"][1:])
        assert cells[3] == others if others else cells[3].startswith("none"), label
        assert cells[4] == f"{r['static_MN_m']:.1f}", label
        assert cells[5] == f"{r['pinned_pinned']:.1f}, {r['midspan_peak']:.1f}", label
        passing = r["order"] * 70 / 3.6 / (math.pi * 0.84)  # Hz: the metro wheel's order at 70 km/h
        assert cells[6] == f"{r['order']} ({passing:.1f} Hz, {r['growth']:+.3f})", label
