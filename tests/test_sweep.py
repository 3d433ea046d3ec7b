"""Sweeps: the same numbers serially, on local workers and on a Dask cluster; nothing lost."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import sweep
from railwear.cli import app
from railwear.errors import ScenarioError
from railwear.pde import measured_growth_map, stability_map
from railwear.scenario import build, load_scenario

# Coarse grids keep these tests fast; what they check does not depend on resolution.
pytestmark = pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")


def small(name="smoothing"):
    base = load_scenario(name)
    solver = base.solver.model_copy(update={"points": 64, "n_save": 11})
    initial = base.initial.model_copy(update={"highest_order": 8})
    return base.model_copy(update={"solver": solver, "initial": initial})


VARY = [sweep.parse_vary("operation.speed_kmh=100,220"), sweep.parse_vary("wheel.static_load_kN=70,90")]


def test_serial_local_and_dask_agree(tmp_path):
    from distributed import LocalCluster

    base = small()
    serial = sweep.run_sweep(base, VARY, tmp_path / "serial", executor=sweep.SerialExecutor())
    local = sweep.run_sweep(base, VARY, tmp_path / "local", executor=sweep.LocalExecutor(2))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster:
        dask = sweep.run_sweep(base, VARY, tmp_path / "dask",
                               executor=sweep.DaskExecutor(cluster.scheduler_address))
    for other in (local, dask):
        np.testing.assert_array_equal(other.u_final.values, serial.u_final.values)
        np.testing.assert_array_equal(other.regime.values, serial.regime.values)
    assert serial.regime.shape == (2, 2)
    assert not np.any(np.isnan(serial.max_removed_depth.values))


def test_batched_speed_grid_equals_points(tmp_path):
    base = small("onset")
    vary = [sweep.parse_vary("operation.speed_kmh=60:260:100")]
    batched = sweep.run_sweep(base, vary, tmp_path / "b")
    serial = sweep.run_sweep(base, vary, tmp_path / "s", executor=sweep.SerialExecutor(), batch=False)
    np.testing.assert_array_equal(batched.u_final.values, serial.u_final.values)


def test_interrupted_sweep_computes_only_the_rest(tmp_path, monkeypatch):
    base = small()
    calls = []
    real = sweep.run_point

    def counted(task):
        calls.append(task)
        if len(calls) == 3:
            raise KeyboardInterrupt  # killed during the third point
        return real(task)

    monkeypatch.setattr(sweep, "run_point", counted)
    with pytest.raises(KeyboardInterrupt):
        sweep.run_sweep(base, VARY, tmp_path, executor=sweep.SerialExecutor())
    assert len(list((tmp_path / "points").glob("*.nc"))) == 2
    calls.clear()
    monkeypatch.setattr(sweep, "run_point", lambda task: (calls.append(task), real(task))[1])
    ds = sweep.run_sweep(base, VARY, tmp_path, executor=sweep.SerialExecutor())
    assert len(calls) == 2
    assert np.all(ds.error.values == "")
    whole = sweep.run_sweep(base, VARY, tmp_path / "whole", executor=sweep.SerialExecutor())
    np.testing.assert_array_equal(ds.u_final.values, whole.u_final.values)


def test_failing_point_is_recorded_and_the_sweep_completes(tmp_path):
    base = small("polygonalisation")
    base = base.model_copy(update={"solver": base.solver.model_copy(update={"nu": 0.0}),
                                   "operation": base.operation.model_copy(update={"speed_kmh": 300.0})})
    vary = [sweep.parse_vary("solver.epsilon=0,1e-4")]
    ds = sweep.run_sweep(base, vary, tmp_path, executor=sweep.SerialExecutor())
    assert "IllPosedError" in str(ds.error.values[0]) and ds.regime.values[0] == "failed"
    assert ds.error.values[1] == "" and np.isfinite(ds.maxima.values[1])
    assert len(list((tmp_path / "points").glob("*.error"))) == 1


def test_latin_hypercube_design_is_seeded_and_covers_ranges():
    varies = [sweep.parse_vary("operation.speed_kmh=100:200:50"), sweep.parse_vary("contact.friction_coefficient=0.2,0.4")]
    c1, p1 = sweep.design(varies, samples=8, seed=3)
    c2, p2 = sweep.design(varies, samples=8, seed=3)
    assert p1 == p2
    speeds = np.sort(c1["operation.speed_kmh"])
    # one sample in each of the 8 equal strata of [100, 200]
    assert np.all(np.floor((speeds - 100) / 12.5) == np.arange(8))


@pytest.mark.parametrize("text, match", [
    ("operation.colour=1,2", "no such scenario field"),
    ("initial.kind=1,2", "not a numeric field"),
    ("wheel.radius_m=-1,1", "wheel.radius_m"),
    ("speed=1:0:1", "expected"),
])
def test_bad_vary(text, match):
    with pytest.raises(ScenarioError, match=match):
        v = sweep.parse_vary(text)
        for a in sweep.design([v])[1]:
            sweep.with_values(small(), a)


def test_dispersion_map_agrees_with_measured_growth():
    """The round-wheel map of the disk-contact h against decay rates measured in one short batched run."""
    sc = load_scenario("onset")
    h = build.wear_rate(sc)
    speeds, orders = np.array([80.0, 200.0, 300.0]) / 3.6, np.array([2, 5, 9])
    derived = stability_map(h, speeds, orders, sc.solver.epsilon, sc.solver.nu)
    measured = measured_growth_map(h, speeds, orders, sc.solver.epsilon, sc.solver.nu, dt=1e-5)
    np.testing.assert_allclose(measured.growth_rate.values, derived.growth_rate.values, rtol=2e-3)


def test_cli_sweep(tmp_path):
    r = CliRunner().invoke(app, ["sweep", "smoothing", "--vary", "operation.speed_kmh=40,120",
                                 "-o", str(tmp_path), "--workers", "1"])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "sweep.nc").exists() and (tmp_path / "sweep.png").exists()
    assert "smoothing" in r.output
    r = CliRunner().invoke(app, ["sweep", "smoothing", "--vary", "wheel.nothing=1,2", "-o", str(tmp_path)])
    assert r.exit_code == 2 and "no such scenario field" in r.output


def test_hunting_map_is_the_closed_form_and_the_eigenvalue_crossing(tmp_path):
    from railwear.dynamics import WheelsetModel, critical_speed, linear_critical_speed

    sc = load_scenario("polygonalisation")
    lam, kpsi = np.array([0.05, 0.2]), np.array([1e6, 8e6])
    m = sweep.hunting_map(sc, lam, kpsi)
    ws = sc.wheelset
    f11, f22 = m.attrs["f11"], m.attrs["f22"]
    for i, c in enumerate(lam):
        for j, k in enumerate(kpsi):
            closed = linear_critical_speed(ws.mass_kg, ws.yaw_inertia_kg_m2, ws.lateral_stiffness_N_m, k,
                                           f11, f22, ws.half_gauge_m, sc.wheel.radius_m, c)
            assert float(m.critical_speed[i, j]) == pytest.approx(closed, rel=1e-14)
    model = WheelsetModel(mass=ws.mass_kg, yaw_inertia=ws.yaw_inertia_kg_m2,
                          lateral_stiffness=ws.lateral_stiffness_N_m, yaw_stiffness=1e6, f11=f11, f22=f22,
                          half_gauge=ws.half_gauge_m, rolling_radius=sc.wheel.radius_m, conicity=0.2, speed=30.0)
    assert float(m.critical_speed[1, 0]) == pytest.approx(critical_speed(model), rel=1e-8)
    assert m.critical_speed.attrs["units"] == "m s-1" and float(m.critical_speed_kmh[1, 0]) == pytest.approx(
        3.6 * float(m.critical_speed[1, 0]), abs=1e-6)
    # a stiffer conicity lowers the critical speed
    assert float(m.critical_speed[1, 0]) < float(m.critical_speed[0, 0])
    r = CliRunner().invoke(app, ["hunting-map", "--conicity", "0.05:0.3:0.05", "--yaw-stiffness",
                                 "1e6,4e6", "-o", str(tmp_path)])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "hunting.png").exists() and "lowest critical speed" in r.output
