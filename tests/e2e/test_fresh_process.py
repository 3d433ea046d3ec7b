"""What a user runs, the way they run it: ``railwear`` started as a new process, killed with
SIGKILL and resumed from a fresh interpreter (no warm registry, no imports shared with the suite).

Each resumed run is compared with an uninterrupted run of the same command (run in this process,
where it costs no start-up), variable by variable and bit for bit (only the ``wall_seconds``
attribute may differ).
"""

import os
import re
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

pytestmark = pytest.mark.e2e

TIMEOUT = 600  # s: a cold numba cache compiles for about a minute
_SCRIPT = shutil.which("railwear", path=str(Path(sys.executable).parent))
COMMAND = [_SCRIPT] if _SCRIPT else [sys.executable, "-m", "railwear"]


def railwear(*args, cwd, check=True):
    """Run ``railwear ARGS`` in a new process in ``cwd``; the completed process."""
    done = subprocess.run([*COMMAND, *map(str, args)], cwd=cwd, capture_output=True, text=True,
                          timeout=TIMEOUT, stdin=subprocess.DEVNULL)
    if check:
        assert done.returncode == 0, f"railwear {' '.join(map(str, args))}: exit {done.returncode}\n{done.stderr[-2000:]}"
        assert "Traceback" not in done.stderr, done.stderr
    return done


def uninterrupted(*args):
    """Run ``railwear ARGS`` in this process (the reference a resumed run must equal)."""
    from typer.testing import CliRunner

    from railwear.cli import app

    done = CliRunner().invoke(app, list(map(str, args)))
    assert done.exit_code == 0, done.output


def killed_at(percent, *args, cwd):
    """Start ``railwear ARGS`` and SIGKILL it once its progress line reaches ``percent``; the
    stderr lines it printed. Fails if the process ends on its own first."""
    process = subprocess.Popen([*COMMAND, *map(str, args)], cwd=cwd, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True)
    lines = []
    try:
        for line in process.stderr:
            lines.append(line)
            match = re.search(r"(\d+)%\s*$", line)
            if match and int(match.group(1)) >= percent:
                process.send_signal(signal.SIGKILL)
                break
        process.wait(timeout=TIMEOUT)
    finally:
        process.kill()
        process.stderr.close()
    assert process.returncode == -signal.SIGKILL, f"ended on its own before {percent}%:\n{''.join(lines)}"
    return lines


def assert_same_result(reference, resumed):
    """Every variable, coordinate and attribute of two result files equal (bit for bit, NaN
    where NaN), but the wall time."""
    with xr.open_dataset(reference) as a, xr.open_dataset(resumed) as b:
        assert set(a.variables) == set(b.variables)
        for name in a.variables:
            x, y = a[name].values, b[name].values
            assert x.dtype == y.dtype and x.shape == y.shape, name
            assert np.array_equal(x, y, equal_nan=x.dtype.kind in "fc"), f"{name} differs after the resume"
        assert set(a.attrs) == set(b.attrs)
        for key in set(a.attrs) - {"wall_seconds"}:
            assert np.array_equal(a.attrs[key], b.attrs[key]), f"attribute {key} differs after the resume"


def dead_pid():
    """The process id of a process that has ended (a writer killed long ago)."""
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def metro_on_the_ring_track(directory):
    """The metro wheel on the time-domain track, direct strategy, 2000 km (a scenario file)."""
    import tomllib

    import tomli_w

    from railwear.scenario import load_scenario, to_toml

    data = tomllib.loads(to_toml(load_scenario("metro")))
    data["solver"].pop("peak_to_peak_limit_mm")
    data["solver"].update(t_end=0.02, points=256)
    data["strategy"] = {"kind": "direct", "acceleration_factor": 2e4}
    path = directory / "metro-ring.toml"
    path.write_text(tomli_w.dumps(data), encoding="utf-8")
    return path.name


# scenario (a built-in name, or a function writing a file), --set fields, the kill points (% of
# the run) of the first run and of each resume
CASES = {
    "stepwise": ("stepwise", (), (10, 40, 70, 90)),
    "direct": ("direct", (), (50,)),
    "vehicle-track-direct": (metro_on_the_ring_track, (), (50,)),
    "phenomenological-batch": ("onset", ("operation.speed_kmh=[170.0, 190.0]", "solver.points=256"), (30,)),
    # the multiplier's [solver] defaults round-trip through the checkpoint's scenario (it was refused)
    "multiplier": ("metro", ("strategy.kind=multiplier",), (10, 20)),
}


@pytest.mark.parametrize("case", list(CASES))
def test_killed_run_resumes_to_the_same_result(case, tmp_path):
    """Run → SIGKILL → ``railwear resume`` (itself killed where several points are given) → the
    uninterrupted run's ``result.nc``, bit for bit; a killed writer's temporary file in the folder
    is removed, and said so."""
    scenario, sets, kills = CASES[case]
    scenario = scenario(tmp_path) if callable(scenario) else scenario
    options = [a for s in sets for a in ("--set", s)]
    uninterrupted("run", tmp_path / scenario if callable(CASES[case][0]) else scenario, "-o", tmp_path / "reference",
                  "--no-figures", *options)
    out = tmp_path / "killed"
    killed_at(kills[0], "run", scenario, "-o", out, "--no-figures", "--checkpoint-every", "0", *options, cwd=tmp_path)
    for percent in kills[1:]:
        assert (out / "checkpoint.npz").is_file()
        killed_at(percent, "resume", out, "--no-figures", "--checkpoint-every", "0", cwd=tmp_path)
    assert (out / "checkpoint.npz").is_file()
    stale = out / f".checkpoint.npz.{dead_pid()}.0123abcd.part"
    stale.write_bytes(b"PK\x03\x04 cut short")  # a checkpoint write killed halfway
    done = railwear("resume", out, "--no-figures", cwd=tmp_path)
    # the SIGKILL itself may land during a checkpoint write and leave a .part of its own: 1 or 2
    assert re.search(r"removed [12] temporary file", done.stderr) and not stale.exists()
    assert not list(out.glob(".*.part")), "a temporary file is left after the resume"
    assert not (out / "checkpoint.npz").exists()
    assert_same_result(tmp_path / "reference" / "result.nc", out / "result.nc")


def test_sweep_killed_between_points_resumes_and_plots(tmp_path):
    """A sweep killed after its first point continues where it stopped (the stored point is not
    run again) to the uninterrupted sweep's table; ``railwear plot`` draws it in a new process."""
    args = ["sweep", "stable", "--vary", "operation.speed_kmh=20:60:20", "--no-batch", "--workers", "1",
            "--set", "solver.points=64"]
    uninterrupted(*args, "-o", tmp_path / "reference")
    out = tmp_path / "killed"
    killed_at(30, *args, "-o", out, cwd=tmp_path)
    first = {p.name: p.stat().st_mtime_ns for p in (out / "points").glob("*.nc")}
    assert 1 <= len(first) < 3
    railwear(*args, "-o", out, cwd=tmp_path)
    assert all((out / "points" / name).stat().st_mtime_ns == t for name, t in first.items())
    assert_same_result(tmp_path / "reference" / "sweep.nc", out / "sweep.nc")
    (out / "sweep.png").unlink()
    railwear("plot", out / "sweep.nc", cwd=tmp_path)
    assert (out / "sweep.png").stat().st_size > 0


def test_forecast_stability_and_hunting_map_files_plot_in_a_new_process(tmp_path):
    """``forecast`` on a measured CSV, ``stability`` and ``hunting-map``, each file drawn again
    by ``railwear plot`` in its own process."""
    angle = np.arange(0.0, 360.0, 5.0)
    deviation = 20 * np.cos(np.radians(8 * angle)) + 5 * np.cos(np.radians(3 * angle))
    (tmp_path / "wheel.csv").write_text("angle_deg,deviation_um\n" + "".join(
        f"{a:g},{d:.4f}\n" for a, d in zip(angle, deviation)), encoding="utf-8")
    done = railwear("forecast", "wheel.csv", "--scenario", "metro", "--limit", "0.1mm", "--samples", "8",
                    "-o", "fc", cwd=tmp_path)
    assert "reached after" in done.stdout
    railwear("stability", "onset", "--speeds", "100:300:100", "-o", "st", cwd=tmp_path)
    railwear("hunting-map", "--conicity", "0.1:0.3:0.1", "--yaw-stiffness", "1e6:3e6:1e6", "-o", "hm", cwd=tmp_path)
    for nc, png in (("fc/forecast.nc", "fc/forecast.png"), ("st/stability.nc", "st/stability.png"),
                    ("hm/hunting.nc", "hm/hunting.png")):
        (tmp_path / png).unlink()
        railwear("plot", nc, cwd=tmp_path)
        assert (tmp_path / png).stat().st_size > 0, png
