"""The MLPG size guard: discretize_local refuses, before allocating, what cannot fit in memory."""

import time

import pytest

from efgkit import MLPG, Domain, Elastic, Scene
from efgkit.methods.local import discretize_local
from efgkit.methods.local_size import local_size_estimate

PLATE = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3))


def test_discretize_local_refuses_1e8_nodes_at_once():
    t0 = time.perf_counter()
    with pytest.raises(ValueError) as info:
        discretize_local(PLATE, MLPG(spacing=1e-4))
    assert time.perf_counter() - t0 < 10  # refused from the estimate, nothing allocated
    msg = str(info.value)
    for part in ("MLPG with spacing = 0.0001: test discs", "about 1e+08 nodes", "quadrature points",
                 "GB", "of memory available", "times coarser", "cut_angular"):
        assert part in msg, part


def test_estimate_against_a_measured_plate():
    # measured (module comment of efgkit.methods.local_size): h = 0.02 on the unit plate,
    # 2,601 nodes, 151,720 disc + 6,400 boundary + 40,000 cell points, width 21
    est = local_size_estimate(PLATE, MLPG(spacing=0.02))
    assert 0.9 < est.nodes / 2601 < 1.15
    assert 0.9 < est.points / 198120 < 1.2
    assert est.width == 21


def test_estimate_needs_an_mlpg():
    from efgkit import EFG

    with pytest.raises(TypeError, match="method must be an MLPG description, got EFG"):
        local_size_estimate(PLATE, EFG(spacing=0.1))
