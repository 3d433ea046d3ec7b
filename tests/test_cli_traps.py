"""Smaller traps of issue 22, item 6: a file named like a built-in that holds no scenario; fields
--set cannot take away (--unset)."""

import pytest
from typer.testing import CliRunner

from railwear.cli import app
from railwear.errors import OptionError, ScenarioError
from railwear.scenario import ShadowWarning, builtin_text, load_scenario


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


@pytest.mark.parametrize("text, holds", [("", "holds nothing"), ('name = "x"\n', "holds only name and no [section]"),
                                         ('name = "x"\ndescription = "y"\n', "holds only name, description")])
def test_a_file_without_a_section_is_refused_naming_the_builtin_it_hides(tmp_path, monkeypatch, text, holds):
    """It ran as a 220 km/h disk wheel from the schema's defaults, in place of the built-in."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "metro").write_text(text)
    done = invoke("run", "metro", "-o", tmp_path / "out")
    assert done.exit_code == 2
    assert f"metro: not a scenario: the file {holds}" in done.stderr
    assert "in place of the built-in scenario 'metro' (railwear show metro prints that one)" in done.stderr
    assert not (tmp_path / "out" / "result.nc").exists()


def test_a_file_without_a_section_is_refused_under_any_name(tmp_path):
    (tmp_path / "mine.toml").write_text('name = "mine"\n')
    with pytest.raises(ScenarioError, match="mine.toml: not a scenario: the file holds only name") as e:
        load_scenario(tmp_path / "mine.toml")
    assert "built-in" not in str(e.value)


def test_a_file_named_like_a_builtin_is_read_with_a_warning(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "metro").write_text(builtin_text("metro").replace("speed_kmh = 70.0", "speed_kmh = 60.0"))
    with pytest.warns(ShadowWarning, match="reading the file metro in this folder, not the built-in scenario 'metro'"):
        assert load_scenario("metro").operation.speed_kmh == 60.0
    done = invoke("run", "metro", "--no-figures", "--set", "solver.t_end=0.01", "-o", tmp_path / "out")
    assert done.exit_code == 0, done.output
    assert "60 km/h" in done.stdout
    assert "railwear: warning: reading the file metro in this folder, not the built-in scenario 'metro'" in done.stderr


RIGID = ["--set", "track.base=rigid", "--unset", "track.ballast_stiffness_MN_m",
         "--unset", "track.ballast_damping_kN_s_m", "--unset", "track.sleeper_mass_kg"]


def test_unset_switches_the_metro_track_to_a_rigid_base(tmp_path):
    """--set alone cannot: the ballast fields of the file do not apply to a rigid base. With them
    unset the run is on the rigid base (railwear track with these options: P2 65.5 Hz, as
    docs/track.md's 65.45 for the rigid base)."""
    short = ["--no-figures", "--set", "solver.t_end=0.01", "-o", tmp_path]
    refused = invoke("run", "metro", "--set", "track.base=rigid", *short)
    assert refused.exit_code == 2 and "does not apply to base 'rigid'" in refused.stderr
    done = invoke("run", "metro", *RIGID, *short)
    assert done.exit_code == 0, done.output
    track = load_scenario("metro", ["track.base=rigid"],
                          ["track.ballast_stiffness_MN_m", "track.ballast_damping_kN_s_m", "track.sleeper_mass_kg"]).track
    assert track.base == "rigid"
    from railwear import results

    import tomllib

    stored = tomllib.loads(results.read_netcdf(tmp_path / "result.nc").attrs["scenario"])["track"]
    assert stored["base"] == "rigid" and not [k for k in stored if "ballast" in k or "sleeper_mass" in k]


def test_unset_takes_the_default():
    base = load_scenario("metro")
    assert base.operation.life_distance_km == 100000.0
    assert load_scenario("metro", unset=["operation.life_distance_km"]).operation.life_distance_km == 50000.0
    whole = load_scenario("metro", unset=["service"])  # a section: every field its default
    assert whole.service.samples != base.service.samples or whole.service.seed != base.service.seed
    fresh = load_scenario("metro", ["track.base=rigid"], ["track"])
    assert fresh.track.base == "rigid"


@pytest.mark.parametrize("unset, sets, message", [
    (["track.bogus"], [], "--unset track.bogus: the scenario does not set it: no such field"),
    (["track.preset"], [], "--unset track.preset: the scenario does not set it"),
    (["wheel.wheel_inertia_kg_m2"], [], "--unset wheel.wheel_inertia_kg_m2: the scenario does not set it"),
    (["track.base"], ["track.base=rigid"], "--unset track.base: also given to --set"),
    ([""], [], "--unset '': expected a dotted scenario field"),
])
def test_unset_refuses_naming_the_field(unset, sets, message):
    with pytest.raises(OptionError) as e:
        load_scenario("metro", sets, unset)
    assert str(e.value).startswith(message), str(e.value)


def test_unset_on_the_command_line_is_bad_input(tmp_path):
    done = invoke("run", "metro", "--unset", "track.bogus", "-o", tmp_path)
    assert done.exit_code == 2 and "railwear: error: --unset track.bogus" in done.stderr
