"""``railwear plan`` killed with SIGKILL and resumed with ``--resume`` from a fresh interpreter:
the uninterrupted plan.nc (run in this process), bit for bit."""

import pytest

from test_fresh_process import assert_same_result, killed_at, railwear, uninterrupted

pytestmark = pytest.mark.e2e

PLAN = ("plan", "metro", "--policy", "metro-condition", "--policy", "metro-interval", "--growth", "0.5,2",
        "--samples", "4", "--seed", "5", "--horizon-km", "450000", "--set", "solver.points=128", "--no-figures")


def test_a_killed_plan_resumes_to_the_same_plan(tmp_path):
    uninterrupted(*PLAN, "-o", tmp_path / "reference")
    out = tmp_path / "killed"
    killed_at(40, *PLAN, "-o", out, "--checkpoint-every", "0", cwd=tmp_path)
    assert (out / "plan-checkpoint.npz").is_file() and not (out / "plan.nc").exists()
    other = ["6" if i and PLAN[i - 1] == "--seed" else a for i, a in enumerate(PLAN)]
    refused = railwear(*other, "-o", out, "--resume", cwd=tmp_path, check=False)
    assert refused.returncode == 2 and "written for another plan" in refused.stderr.strip().splitlines()[-1]
    railwear(*PLAN, "-o", out, "--resume", cwd=tmp_path)
    assert_same_result(tmp_path / "reference" / "plan.nc", out / "plan.nc")
    assert not (out / "plan-checkpoint.npz").exists()
