"""How sensitive the metro wheel's polygon growth is to its uncertain inputs: the fastest order of
1-40 at 70 km/h, its growth rate, the P2 order's rate and the P2 frequency, with the wheel's polar
inertia, the traction demand and the rail pad's stiffness each halved and doubled (the rest held
at METRO's). Prints the table of docs/vehicle_track.md ("Sensitivity of the metro case").

    python docs/metro_sensitivity.py
"""

import dataclasses

import numpy as np

from railwear.longterm.vehicle_track import METRO, VehicleTrackModel, p2_frequency
from railwear.track import Track
from railwear.units import kmh_to_m_s
from railwear.wear import EnergyLaw

ORDERS = np.arange(1, 41)
SPEED = kmh_to_m_s(70.0)
PER_10000_KM = 1e7


def with_pad(case, factor):
    """``case`` on its track with the pad stiffness times ``factor``."""
    t = case.track
    support = dataclasses.replace(t.support, pad_stiffness=t.support.pad_stiffness * factor)
    return dataclasses.replace(case, track=Track(t.rail, support, t.sleeper_spacing, t.beam))


VARIANTS = {
    "wheel polar inertia [kg m²]": ("wheel_inertia", lambda c, f: dataclasses.replace(c, wheel_inertia=c.wheel_inertia * f)),
    "traction demand T/(W R0) [-]": ("traction_coefficient",
                                     lambda c, f: dataclasses.replace(c, traction_coefficient=c.traction_coefficient * f)),
    "rail pad stiffness [MN/m]": ("pad", with_pad),
}


def row(case):
    """Fastest order, its rate and order 8's per 10 000 km, P2 [Hz]."""
    rate = case.fourier(SPEED, EnergyLaw()).rates(ORDERS).real / SPEED * PER_10000_KM
    i = int(np.argmax(rate))
    p2 = p2_frequency(VehicleTrackModel(case.wheel(SPEED), case.track))
    return int(ORDERS[i]), float(rate[i]), float(rate[7]), p2


def table():
    lines = []
    for label, (name, vary) in VARIANTS.items():
        for factor in (0.5, 1.0, 2.0):
            case = vary(METRO, factor)
            value = case.track.support.pad_stiffness / 1e6 if name == "pad" else getattr(case, name)
            fastest, top, eight, p2 = row(case)
            lines.append(f"| {label} | {value:g} | {fastest} | {top:+.3f} | {eight:+.3f} | {p2:.1f} |")
    return lines


if __name__ == "__main__":
    print("| input | value | fastest order (1-40) | its rate per 10 000 km | order 8 | P2 [Hz] |")
    print("|---|---|---|---|---|---|")
    print("\n".join(table()))
