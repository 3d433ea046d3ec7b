"""A cold wear-surface deposit compiles its overlap kernel once (issue 23, cold start).

Not a timing test: it counts what a first deposit types, in a fresh process with an empty numba
cache. The angle is periodic and the lateral grid bounded; passed as literal booleans, the two
flags typed ``_overlaps`` twice."""

from helpers import cold_probe

PROBE = """
from railwear.geometry import wear_surface

w = wear_surface.WearSurface(0.46, 120, np.linspace(-0.02, 0.02, 5))
added = w.deposit(1e-9, 0.0, 0.019, a=6e-3, b=4e-3, footprint="uniform")  # on the seam and the lateral edge
print(json.dumps({"compiled": compiled, "added": added, "removed": w.removed_volume(),
                  "first": w.depth[0].sum(), "last": w.depth[-1].sum(), "edge": w.depth[:, -1].sum(),
                  "overlaps": len(wear_surface._overlaps.signatures)}))
"""


def test_a_cold_deposit_compiles_the_overlaps_once(tmp_path):
    result = cold_probe(PROBE, tmp_path / "cache")
    assert result["compiled"].count("deposit_rectangles") == 1
    assert result["overlaps"] == 1 and result["compiled"].count("_overlaps") == 1  # twice before issue 23
    # the deposit is a real one: the patch reaching past the lateral edge is moved inside whole, the one
    # on the seam splits evenly between the first and the last angle cell, and the volume is kept
    assert abs(result["added"] - 1e-9) < 1e-22 and abs(result["removed"] - 1e-9) < 1e-22
    assert abs(result["first"] - result["last"]) < 1e-12 * result["first"]
    assert abs(result["edge"] - (result["first"] + result["last"])) < 1e-12 * result["edge"]
