"""Scenario names: a path that exists as a file is that file, otherwise a built-in; a folder is
never a scenario (an output folder named like a built-in must not shadow it)."""

import pytest
from typer.testing import CliRunner

from railwear.cli import app
from railwear.errors import ScenarioError
from railwear.scenario import DEFAULT, ShadowWarning, builtin_text, load_scenario
from railwear.scenario.dynamics import load_dynamics_scenario


@pytest.fixture
def folders(tmp_path, monkeypatch):
    """The current folder holds output folders named like built-ins."""
    monkeypatch.chdir(tmp_path)
    for name in ("onset", "forecast", "hunting", DEFAULT):
        (tmp_path / name).mkdir()
    return tmp_path


def test_a_folder_does_not_shadow_a_built_in(folders):
    assert load_scenario("onset").name == "onset"
    assert load_scenario(None) == load_scenario(DEFAULT) and (folders / DEFAULT).is_dir()
    assert load_dynamics_scenario("hunting").name == "hunting"


@pytest.mark.parametrize("command", [["scenarios"], ["show", "forecast"],
                                     ["stability", "onset", "--speeds", "100", "--orders", "1:3:1", "-o", "onset"]])
def test_commands_in_a_folder_holding_built_in_names(folders, command):
    result = CliRunner().invoke(app, command)
    assert result.exit_code == 0, result.output


def test_a_file_of_that_name_is_read(folders):
    (folders / "smoothing").write_text(builtin_text("onset").replace('name = "onset"', 'name = "mine"'))
    with pytest.warns(ShadowWarning, match="reading the file smoothing in this folder, not the built-in"):
        assert load_scenario("smoothing").name == "mine"


@pytest.mark.parametrize("name, says", [("onset/", "is a folder"), ("sub", "is a folder"), ("nothere.toml", "does not exist"),
                                        ("sub/x", "does not exist"), ("nonesuch", "no built-in scenario 'nonesuch'")])
def test_what_is_no_scenario_is_said(folders, name, says):
    (folders / "sub").mkdir()
    with pytest.raises(ScenarioError, match=says):
        load_scenario(name)
    with pytest.raises(ScenarioError, match=says.replace("scenario", "dynamics scenario")):
        load_dynamics_scenario(name)
