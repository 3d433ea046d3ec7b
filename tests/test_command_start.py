"""The command's start: the garbage collector's full passes held while it imports, and restored
(with what was imported frozen out of later passes) when its computation starts."""

import gc

from railwear import cli


def test_full_collections_held_at_the_start_and_restored_when_the_computation_starts():
    before, frozen = gc.get_threshold(), gc.get_freeze_count()
    try:
        cli._full_collections(False)  # as main() does
        held = gc.get_threshold()
        assert held[:2] == before[:2] and held[2] >= 1 << 30
        with cli._Progress("railwear test"):
            assert gc.get_threshold() == before
        assert gc.get_freeze_count() > frozen
        cli._full_collections(True)  # once only: a second computation changes nothing
        assert gc.get_threshold() == before
    finally:
        gc.unfreeze()
        gc.set_threshold(*before)
        cli._state.pop("collector", None)


def test_a_computation_in_a_test_process_leaves_the_collector_alone():
    before, frozen = gc.get_threshold(), gc.get_freeze_count()
    with cli._Progress("railwear test") as progress:  # a computation that does nothing
        assert progress is not None
    assert gc.get_threshold() == before and gc.get_freeze_count() == frozen


def _imported(*args, cwd):
    """Run ``python -X importtime -m railwear ARGS`` in a fresh interpreter; the names of the
    modules it imported (exit status 0 asserted)."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-X", "importtime", "-m", "railwear", *map(str, args)], cwd=cwd,
                          capture_output=True, text=True, timeout=600, stdin=subprocess.DEVNULL)
    assert done.returncode == 0, done.stderr[-2000:]
    return {line.split("|")[-1].strip() for line in done.stderr.splitlines() if line.startswith("import time:")}


def test_a_fourier_run_and_plot_leave_the_contact_geometry_and_plot_numba_unimported(tmp_path):
    """``railwear.geometry`` imports its contact geometry (numba, the contact package) on first use:
    the metro run reads only the out-of-roundness modules, and ``railwear plot`` compiles nothing,
    so it does not import numba at all (0.15-0.3 s of its CPU). The metro run loads no compiled
    kernel and imports only the dynamics, track and contact modules it uses."""
    run = _imported("run", "--no-figures", "-o", tmp_path, cwd=tmp_path)
    assert "railwear.geometry.roundness" in run and "railwear.geometry.contact_geometry" not in run
    # the disk wheel's linearisation and steady creepage interpreted: no compiled kernel loaded (numba's
    # registries, which import scipy.linalg), no scipy.optimize; the packages import what is used
    assert "railwear.dynamics.disk_wheel" in run and "railwear.track.receptance" in run
    assert not run & {"numba.np.arraymath", "scipy.linalg", "scipy.optimize", "railwear.dynamics.integration",
                      "railwear.dynamics.wheelset", "railwear.track.modal", "railwear.contact.rolling"}
    plot = _imported("plot", tmp_path / "result.nc", cwd=tmp_path)
    assert "railwear.plots" in plot and (tmp_path / "spectrum.png").is_file()
    assert "numba" not in plot and "railwear.geometry.contact_geometry" not in plot
