"""The figures of ``railwear run``: placed without a layout engine, yet nothing drawn outside the
figure and no axes' labels over another axes, for one speed and for a batch; drawn by forked
processes (``plots.fork_drawers``) to the same files, byte for byte, as drawing them in turn;
nothing drawn when the run sends nothing; a drawer's failure seen in the process that forked it;
and the command itself, started as a new process."""

import filecmp
import os
import shutil
import subprocess
import sys
import threading
from pathlib import Path

import pytest
import xarray as xr

from railwear import api, plots
from railwear.scenario import load_scenario, parse_scenario, to_toml

_SCRIPT = shutil.which("railwear", path=str(Path(sys.executable).parent))
COMMAND = [_SCRIPT] if _SCRIPT else [sys.executable, "-m", "railwear"]


@pytest.fixture(scope="module")
def result():
    return api.run("metro")


@pytest.fixture(scope="module")
def batch():
    text = to_toml(load_scenario("smoothing")).replace("speed_kmh = 120.0", "speed_kmh = [100.0, 150.0, 200.0]")
    return api.run(parse_scenario(text))


@pytest.mark.parametrize("which", ["result", "batch"])
@pytest.mark.parametrize("name", list(plots.FIGURES))
def test_nothing_outside_the_figure_or_over_another_axes(name, which, request):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = plots.FIGURES[name](request.getfixturevalue(which))
    assert fig.get_layout_engine() is None  # placed by margins: constrained layout was a quarter of the drawing
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    width, height = fig.get_size_inches()
    drawn = fig.get_tightbbox(renderer)  # inches: every label, title, tick and legend drawn
    assert drawn.x0 >= 0 and drawn.y0 >= 0 and drawn.x1 <= width and drawn.y1 <= height, (drawn, width, height)
    axes = [ax for ax in fig.axes if ax.get_visible() and ax.axison]
    for ax in axes:
        reach = ax.get_tightbbox(renderer)  # the axes with its labels, in pixels
        for other in axes:
            assert other is ax or not reach.overlaps(other.bbox), (ax.get_title(), other.get_title())


@pytest.fixture(scope="module")
def smoothing():
    return api.run("smoothing")


@pytest.mark.parametrize("which", ["result", "batch", "smoothing"])
@pytest.mark.parametrize("name", list(plots.FIGURES))
def test_tick_labels_apart_and_no_mathtext(name, which, request, monkeypatch):
    """No two tick labels of an axis over each other (the spectrum's band axis once wrote 6x10^0 and
    its minor ticks over the band centres), and no mathtext, whose parser cost 0.1 s a figure."""
    import itertools

    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.mathtext import MathTextParser

    parsed, parse = [], MathTextParser.parse

    def spy(self, text, *args, **kwargs):
        parsed.append(text)
        return parse(self, text, *args, **kwargs)

    monkeypatch.setattr(MathTextParser, "parse", spy)
    fig = plots.FIGURES[name](request.getfixturevalue(which))
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    assert parsed == []
    renderer = canvas.get_renderer()
    for ax in fig.axes + [child for ax in fig.axes for child in ax.child_axes]:
        for k, axis in enumerate((ax.xaxis, ax.yaxis)):
            low, high = sorted(axis.get_view_interval())
            labels = [label for label in axis.get_ticklabels(which="both") if label.get_visible()
                      and label.get_text() and low <= label.get_position()[k] <= high]
            boxes = [label.get_window_extent(renderer) for label in labels]
            for (a, box_a), (b, box_b) in itertools.combinations(zip(labels, boxes), 2):
                assert not (box_a.overlaps(box_b) and np.isfinite([box_a.x0, box_b.x0]).all()), \
                    (ax.get_title(), a.get_text(), b.get_text())


def _drawers():
    drawers = plots.fork_drawers()
    if drawers is None:  # refused where forking is unsafe: threads running in this test process
        assert threading.active_count() > 1 or len(os.sched_getaffinity(0)) < 2
        pytest.skip("forked drawing needs two processors and no other thread")
    return drawers


def test_shares_cover_every_figure_once():
    for count in range(7):
        drawn = [i for k in range(plots.DRAWERS) for i in plots._share(count, k)]
        assert drawn == list(range(count))


def test_forked_drawers_write_what_drawing_in_turn_writes(result, tmp_path):
    drawers = _drawers()
    drawers.send(result, tmp_path / "forked")
    forked = drawers.wait()
    in_turn = plots.write_figures(result, tmp_path / "in_turn")
    assert [p.name for p in forked] == [p.name for p in in_turn] == [f"{n}.png" for n in plots.FIGURES]
    for a, b in zip(forked, in_turn):
        assert filecmp.cmp(a, b, shallow=False), a.name


def test_drawers_closed_unsent_draw_nothing(tmp_path):
    drawers = _drawers()
    drawers.close()
    assert os.waitpid(drawers.pid, 0)[1] == 0
    assert list(tmp_path.iterdir()) == []


def test_a_failing_drawer_is_seen_here(result, tmp_path):
    drawers = _drawers()
    drawers.send(result.drop_vars("u"), tmp_path)  # no figure can be drawn without u
    with pytest.raises(AttributeError, match="u"):
        drawers.wait()


@pytest.mark.e2e
def test_run_in_a_new_process_writes_the_figures_of_its_result(tmp_path):
    done = subprocess.run([*COMMAND, "run", "metro", "-o", str(tmp_path)], capture_output=True, text=True,
                          timeout=600, stdin=subprocess.DEVNULL)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr[-2000:]
    assert (tmp_path / "report.html").stat().st_size > 0
    again = plots.write_figures(xr.load_dataset(tmp_path / "result.nc"), tmp_path / "again")
    for path in again:
        assert filecmp.cmp(path, tmp_path / path.name, shallow=False), path.name
