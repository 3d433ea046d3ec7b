"""Progress inside a dynamics run (issue 12, item 4): the compiled loop writes its time to a
clock without the GIL, a thread reads it; the numbers stay those of a run without it, bit for bit."""

import numpy as np
import pytest

from railwear import api
from railwear.dynamics import Integrator, simulate, simulation
from railwear.errors import ScenarioError
from railwear.scenario import dynamics


@pytest.fixture
def fast_polling(monkeypatch):
    monkeypatch.setattr(simulation, "POLL_S", 1e-3)


def _hunting(speed_kmh=280.0):
    return dynamics.build(dynamics.load_dynamics_scenario("hunting"), speed_kmh / 3.6)


def test_progress_inside_one_run_and_the_same_numbers(fast_polling):
    model = _hunting()  # above the critical speed: into the flange, many steps (0.1 s of wall time)
    plain = simulate(model, 40.0, n_output=2001)
    seen = []
    watched = simulate(model, 40.0, n_output=2001, progress=seen.append)
    assert set(watched.data_vars) == set(plain.data_vars) and watched.attrs == plain.attrs
    for name in plain.variables:
        np.testing.assert_array_equal(watched[name].values, plain[name].values, err_msg=name)
    inside = [f for f in seen if 0.0 < f < 1.0]
    assert seen[-1] == 1.0 and inside and np.all(np.diff(seen) > 0), seen


def test_the_compiled_loop_writes_its_clock():
    model = _hunting()
    clock = np.full(1, -1.0)
    run = Integrator(rtol=1e-8, atol=model.default_atol).run(model.kind, model.params(), model.surface(),
                                                             model.initial_state(), 0.0, 0.5, clock=clock)
    assert run.success and clock[0] == run.t == 0.5
    with pytest.raises(ScenarioError, match="^clock:"):
        Integrator().run(model.kind, model.params(), model.surface(), model.initial_state(), 0.0, 0.5,
                         clock=np.zeros(2))


def test_simulate_scenario_progress_moves_inside_each_speed(fast_polling, tmp_path):
    text = (dynamics._builtin_dir() / "hunting.toml").read_text()
    path = tmp_path / "long.toml"
    path.write_text(text.replace("duration_s = 4.0", "duration_s = 40.0").replace("n_output = 4001", "n_output = 401"))
    seen = []
    ds = api.simulate(str(path), progress=seen.append)
    assert seen[-1] == 1.0 and np.all(np.diff(seen) >= 0)
    assert any(0.5 < f < 1.0 for f in seen), seen  # inside the second run, not only 0.5 and 1
    plain = simulate(_hunting(), 40.0, n_output=401)
    np.testing.assert_array_equal(ds.sel(speed=280 / 3.6).lateral_displacement.values, plain.lateral_displacement.values)


def test_an_error_in_the_progress_call_reaches_the_caller(fast_polling):
    def broken(fraction):
        raise RuntimeError("display gone")

    with pytest.raises(RuntimeError, match="display gone"):
        simulate(_hunting(), 40.0, n_output=11, progress=broken)
