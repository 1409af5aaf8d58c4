"""Solution.timings: the stages cover the wall time once each, numba compilation apart."""

import time

import numpy as np
import pytest
from numba import njit

from efgkit import EFG, Crack, Domain, Elastic, Scene, Support, Traction, solve
from efgkit.methods.discretize import discretize
from efgkit.timing import COMPILE, Stopwatch


def scene():
    return Scene(Domain.rectangle(0, 0, 2, 2), Elastic(1000.0, 0.25, "strain"),
                 supports=(Support("bottom", ux=0.0, uy=0.0),),
                 tractions=(Traction("top", (0.0, 1.0)),),
                 cracks=(Crack([[0.0, 1.0], [0.8, 1.0]], tips=(False, True)),))


def test_stages_add_up_to_the_wall_time():
    sc, method = scene(), EFG(spacing=0.25)
    t0 = time.perf_counter()
    sol = solve(sc, method)
    wall = time.perf_counter() - t0
    t = dict(sol.timings)
    total = t.pop("total")
    assert {"nodes", "quadrature", "approximation", "search", "shape", "stiffness",
            "solve"} <= set(t), t
    assert sum(t.values()) == pytest.approx(total, rel=0.05)
    assert total == pytest.approx(wall, rel=0.05)  # the discretisation counted once


def test_a_given_discretisation_is_not_timed_again():
    sc, method = scene(), EFG(spacing=0.25)
    disc = discretize(sc, method)
    t0 = time.perf_counter()
    sol = solve(sc, method, disc)
    wall = time.perf_counter() - t0
    t = dict(sol.timings)
    total = t.pop("total")
    assert "shape" not in t and "nodes" not in t
    assert sum(t.values()) == pytest.approx(total, rel=0.05)
    assert total <= wall


def test_compilation_is_a_stage_of_its_own():
    @njit
    def fresh(x):  # a new function: compiled inside the stage below
        return np.sum(x * x)

    sw = Stopwatch()
    t0 = time.perf_counter()
    with sw.stage("work"):
        fresh(np.ones(3))
    sw.lap("nothing")
    wall = time.perf_counter() - t0
    assert sw.timings[COMPILE] > 0.01  # compiling even a tiny function takes > 10 ms
    assert sw.timings["work"] < sw.timings[COMPILE]
    assert sum(sw.timings.values()) == pytest.approx(wall, rel=0.05)
