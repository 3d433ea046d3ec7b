"""A cold contact table compiles each of its kernels once (issue 23, cold start).

Not a timing test: it counts what a first table build types, in a fresh process with an empty
numba cache. numba compiles a callee once per value of a constant integer or boolean argument,
so a wheel side or a flag passed as a literal doubles the kernels behind it."""

from helpers import cold_probe

PROBE = """
from railwear.geometry import contact_geometry, contact_table, load_profile

wheel, rail = load_profile("S1002"), load_profile("UIC60")
y = np.round(np.linspace(-0.006, 0.006, 13), 12)
straight = contact_table(wheel, rail, y=y)
yawed = contact_table(wheel, rail, y=y, yaw=0.002)
kernels = {name: len(f.signatures) for name, f in vars(contact_geometry).items() if isinstance(f, Dispatcher)}
print(json.dumps({"compiled": compiled, "kernels": kernels,
                  "dr": straight["rolling_radius_difference"].values.tolist(),
                  "x": yawed["contact_X"].values.tolist()}))
"""


def test_a_cold_table_compiles_each_kernel_once(tmp_path):
    result = cold_probe(PROBE, tmp_path / "cache")
    ours = {name: count for name, count in result["kernels"].items() if count}
    assert "_table_core" in ours and "_solve_roll" in ours
    assert ours == dict.fromkeys(ours, 1)  # main typed _minima 4 times, _spline and _contact_point 3, _refine 2
    # the tables are real ones: the radius difference rises with the shift, and the yawed one's contacts
    # leave the plane of the axle (contact_X) on both wheels
    assert all(b > a for a, b in zip(result["dr"], result["dr"][1:]))
    assert all(abs(x) > 0 for row in result["x"] for x in row)
