"""Policy files: the built-in ones load and say where their numbers come from; a bad field is
refused in one line naming it."""

import pytest

from railwear.errors import ScenarioError
from railwear.maintenance.policy import builtin_policy_names, builtin_policy_text, load_policy, parse_policy
from railwear.units import KM, MM

GOOD = """
name = "p"
source = "example"
[trigger]
{trigger}
[residual]
{residual}
[wheel]
last_turning_diameter_mm = 770.0
"""


def _policy(trigger="interval_km = 200000.0", residual='kind = "round"'):
    return parse_policy(GOOD.format(trigger=trigger, residual=residual), "p.toml")


def test_the_built_in_policies_load_and_state_their_sources():
    names = builtin_policy_names()
    assert {"metro-interval", "metro-condition", "metro-noise"} <= set(names)
    for name in names:
        policy = load_policy(name)
        assert policy.name == name and len(policy.source) > 20
        assert "example" in policy.source or "assumption" in policy.source  # what is not an operator's says so
        assert builtin_policy_text(name).startswith("#")
    interval = load_policy("metro-interval").build()
    assert interval.triggers.interval == 200_000 * KM and interval.last_diameter == 770 * MM
    condition = load_policy("metro-condition").build()
    assert condition.triggers.limits[0].peak_to_peak == 0.1 * MM and condition.turning.residual.orders == (3,)


def test_a_policy_file_is_read_from_its_path(tmp_path):
    path = tmp_path / "mine.toml"
    path.write_text(GOOD.format(trigger="peak_to_peak_mm = 0.2", residual='kind = "inherit"\nfraction = 0.05'))
    policy = load_policy(path)
    built = policy.build()
    assert built.turning.residual.fractions == (0.05,) and built.triggers.interval is None


@pytest.mark.parametrize("trigger, residual, message", [
    ("interval_km = 10.0", 'kind = "round"', "field 'trigger.interval_km': Input should be greater than or equal to 100"),
    ("", 'kind = "round"', "give at least one trigger"),
    ("order_level_db = [20.0, 25.0]", 'kind = "round"', "trigger.order_level_db: a list of levels needs orders"),
    ("order_level_db = [20.0]\norders = [8, 9]", 'kind = "round"', "trigger.orders: needs order_level_db as a list"),
    ("band_wavelength_mm = [180.0]\nband_level_db = [10.0]", 'kind = "round"',
     "trigger.band_wavelength_mm: 0.18 m is not a one-third-octave band centre"),
    ('band_limit = "iso3095"\ninterval_km = 1e5\npeak_to_peak_mm = -1.0', 'kind = "round"', "trigger.peak_to_peak_mm"),
    ("interval_km = 2e5", 'kind = "round"\nfraction = 0.3', "residual.fraction: does not apply to kind 'round'"),
    ("interval_km = 2e5", 'kind = "lathe"', "residual.kind: unknown residual kind 'lathe'"),
    ("interval_km = 2e5", 'kind = "spectrum"\norders = [3]\namplitudes_um = [1.0, 2.0]', "residual.amplitudes_um: needs one value per order"),
    ("interval_km = 2e5", 'kind = "inherit"\nfraction = 1.5', "residual.fraction': Input should be less than or equal to 1"),
    ("interval_km = 2e5", 'kind = "inherit"\norders = [8]', "residual.fractions: needs one fraction per order"),
    ("interval_km = 2e5", 'kind = "band"\nwavelength_mm = 230.0\nlevel_db = 5.0', "field 'residual.wavelength_mm': 230 mm is not"),
])
def test_a_bad_field_is_refused_in_one_line_naming_it(trigger, residual, message):
    with pytest.raises(ScenarioError) as e:
        _policy(trigger, residual)
    assert message in str(e.value) and "\n" not in str(e.value) and str(e.value).startswith("p.toml: ")


def test_an_unknown_policy_and_a_missing_file_are_named():
    with pytest.raises(ScenarioError, match="no built-in policy 'metro-yearly'; built-in policies: metro-condition"):
        load_policy("metro-yearly")
    with pytest.raises(ScenarioError, match="policy file nowhere/p.toml does not exist"):
        load_policy("nowhere/p.toml")
