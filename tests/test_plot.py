"""efgkit.plot: figures of node clouds, stress fields and K against the domain (Agg, no show,
no files); the tests read what is drawn: legend entries, panels, lines, arrows."""

from types import SimpleNamespace

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.quiver import Quiver  # noqa: E402

from efgkit import EFG, Crack, Domain, Elastic, Field, Loop, Scene, Support, Traction  # noqa: E402
from efgkit.fracture.integrals import SIF  # noqa: E402
from efgkit.fracture.sif import TipResult  # noqa: E402
from efgkit.nodes import generate_nodes  # noqa: E402
from efgkit.plot import COMPONENTS, plot_domain_dependence, plot_nodes, plot_stress  # noqa: E402
from efgkit.problem.crack import Tip  # noqa: E402
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


# ---- plot_nodes: supports, loads, cracks and support circles are drawn and named ----

def _labels(ax) -> list[str]:
    return [t.get_text() for t in ax.get_legend().get_texts()]


def _arrows(ax) -> Quiver | None:
    qs = [c for c in ax.collections if isinstance(c, Quiver)]
    assert len(qs) <= 1
    return qs[0] if qs else None


def test_plot_nodes_marks_supports_and_tractions_of_the_scene(bar):
    fig = plot_nodes(bar, supports_of=(0,))
    ax = fig.axes[0]
    labels = _labels(ax)
    assert "$u_x$ fixed on left" in labels and "$u_y$ fixed on bottom" in labels
    assert any(lab.startswith("traction") and f"{SIGMA:g}" in lab for lab in labels)
    assert f"support of node 0 (radius {bar.nodes.radius[0]:.3g})" in labels
    assert {"interior nodes", "boundary nodes"} <= set(labels)
    assert ax.get_title() == f"bar: nodes ({bar.nodes.n}), supports, loads, 1 support circle"
    # the support lines lie on their edges: x = 0 (left), y = 0 (bottom)
    lines = {ln.get_label(): ln.get_xydata() for ln in ax.lines}
    left, bottom = lines["$u_x$ fixed on left"], lines["$u_y$ fixed on bottom"]
    left, bottom = left[~np.isnan(left).any(1)], bottom[~np.isnan(bottom).any(1)]
    assert np.allclose(left[:, 0], 0.0) and np.ptp(left[:, 1]) == pytest.approx(1.0)
    assert np.allclose(bottom[:, 1], 0.0) and np.ptp(bottom[:, 0]) == pytest.approx(2.0)
    # a few arrows on the right edge (x = 2), just outside it, all (SIGMA, 0)
    q = _arrows(ax)
    assert 2 <= q.N <= 7
    assert np.all((q.X > 2.0) & (q.X < 2.1)) and np.all((q.Y > 0.0) & (q.Y < 1.0))
    np.testing.assert_allclose(np.column_stack([q.U, q.V]), [[SIGMA, 0.0]] * q.N)
    assert ax.get_xlim()[1] > 2.1  # the arrows are inside the view


def test_plot_nodes_with_a_scene_a_mask_support_a_field_traction_and_a_crack():
    dom = Domain.rectangle(0, 0, 2, 1)
    crack = Crack([[0.0, 0.5], [0.8, 0.5]], tips=(False, True), name="edge")
    kirsch = Field.named("kirsch", a=0.1, sigma=1.0, centre=(5.0, 5.0))
    scene = Scene(dom, Elastic(1.0, 0.3), cracks=(crack,), name="cracked",
                  supports=(Support(lambda x: x[:, 0] > 1.5, ux=0.0, uy=lambda x: 0 * x[:, 0]),),
                  tractions=(Traction("top", kirsch), Traction("left", lambda x: x * [0.0, 1.0])))
    nodes = generate_nodes(dom, EFG(spacing=0.25))
    fig = plot_nodes(nodes, scene, supports_of=())
    ax = fig.axes[0]
    labels = _labels(ax)
    assert "crack" in labels and "$u_x$ fixed; $u_y$ prescribed on selected boundary" in labels
    assert ax.get_title() == f"cracked: nodes ({nodes.n}), supports, loads, cracks"
    sup = dict((ln.get_label(), ln.get_xydata()) for ln in ax.lines)[labels[1]]
    sup = sup[~np.isnan(sup).any(1)]
    assert len(sup) and np.all(sup[:, 0] > 1.5)  # only where the mask selects
    crack_line = dict((ln.get_label(), ln.get_xydata()) for ln in ax.lines)["crack"]
    np.testing.assert_allclose(crack_line, crack.vertices)
    q = _arrows(ax)  # the arrows carry the scene's traction values at their edge points
    top = q.Y > 1.0
    x_top = np.column_stack([q.X[top], np.ones(top.sum())])
    s = kirsch.stress(x_top, scene.material)
    np.testing.assert_allclose(np.column_stack([q.U[top], q.V[top]]), s[:, [2, 1]], rtol=1e-12)
    np.testing.assert_allclose(q.V[q.X < 0], q.Y[q.X < 0], atol=1e-12)  # left: t = (0, y)


def test_plot_nodes_of_a_bare_cloud_draws_no_loads():
    dom = Domain.rectangle(0, 0, 1, 1)
    nodes = generate_nodes(dom, EFG(spacing=0.25))
    ax = plot_nodes(nodes, dom, supports_of=range(6)).axes[0]
    assert _arrows(ax) is None and ax.get_title() == f"nodes ({nodes.n}), 6 support circles"
    r = nodes.radius[:6]
    assert _labels(ax) == ["interior nodes", "boundary nodes",
                           f"supports of 6 nodes (radius {r.min():.3g} to {r.max():.3g})"]


# ---- plot_domain_dependence: K_I, K_II and J on their own panels, references ----

def _result(crack: str, end: int, KI, KII, J) -> TipResult:
    doms = tuple(SIF(j, a, b, 0.0, 1.0, 100, 0.5 + 0.25 * k)
                 for k, (a, b, j) in enumerate(zip(KI, KII, J, strict=True)))
    spread = max(np.ptp(KI), np.ptp(KII)) / np.hypot(np.mean(KI), np.mean(KII))
    return TipResult(Tip(np.zeros(2), 0.0, crack, end), float(np.mean(KI)), float(np.mean(KII)),
                     float(np.mean(J)), 0.0, float(spread), doms)


A = _result("c", 1, [1.00, 1.001, 1.002], [0.30, 0.31, 0.32], [2.0, 2.001, 2.003])
B = _result("c", 0, [0.80, 0.80, 0.80], [-0.20, -0.20, -0.20], [1.0, 1.0, 1.0])


def _dashed(ax) -> dict[str, float]:
    return {ln.get_label(): ln.get_ydata()[0] for ln in ax.lines if ln.get_linestyle() == "--"}


def test_domain_dependence_panels_per_quantity_and_tip():
    fig = plot_domain_dependence([A, B])
    assert len(fig.axes) == 6  # K_I, K_II, J for each of two tips
    grid = np.array(fig.axes).reshape(3, 2)
    assert [a.get_ylabel() for a in grid[:, 0]] == ["$K_I$", "$K_{II}$", "$J$"]
    assert grid[0, 0].get_title() == f"tip c:1 (spread {A.spread:.2g} of |K|)"
    assert grid[0, 1].get_title() == "tip c:0 (spread 0 of |K|)"
    for j, res in enumerate((A, B)):
        for i, name in enumerate(("KI", "KII", "J")):
            ax = grid[i, j]
            (domains, mean) = ax.lines[:2]
            np.testing.assert_allclose(domains.get_ydata(), [getattr(d, name) for d in res.domains])
            assert mean.get_ydata()[0] == pytest.approx(getattr(res, name))
            assert _labels(ax)[0].startswith(f"{res.tip.id} per domain (max - min")
            lo, hi = ax.get_ylim()  # the panel's own range: not forced to 0, the values inside
            assert lo <= min(domains.get_ydata()) and max(domains.get_ydata()) <= hi
            assert lo * hi > 0
    # K_II of tip A varies by 0.02, 2% of |K|: it fills most of its panel
    lo, hi = grid[1, 0].get_ylim()
    assert hi - lo < 2 * 0.02
    # a constant K keeps a +-1% |K| range: a flat line reads as flat
    lo, hi = grid[0, 1].get_ylim()
    assert hi - lo == pytest.approx(1.2 * 0.02 * np.hypot(0.8, 0.2))


def test_domain_dependence_reference_lines():
    fig = plot_domain_dependence([A, B], reference={"c:1": (1.01, 0.3), "c:0": (0.8, -0.21)},
                                 reference_label="exact")
    grid = np.array(fig.axes).reshape(3, 2)
    assert _dashed(grid[0, 0]) == {"exact: $K_I$ = 1.01": pytest.approx(1.01)}
    assert _dashed(grid[1, 0]) == {"exact: $K_{II}$ = 0.3": pytest.approx(0.3)}
    assert _dashed(grid[1, 1]) == {"exact: $K_{II}$ = -0.21": pytest.approx(-0.21)}
    assert "exact: $K_I$ = 1.01" in _labels(grid[0, 0])
    assert _dashed(grid[2, 0]) == {}  # no reference for J
    lo, hi = grid[0, 0].get_ylim()
    assert lo < 1.01 < hi  # a near reference joins the range
    # a single pair is the reference of every tip; one far off stays off the panel
    grid = np.array(plot_domain_dependence([A, B], reference=(1.0, 5.0)).axes).reshape(3, 2)
    assert list(_dashed(grid[1, 1]).values()) == [pytest.approx(5.0)]
    assert grid[1, 1].get_ylim()[1] < 0
    # only the tips named get one
    grid = np.array(plot_domain_dependence([A, B], reference={"c:0": (0.8, -0.2)}).axes).reshape(3, 2)
    assert _dashed(grid[0, 0]) == {} and len(_dashed(grid[0, 1])) == 1


def test_domain_dependence_tips_sharing_panels_name_their_references():
    fig, ax = plt.subplots()
    plot_domain_dependence([A, B], ax=ax, reference={"c:1": (1.0, 0.3), "c:0": (0.8, -0.2)})
    assert _dashed(ax) == {"reference (c:1): $K_I$ = 1": 1.0, "reference (c:0): $K_I$ = 0.8": 0.8}


def test_domain_dependence_on_a_given_axes():
    fig, axes = plt.subplots(1, 2)
    assert plot_domain_dependence(A, ax=axes[1], reference=(1.0, 0.3)) is fig
    assert len(fig.axes) == 3  # axes[1] took K_I in its upper half, K_II below it; no J
    below = fig.axes[2]
    assert axes[1].get_ylabel() == "$K_I$" and below.get_ylabel() == "$K_{II}$"
    assert below.get_shared_x_axes().joined(below, axes[1])
    assert axes[1].get_position().y0 > below.get_position().y1 - 1e-9
    assert axes[1].get_title().startswith("domain dependence of K: tip c:1 (spread")
    assert list(_dashed(below).values()) == [pytest.approx(0.3)]
    assert below.get_xlabel() == "J-domain radius"
    ax = fig.add_axes((0.1, 0.1, 0.3, 0.3))  # an axes without a grid cell is split by position
    plot_domain_dependence(B, ax=ax)
    assert len(fig.axes) == 5 and fig.axes[4].get_position().y1 <= ax.get_position().y0 + 1e-9


@pytest.mark.parametrize("reference, match", [({"c:9": (1.0, 0.0)}, "c:9"), ((1.0,), "pair"),
                                               ({"c:1": (np.nan, 0.0)}, "finite")])
def test_domain_dependence_rejects_bad_references(reference, match):
    with pytest.raises(ValueError, match=match):
        plot_domain_dependence([A, B], reference=reference)
    with pytest.raises(TypeError, match="TipResult"):
        plot_domain_dependence([])
