"""docs/outputs.md: the worked example prints what its comments say; the figure script runs and
its numbers are the ones the text quotes."""

import numpy as np
import pytest

from helpers import doc_blocks, doc_script, run_doc_block


def test_worked_example_prints_what_it_says():
    (code,) = doc_blocks("outputs.md")
    printed, expected = run_doc_block(code, "outputs.md")
    assert printed == expected and len(expected) == 6


def test_figure_script_runs(tmp_path):
    levels, over = doc_script("outputs_figure.py").main(tmp_path)
    for name in ("polygonalisation-spectrum.png", "polygonalisation-polar.png"):
        assert (tmp_path / name).stat().st_size > 20_000
    assert int(over.count) == 7
    np.testing.assert_allclose(over.wavelength[over.exceeds], [0.4, 0.315, 0.25, 0.2, 0.16, 0.125, 0.1])
    assert np.min(over.excess[over.exceeds]) == pytest.approx(0.4, abs=0.05)
    assert np.max(over.excess[over.exceeds]) == pytest.approx(13.4, abs=0.05)
    assert np.sum(levels.mean_square) > 0
