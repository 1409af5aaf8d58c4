"""The J domains of the SENT rows of ``verification/mlpg_fracture.py`` (issue 14): the single
domains of the radius table hold the headline and the large domains, all of them fit in the
specimen, the radius table renders, and (slow) plain MLPG's J falls towards the FEM reference as
the domain grows (near-tip error; docs/theory.md, MLPG1, "The plain SENT and the J domain")."""

import sys
from pathlib import Path

import numpy as np
import pytest

VERIFICATION = Path(__file__).resolve().parents[1] / "verification"
if str(VERIFICATION) not in sys.path:  # the scripts import their siblings, as in test_verification
    sys.path.insert(0, str(VERIFICATION))

import mlpg_fracture as mf  # noqa: E402
from sent import A, L, W  # noqa: E402


def test_domains_are_in_the_table_and_fit_the_specimen():
    table = set(mf.SENT_TABLE)
    assert set(mf.SENT_RADII) <= table and set(mf.SENT_LARGE) <= table
    # the largest disc about the tip (L/2, a) stays inside the ligament W - a and behind the
    # crack mouth (distance a), so no domain is clipped by the outer boundary
    assert max(mf.SENT_TABLE) < min(A, W - A, L / 2)
    assert min(mf.SENT_LARGE) >= 0.6 * min(A, W - A)


def test_radius_table_renders_every_row_at_the_largest_size():
    n = max(mf.SENT_SIZES)
    keys = [f"sent_clamped/mlpg/plain/{n}", f"sent_axial/efg/plain/{n}"]
    record = {"J_radius": {k: {str(r): 1e-3 * r for r in mf.SENT_TABLE} for k in keys}}
    lines = mf.radius_table(record)
    rows = [ln for ln in lines if ln.startswith("| clamped") or ln.startswith("| axial")]
    assert len(rows) == 2
    assert rows[0].split("|")[1].strip() == "clamped/mlpg/plain"
    assert rows[0].count("|") == len(mf.SENT_TABLE) + 2
    assert mf.radius_table({}) == []


@pytest.mark.slow
def test_plain_sent_j_falls_with_the_domain_radius():
    rows = mf.sent_rows(20, "clamped", ("plain",))
    key = "sent_clamped/mlpg/plain/20"
    err = rows["J_radius"][key]
    # the headline J is the mean of its single domains
    J = np.mean([(1 + err[r]) * mf.SENT_J_FEM["clamped"] for r in mf.SENT_RADII])
    assert J == pytest.approx(rows["J_sent"][key], rel=1e-12)
    # measured 20 across (verification/out/mlpg_fracture.json): +5.9 % at 1 mm falling to
    # +0.99 % at 4.5 mm against the FEM J (sent record, graded P2 with quarter points)
    big = [err[r] for r in mf.SENT_TABLE if r >= 1.0]
    assert np.all(np.diff(big) < 0)
    assert 0 < err[4.5] < 3e-2
    assert rows["J_error_large"][key] < rows["J_error"][key]
