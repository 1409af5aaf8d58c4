"""Several load cases of one body, solved with one factorisation.

The cases share the body, the material, the cracks' geometry, the supported edges and
points with their prescribed components, and the discretisation; they differ in their loads
(tractions, body force, crack-face pressure) and in the supports' prescribed values. The
stiffness and the constrained system matrix are built and factorised once (SuperLU), and
each case is one right-hand side: the load vector enters the right-hand side linearly for
every bc method (``b = b_0 + E f``, ``E`` the embedding of the coefficients' rows: the
identity for penalty and Nitsche, the first rows for Lagrange multipliers, the free rows
for elimination), and so do the prescribed values (the multipliers' rows ``q``, the penalty
and Nitsche terms of ``ubar``, the eliminated values), while the matrix depends only on
which components are prescribed where: a case with its own support values gets the right-
hand side of its own constrained system (:func:`~efgkit.static.constrained_system`, no
factorisation), which shares the matrix.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import replace

import numpy as np
from scipy.sparse.linalg import splu

from .meshless_solution import MeshlessSolution
from .methods.boundary import loads
from .methods.discretize import discretize
from .methods.efg import EFG
from .problem.graded import modulus_weights
from .problem.scene import Scene
from .static import constrained_system
from .system.assemble import stiffness
from .system.linalg import SolverError

__all__ = ["solve_cases"]


def _check_same_body(name: str, sc: Scene, base: Scene, first: str) -> None:
    def same_domain(a, b):
        loops = [(a.outer, b.outer)] + list(zip(a.holes, b.holes, strict=False))
        return len(a.holes) == len(b.holes) and all(
            np.array_equal(p.vertices, q.vertices) and p.names == q.names
            and np.array_equal(p.sweeps, q.sweeps) for p, q in loops)

    if not isinstance(sc, Scene):
        raise TypeError(f"load case {name!r} must be a Scene, got {type(sc).__name__}")
    what = [w for w, same in (
        ("domain", sc.domain is base.domain or same_domain(sc.domain, base.domain)),
        ("material", sc.material == base.material),
        ("supported edges and components", _pattern(sc) == _pattern(base)),
        ("symmetry", sc.symmetry == base.symmetry),
        ("cracks", len(sc.cracks) == len(base.cracks) and all(
            np.array_equal(c.vertices, d.vertices) and c.tips == d.tips and c.name == d.name
            for c, d in zip(sc.cracks, base.cracks, strict=True)))) if not same]
    if what:
        raise ValueError(f"load case {name!r} differs from {first!r} in its {', '.join(what)}: the "
                         "cases of one factorisation share the body and which components are "
                         "supported where, and differ only in tractions, body force, crack "
                         "pressures and the supports' prescribed values; solve a case with other "
                         "supported edges separately (efgkit.solve)")


def _pattern(sc: Scene) -> tuple:
    """What the constrained system's matrix depends on: the supported edges and points and
    their prescribed components (not the values)."""
    return (tuple((s.edge, s.ux is None, s.uy is None) for s in sc.supports),
            tuple((p.x, p.ux is None, p.uy is None) for p in sc.point_supports))


def solve_cases(cases: Mapping[str, Scene], method: EFG) -> dict[str, MeshlessSolution]:
    """Solve the load cases ``{name: scene}`` with one factorisation of the system matrix.

    Parameters
    ----------
    cases : mapping of str to Scene
        At least one; every scene has the first one's body, material, crack geometry and
        supported edges, points and components (ValueError otherwise) and its own
        tractions, body force, crack pressures and supports' prescribed values.
    method : EFG

    Returns
    -------
    dict of str to MeshlessSolution, in the order of ``cases``; ``info["factorised_once"]``.

    Examples
    --------
    >>> from dataclasses import replace
    >>> from efgkit import Domain, EFG, Elastic, Scene, Support, Traction
    >>> pull = Scene(Domain.rectangle(0, 0, 2, 1), Elastic(1000.0, 0.25, "stress"),
    ...              supports=(Support("left", ux=0.0), Support("bottom", uy=0.0)),
    ...              tractions=(Traction("right", (1.0, 0.0)),))
    >>> sols = solve_cases({"pull": pull, "push": replace(pull, tractions=(Traction("right", (-2.0, 0.0)),))},
    ...                    EFG(spacing=0.25, bc="lagrange"))
    >>> [round(float(s.displacement([[2.0, 0.5]])[0, 0]), 6) for s in sols.values()]   # sigma L / E
    [0.002, -0.004]
    """
    if not isinstance(cases, Mapping) or not cases:
        raise ValueError(f"cases must be a non-empty mapping {{name: Scene}}, got {cases!r}")
    names = list(cases)
    base = cases[names[0]]
    for name in names:
        _check_same_body(name, cases[name], base, names[0])
    t0 = time.perf_counter()
    method = method.for_scene(base)
    disc = discretize(base, method)
    K = stiffness(disc.shape, modulus_weights(base, disc.points.x, disc.points.w), base.material.D)
    f0 = loads(disc)
    system = _constrained(disc, K, f0, method)
    lu = splu(system.A.tocsc())
    t_setup = time.perf_counter() - t0
    out = {}
    for name in names:
        t1 = time.perf_counter()
        cdisc = disc if name == names[0] else replace(disc, scene=cases[name])
        f = f0 if cdisc is disc else loads(cdisc)
        csys = system
        if cases[name].supports != base.supports or cases[name].point_supports != base.point_supports:
            csys = _constrained(cdisc, K, f, method)  # its own values: its right-hand side
            if abs(csys.A - system.A).max() != 0:  # the pattern check makes this unreachable
                raise ValueError(f"load case {name!r}: its supports change the system matrix; "
                                 "solve it separately (efgkit.solve)")
            b = csys.b
        else:
            df = f - f0 if disc.images is None else disc.images.T.T @ (f - f0)
            b = system.b + (df[system.free] if system.free is not None
                            else np.concatenate([df, np.zeros(len(system.b) - len(df))]))
        z = lu.solve(b)
        res = float(np.linalg.norm(system.A @ z - b) / max(np.linalg.norm(b), np.finfo(float).tiny))
        if not np.all(np.isfinite(z)) or res > 1e-8:
            raise SolverError(f"load case {name!r}: relative residual {res:.3g} > 1e-8 after the "
                              "SuperLU solve (or a NaN); the system may be singular")
        forces = csys.support_forces(z) if csys.support_forces is not None else None
        if forces is not None and csys is system and cdisc is not disc:  # f0 in the formula: add df's
            forces = _shifted_forces(system, forces, df)
        info = {"solver": "superlu", "residual": res, "factorised_once": True, "cases": len(names)}
        timings = {"setup (shared)": t_setup, "solve": time.perf_counter() - t1}
        out[name] = MeshlessSolution(cdisc, csys.coefficients(z), info, timings,
                                     support_forces=forces)
    return out


def _constrained(disc, K, f, method):
    """The constrained system of ``disc`` (over the part's unknowns for a half or quarter
    model, :class:`efgkit.system.images.ImageTie`)."""
    system = constrained_system(disc, K, f, method)
    return system if disc.images is None else disc.images.reduce(system)


def _shifted_forces(system, forces, df):
    """Support forces of a case whose load vector is ``f0 + df``: only elimination reads f
    (``K c - f`` on the eliminated rows), which then loses ``df`` there."""
    if system.free is None:
        return forces
    x, F = forces
    fixed = np.setdiff1d(np.arange(system.n_coeffs), system.free)
    F = F.copy()
    F[np.arange(len(fixed)), fixed % 2] -= df[fixed]
    return x, F
