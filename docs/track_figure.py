"""The receptance figure of docs/track.md: a discrete 60E1 track over 10-3000 Hz.

Run: python docs/track_figure.py [--output PATH]   (default docs/figures/track-receptance.png)

Point receptance at midspan and above a sleeper, and of the smeared (continuous) support, with the
pinned-pinned frequency and the P2 resonance of a 900 kg unsprung mass per wheel marked. The P2
frequency is the peak of the wheel-on-track receptance ``1 / (1/(α_track + 1/k_c) - M ω²)``
(``k_c`` the linearised Hertz stiffness); the track resonance is the low-frequency peak of the track.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railwear.track import Support, Track, rail, receptance  # noqa: E402

TRACK = Track(
    rail("60E1", loss_factor=0.02),
    Support(pad_stiffness=120e6, pad_loss_factor=0.25, sleeper_mass=150.0, ballast_stiffness=50e6,
            ballast_loss_factor=1.0),
    sleeper_spacing=0.6,
)
UNSPRUNG_MASS = 900.0  # kg per wheel
CONTACT_STIFFNESS = 1.4e9  # N/m, linearised Hertz contact at about 100 kN


def p2_frequency(track, mass, contact_stiffness, position="midspan"):
    """Peak [Hz] of the receptance of a mass on the track through the contact spring, 20-200 Hz."""
    f = np.linspace(20.0, 200.0, 3601)
    alpha = receptance(track, f, position) + 1.0 / contact_stiffness
    coupled = 1.0 / (1.0 / alpha - mass * (2 * np.pi * f) ** 2)
    return f[np.argmax(np.abs(coupled))]


def main(output):
    f = np.geomspace(10.0, 3000.0, 1500)
    curves = {
        "midspan": receptance(TRACK, f, "midspan"),
        "above a sleeper": receptance(TRACK, f, "sleeper"),
        "smeared (continuous) support": receptance(TRACK.smeared(), f),
    }
    fpp = TRACK.pinned_pinned_frequency()
    fp2 = p2_frequency(TRACK, UNSPRUNG_MASS, CONTACT_STIFFNESS)
    low = f < 400
    f_track = f[low][np.argmax(np.abs(curves["above a sleeper"][low]))]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    styles = {"midspan": "-", "above a sleeper": "--", "smeared (continuous) support": ":"}
    for label, w in curves.items():
        ax1.loglog(f, np.abs(w), styles[label], label=label)
        ax2.semilogx(f, np.degrees(np.angle(w)), styles[label], label=label)
    for ax in (ax1, ax2):
        ax.axvline(fpp, color="0.4", lw=0.8)
        ax.axvline(fp2, color="tab:red", lw=0.8)
        ax.axvline(f_track, color="tab:green", lw=0.8)
        ax.grid(True, which="both", alpha=0.3)
    top = ax1.get_ylim()[1]
    ax1.text(fpp * 1.03, top / 3, f"pinned-pinned\n{fpp:.0f} Hz", fontsize=8, va="top")
    ax1.text(fp2 * 1.03, top / 3, f"P2, {UNSPRUNG_MASS:.0f} kg\nunsprung: {fp2:.0f} Hz", fontsize=8, va="top",
             color="tab:red")
    ax1.text(f_track * 1.03, top / 30, f"track\nresonance\n{f_track:.0f} Hz", fontsize=8, va="top", color="tab:green")
    ax1.set_ylabel("receptance magnitude [m/N]")
    ax2.set_ylabel("phase [deg]")
    ax2.set_xlabel("frequency [Hz]")
    ax2.set_ylim(-180, 0)
    ax2.set_yticks([-180, -135, -90, -45, 0])
    ax1.legend(loc="lower left", fontsize=8)
    ax1.set_title("Vertical point receptance, 60E1 on pads, sleepers and ballast at 0.6 m (Timoshenko)", fontsize=9)
    fig.tight_layout()
    output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(output, dpi=120)
    plt.close(fig)
    return fpp, fp2, f_track


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "figures" / "track-receptance.png")
    print(main(parser.parse_args().output))
