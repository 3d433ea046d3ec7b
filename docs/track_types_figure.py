"""The track types of docs/track.md: rail receptance and the metro wheel's P2 on each support.

Run: python docs/track_types_figure.py [--output PATH]   (default docs/figures/track-types.png)

Each type is the built-in ``metro`` scenario with its ``[track]`` replaced (the same 60E1 rail,
Timoshenko, rail loss factor 0.02, at the set's spacing), evaluated by
``railwear.analysis.track_receptance``, the function behind ``railwear track``: the point
receptance at midspan and above a sleeper, the bay-averaged ``|N/ū|`` of the metro wheel at 70 km/h,
its P2 (the lowest peak of ``|N/ū|`` over 20-150 Hz) and the pinned-pinned frequency, and the
fastest-growing polygon order of the Fourier growth map at 70 km/h (``railwear stability``). ``main``
returns them per type for the table in docs/track.md; about 15 s.
"""

import argparse
import tomllib
from pathlib import Path

import matplotlib

matplotlib.use("agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import tomli_w  # noqa: E402

from railwear.analysis import stability, track_receptance  # noqa: E402
from railwear.scenario import build, load_scenario, parse_scenario, to_toml  # noqa: E402
from railwear.track import receptance  # noqa: E402

# label, the [track] table that replaces the metro scenario's (rail and damping kept)
TYPES = {
    "ballast, single layer (default)": {},
    "ballast on subgrade, two layers (zhai-2004)": {"preset": "zhai-2004"},
    "slab, CA 60 MN/m (crts-slab-2019)": {"preset": "crts-slab-2019"},
    "slab, CA 240 MN/m (crts-slab-2021)": {"preset": "crts-slab-2021"},
    "pads on a rigid base": {"base": "rigid"},
}
STYLES = ["-", "--", "-.", ":", (0, (5, 1, 1, 1, 1, 1))]
FREQUENCIES = np.geomspace(10.0, 3000.0, 1200)  # Hz
SPEED_KMH, ORDERS = 70.0, np.arange(1, 41)  # the metro scenario's speed; the orders of its growth map


def scenario(track):
    """The metro scenario with ``track`` as its ``[track]`` (the rail fields kept)."""
    data = tomllib.loads(to_toml(load_scenario("metro")))
    rail = {k: data["track"][k] for k in ("rail", "beam", "rail_loss_factor", "bay_positions")}
    data["track"] = {**rail, **track}
    return parse_scenario(tomli_w.dumps(data), source="track type")


def main(output):
    results = {}
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 7.0), sharex=True)
    for (label, track), style in zip(TYPES.items(), STYLES):
        sc = scenario(track)
        ds = track_receptance(sc, FREQUENCIES)
        midspan = ds.receptance_magnitude.sel(position="midspan").values
        p2, fpp = float(ds.p2_frequency), float(ds.pinned_pinned_frequency)
        near = np.linspace(0.95 * fpp, 1.05 * fpp, 2001)  # the midspan peak, 0.005 % steps
        results[label] = {
            "p2": p2,
            "resonances": [float(x) for x in ds.attrs.get("coupled_resonances_hz", [p2])],
            "pinned_pinned": fpp,
            "midspan_peak": float(near[np.argmax(np.abs(receptance(build.track(sc), near, "midspan")))]),
            "static_MN_m": 1e-6 / abs(receptance(build.track(sc), 0.0, "sleeper")),  # above a sleeper
            "attrs": ds.attrs["track"],
        }
        growth = stability(sc, speeds_kmh=[SPEED_KMH], orders=ORDERS).growth_rate.values[0] * 1e4  # per 10 000 km
        results[label].update(order=int(ORDERS[np.argmax(growth)]), growth=float(growth.max()))
        line, = top.loglog(FREQUENCIES, midspan, linestyle=style, label=label)
        bottom.loglog(FREQUENCIES, ds.contact_force_transfer.values, linestyle=style, color=line.get_color(),
                      label=f"P2 {p2:.1f} Hz")
        at = np.interp(p2, FREQUENCIES, ds.contact_force_transfer.values)
        bottom.plot([p2], [at], "o", color=line.get_color(), ms=4)
    fpp = next(iter(results.values()))["pinned_pinned"]
    top.axvline(fpp, color="0.4", lw=0.8)
    top.text(fpp * 1.04, top.get_ylim()[1] / 2, f"pinned-pinned\n{fpp:.0f} Hz", fontsize=8, va="top")
    top.set_ylabel("receptance at midspan [m/N]")
    bottom.set_ylabel("metro wheel |N / u| [N/m]")
    bottom.set_xlabel("frequency [Hz]")
    top.legend(loc="lower left", fontsize=8)
    bottom.legend(loc="lower right", fontsize=8, title="metro wheel, 70 km/h", title_fontsize=8)
    for ax in (top, bottom):
        ax.grid(True, which="both", alpha=0.3)
    top.set_title("60E1 rail (Timoshenko) on the track types of railwear.track", fontsize=9)
    fig.tight_layout()
    output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(output, dpi=120)
    plt.close(fig)
    return results


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "figures" / "track-types.png")
    for name, r in main(parser.parse_args().output).items():
        peaks = ", ".join(f"{x:.2f}" for x in r["resonances"])
        print(f"{name}: P2 {r['p2']:.2f} Hz (peaks {peaks}), pinned-pinned {r['pinned_pinned']:.0f} Hz "
              f"(midspan peak {r['midspan_peak']:.1f} Hz), static {r['static_MN_m']:.1f} MN/m, "
              f"fastest order {r['order']} ({r['growth']:+.3f} per 10 000 km)")
