"""The evolution figure's panel of orders shows the dominant order (issue 22, item 4)."""

import pytest

import railwear
from railwear import plots


def _legend_orders(fig):
    """The orders named in the legend of the amplitude panel."""
    (legend,) = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    return [int(t.get_text().split(":")[0].split()[1]) for t in legend.get_texts()]


@pytest.mark.parametrize("name", ["stable", "smoothing"])
def test_the_dominant_order_is_drawn_when_the_starts_tie(name):
    """The paper's starts give orders 2-16 the same amplitude; ranked by their maximum over the
    run, the ties left out order 2, the largest at the end (stable: orders 7, 8, 11, 12, 14, 15
    were drawn). Ranked by the end, the dominant order is first."""
    ds = railwear.run(name)
    drawn = _legend_orders(plots.evolution(ds))
    assert drawn[0] == int(ds.dominant_order) == 2
    assert len(drawn) == 6


def test_the_orders_are_the_largest_at_the_end():
    ds = railwear.run("linear-dynamics")
    end = ds.amplitude.values
    largest = sorted(range(end.size), key=lambda k: -end[k])[:6]
    assert _legend_orders(plots.evolution(ds)) == [int(ds.order.values[k]) for k in largest]
