"""Bad input of every kind is refused in one line with exit status 2 and nothing written; the
output folder is written only through temporary files renamed into place (issue 14)."""

import os
import stat

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import results
from railwear.cli import app
from railwear.errors import CheckpointError, MeasuredFileError, ScenarioError
from railwear.longterm.base import Checkpoint, rng_from_text
from railwear.measured import read_measured
from railwear.scenario import builtin_text, load_scenario

ONSET = builtin_text("onset")
LINEAR = builtin_text("linear-dynamics")


def refused(args, *named, out=None):
    """Run the command; assert exit 2, one line naming each of ``named``, no traceback and no file
    in ``out``."""
    result = CliRunner().invoke(app, [str(a) for a in args])
    result_lines = [line for line in result.output.splitlines() if not line.startswith("compiling kernels")]
    assert result.exit_code == 2, (result.output, result.exception)
    assert "Traceback" not in result.output and len(result_lines) == 1, result.output
    for name in named:
        assert name in result.output, result.output
    if out is not None:
        assert not out.exists() or not any(out.rglob("*")), list(out.rglob("*"))
    return result.output


def edit(text, old, new):
    assert old in text, old
    return text.replace(old, new)


@pytest.mark.parametrize("text, field", [
    (edit(ONSET, "radius_m = 0.46", "radius_m = 1e-30"), "wheel.radius_m"),
    (edit(ONSET, "radius_m = 0.46", "radius_m = 1e-300"), "wheel.radius_m"),
    (edit(ONSET, "radius_m = 0.46", "radius_m = true"), "wheel.radius_m"),
    (edit(ONSET, "points = 1024", "points = 1024.0"), "solver.points"),
    (edit(ONSET, "speed_kmh = 190.0", "speed_kmh = 1e300"), "operation.speed_kmh"),
    (edit(ONSET, "n_save = 101", "n_save = 101\ndt = 1e-12"), "dt"),
    (edit(ONSET, 'form = "disk_contact"', 'form = "disk_contact"\ndrift_rad = []'), "drift_rad"),
    (edit(ONSET, 'form = "disk_contact"', 'form = "cubic"\nc1 = 1e300'), "wear_rate.c1"),
    (edit(ONSET, 'name = "onset"', 'name = "on\\u0000set"'), "name"),
    (edit(ONSET, "life_distance_km = 50000.0", "life_distance_km = 1e300"), "operation.life_distance_km"),
    (edit(LINEAR, "primary_stiffness_N_m = 1.2e6", "primary_stiffness_N_m = 1e300"), "body.primary_stiffness_N_m"),
    ("x = " + "[" * 5000 + "]" * 5000, "nested too deeply"),
])
def test_absurd_or_contradictory_scenario_is_refused_naming_the_field(tmp_path, text, field):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ScenarioError, match=field):
        load_scenario(path)
    refused(["run", path, "-o", tmp_path / "out"], field, out=tmp_path / "out")


def test_a_latin1_scenario_is_refused_naming_line_and_column(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_bytes(edit(ONSET, 'name = "onset"', 'name = "Pr\u00fcfstand"').encode("latin-1"))
    message = refused(["run", path, "-o", tmp_path / "out"], "bad.toml", "not UTF-8", out=tmp_path / "out")
    line = 1 + ONSET[:ONSET.index('name = "onset"')].count("\n")
    assert f"line {line}, column 11" in message  # the ü of name = "Prüfstand"


@pytest.mark.parametrize("change, field", [
    (("mass_kg = 1022.0", "mass_kg = true"), "mass_kg"),
    (("mass_kg = 1022.0", "mass_kg = 1e300"), "mass_kg"),
    (("speeds_kmh = [180.0, 280.0]", "speeds_kmh = []"), "run.speeds_kmh"),
    (('name = "hunting"', 'name = "a\\u0000"'), "name"),
])
def test_a_bad_dynamics_scenario_is_refused(tmp_path, change, field):
    from railwear.scenario import dynamics

    path = tmp_path / "bad.toml"
    path.write_text(edit((dynamics._builtin_dir() / "hunting.toml").read_text(), *change))
    refused(["simulate", path, "-o", tmp_path / "out"], field, out=tmp_path / "out")


def _wheel(rows=None, header="angle_deg,deviation_um"):
    angles = np.arange(0.0, 360.0, 10.0)
    lines = [header] + [f"{a:g},{10 * np.cos(np.radians(3 * a)):.3f}" for a in angles]
    for i, row in (rows or {}).items():
        lines[i] = row
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("text, where", [
    (_wheel({3: "20,1_0"}), "line 4, column 2"),
    (_wheel({3: "20,0,5"}), "line 4: 3 cells"),  # a decimal comma in a comma-separated file
    (_wheel({3: "20,inf"}), "line 4, column 2"),
    (_wheel({3: "20,0x10"}), "line 4, column 2"),
    (_wheel({3: "20,\u0661\u0662"}), "line 4, column 2"),  # Arabic-Indic digits, which float() takes
    (_wheel({36: "370,1.0"}), "line 37, column 1"),
    (_wheel({1: "-10,1.0"}), "line 2, column 1"),
    (_wheel({5: "40,2000000"}), "line 6, column 2"),  # a 2 m deviation
    (_wheel({5: "40,1\x00"}), "line 6"),
])
def test_a_bad_measured_wheel_names_file_line_and_column(tmp_path, text, where):
    path = tmp_path / "wheel.csv"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(MeasuredFileError, match="wheel.csv"):
        read_measured(path)
    refused(["forecast", path, "--scenario", "forecast", "-o", tmp_path / "out"], "wheel.csv", where,
            out=tmp_path / "out")


def test_a_measured_wheel_in_latin1_is_refused_and_one_with_a_bom_is_read(tmp_path):
    path = tmp_path / "wheel.csv"
    path.write_bytes(("# Pr\u00fcfstand\n" + _wheel()).encode("latin-1"))
    with pytest.raises(MeasuredFileError, match="line 1, column 5: not UTF-8"):
        read_measured(path)
    path.write_bytes(_wheel().encode("utf-8-sig"))
    angle, deviation = read_measured(path)
    assert angle.size == 36 and deviation[0] == pytest.approx(10e-6)


@pytest.mark.parametrize("args, name", [
    (["--samples", "0"], "samples"),
    (["--seed", "-1"], "seed"),
    (["--limit", "infmm"], "--limit"),
    (["--limit", "1_0mm"], "--limit"),
    (["--horizon-km", "inf"], "--horizon-km"),
    (["--angle-unit", "grad"], "angle_unit"),
])
def test_bad_forecast_options_exit_2(tmp_path, args, name):
    path = tmp_path / "wheel.csv"
    path.write_text(_wheel())
    refused(["forecast", path, "--scenario", "forecast", *args, "-o", tmp_path / "out"], name, out=tmp_path / "out")


@pytest.mark.parametrize("args, name", [
    (["stability", "onset", "--speeds", "nan"], "--speeds"),
    (["stability", "onset", "--orders", "1:1e12:1"], "--orders"),
    (["run", "onset", "--checkpoint-every", "nan"], "--checkpoint-every"),
    (["sweep", "onset", "--vary", "operation.speed_kmh=100,200", "--samples", "2", "--seed", "-1"], "--seed"),
    (["hunting-map", "--conicity", "0.1:0.2:0"], "--conicity"),
])
def test_bad_options_exit_2(tmp_path, args, name):
    refused([*args, "-o", tmp_path / "out"], name, out=tmp_path / "out")


def _ill_posed(tmp_path):
    path = tmp_path / "ill.toml"
    path.write_text(edit(edit(ONSET, "epsilon = 1e-4", "epsilon = 0.0"), "nu = 1e-3", "nu = 0.0"))
    return path


def test_a_planted_link_is_replaced_not_written_through(tmp_path):
    """A link named like an output (pointing outside the folder) is replaced by the file."""
    outside = tmp_path / "outside.npy"
    outside.write_bytes(b"precious")
    out = tmp_path / "out"
    out.mkdir()
    (out / "last_good_state.npy").symlink_to(outside)
    result = CliRunner().invoke(app, ["run", str(_ill_posed(tmp_path)), "-o", str(out)])
    assert result.exit_code == 1, result.output
    assert outside.read_bytes() == b"precious"
    kept = out / "last_good_state.npy"
    assert not kept.is_symlink() and np.all(np.isfinite(np.load(kept)))
    assert os.stat(kept).st_mode & stat.S_IRGRP or os.umask(os.umask(0)) & stat.S_IRGRP


def test_every_write_is_a_rename_and_group_readable(tmp_path):
    outside = tmp_path / "outside.txt"
    outside.write_text("precious")
    (tmp_path / "out").mkdir()
    link = tmp_path / "out" / "summary.txt"
    link.symlink_to(outside)
    old = os.umask(0o022)
    try:
        results.write_text("new", link)
    finally:
        os.umask(old)
    assert outside.read_text() == "precious" and not link.is_symlink() and link.read_text() == "new"
    assert stat.S_IMODE(os.stat(link).st_mode) == 0o644
    assert [p.name for p in (tmp_path / "out").iterdir()] == ["summary.txt"]


def test_leftover_temporaries_are_cleaned_and_never_read(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    dead = out / ".result.nc.999999999.0a1b2c3d.part"  # no process has that id
    dead.write_bytes(b"half a file")
    alive = out / f".result.nc.{os.getpid()}.0a1b2c3d.part"
    alive.write_bytes(b"being written")
    with pytest.raises(ScenarioError, match="temporary"):
        results.read_netcdf(dead)
    assert results.clean_partial(out) == [dead.name]
    assert alive.exists() and not dead.exists()
    dead.write_bytes(b"half a file")
    result = CliRunner().invoke(app, ["resume", str(out)])
    notice, error = result.output.splitlines()  # what was removed is said, then the one-line refusal
    assert result.exit_code == 2 and "removed 1 temporary file(s)" in notice and dead.name in notice
    assert error.startswith("railwear: error:") and "no checkpoint" in error
    assert not dead.exists()


@pytest.fixture(scope="module")
def checkpointed(tmp_path_factory):
    """A folder with the checkpoint of a stopped stepwise run (the driver's fields)."""
    import railwear

    out = tmp_path_factory.mktemp("stopped")
    text = builtin_text("stepwise")
    railwear.run(load_scenario_text(text), checkpoint_path=out / "checkpoint.npz", checkpoint_every=0)
    return out / "checkpoint.npz"


def load_scenario_text(text):
    from railwear.scenario import parse_scenario

    return parse_scenario(text)


def _edited(checkpoint, tmp_path, **changes):
    with np.load(checkpoint) as data:
        fields = {k: data[k] for k in data.files}
    for k, v in changes.items():
        if v is None:
            fields.pop(k)
        else:
            fields[k] = np.asarray(v)
    out = tmp_path / "out"
    out.mkdir(exist_ok=True)
    np.savez(out / "checkpoint.npz", **fields)
    return out


@pytest.mark.parametrize("changes, why", [
    ({"field_u": None}, "field u is missing"),
    ({"field_u": np.array(["a", "b"])}, "field u is <U1"),
    ({"field_steps": np.array([1.5])}, "field steps"),
    ({"field_rng_state": '{"bit_generator": "MT19937", "state": {}}'}, "random generator"),
    ({"field_rng_state": '{"bit_generator": "__class__"}'}, "random generator"),
    ({"field_extra": np.zeros(3)}, "unknown field"),
    ({"checkpoint_kind": "Strategy"}, "unknown strategy"),
    ({"field_u": np.full(64, np.nan)}, "not finite"),
])
def test_an_edited_checkpoint_is_refused_in_one_line(checkpointed, tmp_path, changes, why):
    out = _edited(checkpointed, tmp_path, **changes)
    with pytest.raises(CheckpointError, match=why):
        results.read_checkpoint(out / "checkpoint.npz")
    refused(["resume", out], why)


def test_a_truncated_checkpoint_is_refused(checkpointed, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "checkpoint.npz").write_bytes(checkpointed.read_bytes()[:300])
    refused(["resume", out], "cannot be read")


def test_the_checkpoint_of_an_earlier_run_is_not_resumed(checkpointed, tmp_path):
    """A new run in the folder replaces the earlier run's checkpoint; if it is stopped before its
    own first checkpoint, resume finds none rather than completing the earlier run."""
    out = _edited(checkpointed, tmp_path)
    assert CliRunner().invoke(app, ["run", str(_ill_posed(tmp_path)), "-o", str(out)]).exit_code == 1
    refused(["resume", out], "no checkpoint")


def test_rng_state_from_text_allows_only_pcg64():
    with pytest.raises(CheckpointError):
        rng_from_text('{"bit_generator": "SFC64", "state": {}}')
    with pytest.raises(CheckpointError):
        rng_from_text("[" * 100000)
    good = np.random.default_rng(3)
    from railwear.longterm.base import rng_state_text

    assert rng_from_text(rng_state_text(good)).random() == np.random.default_rng(3).random()


def test_checkpoint_fields_of_the_evolution_solver_are_checked(tmp_path):
    import railwear

    text = edit(edit(ONSET, "points = 1024", "points = 64"), "t_end = 1.0", "t_end = 0.02")
    path = tmp_path / "cp.npz"
    railwear.run(load_scenario_text(text), checkpoint_path=path, checkpoint_every=0)
    with np.load(path) as data:
        fields = {k: data[k] for k in data.files if k not in ("scenario", "scenario_hash")}
    Checkpoint.from_plain(fields)
    with pytest.raises(CheckpointError, match="inconsistent shapes"):
        Checkpoint.from_plain({**fields, "field_times": fields["field_times"][:-1]})
    with pytest.raises(CheckpointError, match="halvings is missing"):
        Checkpoint.from_plain({k: v for k, v in fields.items() if k != "field_halvings"})


def test_a_sweep_records_a_bad_point_and_recomputes_a_cut_file(tmp_path):
    from railwear.sweep import SerialExecutor, parse_vary, point_key, run_sweep, with_values

    text = edit(edit(ONSET, "points = 1024", "points = 64"), "n_save = 101", "n_save = 11")
    base = load_scenario_text(text)
    varies = [parse_vary("operation.speed_kmh=100,2000,140")]
    ds = run_sweep(base, varies, tmp_path, executor=SerialExecutor(), batch=False)
    assert list(ds.regime.values[[0, 2]]) != ["failed", "failed"] and ds.regime.values[1] == "failed"
    assert "operation.speed_kmh" in str(ds.error.values[1]) and str(ds.error.values[0]) == ""
    point = tmp_path / "points" / f"{point_key(with_values(base, {'operation.speed_kmh': 140.0}))}.nc"
    point.write_bytes(point.read_bytes()[:200])
    again = run_sweep(base, varies, tmp_path, executor=SerialExecutor(), batch=False)
    assert float(again.maxima[2]) == float(ds.maxima[2]) and results.read_netcdf(point).sizes


def test_the_workers_of_a_killed_sweep_exit(tmp_path):
    """``kill -9`` of the process running a sweep: its local workers exit instead of going on."""
    import signal
    import subprocess
    import sys
    import time

    script = ("import os, sys, time\nfrom railwear.sweep import LocalExecutor\nex = LocalExecutor(1)\n"
              "print(*[p.pid for p in ex.pool._processes.values()], flush=True)\ntime.sleep(60)\n")
    parent = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    workers = [int(p) for p in parent.stdout.readline().split()]
    assert workers
    parent.send_signal(signal.SIGKILL)
    parent.wait()
    for _ in range(40):
        alive = []
        for pid in workers:
            try:
                os.kill(pid, 0)
                alive.append(pid)
            except ProcessLookupError:
                pass
        if not alive:
            break
        time.sleep(0.25)
    assert not alive
