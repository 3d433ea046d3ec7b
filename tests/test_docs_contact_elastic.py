"""docs/contact_elastic.py --quick: the elastic half-space reference on S1002/UIC60 runs, draws
its figure, and shows what docs/contact.md says of it (coarse grid, 0.3 mm elements)."""

import io

import numpy as np
import pytest
from helpers import doc_script


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("elastic") / "contact-elastic-y0.png"
    printed = io.StringIO()
    res = doc_script("contact_elastic.py").main(quick=True, output=out, out=printed)
    return res, out, printed.getvalue()


def test_figure_and_tables(run):
    res, out, printed = run
    assert out.stat().st_size > 20_000
    assert printed.count("| +0.0 |") == 4 and printed.count("| +4.9 |") == 8  # reference and errors


def test_centred_running_is_one_patch_wider_than_the_published_one(run):
    """y = 0: the elastic solution on railwear's geometry joins the two minima into one patch
    (about 20 mm wide, b 9.9-10.1 mm against the published 6.65 mm; a 4.5-4.6 against 5.95 mm),
    carrying 76-80 % of the load on the field side of the watershed (the models: 69-70 %)."""
    res, _, _ = run
    (row,) = [r for r in res["rows"] if r["y"] == 0.0]
    (whole,) = row["whole"]
    assert 9.6e-3 < whole[3] < 10.3e-3 and 4.3e-3 < whole[2] < 4.8e-3
    main = row["elastic"][0]
    assert 0.76 < main["share"] < 0.80 and main["y"] > 0
    assert row["elastic"][0]["patch"] == row["elastic"][1]["patch"]
    assert sum(p["share"] for p in row["elastic"]) == pytest.approx(1.0, rel=1e-9)
    for model in ("multi-hertz", "semi-hertzian"):
        assert 0.68 < res["rows"][0]["models"][model][0]["share"] < 0.71


def test_flange_sharing_in_own_planes_and_in_one(run):
    """y = 4.9 mm: tread and flange share about 58 / 42 % in both formulations; in their own
    planes (no interaction) the tread patch runs into the cut, in one plane it stops short of it."""
    res, _, _ = run
    own, one = [r for r in res["rows"] if r["y"] == pytest.approx(4.9e-3)]
    assert own["planes"] == "own" and one["planes"] == "one"
    for r in (own, one):
        shares = [p["share"] for p in r["elastic"]]
        assert shares[0] == pytest.approx(0.58, abs=0.03) and sum(shares) == pytest.approx(1.0, rel=1e-6)
    assert any(p["border"] for p in own["elastic"]) and not any(p["border"] for p in one["elastic"])
    assert one["approach"] > own["approach"]  # the patches' interaction adds to the approach


def test_semi_hertzian_outline_is_the_tables_patch(run):
    """The outline drawn for the semi-hertzian patches, rebuilt from the table's ε and B_eff on
    this script's gap, has the table's largest half-length (2 %)."""
    res, _, _ = run
    for o in res["outlines"]:
        assert np.max(o["L"]) == pytest.approx(o["half_length"], rel=0.02)
