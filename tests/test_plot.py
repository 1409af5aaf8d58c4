"""efgkit.plot: figures of node clouds and stress fields (Agg, no show, no files)."""

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from efgkit import EFG, Domain, Elastic, Loop, Scene, Support, Traction  # noqa: E402
from efgkit.nodes import generate_nodes  # noqa: E402
from efgkit.plot import COMPONENTS, plot_nodes, plot_stress  # noqa: E402
from efgkit.static import solve  # noqa: E402

SIGMA = 2.0  # uniform tension of the bar below: sigma_xx = SIGMA, the rest 0


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.fixture(scope="module")
def bar():
    """Uniaxial tension of a bar: a uniform stress field (a patch-test state)."""
    scene = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.25, "stress"),
                  supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
                  tractions=(Traction("right", (SIGMA, 0.0)),), name="bar")
    return solve(scene, EFG(spacing=0.25, bc="lagrange"))


@pytest.fixture(scope="module")
def plate():
    scene = Scene(Domain.rectangle(0, 0, 2, 1, holes=[Loop.circle([1, 0.5], 0.25)]),
                  Elastic(1000.0, 0.25, "strain"),
                  supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
                  tractions=(Traction("right", (1.0, 0.0)),), name="plate")
    return solve(scene, EFG(spacing=0.125, bc="lagrange"))


@pytest.mark.parametrize("supports_of", [None, (), (0,), (3, 7, 11)])
def test_plot_nodes_draws_requested_supports(plate, supports_of):
    fig = plot_nodes(plate, supports_of=supports_of)
    assert isinstance(fig, Figure)
    circles = fig.axes[0].patches
    if supports_of is None:
        assert 1 <= len(circles) <= 3
    else:
        assert len(circles) == len(supports_of)
        for c, i in zip(circles, supports_of, strict=True):
            assert c.get_radius() == pytest.approx(plate.nodes.radius[i])
            assert np.allclose(c.center, plate.nodes.x[i])


def test_plot_nodes_on_a_given_axes_with_a_bare_cloud():
    dom = Domain.rectangle(0, 0, 1, 1)
    nodes = generate_nodes(dom, EFG(spacing=0.25))
    fig, ax = plt.subplots()
    assert plot_nodes(nodes, dom, ax=ax, supports_of=[0]) is fig
    with pytest.raises(ValueError, match="domain"):
        plot_nodes(nodes)
    with pytest.raises(ValueError, match="supports_of"):
        plot_nodes(nodes, dom, supports_of=[nodes.n])


@pytest.mark.parametrize("component", COMPONENTS)
def test_plot_stress_returns_figure_with_colourbar(plate, component):
    fig = plot_stress(plate, component, n_target=1500, levels=12)
    assert isinstance(fig, Figure)
    ax, cax = fig.axes  # the plot and its colourbar
    assert ax.get_aspect() == 1.0
    assert len(ax.collections[0].get_paths()) >= 1


def test_plot_stress_levels_span_the_field(plate):
    fig = plot_stress(plate, "xx", n_target=1500, levels=10)
    cs = fig.axes[0].collections[0]
    x = np.array([[0.1, 0.1], [1.0, 0.77], [1.9, 0.9]])  # incl. the stress concentration
    s = plate.stress(x)[:, 0]
    assert len(cs.levels) == 11
    assert cs.levels[0] <= s.min() and s.max() <= cs.levels[-1]


def test_plot_stress_shows_the_discretisation_error_of_a_uniform_field(bar):
    # sigma_xx = SIGMA up to quadrature error (~1e-4 here): the levels span that error
    fig = plot_stress(bar, "xx", n_target=500, levels=30)
    levels = fig.axes[0].collections[0].levels
    assert levels[0] < SIGMA < levels[-1]
    assert levels[-1] - levels[0] <= 1e-2 * SIGMA


def test_plot_stress_exactly_constant_field_is_one_band(bar):
    # a field constant to round-off gets one band around its value, not contours of noise
    const = SimpleNamespace(scene=bar.scene, stress=lambda x: np.tile(
        [SIGMA * (1 + 1e-14), 0.0, 0.0], (len(x), 1)) * (1 + 1e-13 * (x[:, :1] > 1)))
    fig = plot_stress(const, "xx", n_target=500, levels=4)
    levels = fig.axes[0].collections[0].levels
    np.testing.assert_allclose(levels, SIGMA * (1 + np.linspace(-1e-3, 1e-3, 5)), rtol=1e-12)


def test_plot_stress_rejects_bad_arguments(bar):
    with pytest.raises(ValueError, match="component"):
        plot_stress(bar, "zz")
    with pytest.raises(ValueError, match="levels"):
        plot_stress(bar, levels=0)
