"""docs/track.md: the worked example prints what its comments say; the figure script runs."""

from helpers import doc_blocks, doc_script, run_doc_block


def test_worked_example_prints_what_it_says():
    (code,) = doc_blocks("track.md")
    printed, expected = run_doc_block(code, "track.md")
    assert printed == expected and len(expected) == 5


def test_figure_script_runs(tmp_path):
    module = doc_script("track_figure.py")
    out = tmp_path / "receptance.png"
    fpp, fp2, f_track = module.main(out)
    assert out.stat().st_size > 10_000
    assert abs(fpp - 1067.3) < 1 and 40 < fp2 < 60 and 60 < f_track < 90
