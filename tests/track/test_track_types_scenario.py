"""[track] base and preset: the support sets from a scenario, the fields each base takes, the files
of the bases before them unchanged, and ``railwear track`` on every base."""

import tomllib

import numpy as np
import pytest
import tomli_w

from railwear import analysis
from railwear.errors import ScenarioError
from railwear.scenario import build, load_scenario, parse_scenario, scenario_hash, to_toml
from railwear.scenario.schema import TrackSection
from railwear.track import support_set

# the [track] fields every file had before the bases with a ballast mass or a slab
BEFORE = {"rail", "beam", "rail_loss_factor", "support", "sleeper_spacing_m", "pad_stiffness_MN_m", "pad_damping_kN_s_m",
          "pad_loss_factor", "sleeper_mass_kg", "base", "ballast_stiffness_MN_m", "ballast_damping_kN_s_m",
          "ballast_loss_factor", "bay_positions", "ring_sleepers", "ring_max_frequency_hz"}


def metro(track):
    """The metro scenario with ``track`` as its ``[track]``."""
    data = tomllib.loads(to_toml(load_scenario("metro")))
    data["track"] = track
    return parse_scenario(tomli_w.dumps(data), source="test")


def same_support(a, b):
    for name in a.__dataclass_fields__:
        assert getattr(a, name) == pytest.approx(getattr(b, name), rel=1e-15), name


@pytest.mark.parametrize("track, name", [
    ({"preset": "zhai-2004"}, "zhai-2004"),
    ({"base": "ballast_subgrade"}, "zhai-2004"),
    ({"base": "slab"}, "crts-slab-2019"),
    ({"preset": "crts-slab-2021"}, "crts-slab-2021"),
    ({"preset": "zhai-2004-no-subgrade"}, "zhai-2004-no-subgrade"),
])
def test_a_preset_or_a_base_gives_the_shipped_set(track, name):
    sc = metro(track)
    s = support_set(name)
    t = build.track(sc)
    same_support(t.support, s.support)
    assert sc.track.base == s.base and t.sleeper_spacing == s.sleeper_spacing


def test_given_fields_override_the_preset_and_round_trip():
    sc = metro({"preset": "zhai-2004", "subgrade_stiffness_MN_m": 120.0, "pad_stiffness_MN_m": 80.0,
                "sleeper_spacing_m": 0.65})
    t = build.track(sc)
    assert (t.support.subgrade_stiffness, t.support.pad_stiffness, t.sleeper_spacing) == (120e6, 80e6, 0.65)
    assert t.support.ballast_mass == 531.4
    for track in ({"preset": "zhai-2004"}, {"base": "slab", "mortar_loss_factor": 0.2}, {"base": "rigid"}, {},
                  {"preset": "crts-slab-2021", "support": "continuous"}):
        sc = metro(track)
        again = parse_scenario(to_toml(sc))
        assert scenario_hash(again) == scenario_hash(sc) and build.track(again) == build.track(sc)


def test_the_bases_before_dump_as_before():
    """A ballast or rigid [track] writes the fields it wrote before (so its text and hash stay); a
    rigid base no longer writes the sleeper and ballast defaults it then refused to read back."""
    assert set(TrackSection().model_dump()) == BEFORE
    assert set(TrackSection(base="rigid").model_dump()) == BEFORE - {"sleeper_mass_kg", "ballast_stiffness_MN_m",
                                                                      "ballast_damping_kN_s_m", "ballast_loss_factor"}
    assert set(TrackSection(preset="zhai-2004").model_dump()) == BEFORE | {
        "preset", "ballast_mass_kg", "subgrade_stiffness_MN_m", "subgrade_damping_kN_s_m", "subgrade_loss_factor"}
    assert set(TrackSection(base="slab").model_dump()) == (BEFORE - {
        "sleeper_mass_kg", "ballast_stiffness_MN_m", "ballast_damping_kN_s_m", "ballast_loss_factor"}) | {
        "slab_mass_kg", "mortar_stiffness_MN_m", "mortar_damping_kN_s_m", "mortar_loss_factor"}


@pytest.mark.parametrize("track, field", [
    ({"base": "slab", "sleeper_mass_kg": 125.5}, "track.sleeper_mass_kg"),
    ({"base": "ballast", "ballast_mass_kg": 500.0}, "track.ballast_mass_kg"),
    ({"subgrade_stiffness_MN_m": 80.0}, "track.subgrade_stiffness_MN_m"),
    ({"base": "rigid", "slab_mass_kg": 300.0}, "track.slab_mass_kg"),
    ({"preset": "zhai-2004", "mortar_stiffness_MN_m": 60.0}, "track.mortar_stiffness_MN_m"),
    ({"preset": "crts-slab-2019", "ballast_damping_kN_s_m": 50.0}, "track.ballast_damping_kN_s_m"),
    ({"base": "slab", "preset": "zhai-2004"}, "track.base"),
    ({"preset": "granite"}, "track.preset"),
    ({"base": "gravel"}, "track.base"),
    ({"preset": "zhai-2004", "subgrade_stiffness_MN_m": 0.0}, "track.subgrade_stiffness_MN_m"),
    ({"preset": "zhai-2004", "ballast_mass_kg": 2e4}, "track.ballast_mass_kg"),
    ({"base": "slab", "slab_mass_kg": 0.5}, "track.slab_mass_kg"),
    ({"base": "slab", "mortar_damping_kN_s_m": -1.0}, "track.mortar_damping_kN_s_m"),
    ({"preset": "zhai-2004", "subgrade_loss_factor": 3.0}, "track.subgrade_loss_factor"),
])
def test_fields_of_another_base_and_out_of_bounds_are_refused_naming_them(track, field):
    with pytest.raises(ScenarioError, match=field.replace(".", r"\.")):
        metro(track)


def test_time_domain_strategies_refuse_the_ballast_mass():
    sc = load_scenario("metro", {"strategy.kind": "stepwise", "track.preset": "zhai-2004"})
    with pytest.raises(ScenarioError, match="^subgrade_stiffness: the time-domain track"):
        build.strategy(sc)


@pytest.mark.parametrize("track, p2, others", [
    ({}, 55.75, []),
    ({"preset": "zhai-2004"}, 40.35, [84.7]),
    ({"base": "slab"}, 40.7, []),
    ({"preset": "crts-slab-2021"}, 51.75, []),
    ({"base": "rigid"}, 65.45, []),
    ({"preset": "zhai-2004", "support": "continuous"}, 40.4, [85.05]),
])
def test_track_command_reports_p2_and_pinned_pinned_on_every_base(track, p2, others):
    """``railwear track`` (analysis.track_receptance) on each base: the P2 is the lowest peak of
    the metro wheel's |N/ū| (grid 0.05 Hz), the others listed; the pinned-pinned frequency of the
    60E1 rail at 0.6 m (1067.3 Hz, Timoshenko) on a discrete track."""
    ds = analysis.track_receptance(metro(track), np.geomspace(10, 3000, 50))
    assert float(ds.p2_frequency) == pytest.approx(p2, abs=1e-9)
    assert list(ds.attrs.get("coupled_resonances_hz", [p2]))[1:] == pytest.approx(others, abs=1e-9)
    if track.get("support") == "continuous":
        assert "pinned_pinned_frequency" not in ds
    else:
        assert float(ds.pinned_pinned_frequency) == pytest.approx(1067.26, abs=0.01)
    assert ("base" in ds.attrs["track"]) == bool(track)


def test_metro_wheel_on_the_two_layer_support():
    """What the two-layer set would change for the metro case (its track is not changed): the
    growth map at 70 km/h selects order 6 (44.2 Hz, just above the lower P2 peak at 40.35 Hz) at
    +0.058 per 10 000 km, where the single layer selects order 8 (58.9 Hz) at +0.179."""
    orders = np.arange(1, 41)
    for track, order, rate in (({}, 8, 0.179), ({"preset": "zhai-2004"}, 6, 0.058)):
        growth = analysis.stability(metro(track), speeds_kmh=[70.0], orders=orders).growth_rate.values[0] * 1e4
        assert orders[np.argmax(growth)] == order and growth.max() == pytest.approx(rate, abs=5e-4)
