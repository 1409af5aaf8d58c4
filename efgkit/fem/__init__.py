"""The finite-element reference model of a scene, with scikit-fem triangles.

``pslg`` (Triangle's input: the planar straight-line graph, tip fans, refinement),
``mesh`` (the graded triangle mesh with cracks opened: :class:`TriMesh`), ``model``
(:class:`FEM` and :func:`solve_fem`), ``dofs`` (DOFs selected by edge or mask),
``locate`` (point location for field evaluation), ``solution`` (:class:`FEMSolution`,
the same :class:`~efgkit.solution.Solution` contract as the meshless methods) and
``output`` (vertex stresses, VTU on the mesh, the stress figure).
"""

from .mesh import TriMesh, mesh_scene
from .mirror import mirror_mesh
from .model import FEM, solve_fem
from .solution import FEMSolution

__all__ = ["FEM", "FEMSolution", "TriMesh", "mesh_scene", "mirror_mesh", "solve_fem"]
