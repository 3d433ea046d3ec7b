"""Dynamics scenarios (``railwear simulate``): a unit in every field name, physical bounds per
field, SI only inside the models, and the old SI names refused naming the new one."""

import dataclasses
import math
import tomllib
from decimal import Decimal

import pytest
from typer.testing import CliRunner

from railwear.cli import app
from railwear.dynamics import CooperriderBogie, DiskWheelModel, TableBogieModel, TableWheelsetModel, WheelsetModel
from railwear.errors import ScenarioError
from railwear.scenario import dynamics

# what a name ends with for each unit of the table
SUFFIX = {"kg": "_kg", "kg m^2": "_kg_m2", "N/m": "_N_m", "N m/rad": "_N_m_rad", "N s/m": "_N_s_m",
          "N m s/rad": "_N_m_s_rad", "MN": "_MN", "N m": "_N_m", "N m^2": "_N_m2", "m": "_m", "kN": "_kN",
          "mm": "_mm", "mrad": "_mrad", "m/s": "_m_s", "rad/s": "_rad_s", "rad": "_rad", "N/m^1.5": "_N_m1_5"}
MODELS = {("wheelset", False): WheelsetModel, ("wheelset", True): TableWheelsetModel,
          ("cooperrider", False): CooperriderBogie, ("cooperrider", True): TableBogieModel,
          ("disk_wheel", False): DiskWheelModel}
# model fields a scenario does not set: the speed comes from [run], the table from profiles, the
# radius deviation from out_of_round; an irregularity (a tuple) and a boolean are Python-only
NOT_IN_SCENARIOS = {"speed", "table", "radius_deviation", "lateral_irregularity", "irregularity_wavelength", "spin"}
TEXTS = {name: (dynamics._builtin_dir() / f"{name}.toml").read_text() for name in dynamics.builtin_names()}


def test_every_field_name_carries_its_unit():
    for name, q in dynamics.QUANTITIES.items():
        if q.unit:
            assert name == q.model + SUFFIX[q.unit], name
        else:
            assert name == q.model and q.factor == "1", name
        assert q.low < q.high and math.isfinite(q.low) and math.isfinite(q.high), name
        assert Decimal(q.factor).as_tuple().digits == (1,), name  # a power of ten


@pytest.mark.parametrize("key", sorted(dynamics.MODEL_FIELDS))
def test_the_table_covers_each_model(key):
    given = {dynamics.QUANTITIES[n].model if n in dynamics.QUANTITIES else dynamics.NAMES[n]
             for n in dynamics.MODEL_FIELDS[key]}
    model = {f.name for f in dataclasses.fields(MODELS[key])}
    assert given <= model
    assert model - given == model & NOT_IN_SCENARIOS


def test_builtin_scenarios_use_only_named_units():
    for name, text in TEXTS.items():
        model = tomllib.loads(text)["model"]
        fields = set(model) - {"kind", "out_of_round", "profiles"}
        assert fields <= set(dynamics.MODEL_FIELDS[model["kind"], "profiles" in model]), name


def test_the_edge_converts_to_the_si_model():
    """The built-in hunting and contact-path scenarios build the SI models they stand for, exactly."""
    hunting = dynamics.build(dynamics.load_dynamics_scenario("hunting"), 50.0)
    assert hunting == WheelsetModel(
        mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2e6, f11=6.4e6, f22=5.9e6,
        half_gauge=0.7163, rolling_radius=0.4572, conicity=0.2, speed=50.0, flange_clearance=5e-3,
        flange_stiffness=1.5e7, friction_coefficient=0.3, wheel_load=50e3, initial_lateral_displacement=1e-3)
    disk = dynamics.build(dynamics.load_dynamics_scenario("contact-path"), 27.0)
    assert (disk.f11, disk.static_load, disk.patch_half_length, disk.radius) == (1.2516e7, 80e3, 6.676e-3, 0.46)
    assert dynamics.to_model("initial_yaw_angle_mrad", 2.5) == ("initial_yaw_angle", 2.5e-3)


def _old_name_cases():
    for scenario, text in TEXTS.items():
        model = tomllib.loads(text)["model"]
        for name in model:
            q = dynamics.QUANTITIES.get(name)
            if q is not None and q.model != name:
                yield scenario, name


@pytest.mark.parametrize("scenario, name", list(_old_name_cases()))
def test_an_old_name_is_refused_naming_the_new_one(scenario, name, tmp_path):
    q = dynamics.QUANTITIES[name]
    text = TEXTS[scenario]
    line = next(x for x in text.splitlines() if x.startswith(f"{name} = "))
    si = dynamics.to_model(name, float(line.split("=")[1]))[1]
    path = tmp_path / "old.toml"
    path.write_text(text.replace(line, f"{q.model} = {si!r}"))
    with pytest.raises(ScenarioError, match=f"{q.model}: renamed {name} "):
        dynamics.load_dynamics_scenario(path)


def test_an_old_name_on_the_command_line(tmp_path):
    path = tmp_path / "old.toml"
    path.write_text(TEXTS["hunting"].replace("wheel_load_kN = 50.0", "wheel_load = 50e3"))
    r = CliRunner().invoke(app, ["simulate", str(path), "-o", str(tmp_path / "out")])
    assert r.exit_code == 2 and "Traceback" not in r.output, r.output
    assert len(r.output.strip().splitlines()) == 1 and "wheel_load: renamed wheel_load_kN (in kN)" in r.output
    assert not (tmp_path / "out" / "dynamics.nc").exists()


@pytest.mark.parametrize("key", sorted(dynamics.MODEL_FIELDS))
def test_each_field_has_physical_bounds(key):
    kind, profiles = key
    for name in dynamics.MODEL_FIELDS[key]:
        if name in dynamics.NAMES:
            with pytest.raises(ValueError, match=f"^{name}: must be a name"):
                dynamics.check_field(kind, profiles, name, 1.0)
            continue
        q = dynamics.QUANTITIES[name]
        for inside in (q.low, q.high):
            assert dynamics.check_field(kind, profiles, name, inside) == inside
        step = max(abs(q.low), abs(q.high)) * 1e-6
        for outside in (q.low - step, q.high + step, float("nan"), True, "1"):
            with pytest.raises(ValueError, match=f"^{name}: must be"):
                dynamics.check_field(kind, profiles, name, outside)


def test_a_value_beyond_its_bound_is_refused_in_one_line(tmp_path):
    """A wheel load of 1000 t (SI 1e7 N was within the old overall bound of 1e13)."""
    path = tmp_path / "heavy.toml"
    path.write_text(TEXTS["hunting"].replace("wheel_load_kN = 50.0", "wheel_load_kN = 1e4"))
    r = CliRunner().invoke(app, ["simulate", str(path), "-o", str(tmp_path / "out")])
    assert r.exit_code == 2 and len(r.output.strip().splitlines()) == 1, r.output
    assert "wheel_load_kN: must be between 0.01 and 1000 kN, got 10000.0" in r.output


def test_a_field_of_another_model_is_refused(tmp_path):
    path = tmp_path / "disk.toml"
    path.write_text(TEXTS["contact-path"].replace("[run]", "conicity = 0.1\n\n[run]"))
    with pytest.raises(ScenarioError, match="conicity: not a field of the disk_wheel model"):
        dynamics.load_dynamics_scenario(path)
    path.write_text(TEXTS["contact-path"].replace("[run]", 'profiles = { wheel = "S1002" }\n\n[run]'))
    with pytest.raises(ScenarioError, match="model.profiles: only the wheelset and the cooperrider"):
        dynamics.load_dynamics_scenario(path)


def test_the_docs_list_every_field_of_each_model():
    from pathlib import Path

    text = (Path(__file__).parents[2] / "docs" / "dynamics.md").read_text()
    section = text[text.index("`railwear simulate NAME_OR_FILE`"):text.index("## What the tests check")]
    for names in dynamics.MODEL_FIELDS.values():
        for name in names:
            assert f"`{name}`" in section, name
