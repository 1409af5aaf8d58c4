"""Half and quarter models: mirror lines and the cracks that lie on them.

A symmetric body loaded symmetrically (mode I) is modelled by the part on one side of a
mirror line (a half model) or of two perpendicular lines (a quarter model). A crack on a
mirror line is then boundary: its face is a free edge, its ligament carries the symmetry
condition u_n = 0 (a :class:`~efgkit.problem.scene.Support`), and the tip is the point where
they meet. :class:`Symmetry` names the lines and the cracks of the whole body that lie on
them, so that :meth:`Solution.sifs <efgkit.solution.Solution.sifs>` can take K_I, J and T of
the modelled tips from the fields mirrored onto the whole body (:func:`full_scene`,
:func:`mirror_fields`); K_II = 0 by symmetry.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .crack import Crack
from .geometry import Domain, Loop

__all__ = ["Symmetry", "full_domain", "mirror_fields", "reflection", "without_mirror_conditions"]


def reflection(point, normal) -> tuple[np.ndarray, np.ndarray]:
    """``(p (2,), R (2, 2))`` of the mirror line through ``point`` with normal ``normal``:
    ``x' = p + R (x - p)``, ``R = I - 2 n n^T``."""
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n)
    return np.asarray(point, dtype=float), np.eye(2) - 2.0 * np.outer(n, n)


@dataclass(frozen=True)
class Symmetry:
    """Mirror lines of a half (one line) or quarter (two perpendicular lines) model, and the
    cracks of the whole body lying on them.

    Parameters
    ----------
    lines : sequence of ((x0, y0), (nx, ny))
        One or two mirror lines, each a point and a normal; each must carry an edge of the
        model's outer boundary.
    cracks : sequence of Crack
        Straight cracks of the whole body, each along a mirror line; its tips that lie on
        the model's boundary are the modelled tips. No crack-face pressure (apply it as a
        traction on the face edge; the J integral's face term is not computed here).

    Examples
    --------
    >>> s = Symmetry((((0.0, 0.0), (0.0, 1.0)),), (Crack([[-1.0, 0.0], [1.0, 0.0]], name="c"),))
    >>> len(s.lines), s.cracks[0].name
    (1, 'c')
    """

    lines: tuple
    cracks: tuple[Crack, ...] = ()

    def __post_init__(self):
        try:
            lines = tuple((tuple(map(float, p)), tuple(map(float, n))) for p, n in self.lines)
        except (TypeError, ValueError) as err:
            raise ValueError(f"symmetry lines must be ((x0, y0), (nx, ny)) pairs, got "
                             f"{self.lines!r}") from err
        if not 1 <= len(lines) <= 2 or any(len(p) != 2 or len(n) != 2 for p, n in lines):
            raise ValueError(f"symmetry needs one or two lines ((x0, y0), (nx, ny)), got {self.lines!r}")
        for p, n in lines:
            if not np.all(np.isfinite(p + n)) or np.hypot(*n) == 0:
                raise ValueError(f"symmetry line {(p, n)}: point and normal must be finite, the "
                                 "normal non-zero")
        if len(lines) == 2 and abs(np.dot(*(np.array(n) / np.hypot(*n) for _, n in lines))) > 1e-12:
            raise ValueError("the two symmetry lines of a quarter model must be perpendicular")
        object.__setattr__(self, "lines", lines)
        object.__setattr__(self, "cracks", tuple(self.cracks))
        for c in self.cracks:
            if not isinstance(c, Crack):
                raise TypeError(f"symmetry cracks must be Crack objects, got {type(c).__name__}")
            if c.pressure != 0.0:
                raise ValueError(f"symmetry crack {c.name!r}: pressure must be 0 (apply it as a "
                                 "Traction on the face edge of the model)")
            if not any(_on_line(c.vertices, p, n, 1e-9 * max(c.length, 1.0)).all() for p, n in lines):
                raise ValueError(f"symmetry crack {c.name!r} does not lie on a symmetry line; a crack "
                                 "off the lines belongs in Scene.cracks")

    def line_of(self, x, tol: float) -> int | None:
        """Index of the line all points ``x (n, 2)`` lie on (within ``tol``), else None."""
        x = np.asarray(x, dtype=float).reshape(-1, 2)
        return next((k for k, (p, n) in enumerate(self.lines)
                     if len(x) and _on_line(x, p, n, tol).all()), None)

    def modelled_tips(self, domain: Domain) -> tuple:
        """The tips of :attr:`cracks` on the model's boundary (its own tips)."""
        tol = 1e-9 * domain.size
        return tuple(t for c in self.cracks for t in c.tip_list
                     if domain.distance_to_boundary(t.x[None])[0] <= tol)


def _on_line(x, p, n, tol) -> np.ndarray:
    n = np.asarray(n) / np.hypot(*n)
    return np.abs((np.asarray(x) - p) @ n) <= tol


def _mirror_loop(loop: Loop, p, n, tol: float) -> Loop:
    """The loop glued to its mirror image along its edges on the line."""
    v, k = loop.vertices, len(loop.vertices)
    on = _on_line(v, p, n, tol)
    edge_on = on & np.roll(on, -1) & (loop.sweeps == 0)
    if not edge_on.any():
        raise ValueError(f"symmetry line through {p} with normal {n}: no edge of the outer "
                         "boundary lies on it; the model must end on its symmetry lines")
    if edge_on.all():
        raise ValueError("every edge of the outer boundary lies on one symmetry line")
    # rotate so that the run of edges on the line is last: edges k - m .. k - 1
    start = int(np.flatnonzero(edge_on & ~np.roll(edge_on, -1))[0]) + 1  # first edge after the run
    order = (np.arange(k) + start) % k
    edge_on, v = edge_on[order], v[order]
    names, cen, sw = [loop.names[i] for i in order], loop.centres[order], loop.sweeps[order]
    m = int(edge_on.sum())
    if edge_on[: k - m].any():
        raise ValueError("the model's edges on a symmetry line must be one contiguous run")
    q, R = reflection(p, n)
    c = k - m  # chain edges 0 .. c-1, vertices 0 .. c
    chain = np.vstack([v, v[:1]])[: c + 1]
    back = [q + R @ (chain[i] - q) for i in range(c - 1, 0, -1)]
    verts = np.vstack([chain] + ([np.array(back)] if back else []))
    rc = [np.full(2, np.nan) if np.isnan(cen[i]).any() else q + R @ (cen[i] - q)
          for i in range(c - 1, -1, -1)]
    return Loop(verts, tuple(names[:c]) + tuple(names[i] for i in range(c - 1, -1, -1)),
                np.vstack([cen[:c], np.array(rc)]), np.concatenate([sw[:c], sw[c - 1::-1]]))


def full_domain(domain: Domain, symmetry: Symmetry) -> Domain:
    """The whole body: ``domain`` glued to its mirror images across the symmetry lines
    (holes mirrored with it; a hole cut by a line is part of the outer boundary)."""
    tol = 1e-9 * domain.size
    outer, holes = domain.outer, list(domain.holes)
    for p, n in symmetry.lines:
        q, R = reflection(p, n)
        outer = _mirror_loop(outer, q, n, tol)
        holes += [_mirror_hole(h, q, R) for h in holes]
    return Domain(outer, tuple(holes))


def _mirror_hole(h: Loop, q, R) -> Loop:
    """A hole's mirror image, still clockwise: vertices reversed, and edge j of the result is
    edge n - 2 - j of ``h`` run backwards (reflected and reversed: the same sweep)."""
    def back(a):
        return np.roll(np.asarray(a)[::-1], -1, axis=0)
    return Loop((q + (h.vertices - q) @ R.T)[::-1], tuple(back(np.array(h.names, dtype=object))),
                back(q + (h.centres - q) @ R.T), back(h.sweeps))


def mirror_fields(symmetry: Symmetry, x, w, stress, grad):
    """The fields at points ``x (n, 2)`` (weights ``w (n,)``, Voigt ``stress (n, 3)``,
    ``grad (n, 2, 2)``) and their mirror images across every line: ``2^lines n`` points.

    A mode-I field is symmetric: ``u'(x') = R u(x)``, so ``grad' = R grad R`` and
    ``sigma' = R sigma R`` at ``x' = p + R (x - p)``.
    """
    for p, n in symmetry.lines:
        q, R = reflection(p, n)
        S = np.stack([np.column_stack([stress[:, 0], stress[:, 2]]),
                      np.column_stack([stress[:, 2], stress[:, 1]])], axis=1)
        Sm = np.einsum("ij,njk,kl->nil", R, S, R)
        x = np.vstack([x, q + (x - q) @ R.T])
        w = np.concatenate([w, w])
        stress = np.vstack([stress, np.column_stack([Sm[:, 0, 0], Sm[:, 1, 1], Sm[:, 0, 1]])])
        grad = np.concatenate([grad, np.einsum("ij,njk,kl->nil", R, grad, R)])
    return x, w, stress, grad


def without_mirror_conditions(scene):
    """``scene`` without the conditions u_n = 0 on its mirror lines, which the EFG image nodes
    hold identically (:mod:`efgkit.system.images`; a constraint row would be zero): the normal component of a
    :class:`~efgkit.problem.scene.Support` on a named edge lying on a line, and of a
    :class:`~efgkit.problem.supports.PointSupport` on a line, is dropped.

    Raises
    ------
    ValueError
        When such a condition prescribes u_n other than 0 (symmetry holds u_n = 0 there).
    """
    tol = 1e-9 * scene.domain.size

    def normal_key(points):
        k = scene.symmetry.line_of(points, tol)
        return None if k is None else "ux" if abs(scene.symmetry.lines[k][1][0]) > 0 else "uy"

    def reduced(sup, key, where):
        v = getattr(sup, key)
        if v is None:
            return sup
        if isinstance(v, bool) or not isinstance(v, (int, float)) or v != 0:
            raise ValueError(f"{where} lies on a symmetry line and prescribes {key} = {v!r}: a half "
                             f"or quarter model has {key} = 0 there by symmetry; remove it or give 0")
        other = "uy" if key == "ux" else "ux"
        return None if getattr(sup, other) is None else replace(sup, **{key: None})

    supports = []
    for s in scene.supports:
        key = None if callable(s.edge) else normal_key(
            np.vstack([e.polyline() for e in scene.domain.edges(s.edge)]))
        s = s if key is None else reduced(s, key, f"support on {s.edge!r}")
        supports += [] if s is None else [s]
    points = []
    for s in scene.point_supports:
        key = normal_key(np.asarray([s.x]))
        s = s if key is None else reduced(s, key, f"point support at {s.x}")
        points += [] if s is None else [s]
    return replace(scene, supports=tuple(supports), point_supports=tuple(points))
