"""Parameter studies: a base scene, parameters to vary, every point a dask task.

>>> from efgkit.study import Parameter, Study, read_study, run_study  # doctest: +SKIP

A :class:`Study` (:mod:`~efgkit.study.spec`) is a base scene document and
:class:`Parameter` s (dotted paths, :mod:`~efgkit.study.paths`) combined as a grid, a
zip or random samples; a study file (:mod:`~efgkit.study.studyfile`, ``docs/studies.md``)
says the same in TOML. :func:`run_study` (:mod:`~efgkit.study.run`) runs the points on a
local dask cluster, an existing scheduler, or in this process, each as
:func:`~efgkit.study.point.run_point`, and writes a row per point as it finishes, then
one table (:mod:`~efgkit.study.table`) and the figures (:mod:`~efgkit.study.figures`).
Importing this package does not import dask, distributed or pandas: they are loaded when
a study runs.
"""

from .figures import plot_study
from .paths import get_path, set_path
from .point import run_point
from .run import StudyRun, TerminalProgress, open_client, run_study
from .spec import Parameter, Point, Study
from .studyfile import StudyFile, read_study
from .table import study_table, write_table

__all__ = ["Parameter", "Point", "Study", "StudyFile", "StudyRun", "TerminalProgress",
           "get_path", "open_client", "plot_study", "read_study", "run_point", "run_study",
           "set_path", "study_table", "write_table"]
