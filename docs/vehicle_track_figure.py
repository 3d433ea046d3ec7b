"""The growth-map figure of docs/vehicle_track.md: the metro case over speed × polygon order.

Run: python docs/vehicle_track_figure.py [--output PATH]   (default docs/figures/vehicle-track-growth.png)

Fourier growth rate per kilometre of orders 1-40 over 40-100 km/h, with the lines of constant
frequency ``n = f π D / V`` of the P2 resonance (the peak of the bay-averaged normal-force
transfer) and of the pinned-pinned frequency, and the fastest-growing order at each speed.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railwear.longterm.vehicle_track import METRO, VehicleTrackModel, p2_frequency  # noqa: E402
from railwear.units import kmh_to_m_s  # noqa: E402
from railwear.wear import EnergyLaw  # noqa: E402


def main(output):
    kmh = np.linspace(40.0, 100.0, 61)
    orders = np.arange(1, 41)
    rate = METRO.growth_map(kmh_to_m_s(kmh), orders, EnergyLaw()).growth_rate.values * 1e4  # per 10 000 km
    fp2, fpp = p2_frequency(VehicleTrackModel(METRO.wheel(20.0), METRO.track)), METRO.track.pinned_pinned_frequency()
    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    limit = np.max(np.abs(rate))
    mesh = ax.pcolormesh(kmh, orders, rate.T, cmap="RdBu_r", vmin=-limit, vmax=limit, shading="nearest")
    bar = fig.colorbar(mesh, ax=ax)
    bar.set_label("growth rate of the harmonic [1 / 10 000 km]")
    v = kmh_to_m_s(kmh)
    ax.plot(kmh, fp2 * np.pi * METRO.diameter / v, "k-", lw=1.2, label=f"P2 resonance, {fp2:.1f} Hz")
    npp = fpp * np.pi * METRO.diameter / v
    ax.plot(kmh, npp, "k--", lw=1.2,
            label=f"pinned-pinned, {fpp:.0f} Hz (n = {npp.min():.0f}-{npp.max():.0f}, above the axes)")
    fastest = orders[np.argmax(rate, axis=1)]
    ax.plot(kmh, fastest, "o", ms=3, mfc="gold", mec="k", mew=0.5, label="fastest-growing order")
    ax.set_ylim(0.5, 40.5)
    ax.set_xlabel("speed [km/h]")
    ax.set_ylabel("polygon order n")
    ax.set_title(f"Metro wheel (D = {METRO.diameter} m) on 60E1, pads and sleepers at 0.6 m: Fourier growth",
                 fontsize=9)
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    fig.tight_layout()
    output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(output, dpi=120)
    plt.close(fig)
    return fp2, fpp, dict(zip(kmh, fastest))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "figures" / "vehicle-track-growth.png")
    print(main(parser.parse_args().output)[:2])
