"""The stepwise strategy over a duty cycle against the cycle's averaged Fourier rates: the table of
docs/vehicle_track.md's "Duty cycles" section (about 20 s).

The disk wheel on its rail mass (the 'stepwise' built-in, 64 cells) pulls at +0.05 x its load at
40 km/h and brakes at -0.05 at 60 km/h, half the distance each, from 2 um harmonics of orders
3, 4, 13, 14 and 15. Each step's growth of order n, Re(Δû_n / (û_n ΔT)), is that step's Monte
Carlo rate; their mean over the run is set against Σ p_k λ_n^k / V_k (with the grid's sinc³(n/64)).
The Monte Carlo error expected of N draws, sqrt(p (1 - p) / N) |r_1 - r_2|, comes from the rates
r_k of each segment alone (every draw of a segment gives the same rate).

    python docs/duty_cycle_stepped.py
"""

import tomllib

import numpy as np

import railwear
from railwear.scenario import build, builtin_text, parse_scenario

ORDERS = np.array([3, 4, 13, 14, 15])
TWO = [{"share": 0.5, "speed_kmh": 40.0, "traction_coefficient": 0.05},
       {"share": 0.5, "speed_kmh": 60.0, "traction_coefficient": -0.05}]
LIFE_KM = 2500.0


def scenario(cycle, samples, steps, seed):
    data = tomllib.loads(builtin_text("stepwise"))
    data["operation"] = {"life_distance_km": LIFE_KM, "cycle": cycle}
    data["contact"].pop("traction_coefficient")
    data["service"] = {"seed": seed}
    data["body"].update(samples=samples, revolutions=2, transient_revolutions=2)
    data["initial"] = {"kind": "harmonics", "orders": ORDERS.tolist(), "amplitudes_um": [2.0] * ORDERS.size}
    # the uniform wear (79 um over the run) sets the steps
    data["strategy"] = {"kind": "stepwise", "step_limit_um": 80.0 / steps}
    return parse_scenario(data)


def fourier(sc):
    """The averaged Fourier rates per unit normed time, with the grid's filter."""
    technique = build.fourier_technique(sc)
    return technique.rates(ORDERS).real * build.life_distance(sc) / technique.speed * np.sinc(ORDERS / 64) ** 3


def segment_rates():
    """Each segment's frozen-geometry rate per order (per unit normed time): two draws of it alone."""
    out = []
    for segment in TWO:
        sc = scenario([dict(segment, share=1.0)], 2, 1, 0)
        u = build.initial_state(sc)
        rate = build.body(sc).statistics(u, np.random.default_rng(0))[0]
        out.append((-np.fft.rfft(rate)[ORDERS] / np.fft.rfft(u)[ORDERS]).real)
    return np.array(out)


def stepped(samples, steps, seed):
    """The stepwise run's mean rate per order, its standard error over the steps, and its steps."""
    ds = railwear.run(scenario(TWO, samples, steps, seed))
    spectrum = np.fft.rfft(ds.u.values, axis=1)[:, ORDERS]
    dT = np.diff(ds.time.values)
    per_step = ((spectrum[1:] - spectrum[:-1]) / (spectrum[:-1] * dT[:, None])).real
    return (per_step * dT[:, None]).sum(0) / dT.sum(), per_step.std(0, ddof=1) / np.sqrt(len(dT)), len(dT)


def main():
    reference = fourier(scenario(TWO, 8, 8, 0))
    alone = segment_rates()
    print("segments alone against their own Fourier rates (%):")
    for k, segment in enumerate(TWO):
        own = fourier(scenario([dict(segment, share=1.0)], 2, 1, 0))
        print(f"  {segment['traction_coefficient']:+.2f} at {segment['speed_kmh']:g} km/h: "
              + ", ".join(f"n={n} {100 * (a / b - 1):+.1f}" for n, a, b in zip(ORDERS, alone[k], own)))
    print("| draws (steps x samples) | seed | " + " | ".join(f"order {n}" for n in ORDERS) + " |")
    print("|---|---|" + "---|" * ORDERS.size)
    print("| averaged Fourier rate, per 10 000 km | | "
          + " | ".join(f"{r * 1e4 / LIFE_KM:+.3f}" for r in reference) + " |")
    for samples, steps, seeds in ((8, 8, (3, 4, 5, 6)), (16, 16, (3,))):
        n = samples * steps
        sigma = np.sqrt(0.25 / n) * np.abs(alone[0] - alone[1]) / np.abs(reference)
        for seed in seeds:
            mean, error, taken = stepped(samples, steps, seed)
            print(f"| {n} ({taken} x {samples}) | {seed} | "
                  + " | ".join(f"{100 * (m / r - 1):+.1f} % (±{100 * e / abs(r):.1f}; σ {100 * s:.1f})"
                               for m, e, r, s in zip(mean, error, reference, sigma)) + " |")


if __name__ == "__main__":
    main()
