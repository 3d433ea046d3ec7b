"""Validation messages in plain words: the field, what is wrong, no pydantic internals."""

import pytest
from typer.testing import CliRunner

from railwear.cli import app
from railwear.errors import ScenarioError
from railwear.scenario import load_scenario

INTERNALS = ("constrained", "list[", "instance of", "after validation", "Extra inputs", "Value error", "float.", "(and")


@pytest.mark.parametrize("sets, says", [
    ({"operation.speed_kmh": [100, 0]}, "field 'operation.speed_kmh[1]': Input should be greater than or equal to 1"),
    ({"operation.speed_kmh": [100, "x"]}, "field 'operation.speed_kmh[1]': Input should be a valid number"),
    ({"operation.speed_kmh": "fast"}, "field 'operation.speed_kmh': Input should be a valid number or a valid list"),
    ({"wear_rate.rate_m": [[1.0, "x"]]}, "field 'wear_rate.rate_m[0][1]': Input should be a valid number"),
    ({"wear_rate.drift_rad": [1e20]}, "field 'wear_rate.drift_rad[0]': Input should be less than or equal to 1000000000"),
    ({"wear_rate.curvature_m": []}, "field 'wear_rate.curvature_m': List should have at least 1 item, not 0"),
    ({"wheel": 3}, "field 'wheel': should be a table"),
    ({"wheel.bogus": 1}, "field 'wheel.bogus': no such field"),
    ({"bogus": 1}, "field 'bogus': no such field"),
    ({"initial.orders": [1, 2.0]}, "field 'initial.orders[1]': Input should be a valid integer"),
])
def test_one_plain_line_naming_the_field(sets, says):
    with pytest.raises(ScenarioError) as err:
        load_scenario("onset", sets)
    message = str(err.value)
    assert message.endswith(says) and not any(word in message for word in INTERNALS), message


def test_two_bad_fields_count_once_each():
    with pytest.raises(ScenarioError, match=r"field 'wheel.radius_m': .* \(and 1 more\)$"):
        load_scenario("onset", {"wheel.radius_m": -1, "wheel.static_load_kN": [1, 2]})


def test_a_scenario_file_on_the_command_line(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text('[operation]\nspeed_kmh = [100, 0]\n')
    result = CliRunner().invoke(app, ["run", str(path), "-o", str(tmp_path / "out")])
    assert result.exit_code == 2
    assert result.output == ("railwear: error: s.toml: field 'operation.speed_kmh[1]': Input should be greater "
                             "than or equal to 1\n"), result.output
