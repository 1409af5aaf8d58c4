"""The trial functions of an EFG discretisation, evaluated at any points.

:class:`Approximation` binds the node cloud and its search structure to the
choices of the method (weight, basis, crack rule, enrichment) and turns points
into a :class:`~efgkit.approx.shape.Shape`. Each point takes the cheapest path
that is exact for it:

1. points whose neighbours' supports reach no crack: the compiled MLS kernel
   with weights from distances (a scene without cracks only takes this path);
2. points near a crack (or a hole, with a hole rule): the rules' pair weights
   (:mod:`efgkit.approx.crack_rules`, :mod:`efgkit.approx.hole_rules`), then the
   same kernel;
3. points within the ramp radius of a tip (intrinsic enrichment): the
   enriched moment matrices, blended with 1. or 2. by the ramp;
4. enrichment unknowns (extrinsic MLS, PU): component operators from the
   nodal functions and the tip functions.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..jit import resolve_backend
from ..nodes import NodeCloud
from ..search import BoxGrid, Neighbours, find_neighbours
from .crack_prefilter import points_near
from .crack_rules import CrackLines, CrackRule, crack_distances, padded_weights, pair_arrays, sight_positions
from .enrichment import INTRINSIC, Enrichment, blend_intrinsic, extra_columns
from .hole_rules import Holes, hole_distances
from .mls import mls_shape
from .shape import Shape
from .weights import pair_weights, weight_function

__all__ = ["Approximation"]


@dataclass(frozen=True, eq=False)
class Approximation:
    """MLS trial functions of a node cloud under a crack rule and an enrichment.

    Attributes
    ----------
    nodes : NodeCloud
    boxes : BoxGrid
        Neighbour-search structure of ``nodes``.
    weight, basis : str
    d_max, alpha : float
    spacing : float
        The nominal spacing (a length scale for tolerances).
    interpolate : ndarray (n_nodes,) bool, optional
        Modified-MLS interpolation nodes (seed 002).
    lines : CrackLines, optional
        The scene's cracks (None: no crack tests at all).
    rule : CrackRule, optional
    enrichment : Enrichment, optional
    holes : Holes, optional
        The domain's holes, when ``hole_rule`` is not "see_through".
    hole_rule : {"see_through", "visibility", "diffraction"}
    k : int
        Exponent of the Gaussian weight (seed 002 Eq. 7; 1 for seed 003 Eq. 1a).
    """

    nodes: NodeCloud
    boxes: BoxGrid
    weight: str = "quartic"
    basis: str = "linear"
    d_max: float = 2.0
    alpha: float = 0.5
    spacing: float = 1.0
    interpolate: np.ndarray | None = None
    lines: CrackLines | None = None
    rule: CrackRule | None = None
    enrichment: Enrichment | None = None
    holes: Holes | None = None
    hole_rule: str = "see_through"
    k: int = 1

    @property
    def n_dofs(self) -> int:
        return 2 * self.nodes.n + (0 if self.enrichment is None else self.enrichment.n_extra)

    def _mls(self, x, nb, derivatives, weights=None, backend="auto") -> Shape:
        return mls_shape(x, self.nodes, self.weight, self.basis, d_max=self.d_max, alpha=self.alpha,
                         derivatives=derivatives, neighbours=nb, interpolate=self.interpolate,
                         weights=weights, k=self.k, backend=backend)

    def cracked_rows(self, x: np.ndarray, nb: Neighbours) -> np.ndarray:
        """Points whose neighbours' supports reach a crack or a ruled hole (the only ones a
        rule can change)."""
        if (self.lines is None and self.holes is None) or len(x) == 0:
            return np.zeros(0, np.int64)
        near = np.zeros(len(x), bool)
        if self.lines is not None:  # only points some support can reach a crack from
            pts = points_near(self.lines, x, float(self.nodes.radius.max()))
            if len(pts):
                reach = np.where(nb.mask[pts], self.nodes.radius[nb.idx[pts]], 0.0).max(
                    axis=1, initial=0.0)
                near[pts] = self.lines.distance(x[pts]) < reach
        if self.holes is not None:
            reach = np.where(nb.mask, self.nodes.radius[nb.idx], 0.0).max(axis=1)
            near |= self.holes.distance(x) < reach
        return np.flatnonzero(near)

    @cached_property
    def node_sight(self) -> np.ndarray:
        """Where each node looks from in the crack tests (:func:`~efgkit.approx.crack_rules.
        sight_positions`), shape (n_nodes, 2): formed once, gathered per pair."""
        n = self.nodes.n
        return sight_positions(self.nodes.x, self.nodes.radius, np.arange(n), self.nodes,
                               self.lines)

    def sight_weights(self, x: np.ndarray, nb: Neighbours):
        """Pair weights at ``x (n, 2)`` under the crack and hole rules: (mask, w, dwx, dwy),
        padded (n, k) like ``nb`` (for points near cracks or holes)."""
        wfun = weight_function(self.weight, self.d_max, self.alpha, self.k)
        rows, cols, I, xq, xn, dm = pair_arrays(x, self.nodes, nb)
        if self.lines is not None:
            cut, d, dd = crack_distances(xq, xn, dm, I, self.nodes, self.lines, self.rule,
                                         sight=self.node_sight[I])
        else:
            diff = xq - xn
            d = np.hypot(*diff.T)
            cut, dd = np.zeros(len(d), bool), diff / np.where(d > 0, d, 1.0)[:, None]
        if self.holes is not None:
            power = self.rule.power if self.rule is not None else 2.0
            cut, d, dd = hole_distances(xq, xn, cut, d, dd, self.holes, self.hole_rule, power)
        return padded_weights(nb, rows, cols, cut, d, dd, dm, wfun)

    def weights(self, x: np.ndarray, nb: Neighbours, derivatives: bool = True):
        """Pair weights at ``x (n, 2)`` under the rules: mask, w (n, k), dw (n, k, 2)."""
        wfun = weight_function(self.weight, self.d_max, self.alpha, self.k)
        mask = nb.mask.copy()
        w, dw = pair_weights(x, self.nodes, nb, wfun, derivatives)
        rows = self.cracked_rows(x, nb)
        if len(rows):
            m, wc, dwx, dwy = self.sight_weights(x[rows], nb.subset(rows))
            mask[rows], w[rows] = m, wc
            if derivatives:
                dw[rows] = np.stack([dwx, dwy], axis=-1)
        return mask, w, dw

    def weight_values(self, x: np.ndarray) -> np.ndarray:
        """The weights w_I(x) under the rules, dense (n_points, n_nodes): for plots and
        checks of the crack rules on a few points."""
        nb = find_neighbours(x, self.nodes, self.boxes)
        mask, w, _ = self.weights(x, nb, derivatives=False)
        out = np.zeros((len(x), self.nodes.n))
        rows, cols = np.nonzero(mask)
        out[rows, nb.idx[rows, cols]] = w[rows, cols]
        return out

    def shape(self, x: np.ndarray, derivatives: bool = True,
              neighbours: Neighbours | None = None) -> Shape:
        """Shape functions (and the enrichment operators) at points ``x (n, 2)``;
        ``neighbours`` of ``x`` found before (:func:`~efgkit.search.find_neighbours`) are used.

        Examples
        --------
        >>> from efgkit import EFG, Domain
        >>> from efgkit.nodes import generate_nodes
        >>> nodes = generate_nodes(Domain.rectangle(0, 0, 1, 1), EFG(spacing=0.25))
        >>> sh = Approximation(nodes, BoxGrid.build(nodes)).shape(np.array([[0.3, 0.7]]))
        >>> round(float(sh.phi.sum()), 12)
        1.0
        """
        x = np.atleast_2d(np.asarray(x, dtype=float))
        if x.ndim != 2 or x.shape[1] != 2:
            raise ValueError(f"x must have shape (n_points, 2), got {x.shape}")
        nb = find_neighbours(x, self.nodes, self.boxes) if neighbours is None else neighbours
        rows = self.cracked_rows(x, nb)
        if len(rows) == 0:
            sh = self._mls(x, nb, derivatives)
            mask, vals = nb.mask, [sh.values, sh.ddx, sh.ddy]
        else:  # all points as if crack-free, then the few near a crack redone under the
            # rules: the arrays are allocated once (no zeros plus a copy of the plain rows)
            mask = nb.mask.copy()
            if resolve_backend("auto", len(x)) == "numpy":  # small: the plain rows alone
                # (the near rows can be most of them; each row's arithmetic is its own)
                vals = [np.zeros(nb.idx.shape) if i == 0 or derivatives else None for i in range(3)]
                away = np.ones(len(x), bool)
                away[rows] = False
                plain = np.flatnonzero(away)
                if len(plain):
                    sp = self._mls(x[plain], nb.subset(plain), derivatives)
                    for v, r in zip(vals, (sp.values, sp.ddx, sp.ddy), strict=True):
                        if v is not None:
                            v[plain] = r
            else:
                sp = self._mls(x, nb, derivatives)
                vals = [sp.values, sp.ddx, sp.ddy]
            cw = self.sight_weights(x[rows], nb.subset(rows))
            # the rows near a crack take the kernel of all the points (compiled for those
            # already), not the numpy path their smaller number would choose
            sc = self._mls(x[rows], nb.subset(rows), derivatives, weights=cw,
                           backend=resolve_backend("auto", len(x)))
            mask[rows] = cw[0]
            for v, r in zip(vals, (sc.values, sc.ddx, sc.ddy), strict=True):
                if v is not None:
                    v[rows] = r
        nb = Neighbours(nb.idx, mask)
        enr = self.enrichment
        if enr is not None and enr.kind in INTRINSIC:
            taken = np.zeros(len(x), bool)  # each point is enriched by one tip
            for t in range(len(enr.tips)):
                near = enr.in_ramp(x, t)
                near = near[~taken[near]]
                taken[near] = True
                if len(near) == 0:
                    continue
                sub = nb.subset(near)
                m, w, dw = self.weights(x[near], sub, derivatives)
                lin = [None if v is None else v[near] for v in vals]
                out = blend_intrinsic(x[near], self.nodes, Neighbours(sub.idx, m), w, dw, lin, enr, t,
                                      self.basis, derivatives)
                for v, r in zip(vals, out, strict=True):
                    if v is not None:
                        v[near] = r
        nodal = Shape(nb, vals[0], vals[1] if derivatives else None,
                      vals[2] if derivatives else None, self.nodes.n)
        if enr is None or not enr.n_extra:
            return nodal
        extra = extra_columns(x, nodal, enr, derivatives, self.spacing)
        return Shape(nodal.neighbours, nodal.values, nodal.ddx, nodal.ddy, nodal.n_functions, extra)
