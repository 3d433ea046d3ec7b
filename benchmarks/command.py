"""The warm floor of a command: ``railwear run`` (the built-in metro scenario: result.nc, summary,
four figures, report.html) in a fresh process against the bare import of numpy, scipy, xarray and
matplotlib, timed in turn in the same run; prints both and the ratio. A third process in the same
turn, the third-party floor, imports what the command's own process needs from other packages for
that run and nothing of railwear: numpy, xarray, typer, pydantic, numba (imported with railwear's
compiled modules; the run calls no compiled kernel, so numba's registries and cache are not
loaded), scipy.special (Carlson's integrals of the Hertz contact; scipy's array-API layer, which
imports numpy.f2py and numpy.testing, comes with it) and h5netcdf; matplotlib is left out, the
drawers import it alongside.

    python benchmarks/command.py [--rounds 5]

The first ``railwear run`` fills the numba cache if it is cold and is not counted. Wall time is
what a user waits for; CPU time (user + system of the child) is printed beside it because on a
shared machine the wall time moves with the other jobs. The load average is printed too.

Then, where the time goes: one fresh process does the command's steps in turn, in one process
(no forked drawers), and prints each step's wall and CPU time: importing the command, railwear's
API, numba, scipy.special, the first run (the modules the run imports on use), the same run again
(the computation alone), result.nc and the summary, matplotlib's import, each figure drawn
and saved, the report.
"""

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

BARE = [sys.executable, "-c", "import numpy, scipy, xarray, matplotlib"]

FLOOR = [sys.executable, "-c", "import gc, sys; gc.set_threshold(*gc.get_threshold()[:2], 1 << 30); "  # as the command
         "sys.modules['dask'] = None; "  # does (railwear.cli._full_collections, _hide_dask)
         "import numpy, xarray, typer, pydantic, numba, scipy.special, h5netcdf; "
         "import os; os._exit(0)"]  # no teardown, as the command (railwear.cli._exit)


STEPS = r"""
import json, sys, time
sys.modules["dask"] = None  # as the command does (railwear.cli._hide_dask)
steps, out = [], sys.argv[1]
def step(name, then=[time.perf_counter(), time.process_time()]):
    now = [time.perf_counter(), time.process_time()]
    steps.append((name, now[0] - then[0], now[1] - then[1]))
    then[:] = now
import railwear.cli
step("import railwear.cli (typer)")
from railwear import api, report, results
step("import railwear's API (scenario, pydantic, xarray)")
import numba
step("import numba")
import scipy.special
step("import scipy.special (Hertz integrals; scipy's array-API layer, numpy.f2py)")
ds = api.run("metro")
step("first run: the rest (modules imported on use; numba's registries "
     + ("loaded" if "numba.np.arraymath" in sys.modules else "not loaded") + ")")
ds = api.run("metro")
step("the same run again: the computation alone")
results.write_netcdf(ds, f"{out}/result.nc")
summary = results.write_summary(ds, out)
step("result.nc and the summary (h5netcdf imported)")
import matplotlib.backends.backend_agg, matplotlib.figure
from railwear import plots
step("import matplotlib (figure, agg)")
paths = []
for name, make in plots.FIGURES.items():
    paths.append(plots.save(make(ds), f"{out}/{name}.png"))
    step(f"figure {name}: drawn and saved")
report.write_report(ds, f"{out}/{report.NAME}", paths, [], False)
step("report.html")
print(json.dumps(steps))
"""


def railwear_run(directory):
    return [sys.executable, "-m", "railwear", "run", "-o", directory]


def timed(command):
    """Wall and CPU seconds of one run of ``command`` in a fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    out = tempfile.mkdtemp(prefix="railwear-command-")
    try:
        run = railwear_run(out)
        timed(run)  # warm the numba cache and the file system
        timed(BARE)
        timed(FLOOR)
        rows = {"railwear run": [], "bare import": [], "third-party floor": []}
        for _ in range(args.rounds):  # in turn, so all see the same moments of a shared machine
            rows["railwear run"].append(timed(run))
            rows["bare import"].append(timed(BARE))
            rows["third-party floor"].append(timed(FLOOR))
    finally:
        shutil.rmtree(out, ignore_errors=True)
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores; {args.rounds} rounds, medians "
          f"(min-max)")
    for name, samples in rows.items():
        wall, cpu = zip(*samples)
        print(f"{name:17s} wall {statistics.median(wall):.2f} s ({min(wall):.2f}-{max(wall):.2f}), "
              f"CPU {statistics.median(cpu):.2f} s ({min(cpu):.2f}-{max(cpu):.2f})")
    for name, note in (("railwear run", "target at most 2"), ("third-party floor", "what the run needs of other packages")):
        for k, what in enumerate(("wall", "CPU")):
            ratios = [a[k] / b[k] for a, b in zip(rows[name], rows["bare import"])]
            print(f"ratio {name} / bare import, {what}: {statistics.median(ratios):.2f} "
                  f"({min(ratios):.2f}-{max(ratios):.2f}, pair by pair; {note})")
    print("where the time goes, the steps in turn in one fresh process (wall, CPU):")
    out = tempfile.mkdtemp(prefix="railwear-steps-")
    try:
        done = subprocess.run([sys.executable, "-c", STEPS, out], check=True, capture_output=True, text=True)
    finally:
        shutil.rmtree(out, ignore_errors=True)
    steps = json.loads(done.stdout.splitlines()[-1])
    for name, wall, cpu in steps:
        print(f"  {wall:5.2f} s  {cpu:5.2f} s  {name}")
    print(f"  {sum(w for _, w, _ in steps):5.2f} s  {sum(c for _, _, c in steps):5.2f} s  in all (the interpreter's "
          f"start not counted)")


if __name__ == "__main__":
    main()
