"""The ``[body]`` section: built-in bodies chosen by ``kind``, what a strategy needs of a body,
and scenario files of the layout before it (``[strategy] body``, ``[disk_wheel]``, ``[vehicle]``,
``[wheelset_wear]``) read in today's with one warning line."""

import subprocess
import sys
import warnings

import pytest

from railwear.errors import ScenarioError, ScenarioLayoutWarning
from railwear.scenario import builtin_names, load_scenario, parse_scenario, scenario_hash, to_toml
from railwear.scenario.schema import BODY_SECTIONS, STRATEGY_SECTIONS

OLD = {  # the layout before [body], as files of the previous release wrote it
    "stepwise": """
[strategy]
kind = "stepwise"
step_limit_um = 25.0
samples = 2
revolutions = 3
transient_revolutions = 3

[disk_wheel]
rail_mass_kg = 150.0
pad_stiffness_N_m = 1e8
""",
    "metro": """
[strategy]
kind = "fourier"
body = "vehicle_track"

[vehicle]
wheel_inertia_kg_m2 = 60.0
sprung_mass_kg = 855.0

[track]
rail = "60E1"
""",
    "wheelset": """
[operation]
speed_kmh = 216.0

[strategy]
kind = "stepwise"
body = "wheelset"
step_limit_um = 1.0
samples = 2

[wheelset_wear]
lateral_cells = 90
""",
}
NEW = {
    "stepwise": """
[strategy]
kind = "stepwise"
step_limit_um = 25.0

[body]
kind = "disk_wheel"
samples = 2
revolutions = 3
transient_revolutions = 3
rail_mass_kg = 150.0
pad_stiffness_N_m = 1e8
""",
    "metro": """
[strategy]
kind = "fourier"

[body]
kind = "vehicle_track"
wheel_inertia_kg_m2 = 60.0
sprung_mass_kg = 855.0

[track]
rail = "60E1"
""",
    "wheelset": """
[operation]
speed_kmh = 216.0

[strategy]
kind = "stepwise"
step_limit_um = 1.0

[body]
kind = "wheelset"
samples = 2
lateral_cells = 90
""",
}


@pytest.mark.parametrize("name", builtin_names())
def test_builtins_are_in_the_new_layout_and_round_trip(name):
    with warnings.catch_warnings():
        warnings.simplefilter("error", ScenarioLayoutWarning)
        sc = load_scenario(name)
        again = parse_scenario(to_toml(sc))
    assert again == sc and scenario_hash(again) == scenario_hash(sc)
    assert "[body]" in to_toml(sc) and "[disk_wheel]" not in to_toml(sc)


@pytest.mark.parametrize("case", sorted(OLD))
def test_an_old_file_is_read_as_the_new_one_with_one_warning(case):
    with pytest.warns(ScenarioLayoutWarning) as caught:
        old = parse_scenario(OLD[case])
    assert len(caught) == 1 and "read as [body] kind" in str(caught[0].message)
    assert old == parse_scenario(NEW[case]) and scenario_hash(old) == scenario_hash(parse_scenario(NEW[case]))


@pytest.mark.parametrize("text, field", [
    (OLD["metro"].replace('[track]', '[disk_wheel]\nrail_mass_kg = 1.0\n\n[track]'), "disk_wheel: applies to body 'disk_wheel' only"),
    (OLD["metro"] + '\n[body]\nkind = "disk_wheel"\n', "strategy.body: is body.kind now"),
    (OLD["stepwise"].replace("[disk_wheel]", "[body]\nsamples = 4\n\n[disk_wheel]"), "body.samples: given twice"),
])
def test_old_and_new_layouts_that_disagree_are_refused_naming_the_field(text, field):
    with pytest.raises(ScenarioError, match=field), warnings.catch_warnings():
        warnings.simplefilter("ignore", ScenarioLayoutWarning)
        parse_scenario(text)


def test_old_field_paths_given_with_set_move_with_a_warning():
    with pytest.warns(ScenarioLayoutWarning, match="strategy.samples is body.samples now"):
        sc = load_scenario("stepwise", ["strategy.samples=3"])
    assert sc.body.samples == 3
    with pytest.warns(ScenarioLayoutWarning, match="disk_wheel.rail_mass_kg is body.rail_mass_kg now"):
        assert load_scenario("stepwise", ["disk_wheel.rail_mass_kg=120"]).body.rail_mass_kg == 120


@pytest.mark.parametrize("sets, field", [
    (["strategy.kind=fourier", "body.kind=wheelset"], "body.kind: the fourier strategy needs a linear model, "
                                                      "which body 'wheelset' does not give; bodies that do: disk_wheel, vehicle_track"),
    (["strategy.kind=direct", "body.samples=4"], "body.samples: applies to the stepwise strategy only, not 'direct'"),
    (["strategy.kind=stepwise", "body.updates_per_revolution=2"], "body.updates_per_revolution: applies to the direct strategy only"),
    (["track.sleeper_spacing_m=0.65"], "track.sleeper_spacing_m: applies to body 'vehicle_track' only"),
    (["body.kind=ring"], "body.kind: unknown body kind 'ring'; known: disk_wheel, vehicle_track, wheelset"),
])
def test_what_a_strategy_needs_of_its_body_is_checked_naming_the_field(sets, field):
    with pytest.raises(ScenarioError, match=field.replace(".", r"\.").replace("(", r"\(")):
        load_scenario("onset", sets)


def test_every_strategy_finds_a_body_that_gives_what_it_needs():
    for kind, section in STRATEGY_SECTIONS.items():
        assert section.needs is None or any(section.needs in b.provides for b in BODY_SECTIONS.values()), kind


def test_the_multiplier_defaults_are_written_so_its_scenario_round_trips():
    """The multiplier's [solver] epsilon and nu default to 0: written into the scenario, so that
    its text (what a checkpoint's resume reads) is the same problem with the same hash."""
    sc = load_scenario("metro", ["strategy.kind=multiplier"])
    assert (sc.solver.epsilon, sc.solver.nu) == (0.0, 0.0)
    again = parse_scenario(to_toml(sc))
    assert again == sc and scenario_hash(again) == scenario_hash(sc)
    assert load_scenario("onset").solver.epsilon > 0  # the phenomenological default is kept


def test_a_fresh_railwear_reads_an_old_file_with_one_warning_line(tmp_path):
    """Run as a user does: ``railwear run`` of a file in the old layout says so on one line and
    runs the same problem as the new layout's file."""
    old = tmp_path / "old.toml"
    old.write_text(OLD["metro"] + '\n[solver]\npoints = 64\nt_end = 0.1\n', encoding="utf-8")
    r = subprocess.run([sys.executable, "-m", "railwear", "run", str(old), "-o", str(tmp_path / "out"), "--no-figures"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    notes = [line for line in r.stderr.splitlines() if "layout" in line]
    assert notes == ["railwear: warning: scenario layout before [body]: [vehicle], strategy.body read as [body] "
                     "kind = 'vehicle_track' (railwear show NAME prints the new layout)"]
