"""``efgkit run`` of a scene file with ``[[load_cases]]``: every case solved with one
factorisation (:func:`efgkit.loadcases.solve_cases`), their SIFs side by side."""

from __future__ import annotations

import json
import math
import time
import warnings
from pathlib import Path

from .errors import FAILED, CLIError, stage

__all__ = ["cases_summary", "run_cases"]


def _fmt(v) -> str:
    return "n/a" if v is None else format(v, ".5g")


def cases_summary(rep: dict) -> str:
    """The text report: one column per case, one row per tip and quantity."""
    names = [c["name"] for c in rep["cases"]]
    w = max(12, *(len(n) + 2 for n in names))
    head = "".join(f"{n:>{w}}" for n in names)
    lines = [f"scene     {rep['scene']} ({rep['file']})",
             f"nodes     {rep['n_nodes']} ({rep['n_boundary_nodes']} on the boundary), "
             f"{rep['n_dofs']} dofs",
             f"solver    superlu, factorised once for {len(names)} load cases",
             f"{'case':<18}{head}",
             f"{'energy':<18}" + "".join(f"{c['energy']:>{w}.5g}" for c in rep["cases"])]
    tips = [t["id"] for t in rep["cases"][0]["tips"]]
    for i, tid in enumerate(tips):
        for q, label in (("KI", "K_I"), ("KII", "K_II"), ("J", "J"), ("T", "T")):
            row = [c["tips"][i][q] for c in rep["cases"]]
            lines.append(f"{(tid + ' ' + label)[:17]:<18}" + "".join(f"{_fmt(v):>{w}}" for v in row))
        for c in rep["cases"]:
            lines += [f"          warning ({c['name']}, {tid}): {m}" for m in c["tips"][i]["warnings"]]
    lines.append(f"timings   total {rep['timings']['total']:.2f} s")
    lines += [("wrote     " if i == 0 else "          ") + f for i, f in enumerate(rep["outputs"])]
    return "\n".join(lines)


def run_cases(args, path: Path, scene, method, cases: dict, out: Path, name: str) -> int:
    """Solve the load cases of ``path`` with one factorisation, write one VTU per case,
    print the report (text or ``--json``: ``cases`` is a list of ``{name, energy, tips}``)."""
    from ..growth.command import growth_table
    from ..io import file_name, jsonable
    from ..loadcases import solve_cases
    from ..methods.efg import EFG
    from ..solution import method_record

    t_run = time.perf_counter()
    if not isinstance(method, EFG):
        raise CLIError(f"{path}: [[load_cases]] are solved by EFG (one factorisation); "
                       f"the file's method is {type(method).__name__}: use an [efg] table")
    if not scene.is_static or growth_table(path) is not None:
        raise CLIError(f"{path}: [[load_cases]] are for static scenes; remove [time] or [growth], "
                       "or the load cases")
    with stage(f"{path}: cannot solve the load cases", f"{path}: the load cases failed"):
        sols = solve_cases(cases, method)
    records = []
    for case, sol in sols.items():
        energy = sol.strain_energy()
        if not math.isfinite(energy):
            raise CLIError(f"{path}: load case {case!r}: the solution is not finite (strain "
                           f"energy {energy:g}); rescale the scene's units", FAILED)
        tips = ()
        if scene.cracks or scene.symmetry is not None:
            with warnings.catch_warnings(), stage(
                    f"{path}: load case {case!r}: cannot compute the stress intensity factors",
                    f"{path}: load case {case!r}: the stress intensity factors failed"):
                warnings.simplefilter("ignore", UserWarning)
                tips = sol.sifs()
        records.append({"name": case, "energy": energy, "tips": [t.as_dict() for t in tips]})
    outputs = []
    try:
        for case, sol in sols.items():
            outputs.append(sol.write_vtu(out / f"{name}_{file_name(case)}.vtu", n_target=args.samples))
    except OSError as err:
        raise CLIError(f"cannot write to {str(out)!r}: {err}") from err
    first = next(iter(sols.values()))
    rep = jsonable({"scene": scene.name, "file": str(path), "method": method_record(first.method),
                    **first.sizes(), "timings": {"total": time.perf_counter() - t_run},
                    "outputs": outputs, "solver": dict(first.info), "cases": records})
    print(json.dumps(rep, indent=1, allow_nan=False) if args.json else cases_summary(rep))
    return 0
