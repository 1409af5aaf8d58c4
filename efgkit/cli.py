"""Command line: ``efgkit run SCENE.toml`` and ``efgkit verify [NAME ...]``.

Thin by design (design rule 11): one function per subcommand over the public
API, testable as ``main(argv)``. A user error (missing file, bad scene,
unsolvable system) prints one line to stderr and returns 2; a failed
verification returns 1.
"""

from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import json
import re
import sys
import textwrap
import time
import warnings
from pathlib import Path

__all__ = ["main"]


class CLIError(Exception):
    """A user error: reported as one line on stderr, exit status 2."""


def _message(err: BaseException) -> str:
    # KeyError quotes its argument; the others read as written
    return str(err.args[0]) if isinstance(err, KeyError) and err.args else str(err)


def _user_errors() -> tuple[type[BaseException], ...]:
    """Exceptions that mean "the input is wrong", not "efgkit has a bug"."""
    from .system.linalg import SolverError

    return (OSError, ValueError, TypeError, KeyError, SolverError)


# ----------------------------------------------------------------------------- run


def _method_fields(method) -> dict:
    """The discretisation choices as a dict (user coordinates left out)."""
    return {f.name: getattr(method, f.name) for f in dataclasses.fields(method)
            if f.name != "coordinates"}


def _safe_name(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("._") or "scene"


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
        f"energy    {rep['energy']:.6e}",
    ]
    if rep["errors"] is not None:
        lines.append("errors    " + ", ".join(f"{k} {v:.3e}" for k, v in rep["errors"].items()))
    for i, t in enumerate(rep["tips"]):
        own = (f" (extrinsic K_I {t['KI_enriched']:.5g}, K_II {t['KII_enriched']:.5g})"
               if "KI_enriched" in t else "")
        lines.append(("tips      " if i == 0 else "          ")
                     + f"{t['id']} at ({t['x']:.6g}, {t['y']:.6g}): K_I {t['KI']:.5g}, "
                     f"K_II {t['KII']:.5g}, J {t['J']:.5g}, T {t['T']:.5g}, spread "
                     f"{t['spread']:.1e} over {len(t['domains'])} domains{own}")
        lines += [f"          warning: {w}" for w in t["warnings"]]
    t = rep["timings"]
    stages = ", ".join(f"{k} {v:.3f}" for k, v in t.items() if k != "total")
    lines.append(textwrap.fill(f"timings   total {t['total']:.2f} s: {stages} (s)", width=96,
                               subsequent_indent=" " * 10))
    lines += [("wrote     " if i == 0 else "          ") + f for i, f in enumerate(rep["outputs"])]
    return "\n".join(lines)


def _write_outputs(sol, out: Path, name: str, samples: int, timings: dict,
                   tips=()) -> list[Path]:
    """Fields (VTU), the discretisation (node cloud VTU) and the figures (PNG: nodes, stress
    and, with crack tips, K against the J-domain radius); adds their timings."""
    from .io import nodes_path, write_figure
    from .plot import plot_domain_dependence

    t0 = time.perf_counter()
    vtu = sol.write_vtu(out / f"{name}.vtu", n_target=samples)
    outputs = [vtu, nodes_path(vtu)]
    timings["vtu"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    figures = [("nodes", sol.plot_discretization),
               ("stress", lambda: sol.plot_stress(n_target=samples))]
    if tips:
        figures.append(("sif", lambda: plot_domain_dependence(tips)))
    for suffix, draw in figures:
        outputs.append(write_figure(draw(), out / f"{name}_{suffix}.png"))
    timings["figures"] = time.perf_counter() - t0
    return outputs


def cmd_run(args) -> int:
    """Load a scene file, solve it, write fields and figures, report."""
    path = Path(args.scene)
    if not path.is_file():
        raise CLIError(f"scene file {str(path)!r} not found")
    from .io import jsonable
    from .scenefile import load_study
    from .static import solve
    from .system.linalg import SolverError

    t_run = time.perf_counter()
    timings = {}
    t0 = time.perf_counter()
    try:
        scene, method = load_study(path)
    except _user_errors() as err:
        msg = _message(err)  # scene-file errors name the file already
        raise CLIError(msg if str(path) in msg else f"{path}: {msg}") from err
    timings["load"] = time.perf_counter() - t0
    try:
        sol = solve(scene, method)
    except (ValueError, SolverError) as err:  # rigid-body modes, singular moments, no convergence
        raise CLIError(f"{path}: cannot solve: {_message(err)}") from err
    timings.update({k: v for k, v in sol.timings.items() if k != "total"})
    t0 = time.perf_counter()
    energy = sol.strain_energy()
    errors = sol.errors() if scene.exact is not None else None
    timings["post"] = time.perf_counter() - t0
    tips = ()
    if scene.cracks:
        t0 = time.perf_counter()
        with warnings.catch_warnings():  # each result carries its warnings; the report shows them
            warnings.simplefilter("ignore", UserWarning)
            tips = sol.sifs()
        timings["sifs"] = time.perf_counter() - t0

    name = _safe_name(scene.name if scene.name != "scene" else path.stem)
    out = Path(args.out) if args.out is not None else Path("out") / name
    try:
        outputs = _write_outputs(sol, out, name, args.samples, timings, tips)
    except OSError as err:
        raise CLIError(f"cannot write to {str(out)!r}: {err}") from err
    timings["total"] = time.perf_counter() - t_run

    rep = {"scene": scene.name, "file": str(path), "method": _method_fields(method),
           **sol.sizes(), "timings": timings, "outputs": outputs,
           "energy": energy, "errors": errors, "solver": dict(sol.info),
           "tips": [t.as_dict() for t in tips]}
    rep = jsonable(rep)
    print(json.dumps(rep, indent=1, allow_nan=False) if args.json else _summary(rep))
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

    p = argparse.ArgumentParser(prog="efgkit", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"efgkit {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    r = sub.add_parser("run", help="solve a scene file and write fields, figures and a report")
    r.add_argument("scene", metavar="SCENE.toml")
    r.add_argument("--out", metavar="DIR", help="output directory (default: out/<scene name>)")
    r.add_argument("--json", action="store_true", help="print one JSON object instead of text")
    r.add_argument("--samples", type=_sample_count, default=20000, metavar="N",
                   help="approximate number of field sample points (default: 20000)")
    r.set_defaults(func=cmd_run)
    v = sub.add_parser("verify", help="run verification scripts (verification/<name>.py)")
    v.add_argument("names", nargs="*", metavar="NAME", help="scripts to run (default: all)")
    v.add_argument("--quick", action="store_true", help="quick mode (coarse, for CI)")
    v.add_argument("--list", action="store_true", help="list the available scripts")
    v.set_defaults(func=cmd_verify)
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``efgkit`` command; returns the exit status.

    Examples
    --------
    >>> main(["run", "no/such/scene.toml"])  # one line on stderr: scene file ... not found
    2
    """
    try:
        args = _parser().parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors (argparse printed them)
        return exc.code if isinstance(exc.code, int) else 2
    try:
        return args.func(args)
    except CLIError as err:
        print(f"efgkit: error: {err}", file=sys.stderr)
        return 2
