"""A checkpoint consumer that is not due is not handed a state: a run of many saves does not copy
its history at every save (it did: 10 000 saves of 64 points took 62 s, 7 s without the copies)."""

import numpy as np

from railwear.checkpoints import Periodic, wanted
from railwear.scenario import build, load_scenario


class Counting:
    def __init__(self, due):
        self.calls, self._due = 0, due

    def due(self):
        return self._due

    def __call__(self, state):
        self.calls += 1


def _run(name, sets, checkpoint):
    sc = load_scenario(name, sets)
    return build.strategy(sc).run(build.initial_wear(sc), until=sc.solver.t_end, checkpoint=checkpoint)


def test_wanted_asks_due_where_there_is_one():
    assert not wanted(None) and wanted(lambda state: None)
    assert wanted(Counting(True)) and not wanted(Counting(False))
    later = Periodic(lambda state: None, 1e9)
    assert not later.due() and Periodic(lambda state: None, 0.0).due()


def test_evolution_and_stepped_runs_build_states_only_when_due():
    for name, sets in (("onset", ["solver.points=64", "solver.n_save=21", "solver.t_end=0.01"]),
                       ("stepwise", ["solver.n_save=4"])):
        never, always = Counting(False), Counting(True)
        quiet, told = _run(name, sets, never), _run(name, sets, always)
        assert never.calls == 0 and always.calls >= 3, (name, always.calls)
        np.testing.assert_array_equal(quiet.u.values, told.u.values)
