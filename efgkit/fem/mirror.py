"""Whole-body meshes mirrored from the mesh of a half or quarter model.

:func:`mirror_mesh` reflects a part's triangle mesh across its symmetry lines and opens the
cracks that lie on them, so that a full model can be solved on exactly the mirror image of
the part's mesh and any difference between the two is the symmetry treatment itself
(``verification/symmetry.py``).
"""

from __future__ import annotations

import numpy as np

from ..problem.scene import Scene
from .mesh import TriMesh, arclength, crack_node_pairs, edge_keys, open_cracks

__all__ = ["mirror_mesh"]


def mirror_mesh(mesh: TriMesh, scene, lines) -> TriMesh:
    """Mesh of the whole body ``scene`` as the union of a part's ``mesh`` and its mirror images.

    ``lines``: one or two mirror lines ``((x0, y0), (nx, ny))`` (``Symmetry.lines`` of the
    part), applied in turn: ``x' = p + (I - 2 n n^T)(x - p)``, nodes on a line shared. Then
    the cracks of ``scene`` are opened as in :func:`mesh_scene`. The symmetric fields of the
    result are those of the part, so a half or quarter model is compared like for like.

    >>> from efgkit import Crack, Domain, Elastic, Scene
    >>> from efgkit.fem.mesh import mesh_scene
    >>> part = Scene(Domain.rectangle(0, 0, 1, 1), Elastic(1.0, 0.3))
    >>> full = Scene(Domain.rectangle(0, -1, 1, 1), Elastic(1.0, 0.3),
    ...              cracks=(Crack([[0.0, 0.0], [0.5, 0.0]], tips=(False, True)),))
    >>> m = mirror_mesh(mesh_scene(part, 0.5, 0.1, refine=[(0.5, 0.0)]), full, [((0, 0), (0, 1))])
    >>> round(float(m.area.sum()), 12), len(m.crack_nodes[0][0]) > 0
    (2.0, True)
    """
    if not isinstance(mesh, TriMesh) or not isinstance(scene, Scene):
        raise TypeError(f"mesh must be a TriMesh and scene a Scene, got {type(mesh).__name__}, "
                        f"{type(scene).__name__}")
    if mesh.crack_nodes and any(len(a) for a, _ in mesh.crack_nodes):
        raise ValueError("mesh must be a part without open cracks (its cracks lie on the mirror lines)")
    tol = 1e-9 * scene.domain.size
    x, t = mesh.x, mesh.t
    for p, n in lines:
        p, n = np.asarray(p, float), np.asarray(n, float) / np.linalg.norm(n)
        d = (x - p) @ n
        if d.min() < -tol and d.max() > tol:
            raise ValueError(f"mesh lies on both sides of the mirror line through {p.tolist()}, "
                             f"normal {n.tolist()}: give the lines of the part's symmetry")
        new = np.abs(d) > tol
        m = np.where(new, len(x) + np.cumsum(new) - 1, np.arange(len(x)))
        x = np.vstack([x, x[new] - 2.0 * d[new, None] * n])
        t = np.vstack([t, m[t][:, ::-1]])
    a, b = t[:, [0, 1, 2]].ravel(), t[:, [1, 2, 0]].ravel()
    uk, first = np.unique(edge_keys(a, b, len(x)), return_index=True)
    ea, eb = a[first], b[first]
    cf, cidx = np.zeros((0, 2), np.int64), np.zeros(0, np.int64)
    for ci, c in enumerate(scene.cracks):  # mesh edges on the crack, oriented along it
        on = (c.project(x[ea])[2] < tol) & (c.project(x[eb])[2] < tol)
        f = np.column_stack([ea[on], eb[on]])
        f = np.where((arclength(c, x[f[:, 0]]) > arclength(c, x[f[:, 1]]))[:, None], f[:, ::-1], f)
        cf, cidx = np.vstack([cf, f]), np.concatenate([cidx, np.full(len(f), ci)])
    tips = scene.tips
    tip_nodes = tuple(int(np.argmin(np.linalg.norm(x - tp.x, axis=1))) for tp in tips)
    if any(np.linalg.norm(x[k] - tp.x) > tol for k, tp in zip(tip_nodes, tips, strict=True)):
        raise ValueError("a crack tip of scene is no node of the mirrored mesh: mesh the part "
                         "with its modelled tips as vertices (mesh_scene refine=...)")
    n_orig = len(x)
    x, t, origin = open_cracks(x, t, cf, np.array(tip_nodes, dtype=np.int64))
    edges = scene.domain.edges()
    if any(e.is_arc for e in edges):
        raise ValueError("mirror_mesh supports straight domain edges only")
    segs = np.array([[e.start, e.end] for e in edges])
    seg_own = np.arange(len(edges))
    for ci, c in enumerate(scene.cracks):
        segs = np.vstack([segs, c.segments])
        seg_own = np.concatenate([seg_own, np.full(len(c.segments), -1 - ci)])
    key = edge_keys(t[:, [0, 1, 2]].ravel(), t[:, [1, 2, 0]].ravel(), len(x))
    uniq, cnt = np.unique(key, return_counts=True)
    bnd = np.isin(key, uniq[cnt == 1])
    fac = np.column_stack([t[:, [0, 1, 2]].ravel()[bnd], t[:, [1, 2, 0]].ravel()[bnd]])
    mid = 0.5 * (x[fac[:, 0]] + x[fac[:, 1]])
    sa, ab = segs[None, :, 0], segs[None, :, 1] - segs[None, :, 0]
    s = np.clip(np.sum((mid[:, None] - sa) * ab, -1) / np.sum(ab * ab, -1), 0.0, 1.0)
    dist = np.linalg.norm(mid[:, None] - sa - s[..., None] * ab, axis=-1)
    if np.any(dist.min(axis=1) > tol):
        raise ValueError("a boundary facet of the mirrored mesh lies on no edge or crack of scene: "
                         "scene must be the whole body of which mesh meshes the part")
    own = seg_own[np.argmin(dist, axis=1)]
    crack_nodes = crack_node_pairs(scene.cracks, x, origin, n_orig, cf, cidx, tip_nodes)
    return TriMesh(x, t, fac, own, origin, crack_nodes, tip_nodes, scene.domain, tuple(scene.cracks))
