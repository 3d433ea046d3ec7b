"""Short-wavelength contact physics: the figure docs/figures/transient-contact.png and the table of
docs/vehicle_track.md ("Short-wavelength contact physics").

Left: the non-steady contact's factors against the wavelength in patch lengths, Kalker's exact
linear theory on the half-space grid and the simplified theory, with the steady model's ``sinc²``
on the rolling-radius term. Right: growth per order of the metro wheel braking at 70 km/h under
the three contacts. Prints the fastest orders (1-80) of the metro and high-speed cases. Then the
longitudinal compliance in series with the contact (the rail head's, the wheel centre's): its table
and docs/figures/tangential-compliance.png.
Run: python docs/transient_contact.py
"""

import dataclasses
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from railwear.contact.transient import halfspace_transfer, simplified_transfer  # noqa: E402
from railwear.longterm.vehicle_track import HIGH_SPEED, METRO  # noqa: E402
from railwear.units import kmh_to_m_s  # noqa: E402
from railwear.wear import EnergyLaw  # noqa: E402

CONTACTS = {"steady": "steady (today)", "transient": "non-steady, half-space", "simplified": "non-steady, simplified"}
PER_10000_KM = 1e7


TANGENTIAL = {(): "rigid (today)", ("rail",): "rail head", ("wheel",): "wheel centre", ("rail", "wheel"): "both"}


def rates(case, kmh, traction, orders, contact, tangential=()):
    """Growth per 10 000 km of ``orders`` for ``case`` at ``kmh`` with ``traction`` (signed)."""
    v = kmh_to_m_s(kmh)
    c = dataclasses.replace(case, traction_coefficient=traction)
    return c.fourier(v, EnergyLaw(), contact=contact, tangential=tangential).rates(orders).real / v * PER_10000_KM


def tangential_table():
    """Fastest order of 1-120 (its rate) and order 8's / 22's under each compliance."""
    orders = np.arange(1, 121)
    rows = []
    for case, kmh, demand, mark in ((METRO, 70, 0.05, 8), (HIGH_SPEED, 300, 0.035, 22)):
        for sign in (1, -1):
            for contact in ("steady", "transient"):
                cells = []
                for tangential in TANGENTIAL:
                    r = rates(case, kmh, sign * demand, orders, contact, tangential)
                    i = int(np.argmax(r))
                    cells.append(f"{orders[i]} ({r[i]:+.2f}); {r[mark - 1]:+.2f}")
                rows.append(f"| {case.name} {kmh} km/h | {sign * demand:+.3f} | {contact} | " + " | ".join(cells) + " |")
    return rows


def tangential_figure(out=Path(__file__).parent / "figures" / "tangential-compliance.png"):
    orders = np.arange(1, 121)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True, sharex=True)
    for ax, traction in zip(axes, (0.05, -0.05)):
        for i, (tangential, label) in enumerate(TANGENTIAL.items()):
            ax.plot(orders, rates(METRO, 70, traction, orders, "steady", tangential), color=f"C{i}", label=label)
        ax.plot(orders, rates(METRO, 70, traction, orders, "transient", ("rail", "wheel")), "k--",
                label="both, non-steady contact")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.axvspan(6, 9, color="0.85", zorder=0, label="field: metro orders 6-9")
        ax.set_xlabel("polygon order n [-]")
        ax.set_ylabel("growth rate [1 per 10 000 km]")
        ax.set_title(f"Metro wheel, 70 km/h, {'traction' if traction > 0 else 'braking'} {traction:+.2f} W")
    axes[0].legend(fontsize=8, title="longitudinal compliance", title_fontsize=8)
    fig.savefig(out, dpi=130)
    plt.close(fig)
    return out


def table():
    orders = np.arange(1, 81)
    rows = []
    for case, kmh, demand in ((METRO, 70, 0.05), (HIGH_SPEED, 250, 0.035), (HIGH_SPEED, 300, 0.035),
                              (HIGH_SPEED, 350, 0.035)):
        for sign in (1, -1):
            cells = []
            for contact in CONTACTS:
                r = rates(case, kmh, sign * demand, orders, contact)
                i = int(np.argmax(r))
                cells.append(f"{orders[i]} ({r[i]:+.2f})")
            rows.append(f"| {case.name} | {kmh} | {sign * demand:+.3f} | " + " | ".join(cells) + " |")
    return rows


def main(out=Path(__file__).parent / "figures" / "transient-contact.png"):
    kappa = np.linspace(0.0, 3.0, 61)
    wavelength = np.pi / np.maximum(kappa, 1e-9)  # in patch lengths 2a
    half = halfspace_transfer(kappa, aspect=1.25, nx=16)
    simple = simplified_transfer(kappa)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.4), constrained_layout=True)
    keep = kappa > 0.5
    ax1.plot(wavelength[keep], np.abs(half["force_uniform"][keep]), "C0-", label="creep force / uniform creepage, half-space")
    ax1.plot(wavelength[keep], np.abs(simple["force_uniform"][keep]), "C0--", label="creep force / uniform creepage, simplified")
    ax1.plot(wavelength[keep], np.real(half["wear_material"][keep]), "C3-", label="rolling-radius wear (in phase), half-space")
    ax1.plot(wavelength[keep], np.real(simple["wear_material"][keep]), "C3--", label="rolling-radius wear, simplified (= 1)")
    ax1.plot(wavelength[keep], np.sinc(kappa[keep] / np.pi) ** 2, "k:", label="steady model: sinc²(κ)")
    ax1.set_xscale("log")
    ax1.set_xticks([1, 1.5, 2, 3, 4, 6], ["1", "1.5", "2", "3", "4", "6"])
    ax1.minorticks_off()
    ax1.set_xlabel("wavelength / patch length 2a [-]")
    ax1.set_ylabel("factor relative to steady [-]")
    ax1.set_ylim(0, 1.15)
    ax1.set_title("Non-steady contact, a/b = 1.25 (metro patch)")
    ax1.legend(fontsize=7.5, loc="lower right")
    orders = np.arange(1, 121)
    for contact, label in CONTACTS.items():
        ax2.plot(orders, rates(METRO, 70, -0.05, orders, contact), label=label)
    ax2.axhline(0.0, color="0.5", lw=0.8)
    ax2.set_xlabel("polygon order n [-]")
    ax2.set_ylabel("growth rate [1 per 10 000 km]")
    ax2.set_title("Metro wheel braking at -0.05 W, 70 km/h")
    ax2.legend(fontsize=8)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=130)
    plt.close(fig)
    return out


if __name__ == "__main__":
    print("| case | speed [km/h] | traction | " + " | ".join(CONTACTS.values()) + " |")
    print("|---|---|---|---|---|---|")
    print("\n".join(table()))
    print(main())
    print("| case | traction | contact | " + " | ".join(TANGENTIAL.values()) + " |")
    print("|---|---|---|---|---|---|---|")
    print("\n".join(tangential_table()))
    print(tangential_figure())
