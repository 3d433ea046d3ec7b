"""The Cooperrider bogie is railwear's model of it, whose Hopf point does not reproduce the
published one (issue 22, item 6; docs/dynamics.md: 52.245 m/s against 68.66 m/s)."""

from typer.testing import CliRunner

from railwear.cli import app, published_hopf_line
from railwear.scenario import dynamics


def test_scenarios_does_not_call_it_the_published_bogie():
    done = CliRunner().invoke(app, ["scenarios"])
    (line,) = [line for line in done.stdout.splitlines() if line.startswith("cooperrider ")]
    assert "The published Cooperrider bogie" not in line and line.count("published") == 1
    assert "railwear's model of the Cooperrider bogie" in line
    assert "188 km/h, is 24 % below the published bogie's 247 km/h (68.66 m/s): not reproduced" in line


def test_the_published_hopf_point_is_known_for_the_conical_model_only():
    assert dynamics.published_hopf(dynamics.load_dynamics_scenario("cooperrider"))[0] == 68.66
    assert dynamics.published_hopf(dynamics.load_dynamics_scenario("hunting")) is None


def test_the_line_says_it_is_not_reproduced():
    line = published_hopf_line(52.245, 68.66, "a source")
    assert line == ("  not the published bogie's: its Hopf point is 247.2 km/h (68.66 m/s; a source), and this "
                    "model's is 24% lower: not reproduced (docs/dynamics.md, 'The published Cooperrider bogie')")


def test_simulate_cooperrider_says_so(tmp_path):
    done = CliRunner().invoke(app, ["simulate", "cooperrider", "-o", str(tmp_path)])
    assert done.exit_code == 0, done.output
    lines = done.stdout.splitlines()
    k = next(i for i, line in enumerate(lines) if line.startswith("Hopf point 188.1 km/h"))
    assert lines[k + 1].startswith("  not the published bogie's: its Hopf point is 247.2 km/h (68.66 m/s; Seydel")
    assert "24% lower: not reproduced" in lines[k + 1]
