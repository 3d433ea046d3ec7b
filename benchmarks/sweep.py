"""Sweep speed: a 64-speed stability map batched against separate processes; a 16-point sweep
on 1 and 2 workers.

Run: python benchmarks/sweep.py
1. The growth rate of orders 1-30 at 64 speeds, measured in short solver runs
   (``measured_growth_map``): one batched solve in one process, against one solve per speed
   spread over 2 worker processes (what a user would do with a process pool).
2. A dynamic sweep: 16 points of the ``stepwise`` scenario (the disk wheel's dynamics run on
   frozen geometry, strategy 3, each point about 1.5 s) over the wheel load, on 1 and on 2
   worker processes: the parallel efficiency ``T1 / (2 T2)``.
Worker start-up (spawn, imports, loading the compiled loop from the numba cache) is paid when the
pool is made, before timing, and reported apart.
"""

import platform
import tempfile
import time
from pathlib import Path

import numpy as np

from railwear import sweep
from railwear.pde import measured_growth_map
from railwear.scenario import build, load_scenario

ORDERS = np.arange(1, 31)


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def started_pool(workers):
    """A process pool whose workers have started and loaded railwear, and its start-up time."""
    return timed(lambda: sweep.LocalExecutor(workers))[::-1]


def one_speed_map(speed):
    """The map at one speed, as one worker task."""
    h = build.wear_rate(load_scenario("onset"))
    return measured_growth_map(h, [speed], ORDERS, 1e-4, 1e-3).growth_rate.values[0]


def main():
    base = load_scenario("onset")
    print(f"machine: {platform.processor() or platform.machine()}, {__import__('os').cpu_count()} cores, "
          f"python {platform.python_version()}, numpy {np.__version__}")
    with tempfile.TemporaryDirectory() as tmp:
        store = Path(tmp)
        speeds = np.linspace(20, 300, 64) / 3.6
        h = build.wear_rate(base)
        measured_growth_map(h, speeds[:2], ORDERS, 1e-4, 1e-3)  # compile
        t_batch, batched = timed(lambda: measured_growth_map(h, speeds, ORDERS, 1e-4, 1e-3))
        pool, startup = started_pool(2)
        t_pool, pooled = timed(lambda: np.array(list(pool.pool.map(one_speed_map, speeds))))
        pool.close()
        same = np.array_equal(batched.growth_rate.values, pooled)
        print("64-speed stability map, orders 1-30, 128 points, measured in short runs:")
        print(f"  batched evolution equation (one process): {t_batch:7.3f} s")
        print(f"  one solve per speed on 2 worker processes: {t_pool:7.3f} s  (+ {startup:.1f} s to start the workers)")
        print(f"  ratio processes / batched: {t_pool / t_batch:.1f} (target >= 5); identical results: {same}")

        dynamic = load_scenario("stepwise")
        loads = [sweep.parse_vary("wheel.static_load_kN=" + ",".join(f"{v:.1f}" for v in np.linspace(60, 100, 16)))]
        times = {}
        for workers in (1, 2):
            pool, startup = started_pool(workers)
            times[workers], _ = timed(lambda: sweep.run_sweep(dynamic, loads, store / f"w{workers}", executor=pool))
            pool.close()
            print(f"16-point dynamic sweep (stepwise) over the wheel load on {workers} worker(s): "
                  f"{times[workers]:6.2f} s (+ {startup:.1f} s start-up)")
        print(f"  parallel efficiency on 2 workers: {times[1] / (2 * times[2]):.2f} (target >= 0.8)")


if __name__ == "__main__":
    main()
