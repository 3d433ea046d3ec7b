"""A bogie whose wheels start from different surfaces: the metro case's leading wheel with its
re-profiled roughness (orders 1-40, amplitude falling as 1/n, 10 um rms), the trailing wheel
2.5 m behind it round, under the Fourier technique to 0.1 mm out of round; prints each wheel's
end state for docs/vehicle_track.md ('Each wheel from its own surface') and draws the spectrum
figure, every wheel on its own floor.

    python docs/initial_wheels.py [FIGURE.png]
"""

import sys
from pathlib import Path

import numpy as np

from railwear import api, plots
from railwear.scenario import builtin_text, parse_scenario
from railwear.units import UM

INITIAL = """[[initial.wheels]]  # the leading wheel: the metro case's re-profiled roughness
kind = "random"
rms_um = 10.0
lowest_order = 1
highest_order = 40
amplitude_slope = 1.0
seed = 1

[[initial.wheels]]  # the trailing wheel: round
kind = "round"

"""
FIGURE = Path(__file__).parent / "figures" / "initial-wheels-spectrum.png"


def scenario():
    """The built-in metro scenario with ``wheel_positions_m = [0, 2.5]`` and :data:`INITIAL`."""
    text = builtin_text("metro")
    text = text[:text.index("[initial]")] + INITIAL + text[text.index("[strategy]"):]
    return parse_scenario(text.replace('kind = "vehicle_track"', 'kind = "vehicle_track"\nwheel_positions_m = [0, 2.5]'))


def rows(ds):
    """Per wheel: position (m), peak to peak at the start and the end (um), dominant order and its
    amplitude at the end (um)."""
    out = []
    for k in range(ds.sizes["wheel"]):
        d = ds.isel(wheel=k)
        n = int(d.dominant_order)
        out.append((float(d.wheel), float(d.peak_to_peak_initial) / UM, float(d.peak_to_peak) / UM, n,
                    float(d.amplitude.sel(order=n)) / UM))
    return out


def main(figure=FIGURE):
    ds = api.run(scenario())
    print(f"after {float(ds.distance[-1]):,.0f} km:")
    print("| wheel at | peak to peak at the start | at the end | dominant order | its amplitude |")
    print("|---|---|---|---|---|")
    for x, start, end, n, a in rows(ds):
        print(f"| {x:g} m | {start:.1f} um | {end:.1f} um | {n} | {a:.2f} um |")
    plots.save(plots.spectrum(ds), figure)
    return ds


if __name__ == "__main__":
    main(*(Path(p) for p in sys.argv[1:2]))
