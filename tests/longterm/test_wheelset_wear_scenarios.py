"""Wheelset wear from scenario files: the built-in scenario through the command line, a killed run
resumed to the same file, bad fields refused before the run."""

import itertools

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import results
from railwear.cli import app
from railwear.scenario import builtin_text, load_scenario, parse_scenario

NAME = "wheelset-wear"


def edited(tmp_path, *changes):
    """The built-in scenario with ``(old, new)`` text changes, written to a file."""
    text = builtin_text(NAME)
    for old, new in changes:
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / "edited.toml"
    path.write_text(text)
    return str(path)


def killed_run(monkeypatch, runner, scenario, out, k):
    """`railwear run` checkpointing at every step, killed right after the ``k``-th checkpoint."""
    write, count = results.write_checkpoint, itertools.count(1)

    def write_then_die(*args):
        write(*args)
        if next(count) == k:
            raise KeyboardInterrupt

    with monkeypatch.context() as patched:
        patched.setattr(results, "write_checkpoint", write_then_die)
        return runner.invoke(app, ["run", scenario, "-o", str(out), "--no-figures", "--checkpoint-every", "0"])


DIRECT = (('kind = "stepwise"\nstep_limit_um = 1.0\n', 'kind = "direct"\nacceleration_factor = 5000.0\n'),
          ('kind = "wheelset"\nsamples = 2\n', 'kind = "wheelset"\n'), ("t_end = 0.5", "t_end = 0.3"))


def test_the_builtin_runs_through_the_cli(tmp_path):
    """`railwear run wheelset-wear` writes the worn lateral profile over distance, the angular
    pattern, the costs, the summary and the two figures; the wear is spread over the tread (both
    wheels alike), and the surface's volume is the law's."""
    runner = CliRunner()
    assert NAME in runner.invoke(app, ["scenarios"]).output
    shown = runner.invoke(app, ["show", NAME])
    assert shown.exit_code == 0 and parse_scenario(shown.output) == load_scenario(NAME)
    r = runner.invoke(app, ["run", NAME, "-o", str(tmp_path)])
    assert r.exit_code == 0, r.output
    ds = results.read_netcdf(tmp_path / "result.nc")
    assert ds.attrs["body"] == "wheelset" and ds.attrs["strategy"] == "stepwise"
    assert ds.worn_depth.dims == ("time", "wheel", "lateral")
    assert ds.surface_depth.dims == ("wheel", "angle", "lateral")
    assert float(ds.distance[-1]) == pytest.approx(500.0)  # km
    assert int(ds.cost_tables) == ds.sizes["time"] and float(ds.cost_seconds) > 0
    np.testing.assert_allclose(ds.removed_volume.values, ds.law_volume.values, rtol=1e-12)
    final = ds.worn_depth.values[-1]
    assert final.max() > 1e-6
    assert np.count_nonzero(final.mean(0) > 0.1 * final.max()) > 10  # spread over more than 5 mm
    assert not (tmp_path / "checkpoint.npz").exists()
    summary = (tmp_path / "summary.txt").read_text()
    assert "wheelset stepwise: after 500 km" in summary and "band" in summary
    for figure in ("worn-profile.png", "angular-pattern.png"):
        assert (tmp_path / figure).stat().st_size > 1000
    again = runner.invoke(app, ["plot", str(tmp_path / "result.nc"), "-o", str(tmp_path / "again")])
    assert again.exit_code == 0 and (tmp_path / "again" / "worn-profile.png").exists()


@pytest.mark.parametrize("direct, kill_after", [(False, 3), (True, 2)])
def test_a_killed_cli_run_resumes_to_the_same_file(tmp_path, monkeypatch, direct, kill_after):
    """Killed after a checkpoint (written at every step with --checkpoint-every 0), resumed by
    `railwear resume`: every variable of result.nc equals the uninterrupted run's, to the bit."""
    scenario = edited(tmp_path, *DIRECT) if direct else NAME
    runner = CliRunner()
    whole = tmp_path / "whole"
    assert runner.invoke(app, ["run", scenario, "-o", str(whole), "--no-figures"]).exit_code == 0
    killed = tmp_path / "killed"
    r = killed_run(monkeypatch, runner, scenario, killed, kill_after)
    assert r.exit_code != 0 and not (killed / "result.nc").exists()
    state, _, _ = results.read_checkpoint(killed / "checkpoint.npz")
    assert state.steps == kill_after
    r = runner.invoke(app, ["resume", str(killed), "--no-figures"])
    assert r.exit_code == 0, r.output
    a, b = results.read_netcdf(whole / "result.nc"), results.read_netcdf(killed / "result.nc")
    assert a.sizes["time"] > kill_after + 1
    assert set(a.data_vars) == set(b.data_vars)
    for name in a.data_vars:
        np.testing.assert_array_equal(b[name].values, a[name].values, err_msg=name)
    np.testing.assert_array_equal(b.distance.values, a.distance.values)
    assert a.attrs["scenario_hash"] == b.attrs["scenario_hash"]
    assert not (killed / "checkpoint.npz").exists()


@pytest.mark.parametrize("changes, field", [
    ((("step_limit_um = 1.0", "step_limit_um = 0.0"),), "strategy.step_limit_um"),
    ((DIRECT[0], ("acceleration_factor = 5000.0", "acceleration_factor = 0.5")), "strategy.acceleration_factor"),
    ((("step_limit_um = 1.0", "step_limit_um = 1.0\nacceleration_factor = 10.0"),),
     "acceleration_factor: does not apply to kind 'stepwise'"),
    ((("samples = 2", "samples = 2\nrevolutions = 3"),), "body.revolutions: does not apply to kind 'wheelset'"),
    ((("[solver]", "[disk_wheel]\nrail_mass_kg = 100.0\n\n[solver]"),), "disk_wheel: applies to body 'disk_wheel' only"),
    ((('kind = "wheelset"', 'kind = "bogie"'),), "body.kind"),
    ((('kind = "stepwise"', 'kind = "fourier"'),), "strategy.step_limit_um"),
    ((("lateral_cells = 90", "lateral_cells = 1"),), "body.lateral_cells"),
    ((("transient_s = 2.0", "transient_s = -1.0"),), "body.transient_s"),
    ((("lateral_max_mm = 40.0", "lateral_max_mm = -60.0"),), "lateral_min_mm must be below"),
    ((("seconds_per_sample_s = 1.0", "seconds_per_sample_s = 0.0"),), "body.seconds_per_sample_s"),
    ((('wheel_profile = "S1002"', 'wheel_profile = "S1003"'),), "body.wheel_profile"),
    ((("speed_kmh = 216.0", "speed_kmh = [200.0, 216.0]"),), "operation"),
    ((("mass_kg = 1022.0", "mass_kg = -1.0"),), "wheelset.mass_kg"),
])
def test_bad_fields_exit_2_with_one_line_naming_the_field(tmp_path, changes, field):
    r = CliRunner().invoke(app, ["run", edited(tmp_path, *changes), "-o", str(tmp_path / "out")])
    assert r.exit_code == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and field in lines[0] and lines[0].startswith("railwear: error:"), r.stderr
    assert "Traceback" not in r.output
    assert not (tmp_path / "out" / "result.nc").exists()
