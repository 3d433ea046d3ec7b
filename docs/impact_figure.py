"""The figures and numbers of docs/maintenance.md, 'The dynamic wheel load': the metro wheel grown
by the Fourier technique from the built-in scenario's re-profiled roughness to 0.1 mm peak to peak
(the scenario's limit) and on to 0.5 mm, each rolled at 40-120 km/h over the time-domain track as
'railwear load metro --result result.nc' does. Prints each wheel's table and writes
docs/figures/impact-peak.png (both wheels' peak and least force against the detector thresholds)
and impact-trace.png (the 0.5 mm wheel over a revolution at 70 km/h).

    MPLBACKEND=agg python docs/impact_figure.py [--out DIR] [--speeds 40:120:10] [--revolutions 8]
"""

import argparse
import tempfile
from pathlib import Path

from railwear import api, plots, results
from railwear.maintenance import impact
from railwear.scenario import load_scenario
from railwear.sweep import parse_values

LIMITS_MM = (0.1, 0.5)  # peak to peak the wheel is grown to


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parent / "figures")
    parser.add_argument("--speeds", default="40:120:10", help="km/h, A:B:STEP or v1,v2,...")
    parser.add_argument("--revolutions", type=int, default=8)
    args = parser.parse_args(argv)
    speeds = parse_values(args.speeds, "--speeds")
    loads = {}
    with tempfile.TemporaryDirectory() as tmp:
        for limit in LIMITS_MM:
            sc = load_scenario("metro", [f"solver.peak_to_peak_limit_mm={limit}"])
            path = results.write_netcdf(api.run(sc), Path(tmp) / f"metro-{limit:g}mm.nc")
            loads[limit] = impact.wheel_load(sc, speeds, result=path, revolutions=args.revolutions)
            print(impact.report(loads[limit]))
    grown, first = loads[LIMITS_MM[-1]], loads[LIMITS_MM[0]]
    peak = impact.peak_figure(grown, f"{LIMITS_MM[-1]:g} mm wheel", [(f"{LIMITS_MM[0]:g} mm wheel", first)])
    trace = impact.trace_figure(grown, 70.0)
    written = [plots.save(peak, args.out / "impact-peak.png"), plots.save(trace, args.out / "impact-trace.png")]
    print("wrote", ", ".join(str(p) for p in written))
    return loads


if __name__ == "__main__":
    main()
