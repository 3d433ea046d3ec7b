"""A fleet of 1000 measured wheels: ``railwear fleet``'s path against the loop a user would write.

The fleet: 1000 synthetic wheels (railwear.maintenance.fleet_input.write_synthetic: one polygon
of order 6-10 at 5-30 um plus 1 um of roughness on orders 1-40, files of 180 angles, diameters
780-840 mm) on the built-in metro (512 points, the Fourier technique) under metro-condition: the
distance to each trigger at growth 0.5, 1 and 2, the action and its date. Timed from the manifest
to the Dataset (reading the files included), in this process and on two local worker processes.

The alternative: what a user writes without the fleet path, a loop over the wheels calling
``railwear.forecast.forecast_file`` with a scenario of the wheel's diameter (one sample, the
scatter of [service] set to none: the scenario's conditions, as the fleet path runs them) and the 0.1 mm peak-to-peak limit, over a horizon of 10^6 km: one trigger at
one growth rate, less than the fleet path gives. It is run on a subset of the wheels and the time
extrapolated to 1000 (printed as such).

    python benchmarks/fleet.py [--subset 20] [--wheels 1000]
"""

import argparse
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np


def fleet_path(manifest, workers=None):
    from railwear.maintenance.fleet import fleet
    from railwear.sweep import LocalExecutor

    executor = LocalExecutor(workers) if workers else None  # started (and warmed) before the clock
    try:
        start = time.perf_counter()
        ds = fleet("metro", manifest, "metro-condition", executor=executor)
        return time.perf_counter() - start, ds
    finally:
        if executor is not None:
            executor.close()


def user_loop(manifest, wheels):
    """The loop a user writes: one forecast per wheel at its diameter; seconds and distances (km)."""
    from railwear.forecast import forecast_file
    from railwear.scenario import load_scenario

    rows = manifest.read_text().splitlines()[1:]
    head = manifest.read_text().splitlines()[0].split(",")
    out = []
    start = time.perf_counter()
    for row in rows[:wheels]:
        cell = dict(zip(head, row.split(",")))
        d = float(cell["diameter_mm"]) / 1000
        sc = load_scenario("metro", [f"wheel.radius_m={d / 2}", "service.speed_scatter_kmh=0", "service.load_scatter=0"],
                           unset=["service.friction_range"])  # the scenario's own conditions, as the fleet runs
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # one sample: the forecast warns it has no band
            ds = forecast_file(manifest.parent / cell["file"], sc, limit="0.1mm", samples=1, horizon_km=1e6)
        out.append(float(ds.crossing_distance[0]))
    return time.perf_counter() - start, np.array(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wheels", type=int, default=1000)
    parser.add_argument("--subset", type=int, default=20, help="wheels the user's loop runs (then extrapolated)")
    args = parser.parse_args()
    from railwear.maintenance.fleet_input import write_synthetic

    with tempfile.TemporaryDirectory() as folder:
        manifest, _ = write_synthetic(Path(folder), args.wheels, np.random.default_rng(2024))
        fleet_path(manifest)  # warm: imports, numba caches
        serial, ds = fleet_path(manifest)
        parallel, _ = fleet_path(manifest, workers=2)
        loop, distances = user_loop(manifest, args.subset)
        per_wheel = loop / args.subset
        extrapolated = per_wheel * args.wheels
        fleet_km = ds.distance_to_trigger.sel(growth=1.0, trigger="0.1 mm peak to peak").values[:args.subset]
        agree = np.max(np.abs(fleet_km - distances) / distances)
        print(f"{args.wheels} wheels, metro (512 points), metro-condition, growth 0.5, 1, 2; "
              f"{ds.node_diameter.size} rate nodes")
        print(f"  fleet path, this process:         {serial:7.1f} s")
        print(f"  fleet path, 2 worker processes:   {parallel:7.1f} s")
        print(f"  user's loop of forecast_file:     {per_wheel:7.2f} s a wheel over {args.subset} wheels; "
              f"EXTRAPOLATED to {args.wheels}: {extrapolated:7.0f} s")
        print(f"  ratio (extrapolated loop / fleet path in this process): {extrapolated / serial:.0f}")
        print(f"  the loop's 0.1 mm distances against the fleet's: largest difference {agree:.2%} "
              "(the forecast interpolates between 201 saved states; the fleet's rates are interpolated between nodes)")


if __name__ == "__main__":
    main()
