"""The main job end to end: built-in scenarios, results on disk, command line, bad input."""

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import railwear
from railwear import results
from railwear.cli import app
from railwear.errors import IllPosedError, ScenarioError
from railwear.pde import Cubic, Table, solve_evolution
from railwear.scenario import builtin_names, builtin_text, load_scenario, parse_scenario

EXPECTED_REGIME = {"stable": "stable", "smoothing": "smoothing", "onset": "onset",
                   "polygonalisation": "polygonalising", "metro": "polygonalising",
                   # the same 70 km/h wheel by three strategies: order 8 grows 24-47 % per 10 000 km
                   # in each and is the largest at the end (docs/outputs.md, the regime)
                   "linear-dynamics": "polygonalising", "stepwise": "polygonalising", "direct": "polygonalising"}


@pytest.fixture(scope="module")
def runs():
    return {name: railwear.run(name) for name in builtin_names()}


def test_every_builtin_runs_to_its_regime(runs):
    assert set(EXPECTED_REGIME) <= set(runs)
    for name, ds in runs.items():
        if ds.attrs["body"] == "wheelset":
            continue  # the wheelset wear case runs a given distance (tests/longterm/test_wheelset_wear_scenarios.py)
        if name in EXPECTED_REGIME:
            assert str(ds.regime.values) == EXPECTED_REGIME[name], name
        if name in ("linear-dynamics", "stepwise", "direct"):
            assert int(ds.leading_order) == 8, name
        if "peak_to_peak_limit" in ds:  # the metro case runs until it is out of round
            assert float(ds.peak_to_peak) == pytest.approx(float(ds.peak_to_peak_limit), rel=1e-9), name
            continue
        # every other built-in case runs until 1 mm is gone at the most worn spot
        assert float(ds.removed_depth[-1]) == pytest.approx(1e-3, rel=1e-9), name


def test_polygonalisation_ends_with_three_to_eight_maxima(runs):
    assert 3 <= int(runs["polygonalisation"].maxima) <= 8


def test_linear_dynamics_grows_the_p2_order(runs):
    """Fourier strategy: the order whose passing frequency n V / (2π R0) sits just above the P2
    resonance of wheel and rail on the pads, sqrt(k_pad / (m_wheel + m_rail)) / 2π = 47 Hz, wins."""
    ds = runs["linear-dynamics"]
    assert ds.attrs["strategy"] == "fourier"
    order = int(ds.dominant_order)
    frequency = order * float(ds.speed) / (2 * np.pi * 0.46)
    p2 = np.sqrt(1e8 / (1000.0 + 150.0)) / (2 * np.pi)
    assert 7 <= order <= 9 and p2 < frequency < 1.5 * p2


def test_stable_largest_deviation_falls_monotonically(runs):
    u = runs["stable"].u
    largest = np.abs(u - u.mean("angle")).max("angle").values
    assert np.all(np.diff(largest) <= 0)
    assert largest[-1] < largest[0]


def test_result_roundtrip_netcdf(runs, tmp_path):
    ds = runs["onset"]
    path = results.write_netcdf(ds, tmp_path / "r.nc")
    back = results.read_netcdf(path)
    np.testing.assert_array_equal(back.u.values, ds.u.values)
    assert back.attrs["scenario_hash"] == ds.attrs["scenario_hash"]
    assert back.attrs["railwear_version"] == railwear.__version__
    assert parse_scenario(back.attrs["scenario"]) == load_scenario("onset")
    for name, var in back.variables.items():
        assert "long_name" in var.attrs, name
    assert back.u.attrs["units"] == "m"
    assert not list(tmp_path.glob(".*part"))


def test_batch_of_speeds_matches_single_runs():
    x = 2 * np.pi * np.arange(128) / 128
    u0 = 3e-5 * np.cos(4 * x) + 2e-5 * np.sin(9 * x)
    disk = railwear.pde.DiskContact()
    speeds = np.array([60.0, 200.0]) / 3.6
    batch = solve_evolution(u0, 0.2, disk, speeds, 1e-4, 1e-3, n_save=3, dt=2e-4)
    for i, v in enumerate(speeds):
        single = solve_evolution(u0, 0.2, disk, v, 1e-4, 1e-3, n_save=3, dt=2e-4)
        np.testing.assert_allclose(batch.u.isel(speed=i).values, single.u.values, rtol=0, atol=1e-15)


def test_table_form_reproduces_cubic_and_speed_interpolation():
    s = np.linspace(-0.01, 0.01, 21)
    cubic = Cubic(c0=-1e-3, c1=0.02, c3=-30.0)
    table = Table(s, cubic(s))
    probe = np.linspace(-0.009, 0.009, 7)
    np.testing.assert_allclose(table(probe), cubic(probe), rtol=1e-9, atol=1e-15)
    two = Table(s, np.stack([cubic(s), 3 * cubic(s)], axis=1), speed=np.array([10.0, 30.0]))
    np.testing.assert_allclose(two(probe, speed=20.0), 2 * cubic(probe), rtol=1e-9, atol=1e-15)
    with pytest.raises(ScenarioError, match="outside"):
        two(probe, speed=40.0)


def test_unregularised_ill_posed_run_is_detected():
    x = 2 * np.pi * np.arange(64) / 64
    with pytest.raises(IllPosedError, match="ill-posed"):
        solve_evolution(1e-5 * np.cos(3 * x), 1.0, Cubic(c1=-0.1), 0.0)


def test_ill_posedness_met_during_the_run_is_detected_not_written_as_nan():
    """Well-posed at the start; backward-parabolic once 0.5 mm has gone."""
    x = 2 * np.pi * np.arange(64) / 64

    def h(s, u, ux, speed):
        worn = np.mean(np.atleast_1d(u), axis=-1, keepdims=True) < -5e-4
        return -1e-2 + np.where(worn, -1.0, 0.01) * s

    with pytest.raises(IllPosedError) as info:
        solve_evolution(1e-5 * np.cos(3 * x), 0.2, h, 0.0, dt=1e-4)
    assert np.all(np.isfinite(info.value.last_good))
    assert 0.05 <= info.value.last_time < 0.2


def _scenario(tmp_path, text, name="bad.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


BASE = builtin_text("onset")


@pytest.mark.parametrize("edit, field", [
    (("epsilon = 1e-4", "epsilon = -1e-4"), "solver.epsilon"),
    (('form = "disk_contact"', 'form = "foo"'), "wear_rate.form"),
    (('form = "disk_contact"', 'form = "table"\ncurvature_m = [-1.0, 0.0, 1.0, 2.0]\nrate_m = [0.0, nan, 0.0, 0.0]'), "wear_rate.rate_m"),
    (("radius_m = 0.46", "radius_m = -0.46"), "wheel.radius_m"),
    (("points = 1024", "points = 1023"), "solver.points"),
    (("seed = 1", "seed = 1\ncolour = 3"), "initial.colour"),
])
def test_bad_scenario_field_is_named(tmp_path, edit, field):
    text = BASE.replace(*edit)
    assert text != BASE
    path = _scenario(tmp_path, text)
    with pytest.raises(ScenarioError, match=field.replace(".", r"\.")):
        load_scenario(path)
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(out)])
    assert result.exit_code == 2
    assert "Traceback" not in result.output and field in result.output
    assert len(result.output.strip().splitlines()) == 1
    assert not (out / "result.nc").exists()


def _rows(angles, header="angle_deg,deviation_um", values=None):
    values = values or {}
    return header + "\n" + "\n".join(f"{a},{values.get(i, 1.0)}" for i, a in enumerate(angles)) + "\n"


TURN = list(range(0, 360, 30))


@pytest.mark.parametrize("csv, message", [
    (_rows(TURN, "angle_deg,radius_um"), "deviation"),
    ("deviation_um\n" + "1\n" * 12, "angle"),
    ("Wheel 23, measured on the lathe\n" + _rows(TURN), "line 1"),
    (_rows(TURN[:-1] + [370]), "outside"),
    (_rows(TURN, values={4: "x"}), "line 6"),
    (_rows(TURN, values={4: ""}), "missing value"),
    (_rows(TURN[:5] + [120] + TURN[6:]), "repeats"),
    (_rows(TURN[:5] + [100] + TURN[6:]), "increase"),
    (_rows([a / 57.3 for a in TURN]), "radians in a degrees column"),
    (_rows(TURN, "angle_rad,deviation_um"), "degrees in a radians column"),
    (_rows(list(range(0, 180, 10))), "does not go round"),
])
def test_bad_measured_wheel(tmp_path, csv, message):
    (tmp_path / "wheel.csv").write_text(csv)
    text = BASE.replace('kind = "random"', 'kind = "measured"\nfile = "wheel.csv"')
    path = _scenario(tmp_path, text)
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2, result.output
    assert message in result.output and "initial.file" in result.output
    assert len(result.output.strip().splitlines()) == 1
    assert not (tmp_path / "out" / "result.nc").exists()


def test_measured_wheel_runs(tmp_path):
    angle = np.arange(0, 360, 2.0)
    dev = 30 * np.cos(np.radians(5 * angle))
    lines = ["angle_deg,deviation_um"] + [f"{a},{d}" for a, d in zip(angle, dev)]
    (tmp_path / "wheel.csv").write_text("\n".join(lines))
    text = BASE.replace('kind = "random"', 'kind = "measured"\nfile = "wheel.csv"')
    ds = railwear.run(load_scenario(_scenario(tmp_path, text)))
    assert float(ds.amplitude_initial.sel(order=5)) == pytest.approx(30e-6, rel=1e-4)


def test_cli_ill_posed_run_fails_with_status_1_and_keeps_last_state(tmp_path):
    text = BASE.replace("epsilon = 1e-4", "epsilon = 0.0").replace("nu = 1e-3", "nu = 0.0")
    text = text.replace("speed_kmh = 180.0", "speed_kmh = 300.0")
    out = tmp_path / "out"
    result = CliRunner().invoke(app, ["run", str(_scenario(tmp_path, text)), "-o", str(out)])
    assert result.exit_code == 1, result.output
    assert "ill-posed" in result.output
    assert not (out / "result.nc").exists()
    assert np.all(np.isfinite(np.load(out / "last_good_state.npy")))


def test_cli_run_plot_stability_show(tmp_path):
    runner = CliRunner()
    out = tmp_path / "out"
    r = runner.invoke(app, ["run", "smoothing", "-o", str(out)])
    assert r.exit_code == 0, r.output
    summary = json.loads((out / "summary.json").read_text())
    assert summary["runs"][0]["regime"] == "smoothing"
    for name in ("result.nc", "summary.txt", "profiles.png", "evolution.png", "spectrum.png"):
        assert (out / name).stat().st_size > 0
    (out / "profiles.png").unlink()
    assert runner.invoke(app, ["plot", str(out / "result.nc")]).exit_code == 0
    assert (out / "profiles.png").exists()
    r = runner.invoke(app, ["stability", "polygonalisation", "--speeds", "20:300:40", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert (out / "stability.png").exists() and (out / "stability.nc").exists()
    r = runner.invoke(app, ["stability", "--speeds", "300:20:10"])
    assert r.exit_code == 2
    r = runner.invoke(app, ["show", "polygonalisation"])
    assert r.exit_code == 0 and parse_scenario(r.output) == load_scenario("polygonalisation")
    r = runner.invoke(app, ["scenarios"])
    assert all(name in r.output for name in builtin_names())
    assert runner.invoke(app, ["plot", str(tmp_path / "missing.nc")]).exit_code == 2


def test_default_scenario_is_resolved_and_512_points_are_flagged():
    """The crests sharpen down to orders near 160 at 220 km/h: 1024 points agree with 2048 to
    10 % (measured 5 %) with the same number of maxima; 512 points raise a ResolutionWarning."""
    import warnings

    from railwear.errors import ResolutionWarning

    base = load_scenario("polygonalisation")

    def at(points):
        return railwear.run(base.model_copy(update={"solver": base.solver.model_copy(update={"points": points})}))

    with warnings.catch_warnings():
        warnings.simplefilter("error", ResolutionWarning)
        fine, finer = at(1024), at(2048)
    assert int(fine.maxima) == int(finer.maxima)
    dev = [(d.u.isel(time=-1) - d.u.isel(time=-1).mean()).values for d in (fine, finer)]
    coarse_on_fine = dev[1][::2]
    assert np.linalg.norm(dev[0] - coarse_on_fine) < 0.1 * np.linalg.norm(coarse_on_fine)
    with pytest.warns(ResolutionWarning, match="512 points"):
        at(512)
