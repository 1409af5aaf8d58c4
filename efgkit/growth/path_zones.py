"""Refinement along the crack paths of a growth loop: node zones that follow the tips and stay.

A growing tip needs nodes finer than the gaps it meets: two cracks that pass each other
(seed 003 Sect. 6.1, Figs. 47-48: the tips "avoid each other only to curve around and meet
each other behind the tip") leave a sliver between their faces, and a tip that runs into a
hole beside another crack's mouth leaves one at the hole. A quadrature point in a sliver sees
only the nodes inside it (the faces block the supports, :mod:`efgkit.approx.crack_rules`); at
a background spacing h wider than the sliver it sees fewer than the three nodes a linear basis
needs and its moment matrix is singular. The automatic tip zones (:meth:`EFG.for_scene`)
follow a tip but leave with it, and vanish where a tip joins a hole or a face.

:func:`path_zones` places discs of a given radius r and spacing s along every crack
polyline (initial cracks and every grown segment, re-placed each step), centres every
``r / 2`` of arc length and at both ends (so the tip is always inside one, and every point
within ``r sqrt(15) / 4 ~ 0.97 r`` of the path is covered). Each centre snaps to the
lattice of spacing s anchored at the domain's bounding-box corner, the origin of the
background grid (:func:`efgkit.nodes.generate_nodes`): zones of one spacing then share one
lattice where they overlap (their coincident nodes are merged), and it is the background
grid's lattice refined when ``h / s`` is an integer. A step after a kink therefore adds
nodes ahead of the tip and keeps those already placed along the path. Each pair is graded
to the background spacing by rings whose spacing doubles (:func:`graded`).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..methods.efg import EFG, Zone
from ..problem.scene import Scene

__all__ = ["check_path_zones", "graded", "path_zones", "undiscretisable", "with_path_zones"]


def check_path_zones(value) -> tuple[tuple[float, float], ...]:
    """``value`` as a tuple of (radius, spacing) pairs, each finite and > 0; ValueError
    naming ``path_zones`` otherwise."""
    msg = ("growth path_zones must be a sequence of (radius, spacing) pairs of finite numbers > 0, "
           "e.g. ((1.0, 0.05),), got {!r}")
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise TypeError(msg.format(value))
    out = []
    for pair in value:
        if isinstance(pair, (str, bytes)) or not hasattr(pair, "__len__") or len(pair) != 2:
            raise TypeError(msg.format(value))
        for v in pair:
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                raise ValueError(msg.format(value))
        out.append((float(pair[0]), float(pair[1])))
    return tuple(out)


def _centres(vertices: np.ndarray, step: float) -> np.ndarray:
    """Points every ``step`` of arc length along the polyline ``vertices (n, 2)`` and its
    last vertex, shape (m, 2)."""
    seg = np.diff(vertices, axis=0)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*seg.T))])
    t = np.append(np.arange(0.0, s[-1], step), s[-1])
    return np.column_stack([np.interp(t, s, vertices[:, k]) for k in (0, 1)])


def graded(pairs, spacing: float) -> tuple[tuple[float, float], ...]:
    """``pairs`` with the rings that grade each to the background ``spacing`` h: for a pair
    (r, s), rings of spacing ``s_k = 2^k s`` (k = 1, 2, ... while s_k < h) out to radius
    ``r + 4 (s_1 + ... + s_k)``, so that the spacing at most doubles from one band to the
    next (as the automatic tip zones, :data:`efgkit.methods.efg.AUTO_TIP_ZONES`). A fine
    zone right beside coarse nodes leaves those a support of a few fine spacings (the
    radius is ``d_max`` times the distance to the second nearest node, seed 003 Eq. 2):
    points between the coarse nodes then see fewer than three of them.

    Examples
    --------
    >>> graded([(0.2, 0.05)], 0.25)
    ((0.2, 0.05), (0.6000000000000001, 0.1), (1.4000000000000001, 0.2))
    """
    out = []
    for r, s in check_path_zones(pairs):
        out.append((r, s))
        while 2.0 * s < spacing * (1 - 1e-9):
            s *= 2.0
            r += 4.0 * s
            out.append((r, s))
    return tuple(out)


def path_zones(scene: Scene, pairs, spacing: float | None = None) -> tuple[Zone, ...]:
    """Zones of every (radius, spacing) in ``pairs`` along every crack of ``scene``.

    Parameters
    ----------
    scene : Scene
    pairs : sequence of (float, float)
        ``(r, s)``: discs of radius r with nodal spacing s, centred every r / 2 along each
        crack polyline and at its ends, snapped to the lattice ``corner + s (i, j)`` of the
        domain's bounding-box corner (duplicates dropped).
    spacing : float, optional
        The background spacing h: each pair is graded to it first (:func:`graded`).

    Returns
    -------
    tuple of Zone

    Examples
    --------
    >>> from efgkit import Crack, Domain, Elastic
    >>> sc = Scene(Domain.rectangle(0, 0, 4, 2), Elastic(1.0, 0.3, "stress"),
    ...            cracks=(Crack([[0.0, 1.0], [1.03, 1.0]], (False, True)),))
    >>> [z.centre for z in path_zones(sc, [(1.0, 0.25)])]
    [(0.0, 1.0), (0.5, 1.0), (1.0, 1.0)]
    >>> len(path_zones(sc, [(1.0, 0.25)], spacing=1.0))  # and a ring of spacing 0.5
    5
    """
    pairs = check_path_zones(pairs) if spacing is None else graded(pairs, spacing)
    corner = np.asarray(scene.domain.bbox[:2], float)
    out = []
    for r, s in pairs:
        pts = np.concatenate([_centres(np.asarray(c.vertices, float), 0.5 * r) for c in scene.cracks])
        snapped = corner + s * np.round((pts - corner) / s)
        keep = np.unique(np.round((snapped - corner) / s).astype(np.int64), axis=0, return_index=True)[1]
        out += [Zone(tuple(c), r, s) for c in snapped[np.sort(keep)]]
    return tuple(out)


def with_path_zones(method, scene: Scene, pairs):
    """``method`` with the zones of :func:`path_zones` (graded to its spacing) added to its
    own (an EFG whose zones are chosen per scene and are none here, explicit enrichment,
    counts as no zones);
    ``method`` as is without ``pairs`` or for other methods (FEM, MLPG)."""
    if not pairs or not isinstance(method, EFG):
        return method
    own = method.zones if method.zones is not None else method.automatic_choices(scene).get("zones", ())
    return replace(method, zones=tuple(own) + path_zones(scene, pairs, method.spacing))


def undiscretisable(index: int, events, err: Exception, settings) -> str:
    """The message of a growth step whose scene cannot be discretised (a singular moment
    matrix: too few nodes in a sliver between cracks or at a hole), with what to do."""
    why = f" after {'; '.join(events)}" if events else ""
    have = f" (now {settings.path_zones!r})" if settings.path_zones else ""
    return (f"growth step {index}: the cracks{why} cannot be discretised: {err} Refine along the "
            f"crack paths with Growth(path_zones=((radius, spacing),)){have}: a spacing a few "
            f"times below the narrowest gap between the cracks, the holes and the faces, and "
            f"below da ({settings.da:g}); or enlarge d_max.")
