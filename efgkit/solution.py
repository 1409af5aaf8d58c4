"""The result contract: one set of methods for EFG, MLPG and FEM solutions.

Every solver returns a :class:`Solution`. Its fields evaluate anywhere in the
body, its fracture quantities come from the same domain integrals, and its
outputs have the same signatures and meaning, so the CLI, the verification
scripts and user code never ask which method produced it:

=====================  =====================================================
``displacement(x)``    (n, 2) at points ``x (n, 2)`` (default: quadrature points)
``gradient(x)``        (n, 2, 2), ``du_i/dx_j``
``strain(x)``          (n, 3) Voigt (xx, yy, xy) with engineering shear
``stress(x)``          (n, 3) Voigt (xx, yy, xy)
``strain_energy()``    1/2 int eps : sigma over the body
``errors(exact)``      relative L2 and energy-norm errors against a closed form
``sifs(...)``          one :class:`~efgkit.fracture.sif.TipResult` per crack tip
``reaction(edge)``     (2,) force the supports of ``edge`` apply to the body
``cmod(crack)``        crack-mouth opening of an edge crack
``write_vtu(path)``    fields for ParaView
``plot_stress(...)``   filled contours of a stress component (a figure)
``plot_discretization(ax)``  the nodes or the mesh (a figure)
``record(...)``        JSON-ready summary (the keys of ``efgkit run --json``)
``write(out, ...)``    VTU, figures and the record in a directory
=====================  =====================================================

The coefficients of a meshless solution are MLS parameters, not nodal
displacements: evaluate fields with the methods, never index the coefficients.
"""

from __future__ import annotations

import dataclasses
import re
from abc import ABC, abstractmethod
from pathlib import Path

import numpy as np

from .problem.crack import FACE_OFFSET
from .problem.material import strain_from_gradient

__all__ = ["Solution"]


class Solution(ABC):
    """What every solve returns (module docstring); subclasses hold the method's data.

    Subclasses provide ``scene``, ``info`` (solver information) and ``timings``
    (seconds per stage) attributes and the abstract methods; ``strain``,
    ``stress``, ``cmod``, ``record`` and ``write`` follow from them.
    """

    kind: str = "?"  # "efg", "mlpg" or "fem", the ``method.kind`` of records
    discretization_figure: str = "discretization"  # file suffix of plot_discretization

    # ----------------------------------------------------------------- fields

    @abstractmethod
    def displacement(self, x=None) -> np.ndarray:
        """Displacement at points ``x (n, 2)`` (default: the quadrature points), shape (n, 2)."""

    @abstractmethod
    def gradient(self, x=None) -> np.ndarray:
        """Displacement gradient ``du_i/dx_j`` at points ``x (n, 2)``, shape (n, 2, 2)."""

    def strain(self, x=None) -> np.ndarray:
        """Strain (xx, yy, xy engineering) at points ``x (n, 2)``, shape (n, 3)."""
        return strain_from_gradient(self.gradient(x))

    def stress(self, x=None) -> np.ndarray:
        """Stress (xx, yy, xy) at points ``x (n, 2)``, shape (n, 3): ``D eps``."""
        return self.strain(x) @ self.scene.material.D.T

    @abstractmethod
    def strain_energy(self) -> float:
        """U = 1/2 int eps : sigma dOmega over the body."""

    @abstractmethod
    def errors(self, exact=None) -> dict:
        """Relative ``l2`` and ``energy`` errors (and ``energy_abs``) against ``exact``
        (default ``scene.exact``)."""

    # --------------------------------------------------------------- fracture

    @abstractmethod
    def sifs(self, radii=None, q="wendland_c2", spread_tol: float = 0.01) -> tuple:
        """K_I, K_II, J and T of every crack tip: a tuple of TipResult, one per
        ``scene.tips``, from interaction integrals over several domains."""

    @abstractmethod
    def reaction(self, edge) -> np.ndarray:
        """Force ``(2,)`` that the supports of ``edge`` (a name or a mask ``x -> bool``)
        apply to the body."""

    def cmod(self, crack) -> float:
        """Crack-mouth opening ``(u_left - u_right) . n`` at the mouth of an edge crack.

        ``n`` is the unit normal of the mouth segment pointing to the left face, so
        the opening is positive when the faces separate. The two displacements are
        taken :data:`~efgkit.problem.crack.FACE_OFFSET` of the domain size off the
        crack line, on each face.

        Parameters
        ----------
        crack : Crack or str
            A crack of the scene (or its name) with a mouth.
        """
        c = self._mouth_crack(crack)
        end = 0 if not c.tips[0] else 1
        a, b = c.segments[0] if end == 0 else c.segments[-1][::-1]
        t = (b - a) / np.linalg.norm(b - a)  # into the body along the crack
        n = np.array([-t[1], t[0]]) * (1.0 if end == 0 else -1.0)  # left normal of a -> b
        off = FACE_OFFSET * self.scene.domain.size
        x = np.array([a + off * (t + n), a + off * (t - n)])
        u = self.displacement(x)
        return float((u[0] - u[1]) @ n)

    def _mouth_crack(self, crack):
        """The scene's crack called ``crack`` (or with its name), checked to have a mouth."""
        names = [c.name for c in self.scene.cracks]
        name = getattr(crack, "name", crack)
        if name not in names:
            raise ValueError(f"the scene has no crack {name!r}; its cracks are {names}")
        c = self.scene.cracks[names.index(name)]
        if all(c.tips):
            raise ValueError(f"crack {name!r} has no mouth (both ends are tips): a crack-mouth "
                             "opening needs an edge crack")
        return c

    # ---------------------------------------------------------------- outputs

    @abstractmethod
    def write_vtu(self, path, n_target: int | None = None) -> Path:
        """Write the fields as VTU; ``n_target`` samples the body on about that many points
        (:func:`efgkit.io.sample_grid`), None writes the method's own discretisation
        where it has one (the FE mesh) or 20 000 samples. Returns the path."""

    @abstractmethod
    def plot_stress(self, component: str = "von_mises", ax=None, levels: int = 30,
                    limits=None, n_target: int | None = None):
        """Filled contours of a stress component (``efgkit.plot.COMPONENTS``), colour range
        ``limits = (lo, hi)`` or automatic; ``n_target`` samples as for :meth:`write_vtu`
        (None: the FE mesh, or 20 000 samples). Returns the figure."""

    @abstractmethod
    def plot_discretization(self, ax=None):
        """The node cloud (meshless methods) or the mesh (FEM); returns the figure."""

    @property
    def method(self):
        """The discretisation description (EFG, MLPG or FEM)."""
        raise NotImplementedError  # pragma: no cover - every subclass defines it

    @abstractmethod
    def sizes(self) -> dict:
        """Counts of the discretisation: ``n_nodes``, ``n_dofs`` and the method's own
        (``n_boundary_nodes``, ``n_elements``)."""

    def record(self, radii=None, q="wendland_c2") -> dict:
        """JSON-ready summary, with the keys of ``efgkit run --json``.

        Returns
        -------
        dict
            ``scene``, ``method`` (the description's fields and ``"kind"``), the sizes
            (``n_nodes``, ``n_dofs`` and the method's own counts), ``timings``,
            ``solver``, ``energy`` (strain energy), ``errors`` (against
            ``scene.exact``, or None), ``tips`` (:meth:`TipResult.as_dict` of every tip,
            from :meth:`sifs` with ``radii`` and ``q``) and ``cmod`` (crack name ->
            opening, for cracks with a mouth).
        """
        from .io import jsonable

        m = self.method
        tips = self.sifs(radii=radii, q=q) if self.scene.tips else ()
        fields = {f.name: getattr(m, f.name) for f in dataclasses.fields(m)
                  if f.name != "coordinates"}
        out = {"scene": self.scene.name, "method": {"kind": self.kind, **fields},
               **self.sizes(), "timings": dict(self.timings), "solver": dict(self.info),
               "energy": self.strain_energy(),
               "errors": self.errors() if self.scene.exact is not None else None,
               "tips": [t.as_dict() for t in tips],
               "cmod": {c.name: self.cmod(c) for c in self.scene.cracks if not all(c.tips)}}
        return jsonable(out)

    def write(self, out, name: str | None = None, radii=None) -> dict:
        """Write ``<name>.vtu``, ``<name>_nodes.png`` (meshless) or ``<name>_mesh.png`` (FEM),
        ``<name>_stress.png`` (von Mises) and ``<name>.json`` (:meth:`record` with
        ``outputs``) into the directory ``out``; ``name`` defaults to the scene's name made
        file-safe. Returns the record."""
        from .io import write_figure, write_json

        out = Path(out)
        name = name or (re.sub(r"[^A-Za-z0-9_.-]+", "_", self.scene.name).strip("._") or "scene")
        rec = self.record(radii)
        paths = [self.write_vtu(out / f"{name}.vtu")]
        for suffix, draw in ((self.discretization_figure, self.plot_discretization),
                             ("stress", self.plot_stress)):
            paths.append(write_figure(draw(), out / f"{name}_{suffix}.png"))
        rec["outputs"] = [str(p) for p in paths + [out / f"{name}.json"]]
        write_json(rec, out / f"{name}.json")
        return rec
