"""Short-time dynamics scenarios through the command line (paper Figs 1-3, the bogie's branch)."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import api
from railwear.cli import app
from railwear.scenario import dynamics


def test_every_builtin_dynamics_scenario_runs_headless(tmp_path):
    runner = CliRunner()
    names = dynamics.builtin_names()
    assert {"hunting", "contact-path", "cooperrider"} <= set(names)
    for name in names:
        out = tmp_path / name
        r = runner.invoke(app, ["simulate", name, "-o", str(out)])
        assert r.exit_code == 0, r.output
        assert (out / "dynamics.nc").exists() and len(list(out.glob("*.png"))) == 1
    assert "hunting (railwear simulate)" in runner.invoke(app, ["scenarios"]).output
    assert "kind = \"wheelset\"" in runner.invoke(app, ["show", "hunting"]).output


def test_hunting_below_and_above_the_critical_speed():
    ds = api.simulate("hunting")
    vc = ds.attrs["linear_critical_speed_kmh"]
    slow, fast = ds.sel(speed=180 / 3.6), ds.sel(speed=280 / 3.6)
    assert 180 < vc < 280
    assert float(abs(slow.lateral_displacement[-500:]).max()) < 1e-3 * 1e-3  # decays from 1 mm
    assert float(abs(fast.lateral_displacement[-500:]).max()) > 5e-3  # grows into the flange
    # the variables keep their units through the batch over speeds (and into the netCDF file)
    assert ds.lateral_displacement.attrs["units"] == "m" and ds.frictional_power.attrs["units"] == "W"


def test_contact_point_runs_round_the_wheel():
    ds = api.simulate("contact-path").isel(speed=0)
    v, r0 = float(ds.speed), 0.46
    angle = np.unwrap(ds.contact_angle.values)
    turned = angle[-1] - angle[0]
    # x_c = x0 + V t / R0 + phi, with the wheel turning slightly faster under traction
    assert turned == pytest.approx(v * float(ds.time[-1]) / r0, rel=1e-3)
    assert float(ds.frictional_power.std()) > 0.01 * float(ds.frictional_power.mean())


def test_bogie_branch_is_subcritical():
    """The built-in ``cooperrider`` is the seven-degree-of-freedom ``CooperriderBogie``: Hopf point
    52.245 m/s (188.08 km/h) in this reading of the published parameters (docs/dynamics.md)."""
    ds = api.simulate("cooperrider")
    assert ds.attrs["hopf_speed"] * 3.6 == pytest.approx(188.08, abs=0.01)
    assert ds.attrs["nonlinear_critical_speed"] < ds.attrs["hopf_speed"]


def test_bad_dynamics_scenario(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(dynamics._builtin_dir().joinpath("hunting.toml").read_text().replace("mass_kg = 1022.0", "mas = 1022.0"))
    r = CliRunner().invoke(app, ["simulate", str(path), "-o", str(tmp_path / "o")])
    assert r.exit_code == 2 and "mas" in r.output and len(r.output.strip().splitlines()) == 1
    assert not (tmp_path / "o" / "dynamics.nc").exists()


def test_profiles_choose_the_contact_model_and_the_creep_law(tmp_path):
    """``model.profiles.contact_model`` builds the table of that model; with it a profile scenario
    can run ``creep_law = "strip-fastsim"`` (its critical speed is the table model's, 78.475 m/s in
    tests/dynamics/test_table_multipoint.py); a wrong model name is one line, exit 2."""
    from railwear.dynamics import critical_speed

    text = dynamics._builtin_dir().joinpath("hunting-profiles.toml").read_text()
    text = text.replace('rail = "UIC60" }', 'rail = "UIC60", contact_model = "semi-hertzian" }')
    text = text.replace("friction_coefficient = 0.3", 'friction_coefficient = 0.3\ncreep_law = "strip-fastsim"')
    path = tmp_path / "semi.toml"
    path.write_text(text)
    model = dynamics.build(dynamics.load_dynamics_scenario(path), 60.0)
    assert "point" in model.table.dims and model.creep_law == "strip-fastsim"
    assert critical_speed(model) == pytest.approx(78.475, abs=2e-3)
    path.write_text(text.replace('"semi-hertzian"', '"semi"'))
    r = CliRunner().invoke(app, ["simulate", str(path), "-o", str(tmp_path / "o")])
    assert r.exit_code == 2 and "contact_model" in r.output and len(r.output.strip().splitlines()) == 1
