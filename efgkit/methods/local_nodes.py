"""MLPG node clouds with nodes on the crack faces.

The natural boundary condition of MLPG1 is imposed only through the sub-domains that reach
the boundary: a piece of the boundary enters the equations with the weight of the test
functions v_I of the discs that hold it (seed 002 Eq. 21). Outer edges carry nodes, so every
point of them lies at the centre of some disc (v_I = 1). A crack face without nodes is
reached only by the discs of the nearest node row: on a grid whose rows miss the crack line
by a fraction of the spacing the far face lies near the rim of those discs, where the
quartic spline is small (v = 0.03 at 0.78 r_s), and its traction-free condition is nearly
absent from the system. On the shear edge crack of seed 003 (h = 0.35, rows 0.3 below and
0.05 above the crack) the lower face then carried tractions of 10^3 against a load of 1 and
passed a spurious shear force of 300 into the clamped part (K_I 126 against 34.0).

:func:`local_nodes` therefore places nodes on every crack like the boundary nodes on the
edges: at the local spacing along each crack (tips excepted unless ``tip_node``), split one
per face by :func:`~efgkit.nodes.generate_nodes`; background nodes closer than a quarter of
the local spacing to a crack are dropped (boundary nodes next to a crack mouth too: the
face nodes at the mouth replace them), as next to the outer boundary; nodes already on a
crack (a grid row on it, a node at a tip) stay and no face node is added within half a
spacing of them, so a cloud with a row on the crack is unchanged. Support radii keep the
rule of the background cloud (2nd neighbour on regular grids, 3rd otherwise).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from scipy.spatial import cKDTree

from ..nodes import NodeCloud, generate_nodes, support_radii
from ..quadrature.discs import near_pairs

__all__ = ["local_nodes", "crack_face_positions"]

SAMPLES_PER_SPACING = 8  # samples of the local spacing along a crack per finest spacing
NEAR_FRACTION = 0.25  # background nodes closer than this many local spacings to a crack are dropped


def _spacing(x: np.ndarray, method) -> np.ndarray:
    """The target spacing at ``x (n, 2)``: the finest zone holding the point, else h."""
    h = np.full(len(x), float(method.spacing))
    for z in method.zones or ():  # tiny loop over the zones
        inside = np.hypot(*(x - np.asarray(z.centre)).T) <= z.radius
        h[inside] = np.minimum(h[inside], z.spacing)
    return h


def crack_face_positions(crack, method, tip_node: bool = False) -> np.ndarray:
    """Points along ``crack`` at the local spacing of ``method`` (its zones), shape (m, 2).

    The count of intervals is round(int ds / h(s)) (at least 1) and the points sit at equal
    steps of int ds / h(s), so they follow graded zones. Crack ends that are tips are left
    out unless ``tip_node``.

    Examples
    --------
    >>> from efgkit import Crack, MLPG
    >>> crack = Crack([[0.0, 0.5], [0.5, 0.5]], (False, True))
    >>> crack_face_positions(crack, MLPG(spacing=0.125)).tolist()
    [[0.0, 0.5], [0.125, 0.5], [0.25, 0.5], [0.375, 0.5]]
    """
    p = np.asarray(crack.vertices, float)
    seg = np.hypot(*np.diff(p, axis=0).T)
    s_knots = np.concatenate([[0.0], np.cumsum(seg)])
    hmin = min([method.spacing] + [z.spacing for z in method.zones or ()])
    m = max(2, int(np.ceil(s_knots[-1] / hmin * SAMPLES_PER_SPACING)) + 1)
    s = np.linspace(0.0, s_knots[-1], m)
    xs = np.column_stack([np.interp(s, s_knots, p[:, 0]), np.interp(s, s_knots, p[:, 1])])
    inv = 1.0 / _spacing(xs, method)
    level = np.concatenate([[0.0], np.cumsum(0.5 * (inv[1:] + inv[:-1]) * np.diff(s))])
    n = max(1, int(round(level[-1])))
    sk = np.interp(np.linspace(0.0, level[-1], n + 1), level, s)
    x = np.column_stack([np.interp(sk, s_knots, p[:, 0]), np.interp(sk, s_knots, p[:, 1])])
    keep = np.ones(n + 1, bool)
    if not tip_node:
        keep[0], keep[-1] = not crack.tips[0], not crack.tips[1]
    return x[keep]


def local_nodes(domain, method, cracks=(), tip_node: bool = False) -> NodeCloud:
    """The node cloud of ``method`` with nodes on the crack faces (module docstring).

    Without cracks, or with ``method.crack_nodes`` false, this is
    :func:`~efgkit.nodes.generate_nodes`. ``tip_node`` also puts a node at every tip.

    Examples
    --------
    >>> from efgkit import Crack, Domain, MLPG
    >>> crack = Crack([[0.0, 0.55], [0.5, 0.55]], (False, True))
    >>> cloud = local_nodes(Domain.rectangle(0, 0, 1, 1), MLPG(spacing=0.25), [crack])
    >>> sorted({round(float(y), 2) for y in cloud.x[cloud.face != 0, 1]})   # on the crack
    [0.55]
    >>> row = np.isclose(cloud.x[:, 1], 0.5) & (cloud.x[:, 0] < 0.75)   # 0.05 under the crack
    >>> int((cloud.face == 1).sum()), bool(row.any())   # two face nodes per face, the row dropped
    (2, False)
    >>> cloud.x[cloud.face == 1].tolist()   # the mouth and one spacing on; the tip has none
    [[0.0, 0.55], [0.25, 0.55]]
    """
    base = generate_nodes(domain, method, cracks)
    if not cracks or not getattr(method, "crack_nodes", True):
        return base
    own = base.face >= 0  # one copy of every split node
    x = base.x[own]
    h = _spacing(x, method)
    cseg = np.concatenate([c.segments for c in cracks])
    i, _, _, dist = near_pairs(x, NEAR_FRACTION * h, cseg)
    near, on = np.zeros(len(x), bool), np.zeros(len(x), bool)
    near[i] = True
    on[i[dist <= 1e-6 * h[i]]] = True  # already on a crack (split, or at a tip): kept
    keep = ~near | on
    x, on = x[keep], on[keep]
    faces = []
    for c in cracks:  # tiny loop over the cracks
        f = crack_face_positions(c, method, tip_node)
        if method.rosette is not None:
            for tip in c.tip_list:
                f = f[np.hypot(*(f - tip.x).T) > method.rosette.radius * (1 + 0.5 / method.rosette.rings)]
        faces.append(f)
    f = np.concatenate(faces)
    if on.any() and len(f):  # nodes already on a crack keep their place
        d, _ = cKDTree(x[on]).query(f)
        f = f[d > 0.5 * _spacing(f, method)]
    if keep.all() and not len(f):
        return base
    x = np.concatenate([x, f])
    cloud = generate_nodes(domain, replace(method, coordinates=x, perturb=0.0, rosette=None), cracks)
    radius = support_radii(x, method.d_max, method.regular)
    _, src = cKDTree(x).query(cloud.x)
    return replace(cloud, radius=radius[src])
