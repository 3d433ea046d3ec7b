"""The figures of ``railwear run`` drawn by forked processes (``plots.fork_drawers``): the same files,
byte for byte, as drawing them in turn; nothing drawn when the run sends nothing; a drawer's failure
seen in the process that forked it; and the command itself, started as a new process."""

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

_SCRIPT = shutil.which("railwear", path=str(Path(sys.executable).parent))
COMMAND = [_SCRIPT] if _SCRIPT else [sys.executable, "-m", "railwear"]


@pytest.fixture(scope="module")
def result():
    return api.run("metro")


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
