"""``efgkit run SCENE.toml``: a static solve, a growth loop ([growth]) or an explicit run ([time])."""

from __future__ import annotations

import json
import math
import sys
import textwrap
import time
import warnings
from pathlib import Path

from .errors import FAILED, CLIError, check_out, message, stage

__all__ = ["cmd_run"]

FIGURE_DPI = 100  # the figures of `efgkit run` (cold start: 150 dpi took 0.3 s more)


def _num(v, fmt: str) -> str:
    """``v`` formatted, or "n/a" where the report holds None (a non-finite value)."""
    return "n/a" if v is None else format(v, fmt)


def _summary(rep: dict) -> str:
    """The human-readable report of ``efgkit run``."""
    solver = rep["solver"]
    res = solver.get("residual")
    lines = [
        f"scene     {rep['scene']} ({rep['file']})",
        f"nodes     {rep['n_nodes']} ({rep['n_boundary_nodes']} on the boundary), "
        f"{rep['n_dofs']} dofs",
        f"solver    {solver.get('solver', '?')}"
        + (f", residual {res:.2e}" if isinstance(res, float) else "")
        + (f", {solver['iterations']} CG iterations" if solver.get("iterations") is not None
           and solver.get("solver") == "amg" else "")
        + (f" in {solver['uzawa_steps']} Uzawa steps" if solver.get("uzawa_steps") else "")
        + (f" (fell back to SuperLU: {solver['fallback']})" if solver.get("fallback") else ""),
        f"energy    {_num(rep['energy'], '.6e')}",
    ]
    if rep["errors"] is not None:
        lines.append("errors    " + ", ".join(f"{k} {_num(v, '.3e')}"
                                              for k, v in rep["errors"].items()))
    for i, t in enumerate(rep["tips"]):  # enrichment coefficients are no K: JSON only
        lines.append(("tips      " if i == 0 else "          ")
                     + f"{t['id']} at ({t['x']:.6g}, {t['y']:.6g}): K_I {_num(t['KI'], '.5g')}, "
                     f"K_II {_num(t['KII'], '.5g')}, J {_num(t['J'], '.5g')}, T "
                     f"{_num(t['T'], '.5g')}, spread {_num(t['spread'], '.1e')} over "
                     f"{len(t['domains'])} domains, estimated error "
                     + ("(none)" if t.get("error") is None else _num(t["error"], ".1e"))
                     + (" UNRELIABLE" if t["warnings"] else ""))
        lines += [f"          warning: {w}" for w in t["warnings"]]
    t = rep["timings"]
    stages = ", ".join(f"{k} {v:.3f}" for k, v in t.items() if k != "total")
    lines.append(textwrap.fill(f"timings   total {t['total']:.2f} s: {stages} (s)", width=96,
                               subsequent_indent=" " * 10))
    lines += [("wrote     " if i == 0 else "          ") + f for i, f in enumerate(rep["outputs"])]
    return "\n".join(lines)


def _has_table(path: Path, key: str) -> bool:
    """Whether the TOML file ``path`` (read by load_study already) has a top-level ``key``."""
    try:
        import tomllib
    except ModuleNotFoundError:  # pragma: no cover - Python 3.10
        import tomli as tomllib

    with open(path, "rb") as f:
        return key in tomllib.load(f)


def _write_outputs(sol, out: Path, name: str, samples: int, sw, tips=()) -> list[Path]:
    """Fields (VTU), the discretisation (node cloud VTU) and the figures (PNG: nodes, stress
    and, with crack tips, K against the J-domain radius); adds their timings."""
    from ..io import nodes_path, write_figure
    from ..plot import plot_domain_dependence

    vtu = sol.write_vtu(out / f"{name}.vtu", n_target=samples)
    outputs = [vtu, nodes_path(vtu)]
    sw.lap("vtu")
    figures = [("nodes", sol.plot_discretization),
               ("stress", lambda: sol.plot_stress(n_target=samples))]
    if tips:
        figures.append(("sif", lambda: plot_domain_dependence(tips)))
    for suffix, draw in figures:  # 100 dpi: legible, a third less to rasterise than 150
        outputs.append(write_figure(draw(), out / f"{name}_{suffix}.png", dpi=FIGURE_DPI))
    sw.lap("figures")
    return outputs


def cmd_run(args) -> int:
    """Load a scene file, solve it, write fields and figures, report."""
    path = Path(args.scene)
    if not path.is_file():
        raise CLIError(f"scene file {str(path)!r} " + ("is not a file" if path.exists()
                                                       else "not found"))
    from ..io import file_name, jsonable
    from ..scenefile import load_cases, load_study
    from ..solution import method_record
    from ..static import solve
    from ..timing import Stopwatch

    t_run = time.perf_counter()
    sw = Stopwatch()  # laps: stages that add up to the wall time, compilation apart
    try:
        scene, method = load_study(path)
        cases = load_cases(path)  # [[load_cases]]: several loads, one factorisation
    except (OSError, ValueError, TypeError, KeyError) as err:
        msg = message(err)  # scene-file errors name the file already
        raise CLIError(msg if str(path) in msg else f"{path}: {msg}") from err
    sw.lap("load")
    name = file_name(scene.name if scene.name != "scene" else path.stem)
    out = Path(args.out) if args.out is not None else Path("out") / name
    check_out(out, args.out is not None)
    if cases is not None:
        from .cases import run_cases

        return run_cases(args, path, scene, method, cases, out, name)
    with stage(f"{path}: cannot grow the cracks", f"{path}: the growth loop failed"):
        table = None
        if _has_table(path, "growth"):  # efgkit.growth (and what it needs) only when asked for
            from ..growth.command import growth_table

            table = growth_table(path)  # [growth]: the step loop (efgkit.growth)
        if table is not None:
            from ..growth.command import run_table, summary

            tty = sys.stderr.isatty()  # a progress line only on a terminal
            step = (lambda s: print(f"\rgrowth step {s.index}", end="", file=sys.stderr)) if tty else None
            rep = run_table(scene, method, table, out, vtu=args.vtu_steps, on_step=step)
            print("", file=sys.stderr) if tty else None
    if table is not None:
        print(json.dumps(rep, indent=1, allow_nan=False) if args.json else summary(rep))
        return 0
    if not scene.is_static:  # a [time] table: the explicit driver
        return _run_dynamic(args, path, scene, method, out, name)
    with stage(f"{path}: cannot solve", f"{path}: the solve failed"):
        sol = solve(scene, method)
        sw.merge(sol.timings)
        energy = sol.strain_energy()
        res = sol.info.get("residual")
        if not math.isfinite(energy) or (isinstance(res, float) and not math.isfinite(res)):
            raise CLIError(
                f"{path}: the solve failed: the solution is not finite (strain energy {energy:g}, "
                f"relative residual {res}): a load, modulus or length of the scene overflows "
                "double precision (the energy squares the stresses); rescale the scene's units",
                FAILED)
        errors = sol.errors() if scene.exact is not None else None
        sw.lap("post")
    tips = ()
    if scene.cracks or scene.symmetry is not None:  # a half model: the modelled tips
        with warnings.catch_warnings(), stage(  # each result carries its warnings
                f"{path}: cannot compute the stress intensity factors",
                f"{path}: the stress intensity factors failed"):
            warnings.simplefilter("ignore", UserWarning)
            tips = sol.sifs()
        sw.lap("sifs")
    try:
        outputs = _write_outputs(sol, out, name, args.samples, sw, tips)
    except OSError as err:
        raise CLIError(f"cannot write to {str(out)!r}: {err}") from err
    except (ValueError, ArithmeticError) as err:
        raise CLIError(f"{path}: writing the fields and figures failed: {message(err)}",
                       FAILED) from err
    timings = sw.timings | {"total": time.perf_counter() - t_run}

    rep = {"scene": scene.name, "file": str(path), "method": method_record(sol.method),  # as solved
           **sol.sizes(), "timings": timings, "outputs": outputs,
           "energy": energy, "errors": errors, "solver": dict(sol.info),
           "tips": [t.as_dict() for t in tips]}
    rep = jsonable(rep)
    print(json.dumps(rep, indent=1, allow_nan=False) if args.json else _summary(rep))
    return 0


def _run_dynamic(args, path: Path, scene, method, out: Path, name: str) -> int:
    """``efgkit run`` of a dynamic scene: central differences, histories and their files."""
    from ..explicit import dynamics, integrate, load_stepping
    from ..explicit.dsif_table import load_dsif

    with stage(f"{path}: cannot integrate", f"{path}: the time integration failed"):
        stepping = load_stepping(path)
        settings = load_dsif(path)  # [dsif]: enrichment mass, J' acceleration recovery
        dyn = dynamics(scene, method, enrichment_mass=settings.enrichment_mass)
        sol = integrate(scene, method, stepping, dyn=dyn, dsif=settings.dsif, out=out / "vtu")
    try:
        rec = sol.write(out, name)
    except OSError as err:
        raise CLIError(f"cannot write to {str(out)!r}: {err}") from err
    rec["file"] = str(path)
    print(json.dumps(rec, indent=1, allow_nan=False) if args.json else
          sol.summary() + "\n" + "\n".join(f"wrote     {p}" for p in rec["outputs"]))
    return 0
