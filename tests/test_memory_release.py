"""A large static solve releases the padded shape arrays it no longer needs (efgkit.static:
RELEASE_POINTS): the values before the stiffness, the padded derivatives after it (compact
CSR operators kept, Shape.gradients_only). Every field and K must come out the same as
with the arrays kept: the operators are the same numbers in the same order."""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

import efgkit.static as static
from efgkit.approx.shape import Gradients
from efgkit.methods.size import RELEASE_POINTS
from efgkit.scenefile import load_study
from efgkit.static import solve

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def pair():
    """The edge-cracked plate of the example at 1.6x its spacing (extrinsic enrichment,
    diffraction, Lagrange BCs; ~500 nodes), solved with the arrays kept and released."""
    scene, method = load_study(ROOT / "examples" / "edge_crack.toml")
    method = replace(method, spacing=method.spacing * 1.6,
                     zones=tuple(replace(z, spacing=z.spacing * 1.6) for z in method.zones))
    kept = solve(scene, method)
    keep, static.RELEASE_POINTS = static.RELEASE_POINTS, 0
    try:
        released = solve(scene, method)
    finally:
        static.RELEASE_POINTS = keep
    return kept, released


def test_the_released_solve_keeps_only_the_compact_derivatives(pair):
    kept, released = pair
    assert kept.disc.points.n < RELEASE_POINTS  # the default keeps them here
    assert type(kept.disc.shape).__name__ == "Shape"
    sh = released.disc.shape
    assert isinstance(sh, Gradients) and sh.values is None and sh.ddx is None
    assert sh.extra.ux is None and sh.extra.gxx is not None
    assert sh.dx.indices.dtype == np.int32 and np.shares_memory(sh.dx.indices, sh.dy.indices)
    assert "release" in released.timings


def test_fields_and_sifs_are_unchanged(pair):
    kept, released = pair
    np.testing.assert_array_equal(released.coeffs, kept.coeffs)  # the same K and f
    np.testing.assert_array_equal(released.gradient(), kept.gradient())
    np.testing.assert_array_equal(released.displacement(), kept.displacement())  # recomputed
    assert released.strain_energy() == kept.strain_energy()
    a, b = kept.sifs(error=False)[0], released.sifs(error=False)[0]
    assert (b.KI, b.KII) == (a.KI, a.KII)
    x = np.array([[1.0, 2.0], [5.0, 12.0]])
    np.testing.assert_array_equal(released.stress(x), kept.stress(x))


def test_released_values_say_how_to_get_them(pair):
    _, released = pair
    with pytest.raises(ValueError, match="values were released after the stiffness"):
        released.disc.shape.displacement(released.coeffs)
