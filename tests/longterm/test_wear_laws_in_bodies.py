"""Wear laws through the bodies and strategies: the contact a law reads, its integral, the
energy law's two paths, Archard and USFD from scenarios, and a law plugged in from outside."""

from dataclasses import dataclass, replace
import numpy as np
import pytest

import railwear
from railwear.errors import ScenarioError
from railwear.longterm.disk_wheel import DiskWheel, long_term_integrator, swept_volume, wheel_turn
from railwear.scenario import load_scenario, parse_scenario, to_toml
from railwear.scenario.schema import WEAR_SECTIONS
from railwear.units import MM3
from railwear.wear import USFD, Archard, EnergyLaw, WearLaw

BAND = 0.01  # m


@dataclass(frozen=True)
class PlainEnergy(WearLaw):
    """The energy law without its ``beta``: the bodies take the path of any other law."""

    beta_value: float

    def volume_rate_of(self, contact):
        return self.beta_value * contact.frictional_power


def test_the_round_wheel_wears_by_each_laws_closed_form(wheel_220):
    """Steady rolling on the round wheel: normal force W, creepage ξ0, power F ξ0 V with F = T/R0
    and the Hertz patch π a b; over two turns the cells receive the law's rate times the time,
    evenly round the wheel but for the cells under the patch where it starts and ends."""
    m = replace(wheel_220, radius_deviation=np.zeros(64))
    p, surf, y = m.params(), m.surface(), m.initial_state()
    duration = 2 * wheel_turn(m)
    xi, force = m.steady_creepage(), m.traction_torque / m.radius
    area = np.pi * m.patch_half_length * BAND / 2
    usfd = USFD()
    expected = {
        Archard(1e-4, 3e9): 1e-4 * m.static_load * xi * m.speed / 3e9,
        usfd: usfd.volume_rate(force * xi * m.speed, m.speed, area),
        PlainEnergy(EnergyLaw().beta): EnergyLaw().beta * force * xi * m.speed,
    }
    for law, rate in expected.items():
        _, _, cells = swept_volume(m, p, surf, y, 0.0, duration, law, 64, BAND, long_term_integrator(), 4001)
        assert cells.sum() == pytest.approx(rate * duration, rel=1e-7), law
        np.testing.assert_allclose(cells[2:-2], cells[2:-2].mean(), rtol=1e-6)


def test_the_any_law_path_converges_at_second_order_and_meets_the_compiled_energy_sweep(wheel_220, rough_u0):
    """The energy law through the any-law path (each output interval's trapezoidal volume swept as
    the patch passes) converges at second order in the output interval (measured against 32000
    outputs a turn: 1.3e-3, 7.8e-5, 4.5e-6 of the largest rate at 500, 2000, 8000) to the rates
    of the compiled energy sweep, which it meets within 3.7e-4 (the sweep's own error over the
    integrator's steps); the totals agree to 2e-6."""
    fast = DiskWheel(wheel_220, EnergyLaw(), BAND, 5e7, samples=2)
    rate, _, _ = fast.statistics(rough_u0, np.random.default_rng(0))
    slow = {n: replace(fast, law=PlainEnergy(EnergyLaw().beta), outputs_per_revolution=n).statistics(
        rough_u0, np.random.default_rng(0))[0] for n in (500, 2000, 8000, 32000)}
    ref = slow[32000]
    errors = [np.max(np.abs(slow[n] - ref)) / np.max(np.abs(ref)) for n in (500, 2000, 8000)]
    assert errors[0] > 10 * errors[1] > 100 * errors[2] > 0
    assert np.max(np.abs(rate - ref)) / np.max(np.abs(ref)) < 1e-3
    assert ref.sum() == pytest.approx(rate.sum(), rel=2e-6)


def _edited(name, wear, solver=None, strategy=None):
    """Built-in ``name`` with a new ``[wear]`` section and solver / strategy fields."""
    sc = load_scenario(name, {"strategy.kind": strategy["kind"]} if strategy and "kind" in strategy else {})
    data = sc.applicable()
    data["wear"] = wear
    data["solver"].update(solver or {})
    data["strategy"] = strategy if strategy and "kind" in strategy else {**data["strategy"], **(strategy or {})}
    import tomli_w

    return parse_scenario(tomli_w.dumps(data), source=name)


LAWS = [{"law": "archard", "coefficient": 2e-3}, {"law": "usfd"}]


@pytest.mark.parametrize("wear", LAWS, ids=["archard", "usfd"])
@pytest.mark.parametrize("name, solver", [("stepwise", {"depth_limit_mm": 0.01}),
                                          ("direct", {"depth_limit_mm": 0.01, "t_end": 0.004})])
def test_disk_wheel_runs_each_law_from_a_scenario_and_removes_its_volume(name, solver, wear):
    """The stepwise and direct strategies on the disk wheel with Archard or USFD from ``[wear]``:
    the volume gone from the tread equals the law's volume at every output, to round-off."""
    ds = railwear.run(_edited(name, wear, solver))
    assert ds.attrs["strategy"] == name and "law = \"" + wear["law"] + "\"" in ds.attrs["scenario"]
    np.testing.assert_allclose(ds.removed_volume.values, ds.law_volume.values, rtol=1e-12, atol=0)
    assert ds.removed_volume.values[-1] > 0


@pytest.mark.parametrize("wear", LAWS, ids=["archard", "usfd"])
@pytest.mark.parametrize("kind", ["stepwise", "direct"])
def test_wheelset_runs_each_law_from_a_scenario_and_removes_its_volume(kind, wear):
    strategy = {"kind": kind, **({"acceleration_factor": 2e5} if kind == "direct" else {"step_limit_um": 1.0})}
    ds = railwear.run(_edited("wheelset-wear", wear, {"t_end": 0.002}, strategy))
    assert ds.attrs["wear_law"] == wear["law"]
    np.testing.assert_allclose(ds.removed_volume.values, ds.law_volume.values, rtol=1e-12, atol=0)
    assert ds.removed_volume.values[-1] > 0


def test_a_wheelset_run_deposits_the_trapezoidal_integral_of_the_law(profiles_problem):
    """One run: the volume put on both wheels is the trapezoidal integral of Archard's rate at the
    outputs (normal force, sliding speed V |(ξ, η)|), to round-off."""
    p = replace(profiles_problem, law=Archard(1e-3, 3e9))
    table = p.model.table
    ds, _ = p.run(table, 1.0, offset=2e-3)
    added, law, _ = p.deposit((p.new_surface(), p.new_surface()), ds, table, phase=1.0)
    slip = np.hypot(ds.longitudinal_creepage.values, ds.lateral_creepage.values) * p.model.speed
    rate = 1e-3 * ds.normal_force.values * slip / 3e9
    expected = float(np.sum(0.5 * (rate[1:] + rate[:-1]) * np.diff(ds.time.values)[:, None]))
    assert law == pytest.approx(expected, rel=1e-12) and added == pytest.approx(expected, rel=1e-12)


@pytest.fixture(scope="module")
def profiles_problem():
    from railwear.scenario import build

    sc = load_scenario("wheelset-wear")
    return sc.body.problem(sc)


def test_a_law_without_its_fields_or_of_another_law_is_refused_in_one_line():
    for wear, field in (({"law": "archard", "specific_wear_ug_per_J": 5.3}, "specific_wear_ug_per_J: does not apply to law 'archard'"),
                        ({"law": "usfd", "convention": "smooth"}, "wear.convention"),
                        ({"law": "none"}, "unknown wear law")):
        with pytest.raises(ScenarioError, match=field) as err:
            _edited("stepwise", wear)
        assert "\n" not in str(err.value)
    with pytest.raises(ScenarioError, match="wear.law"):
        railwear.run(_edited("polygonalisation", {"law": "archard"}))


@pytest.fixture
def constant_law():
    """A new wear law from outside the package, in two files: the law and its scenario section
    (tests/longterm/example_constant_law.py, example_constant_section.py)."""
    import importlib

    yield importlib.import_module("example_constant_section").ConstantWear
    WearLaw.registry.pop("constant")
    WEAR_SECTIONS.pop("constant")


def test_a_new_law_is_one_class_and_its_scenario_section(constant_law):
    """``[wear] law = "constant"`` on the round wheel at one speed: the tread loses the law's
    rate times the time in service, evenly, and the scenario round-trips through TOML."""
    sc = _edited("stepwise", {"law": "constant", "rate_mm3_per_s": 2e-3}, {"depth_limit_mm": 0.005},
                 {"step_limit_um": 2.0})
    data = sc.applicable()
    data["initial"] = {"kind": "round"}
    data["service"] = {"speed_kmh": [70.0], "seed": 0}
    import tomli_w

    sc = parse_scenario(tomli_w.dumps(data))
    assert parse_scenario(to_toml(sc)) == sc
    ds = railwear.run(sc)
    seconds = float(ds.stop_time) * sc.operation.life_distance_km * 1e3 / (70 / 3.6)
    assert float(ds.removed_volume[-1]) == pytest.approx(2e-3 * MM3 * seconds, rel=1e-9)
    worn = ds.u.values[0] - ds.u.values[-1]
    np.testing.assert_allclose(worn, worn.mean(), rtol=1e-6)
    assert float(ds.removed_depth[-1]) == pytest.approx(5e-6, rel=1e-9)


def test_a_law_with_an_internal_state_without_its_state_wears_as_the_energy_law(wheel_220, rough_u0):
    """The energy law in internal-state form and a hardening that never hardens, on the body that
    carries the state per cell: the compiled energy sweep's rates to 1e-3 (the any-law path's
    error at 2000 outputs a turn), the state unchanged."""
    from railwear.longterm.disk_wheel_state import StatefulDiskWheel
    from railwear.wear import Hardening, InternalStateLaw

    rate, _, _ = DiskWheel(wheel_220, EnergyLaw(), BAND, 5e7, samples=2).statistics(rough_u0, np.random.default_rng(0))
    for law in (InternalStateLaw.energy(EnergyLaw()), Hardening(saturation=0.0)):
        body = StatefulDiskWheel(wheel_220, law, BAND, 5e7, samples=2)
        both, _, _, _ = body.rates(body.start(rough_u0), np.random.default_rng(0),
                                   {"revolutions": 0, "rhs_evaluations": 0})
        assert np.max(np.abs(both[0] - rate)) < 1e-3 * np.max(np.abs(rate))
        assert np.all(both[1] == 0)


HARDENING = {"law": "hardening", "saturation": 100.0, "power_scale_W_m2": 1e4, "time_constant_s": 600.0}


@pytest.mark.parametrize("name, solver", [("stepwise", {"depth_limit_mm": 0.004, "t_end": 0.004}),
                                          ("direct", {"depth_limit_mm": 0.02, "t_end": 0.004})])
def test_hardening_from_a_scenario_removes_its_volume_and_wears_less(name, solver):
    """``[wear] law = "hardening"`` through stepwise and direct on the disk wheel: the surface
    state rises from 0 (and stays below its saturation), the tread loses exactly the law's volume
    at every output, and at a mean rate at least a fifth below the energy law's (measured: the
    state at 1.6-2.1 of 100, the rate 1.7x (stepwise) and 3.9x (direct) lower)."""
    hard = railwear.run(_edited(name, HARDENING, solver))
    plain = railwear.run(_edited(name, {"law": "energy"}, solver))
    np.testing.assert_allclose(hard.removed_volume.values, hard.law_volume.values, rtol=1e-12, atol=0)
    state = hard.surface_state.values[-1]
    assert 0 < state.mean() < 100.0 and np.all(hard.surface_state.values[0] == 0)
    def mean_rate(ds):  # m³ per unit normed time over the run
        return float(ds.removed_volume[-1]) / float(ds.time[-1])

    assert mean_rate(hard) < 0.8 * mean_rate(plain)


def test_a_killed_hardening_run_resumes_bit_for_bit():
    from helpers import Killed, killed_after

    from railwear.scenario import build

    strategy = build.strategy(_edited("stepwise", HARDENING, {"depth_limit_mm": 0.004, "t_end": 0.004}))
    u0 = build.initial_state(load_scenario("stepwise"))
    whole, saved = strategy.run(u0, until=0.004, depth_limit=4e-6), []
    with pytest.raises(Killed):
        strategy.run(u0, until=0.004, depth_limit=4e-6, checkpoint=killed_after(2, saved))
    resumed = strategy.run(u0, until=0.004, depth_limit=4e-6, resume=saved[-1])
    for name in ("u", "surface_state", "removed_volume"):
        np.testing.assert_array_equal(resumed[name].values, whole[name].values)
    assert whole.sizes["time"] > 3


def test_the_wheelset_refuses_a_law_with_a_state_in_one_line():
    data = load_scenario("wheelset-wear").applicable()
    data["wear"] = HARDENING
    import tomli_w

    with pytest.raises(ScenarioError, match="wear.law") as err:
        railwear.run(parse_scenario(tomli_w.dumps(data)))
    assert "\n" not in str(err.value)
