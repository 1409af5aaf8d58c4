"""The crack rule and enrichment choices a scene's cracks refuse or warn about.

Each refusal names both choices, the measured cause and the remedy (docs/robustness.md);
:func:`check_crack_choices` runs them all before any shape function is built.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..approx.crack_rules import CrackLines
from ..approx.enrichment import INTRINSIC
from ..nodes import NodeCloud
from ..problem.scene import Scene

__all__ = ["check_crack_choices"]


def check_crack_choices(scene: Scene, method, nodes: NodeCloud, lines: CrackLines) -> None:
    """Refuse (ValueError) or warn (UserWarning) about ``method``'s crack rule and enrichment
    on the cracks ``lines`` of ``scene`` with the nodes ``nodes``; ``method`` is an
    :class:`~efgkit.methods.efg.EFG` or an MLPG description with an explicit enrichment."""
    if method.crack_rule == "transparency":
        _warn_close_to_crack(nodes, lines, method.spacing, method.enrichment)
    if method.enrichment != "none":
        # The sqrt(r) basis has no angular discontinuity and needs no smoothing (seed 003
        # Sect. 5.3.2); with it visibility is the more accurate rule (singular patch).
        if method.crack_rule == "visibility" and method.enrichment != "radial":
            raise ValueError(
                f"enrichment={method.enrichment!r} with crack_rule='visibility' is not "
                "supported: visibility makes the shape functions jump along the rays from "
                "the nodes through the tip, and with the singular field in the trial space "
                "those jumps act as extra cracks at the tip (extrinsic K_I 0.92, 0.39, -0.03 "
                "on 9, 17, 25 node grids of the singular patch, docs/theory.md). Use "
                "crack_rule='diffraction' (seed 003 uses it with enrichment), "
                "'transparency' or 'see_through'; of the enrichments only 'radial' works "
                "with visibility.")
        if method.crack_rule == "see_through" and method.enrichment in INTRINSIC:
            raise ValueError(
                f"enrichment={method.enrichment!r} with crack_rule='see_through' is not "
                "supported: see-through lets the nodes whose supports hold the tip see across "
                "the crack, and the ramped linear part of an intrinsic basis then shortens the "
                "crack as see-through does alone (seed 003 Sect. 4.4; singular patch energy "
                "error 0.76-1.1 against 0.28 with diffraction). Use crack_rule='diffraction', "
                "or an extrinsic enrichment, which works with see-through.")
        if method.enrichment == "radial" and method.crack_rule in ("diffraction", "transparency"):
            _check_radial_rule(nodes, lines, method)
        if method.enrichment == "extrinsic_mls" and method.enrich_radius is None:
            _check_global_fields(scene)


def _check_global_fields(scene: Scene) -> None:
    """Unramped extrinsic fields jump along the whole line behind their tip (theta = +-pi,
    mapped at one kink): that line must be the crack itself up to the boundary."""
    for c in scene.cracks:
        if all(c.tips) or len(c.vertices) > 3:
            why = ("has two tips, so the line behind each runs past the other tip into the body"
                   if all(c.tips) else "has more than one kink (the map of seed 003 Sect. 5.5 "
                   "follows one)")
            raise ValueError(
                f"enrichment='extrinsic_mls' without enrich_radius uses the Williams fields over "
                f"the whole body, but crack {c.name!r} {why}: the fields would jump inside the "
                "material (measured: K_I 13% low on an inclined Griffith crack). Give "
                "enrich_radius (smaller than the crack length) to ramp them to zero.")


def _check_radial_rule(nodes: NodeCloud, lines: CrackLines, method) -> None:
    """The sqrt(r) basis (seed 003 Eq. 52) under a rule that lets a point see the other crack
    face near the tip (diffraction, transparency).

    sqrt(r) is even across the crack, the mode-I u_y (mode-II u_x) odd: where a point's nearest
    nodes on the other face are as close as those on its own, the MLS fit mixes the two faces'
    opposite sqrt(r) amplitudes into one coefficient, which then multiplies the 1 / (2 sqrt r)
    gradient of the basis. That is the layout with no node within h/4 of the crack inside the
    enrichment disc of a tip (the crack between node rows, or split face nodes absent): there
    the combination is refused. Measured on the singular patch (tests/test_enrichment.py),
    energy error against the linear basis under the same rule: diffraction 1.14-1.74 times
    (d_max 2-3, lambda 1-8, 10 and 18 nodes across, perturbed grids, a node at the tip),
    transparency 0.96-1.50 times (a tie only at d_max 3: no gain for the cost). With nodes on
    the faces the basis is usable (transparency 0.83-0.96 times); under diffraction with
    lambda < 4 it is still no better than the linear basis (1.03-1.21 times; K error 0.89 %
    against 0.52 % on the 45 degree Griffith crack, verification ``inclined``): a warning.
    """
    rule, h = method.crack_rule, None
    for tip in lines.tip_positions():
        d = np.hypot(*(nodes.x - tip).T)
        h = float(nodes.radius[np.argmin(d)] / method.d_max)  # c_I of the node nearest the tip
        near = (d < method.ramp_outer) & (d > 1e-6 * h)
        if not np.any(near & (lines.distance(nodes.x) < 0.25 * h)):
            raise ValueError(
                f"enrichment='radial' with crack_rule={rule!r} is not supported when no node lies "
                f"within h/4 = {0.25 * h:g} of the crack inside the enrichment disc (radius "
                f"{method.ramp_outer:g}) of the tip at {tip.tolist()} (the crack between node "
                f"rows): {rule} lets points near the tip see the other face, whose nodes are then "
                "as close as their own, and the MLS fit mixes the two faces' opposite sqrt(r) "
                "amplitudes of the odd displacement component into the one even sqrt(r) term, "
                "whose 1/(2 sqrt r) gradient spreads the error (singular patch energy error "
                f"{'1.14-1.74' if rule == 'diffraction' else '0.96-1.50'} times the linear basis's "
                "under the same rule). Use enrichment='extrinsic_mls', 'pu' or 'full' with "
                f"crack_rule={rule!r}, or crack_rule='visibility' with d_max >= 2.5 (seed 003 Sect. "
                "5.3.2: the sqrt(r) basis needs no smoothing; 0.72-0.88 times the linear basis's), "
                "or put nodes on the crack faces.")
    if rule == "diffraction" and method.rule_power < 4:
        warnings.warn(
            "enrichment='radial' with crack_rule='diffraction' and rule_power < 4: measured no "
            "more accurate than the linear basis under the same rule (singular patch energy error "
            "1.03-1.21 times the linear basis's with nodes on the crack faces; K error 0.89 % "
            "against 0.52 % on the 45 degree Griffith crack): diffraction lets points near the tip "
            "see the other face, and the even sqrt(r) term mixes the faces' opposite amplitudes. "
            "Use enrichment='extrinsic_mls', 'pu' or 'full', crack_rule='visibility' on "
            "grid-aligned cracks (seed 003 Sect. 5.3.2: 0.56-0.81 times the linear basis's), or "
            "rule_power >= 4 (0.77-0.88 times).",
            UserWarning, stacklevel=5)


def _warn_close_to_crack(nodes: NodeCloud, lines: CrackLines, h: float, enrichment: str) -> None:
    """Seed 003 Sect. 4.3: transparency needs nodes at least h/4 from the crack surface
    (split face nodes included; nodes at a tip excepted): a warning, and an error with an
    extrinsic enrichment, which such nodes spoil."""
    close = lines.distance(nodes.x) < 0.25 * h
    for tip in lines.tip_positions():
        close &= np.hypot(*(nodes.x - tip).T) > 1e-6 * h
    if close.any() and enrichment in ("extrinsic_mls", "pu"):
        raise ValueError(
            f"enrichment={enrichment!r} with crack_rule='transparency' and {int(close.sum())} "
            f"node(s) closer than h/4 to a crack surface is not supported: such nodes cannot see "
            "ahead of the tip across the crack line's extension (seed 003 Sect. 4.3), which the "
            "enriched fields turn into a wrong K (extrinsic K_I 0.62 on the singular patch). Put "
            "the crack between node rows or use crack_rule='diffraction'.")
    if close.any():
        k = int(np.flatnonzero(close)[0])
        warnings.warn(
            f"crack_rule='transparency': {int(close.sum())} node(s) lie closer than h/4 = "
            f"{0.25 * h:g} to a crack surface (e.g. node {k} at {nodes.x[k].tolist()}); seed 003 "
            "Sect. 4.3 advises against it: such a node's weight has a trough ahead of the tip, "
            "and a node on the crack line cannot see below the line's extension, so the shape "
            "functions jump ahead of the tip. Put the crack between node rows or use another "
            "crack rule.", UserWarning, stacklevel=4)
