"""Command line: ``efgkit run SCENE.toml``, ``efgkit verify [NAME ...]``, ``efgkit sweep STUDY.toml``.

Thin by design (design rule 11): one function per subcommand over the public
API, testable as ``main(argv)``. Every error is one line on stderr,
``efgkit: error: ...`` (``--debug`` adds the traceback); the exit status says
whose it is (:data:`EXIT_STATUS`, shown by ``--help``): 1 when the computation
failed, 2 when the input was refused.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import os
import sys
import textwrap
import time
import traceback
import warnings
from contextlib import contextmanager
from pathlib import Path

__all__ = ["main"]

FAILED, REFUSED = 1, 2
EXIT_STATUS = """exit status:
  0  success
  1  the computation failed: a numerical failure (singular matrix, no convergence,
     non-finite results, out of memory), a failed verification, or a study point that
     failed or was lost
  2  the input was refused: usage, the scene file (missing, malformed, unknown keys),
     a scene or discretisation that cannot be solved as given (rigid-body modes,
     unsupported options, too large for the memory), the output directory
errors are one line on stderr, "efgkit: error: ..."; --debug adds the traceback"""

class CLIError(Exception):
    """An error reported as one line on stderr; ``status`` is the exit status."""

    def __init__(self, message: str, status: int = REFUSED):
        super().__init__(message)
        self.status = status


def _message(err: BaseException) -> str:
    # KeyError quotes its argument; the others read as written
    return str(err.args[0]) if isinstance(err, KeyError) and err.args else str(err)


def _failures() -> tuple[type[BaseException], ...]:
    """Exceptions that mean "the numbers failed" (exit 1) rather than "the input was refused"."""
    import numpy as np

    from .approx.mls import SingularMomentMatrix
    from .system.linalg import SolverError

    return (SolverError, SingularMomentMatrix, np.linalg.LinAlgError, ArithmeticError, MemoryError)


@contextmanager
def _stage(refused: str, failed: str):
    """Turn the errors of one stage of ``run`` into CLIError: ``failed: ...`` (exit 1) for
    numerical failures, ``refused: ...`` (exit 2) for input errors; others propagate (bugs)."""
    try:
        yield
    except CLIError:
        raise
    except _failures() as err:
        msg = _message(err) or type(err).__name__
        if isinstance(err, MemoryError):
            msg = "out of memory; use a coarser spacing or zones only where they are needed"
        raise CLIError(f"{failed}: {msg}", FAILED) from err
    except (ValueError, TypeError, KeyError) as err:
        raise CLIError(f"{refused}: {_message(err)}", REFUSED) from err


# ----------------------------------------------------------------------------- run






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
        + (f", residual {res:.2e}" if isinstance(res, float) else ""),
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


def _check_out(out: Path, given: bool) -> None:
    """Refuse, before the solve, an output directory that cannot be created or written."""
    what = f"--out {str(out)!r}" if given else f"the output directory {str(out)!r}"
    if out.exists() and not out.is_dir():
        raise CLIError(f"{what} is an existing file, not a directory; give a directory (it is "
                       "created if missing) or remove the file")
    base = out
    while not base.exists() and base != base.parent:
        base = base.parent
    if not base.is_dir():
        raise CLIError(f"{what} cannot be created: {str(base)!r} is a file; give another --out")
    if not os.access(base, os.W_OK | os.X_OK):
        raise CLIError(f"{what}: no permission to write in {str(base)!r}; give another --out")


def _write_outputs(sol, out: Path, name: str, samples: int, sw, tips=()) -> list[Path]:
    """Fields (VTU), the discretisation (node cloud VTU) and the figures (PNG: nodes, stress
    and, with crack tips, K against the J-domain radius); adds their timings."""
    from .io import nodes_path, write_figure
    from .plot import plot_domain_dependence

    vtu = sol.write_vtu(out / f"{name}.vtu", n_target=samples)
    outputs = [vtu, nodes_path(vtu)]
    sw.lap("vtu")
    figures = [("nodes", sol.plot_discretization),
               ("stress", lambda: sol.plot_stress(n_target=samples))]
    if tips:
        figures.append(("sif", lambda: plot_domain_dependence(tips)))
    for suffix, draw in figures:
        outputs.append(write_figure(draw(), out / f"{name}_{suffix}.png"))
    sw.lap("figures")
    return outputs


def cmd_run(args) -> int:
    """Load a scene file, solve it, write fields and figures, report."""
    path = Path(args.scene)
    if not path.is_file():
        raise CLIError(f"scene file {str(path)!r} " + ("is not a file" if path.exists()
                                                       else "not found"))
    from .io import file_name, jsonable
    from .scenefile import load_study
    from .solution import method_record
    from .static import solve
    from .timing import Stopwatch

    t_run = time.perf_counter()
    sw = Stopwatch()  # laps: stages that add up to the wall time, compilation apart
    try:
        scene, method = load_study(path)
    except (OSError, ValueError, TypeError, KeyError) as err:
        msg = _message(err)  # scene-file errors name the file already
        raise CLIError(msg if str(path) in msg else f"{path}: {msg}") from err
    sw.lap("load")
    name = file_name(scene.name if scene.name != "scene" else path.stem)
    out = Path(args.out) if args.out is not None else Path("out") / name
    _check_out(out, args.out is not None)
    from .growth.command import growth_table

    with _stage(f"{path}: cannot grow the cracks", f"{path}: the growth loop failed"):
        table = growth_table(path)  # [growth]: the step loop (efgkit.growth)
        if table is not None:
            from .growth.command import run_table, summary

            tty = sys.stderr.isatty()  # a progress line only on a terminal
            step = (lambda s: print(f"\rgrowth step {s.index}", end="", file=sys.stderr)) if tty else None
            rep = run_table(scene, method, table, out, vtu=args.vtu_steps, on_step=step)
            print("", file=sys.stderr) if tty else None
    if table is not None:
        print(json.dumps(rep, indent=1, allow_nan=False) if args.json else summary(rep))
        return 0
    if not scene.is_static:  # a [time] table: the explicit driver
        return _run_dynamic(args, path, scene, method, out, name)
    with _stage(f"{path}: cannot solve", f"{path}: the solve failed"):
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
        with warnings.catch_warnings(), _stage(  # each result carries its warnings
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
        raise CLIError(f"{path}: writing the fields and figures failed: {_message(err)}",
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
    from .explicit import integrate, load_stepping

    with _stage(f"{path}: cannot integrate", f"{path}: the time integration failed"):
        stepping = load_stepping(path)
        sol = integrate(scene, method, stepping, out=out / "vtu")
    try:
        rec = sol.write(out, name)
    except OSError as err:
        raise CLIError(f"cannot write to {str(out)!r}: {err}") from err
    rec["file"] = str(path)
    print(json.dumps(rec, indent=1, allow_nan=False) if args.json else
          sol.summary() + "\n" + "\n".join(f"wrote     {p}" for p in rec["outputs"]))
    return 0


# -------------------------------------------------------------------------- verify


def _verification_dir() -> Path:
    """``./verification`` or, failing that, the one next to the installed package."""
    import efgkit

    tried = [Path.cwd() / "verification",
             Path(efgkit.__file__).resolve().parents[1] / "verification"]
    for d in tried:
        if d.is_dir():
            return d
    raise CLIError("no verification directory: looked for " + " and ".join(map(str, tried)))


def _scripts(directory: Path) -> dict[str, Path]:
    return {p.stem: p for p in sorted(directory.glob("*.py")) if not p.name.startswith("_")}


def _run_script(name: str, path: Path, quick: bool) -> dict:
    """Import ``path`` as a module and return its ``main(quick=quick)``.

    Warnings raised by the script are collected (their count goes on the summary line).
    """
    spec = importlib.util.spec_from_file_location(f"_efgkit_verification_{name}", path)
    module = importlib.util.module_from_spec(spec)
    sys.path.insert(0, str(path.parent))  # scripts may import their siblings
    try:
        spec.loader.exec_module(module)
        result = module.main(quick=quick)
    finally:
        sys.path.remove(str(path.parent))
    if not isinstance(result, dict) or "passed" not in result:
        raise TypeError(f"main() must return a dict with 'passed', got {type(result).__name__}")
    return result


def cmd_verify(args) -> int:
    """List or run verification scripts; 1 if any failed."""
    directory = _verification_dir()
    scripts = _scripts(directory)
    if args.list:
        print("\n".join(scripts) if scripts else f"(no scripts in {directory})")
        return 0
    unknown = [n for n in args.names if n not in scripts]
    if unknown:
        raise CLIError(f"unknown verification script(s) {', '.join(map(repr, unknown))}; "
                       f"available: {', '.join(scripts) or 'none'} (in {directory})")
    names = args.names or list(scripts)
    failed = 0
    for name in names:
        t0 = time.perf_counter()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("default")
            try:
                res = _run_script(name, scripts[name], args.quick)
            except Exception as err:  # a crashing script is a failed verification
                ok, detail = False, f"error: {type(err).__name__}: {_message(err)}"
            else:
                ok = bool(res["passed"])
                checks = res.get("checks")
                detail = (f"{sum(bool(c.get('passed')) for c in checks)}/{len(checks)} checks"
                          if isinstance(checks, list) else "")
        if caught:
            kinds = sorted({w.category.__name__ for w in caught})
            n = len(caught)
            detail += f" ({n} warning{'s' * (n != 1)}: {', '.join(kinds)})"
        failed += not ok
        elapsed = time.perf_counter() - t0
        print(f"{'PASS' if ok else 'FAIL'}  {name:<24} {elapsed:7.1f} s  {detail}".rstrip())
    return 1 if failed else 0


# --------------------------------------------------------------------------- sweep


def cmd_sweep(args) -> int:
    """Run a study file (efgkit.study): its points on dask, a table and figures; 1 unless
    every point of the study has succeeded (in this run or an earlier one)."""
    from .io import file_name
    from .study import TerminalProgress, read_study, run_study

    try:
        sf = read_study(args.study)
    except (OSError, ValueError, TypeError) as err:
        raise CLIError(_message(err)) from err
    out = Path(args.out or sf.out or Path("out") / file_name(sf.study.name))
    _check_out(out, args.out is not None)
    workers = sf.workers if args.workers is None else args.workers
    try:
        run = run_study(sf.study, out=out, scheduler=args.scheduler or sf.scheduler or "local",
                        workers=workers, retry_failed=args.retry_failed,
                        progress=TerminalProgress(sys.stderr))
    except (ValueError, TypeError) as err:
        raise CLIError(f"{args.study}: {_message(err)}") from err
    except OSError as err:
        raise CLIError(f"cannot write to {str(out)!r}: {err}") from err
    print(run.summary())
    return 0 if run.ok else FAILED


# ---------------------------------------------------------------------------- main


def _sample_count(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 100:
        raise argparse.ArgumentTypeError(f"must be an integer >= 100, got {text!r}")
    return n


def _parser() -> argparse.ArgumentParser:
    from . import __version__

    p = argparse.ArgumentParser(prog="efgkit", description=__doc__.splitlines()[0],
                                epilog=EXIT_STATUS,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action="version", version=f"efgkit {__version__}")
    p.add_argument("--debug", action="store_true", help="show the traceback of an error")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    r = sub.add_parser("run", help="solve a scene file and write fields, figures and a report",
                       epilog=EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("scene", metavar="SCENE.toml")
    r.add_argument("--out", metavar="DIR", help="output directory (default: out/<scene name>); "
                   "checked before the solve")
    r.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    r.add_argument("--samples", type=_sample_count, default=20000, metavar="N",
                   help="approximate number of field sample points (default: 20000)")
    r.add_argument("--vtu-steps", action="store_true",
                   help="with a [growth] table: write the fields of every step as VTU")
    r.set_defaults(func=cmd_run)
    v = sub.add_parser("verify", help="run verification scripts (verification/<name>.py)",
                       epilog=EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter)
    v.add_argument("names", nargs="*", metavar="NAME", help="scripts to run (default: all)")
    v.add_argument("--quick", action="store_true", help="quick mode (coarse, for CI)")
    v.add_argument("--list", action="store_true", help="list the available scripts")
    v.set_defaults(func=cmd_verify)
    w = sub.add_parser("sweep", help="run a parameter study (docs/studies.md) on a dask cluster",
                       epilog=EXIT_STATUS, formatter_class=argparse.RawDescriptionHelpFormatter)
    w.add_argument("study", metavar="STUDY.toml")
    w.add_argument("--scheduler", metavar="ADDR", help="'local' (default: one worker per core), "
                   "'synchronous', tcp://host:8786 or a scheduler file *.json")
    w.add_argument("--workers", type=int, metavar="N", help="local cluster: worker processes")
    w.add_argument("--out", metavar="DIR", help="output directory (default: out/<study name>)")
    w.add_argument("--retry-failed", action="store_true", help="run failed points again")
    w.set_defaults(func=cmd_sweep)
    for s in (r, v, w):  # also after the subcommand; SUPPRESS keeps a --debug given before it
        s.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                       help="show the traceback of an error")
    return p


def _warning_lines(caught) -> list[str]:
    """Warnings raised during a command, one line each, without repeats."""
    seen = dict.fromkeys(" ".join(str(w.message).split()) for w in caught)
    return [f"efgkit: warning: {m}" for m in seen]


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``efgkit`` command; returns the exit status (module docstring).

    Warnings raised on the way are printed after the command, one line each
    (``efgkit: warning: ...``); after an error only with ``--debug``, and then with
    the traceback before the error line.

    Examples
    --------
    >>> main(["run", "no/such/scene.toml"])  # one line on stderr: scene file ... not found
    2
    """
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors (argparse printed them)
        return exc.code if isinstance(exc.code, int) else REFUSED
    error = None
    with warnings.catch_warnings(record=True) as caught:  # the filters in force stay
        try:
            status = args.func(args)
        except CLIError as err:
            error, status = err, err.status
    if error is None or args.debug:
        for line in _warning_lines(caught):
            print(line, file=sys.stderr)
    if error is not None:
        if args.debug:
            traceback.print_exception(error, file=sys.stderr)
        print(f"efgkit: error: {error}", file=sys.stderr)
    return status
