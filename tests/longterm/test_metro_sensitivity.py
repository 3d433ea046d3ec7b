"""The metro case's sensitivity to wheel inertia, traction and pad (issue 21 validation): the table
of docs/vehicle_track.md is what docs/metro_sensitivity.py prints, and the trends hold."""

from pathlib import Path

from helpers import doc_script

DOC = Path(__file__).resolve().parents[2] / "docs" / "vehicle_track.md"


def test_order_rises_with_pad_stiffness_and_the_table_is_the_scripts():
    module = doc_script("metro_sensitivity.py")
    rows = module.table()
    assert all(line in DOC.read_text() for line in rows)
    cells = [[c.strip() for c in line.strip("|").split("|")] for line in rows]
    by_input = {}
    for label, value, fastest, top, eight, p2 in cells:
        by_input.setdefault(label, []).append((float(value), int(fastest), float(top), float(eight), float(p2)))
    pad = by_input["rail pad stiffness [MN/m]"]
    assert [r[1] for r in pad] == sorted(r[1] for r in pad) and pad[0][1] < pad[-1][1]  # the order rises
    assert pad[0][4] < pad[1][4] < pad[2][4]  # with the P2 frequency
    traction = by_input["traction demand T/(W R0) [-]"]
    assert traction[0][2] < traction[1][2] < traction[2][2] and all(r[1] == 8 for r in traction)
    inertia = by_input["wheel polar inertia [kg m²]"]
    assert inertia[0][2] > inertia[1][2] > inertia[2][2] > 0
