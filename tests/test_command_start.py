"""The command's start: the garbage collector's full passes held while it imports, and restored
(with what was imported frozen out of later passes) when its computation starts."""

import gc

from railwear import cli


def test_full_collections_held_at_the_start_and_restored_when_the_computation_starts():
    before, frozen = gc.get_threshold(), gc.get_freeze_count()
    try:
        cli._full_collections(False)  # as main() does
        held = gc.get_threshold()
        assert held[:2] == before[:2] and held[2] >= 1 << 30
        with cli._Progress("railwear test"):
            assert gc.get_threshold() == before
        assert gc.get_freeze_count() > frozen
        cli._full_collections(True)  # once only: a second computation changes nothing
        assert gc.get_threshold() == before
    finally:
        gc.unfreeze()
        gc.set_threshold(*before)
        cli._state.pop("collector", None)


def test_a_computation_in_a_test_process_leaves_the_collector_alone():
    before, frozen = gc.get_threshold(), gc.get_freeze_count()
    with cli._Progress("railwear test"):
        pass
    assert gc.get_threshold() == before and gc.get_freeze_count() == frozen
