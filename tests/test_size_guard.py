"""The size guard: discretize and generate_nodes refuse, before allocating, what cannot fit in memory."""

import builtins
import time
from pathlib import Path

import pytest

import efgkit.memory as memory_module
from efgkit import EFG, Crack, Domain, Elastic, Rosette, Scene, Zone
from efgkit.methods.discretize import discretize
from efgkit.methods.size import size_estimate
from efgkit.nodes import ALWAYS_ALLOWED, FALLBACK_MEMORY, available_memory, check_memory, generate_nodes
from efgkit.scenefile import load_study

ROOT = Path(__file__).resolve().parents[1]
PLATE = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3))


def test_discretize_refuses_1e8_nodes_at_once():
    t0 = time.perf_counter()
    with pytest.raises(ValueError) as info:
        discretize(PLATE, EFG(spacing=1e-4))
    assert time.perf_counter() - t0 < 10  # refused from the estimate, nothing allocated
    msg = str(info.value)
    for part in ("spacing = 0.0001", "about 1e+08 nodes", "quadrature points", "GB",
                 "of memory available", "times coarser", "zones"):
        assert part in msg, part


def test_generate_nodes_refuses_on_its_own():
    with pytest.raises(ValueError, match=r"spacing = 2e-05 would give about 2\.5e\+09 nodes"):
        generate_nodes(PLATE.domain, EFG(spacing=2e-5))


def test_the_message_names_the_zone_that_is_too_fine():
    method = EFG(spacing=0.1, zones=(Zone((0.5, 0.5), 0.3, 1e-4),))
    with pytest.raises(ValueError, match=r"zones\[0\] \(radius 0\.3, spacing 0\.0001\)"):
        discretize(PLATE, method)


def test_check_memory_against_the_machine(monkeypatch):
    monkeypatch.setattr(memory_module, "available_memory", lambda: (2.5e9, "a test"))
    check_memory(2.4e9, "x", "y")
    check_memory(0.9 * ALWAYS_ALLOWED, "x", "y")
    with pytest.raises(ValueError, match=r"^w: about 3 GB in all, more than the 2\.5 GB of memory "
                                         r"available \(a test\)\. r 1\.1$"):
        check_memory(3e9, "w", "r {factor:.2g}")
    # below the floor nothing is refused, whatever the machine reports
    monkeypatch.setattr(memory_module, "available_memory", lambda: (1e6, "a test"))
    check_memory(0.99 * ALWAYS_ALLOWED, "x", "y")


def test_available_memory_falls_back(monkeypatch):
    have, source = available_memory()
    assert have > 0 and source

    def no_proc(path, *args, **kwargs):
        raise OSError(path)

    monkeypatch.setattr(builtins, "open", no_proc)
    assert "os.sysconf" in available_memory()[1]

    def no_sysconf(name):
        raise ValueError(name)

    monkeypatch.setattr(memory_module.os, "sysconf", no_sysconf)
    assert available_memory() == (FALLBACK_MEMORY, "a fixed limit: this machine does not report its "
                                                   "memory")


@pytest.mark.parametrize("name", ["patch", "cantilever", "kirsch", "edge_crack"])
def test_estimates_bound_the_examples(name):
    """Counts at or above the real ones; the examples far below the floor, so the guard never
    refuses them on any machine."""
    scene, method = load_study(ROOT / "examples" / f"{name}.toml")
    est = size_estimate(scene, method)
    d = discretize(scene, method)
    width = d.shape.neighbours.mask.shape[1]
    assert d.nodes.n <= est.nodes <= 2 * d.nodes.n
    assert len(d.points.w) <= est.points <= 3.5 * len(d.points.w)
    assert len(d.points.w) * width <= est.points * est.width  # the padded shape arrays
    assert est.bytes < 0.1 * ALWAYS_ALLOWED


def test_estimate_of_a_cracked_rosette_cloud():
    scene = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1.0, 0.3),
                  cracks=(Crack([[0.0, 0.5], [0.8, 0.5]], (False, True)),))
    method = EFG(spacing=0.05, rosette=Rosette(0.1))
    est = size_estimate(scene, method)
    d = discretize(scene, method)
    assert d.nodes.n <= est.nodes and len(d.points.w) <= est.points
    assert d.shape.neighbours.mask.shape[1] <= est.width
