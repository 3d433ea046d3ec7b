"""The dynamic wheel load (railwear.maintenance.impact): a harmonic at low amplitude against the
linear receptance model, contact loss at the static criterion's threshold, the round wheel's
sleeper passing, refusals, and ``railwear load`` run the way a user runs it."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from railwear.errors import OptionError, ScenarioError
from railwear.longterm.vehicle_track import METRO, VehicleTrackModel
from railwear.maintenance import impact
from railwear.maintenance.impact import DynamicLoad, dynamic_load
from railwear.results import read_netcdf
from railwear.units import KN, UM, kmh_to_m_s

POINTS = 512
ANGLE = 2 * np.pi * np.arange(POINTS) / POINTS


def _linear(order, kmh, amplitude):
    """``|H̄(nΩ)| |ū_n|`` [N] by the linear model of the Fourier technique: the metro wheel's
    bay-averaged coupled transfer (8 offsets) at the order's frequency, times the harmonic the
    contact reads, written out: the grid's piecewise-linear interpolation ``sinc²(n/N)`` and the
    patch average ``sin(n h)/(n h)``, ``h = a / R0``."""
    wheel = METRO.wheel(kmh_to_m_s(kmh))
    omega = wheel.speed * (1 + wheel.steady_creepage()) / wheel.radius
    h = wheel.patch_half_length / wheel.radius
    read = amplitude * np.sinc(order / POINTS) ** 2 * np.sin(order * h) / (order * h)
    transfer = VehicleTrackModel(wheel, METRO.track, 8).contact_force_transfer(order * omega)
    return abs(transfer) * read, transfer


def test_a_harmonic_at_low_amplitude_loads_the_rail_as_the_linear_receptance_model():
    """Orders 8 and 12 of 1 µm each at 50 and 70 km/h: the force they add (the run less the round
    wheel's, which takes the sleeper passing out) at the line n Ω over 6 whole revolutions is the
    bay-averaged linear model's |N̂| = |contact_force_transfer(nΩ)| × amplitude within 1 %
    (measured -0.27 to -0.09 %; over 8 revolutions after 1 s, -0.33 to +0.09 %); the filter the contact reads agrees with its closed form to 1e-5 (sampled at 4 N points: 2e-6)."""
    u = UM * (np.cos(8 * ANGLE) + np.cos(12 * ANGLE + 1.0))
    ds = dynamic_load(DynamicLoad(METRO, u, tuple(kmh_to_m_s(np.array([50.0, 70.0]))), revolutions=6, transient=0.6))
    for kmh in (50.0, 70.0):
        for n in (8, 12):
            expected, _ = _linear(n, kmh, UM)
            got = float(ds.order_force_amplitude.sel(speed=kmh_to_m_s(kmh), order=n))
            assert abs(got / expected - 1) < 0.01, (kmh, n, got / expected - 1)
            assert float(ds.linear_force_amplitude.sel(speed=kmh_to_m_s(kmh), order=n)) == pytest.approx(expected, rel=1e-5)
    assert float(ds.contact_loss_fraction.max()) == 0.0 and np.all(np.isnan(ds.contact_loss_angle.values))
    # at 1 um the force of order 8 near P2 is some 300 N on a static load of 68.8 kN
    assert 200 < float(ds.order_force_amplitude.sel(speed=kmh_to_m_s(70.0), order=8)) < 400


def test_contact_is_lost_where_the_linear_force_amplitude_reaches_the_static_load():
    """Order 8 at 70 km/h: the static criterion puts the threshold at A* = W / (|H̄| × filter), where
    the linear force amplitude equals the static load. At 0.97 A* the wheel keeps contact, at
    1.05 A* it loses it (measured threshold 1.02 A*: the Hertz spring's nonlinearity and the
    sleeper ripple), and the loss is reported where the force's trough falls: at the wheel angle
    where n x + arg H̄ = π (mod 2π), within a tenth of the polygon's wavelength."""
    expected, transfer = _linear(8, 70.0, 1.0)
    threshold = METRO.static_load / expected
    assert 200 * UM < threshold < 240 * UM  # 217 um: 0.43 mm peak to peak
    below, lost = (dynamic_load(DynamicLoad(METRO, f * threshold * np.cos(8 * ANGLE), (kmh_to_m_s(70.0),),
                                            revolutions=4)) for f in (0.97, 1.05))
    below, above = below.isel(speed=0), lost.isel(speed=0)
    assert float(below.contact_loss_fraction) == 0.0 and float(below.minimum_force) > 0.01 * METRO.static_load
    assert float(above.contact_loss_fraction) > 0.01 and float(above.minimum_force) == 0.0
    assert 1 <= float(above.contact_loss_per_revolution) <= 8  # at most once a wave (the sleepers shift the troughs)
    trough = (np.pi - np.angle(transfer)) / 8
    wave = 2 * np.pi / 8
    miss = (float(above.contact_loss_angle) - trough + wave / 2) % wave - wave / 2
    assert abs(miss) < 0.1 * wave
    assert 0 <= float(above.contact_loss_offset) < METRO.track.sleeper_spacing
    text = impact.report(lost)
    assert "the wheel loses contact at 70 km/h" in text and " deg, " in text and "mm past a sleeper" in text


def test_a_round_wheel_loads_the_rail_with_its_static_load_and_the_sleeper_passing_only():
    """A round wheel at 90 km/h, every RK4 step kept: the force is the round wheel's to the bit, and
    it is the static load plus lines at the sleeper-passing frequency V/L and its harmonics only: a
    least-squares fit of the first 100 leaves 0.2 % of the ripple's rms (all 232 below the Nyquist
    frequency: 0.05 %; the point-supported Timoshenko rail puts a cusp at each sleeper, whose
    harmonics fall slowly), and its constant term is the static load to 2e-7."""
    p = dynamic_load(DynamicLoad(METRO, np.zeros(POINTS), (kmh_to_m_s(90.0),), revolutions=3,
                                 trace_samples=2048)).isel(speed=0)
    assert float(p.time_step) == pytest.approx(float(p.time[1] - p.time[0]), rel=1e-9)  # every step in the trace
    np.testing.assert_array_equal(p.force.values, p.round_force.values)
    assert float(np.abs(p.order_force_amplitude).max()) == 0.0
    force, t = p.force.values, p.time.values
    f = float(p.sleeper_passing_frequency)
    assert f == pytest.approx(kmh_to_m_s(90.0) / METRO.track.sleeper_spacing, rel=1e-12)
    k = np.arange(1, 101)
    basis = np.column_stack([np.ones_like(t), np.cos(2 * np.pi * f * np.outer(t, k)), np.sin(2 * np.pi * f * np.outer(t, k))])
    fit, *_ = np.linalg.lstsq(basis, force, rcond=None)
    assert np.std(force - basis @ fit) < 3e-3 * np.std(force - force.mean())
    assert fit[0] == pytest.approx(METRO.static_load, rel=1e-5)
    assert 0.1 * KN < float(p.sleeper_ripple) < 0.05 * METRO.static_load  # 1.2 kN: a ripple, no impact
    assert float(p.peak_force) == pytest.approx(float(p.round_peak_force))


def test_refusals_name_the_field():
    u = UM * np.cos(8 * ANGLE)
    for kwargs, field in (({"speeds": (0.0,)}, "speeds"), ({"speeds": (200.0,)}, "speeds"),
                          ({"deviation": 0.05 * np.cos(8 * ANGLE)}, "deviation"), ({"revolutions": 0}, "revolutions"),
                          ({"transient": -1.0}, "transient"), ({"deviation": np.ones(4)}, "deviation"),
                          ({"speeds": (20.0, 20.0)}, "speeds")):
        args = {"case": METRO, "deviation": u, "speeds": (20.0,), **kwargs}
        with pytest.raises(ScenarioError, match=f"^{field}:"):
            DynamicLoad(**args)
    with pytest.raises(OptionError, match="^--wheel, --result:"):
        impact.wheel_load("metro", [70.0], wheel="a.csv", result="b.nc")
    with pytest.raises(ScenarioError, match="^body.kind:"):
        impact.wheel_load("stable", [70.0])


def test_a_result_gives_its_wheel_at_the_end_of_the_run(tmp_path):
    from railwear.results import write_netcdf
    from railwear.scenario import load_scenario

    u = np.stack([np.zeros(64), 3 * UM * np.cos(8 * ANGLE[::8])])
    ds = xr.Dataset({"u": (("time", "angle"), u), "nominal_radius": ((), 0.42)},
                    coords={"time": [0.0, 1.0], "angle": ANGLE[::8], "distance": ("time", [0.0, 12345.0])},
                    attrs={"scenario_name": "metro"})
    write_netcdf(ds, tmp_path / "result.nc")
    sc = load_scenario("metro")
    shape, words = impact.shape_from_result(tmp_path / "result.nc", sc)
    np.testing.assert_array_equal(shape, u[-1])
    assert "after 12,345 km" in words and "6.0 um peak to peak" in words
    with pytest.raises(OptionError, match="^--result: the result's wheel is 840 mm, the scenario's 920 mm"):
        impact.shape_from_result(tmp_path / "result.nc", load_scenario("metro", ["wheel.radius_m=0.46"]))


@pytest.mark.e2e
def test_railwear_load_in_a_fresh_interpreter(tmp_path):
    """``railwear load`` on a measured wheel (order 8, 30 um) at 60 and 80 km/h writes its files;
    order 8 leads the force's spectrum."""
    wheel = tmp_path / "wheel.csv"
    deg = np.arange(0, 360, 2.0)
    wheel.write_text("angle_deg,deviation_um\n" + "".join(f"{a:g},{30 * np.cos(8 * np.radians(a)):.4f}\n" for a in deg))
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-m", "railwear", "load", "metro", "--wheel", str(wheel), "--speeds", "60,80",
                          "--revolutions", "2", "--transient-s", "0.3", "-o", str(out)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "no detector flags this wheel at 60-80 km/h" in run.stdout and "Network Rail" in run.stdout
    for name in ("load.nc", "load.txt", "load.csv", "load-peak.png", "load-trace.png"):
        assert (out / name).is_file()
    ds = read_netcdf(out / "load.nc")
    np.testing.assert_array_equal(ds.speed_kmh.values, [60.0, 80.0])
    assert ds.peak_force.attrs["units"] == "N" and np.all(ds.peak_force.values > ds.static_load.values)
    assert int(np.argmax(ds.order_force_amplitude.isel(speed=0).values)) + 1 == 8


def test_a_bad_option_exits_2_with_one_line_naming_it(tmp_path):
    from typer.testing import CliRunner

    from railwear.cli import app

    for args, option in ((["--speeds", "500"], "--speeds"), (["--revolutions", "0"], "--revolutions"),
                         (["--transient-s", "-1"], "--transient-s"), (["stable"], "body.kind"),
                         (["--wheel", str(tmp_path / "none.csv")], "--wheel")):
        got = CliRunner().invoke(app, ["load", *args, "-o", str(tmp_path / "out")])
        assert got.exit_code == 2 and got.output.count("\n") == 1, got.output
        assert got.output.startswith(f"railwear: error: {option}"), got.output
