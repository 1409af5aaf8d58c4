"""The package tree is the pipeline: imports point down the stages, never up, never in a
circle, and never at another module's private names (docs/architecture.md)."""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "efgkit"

# Stages from the bottom up; a module may import from its own stage and the ones below.
# The most specific prefix decides a module's stage. Keep in step with docs/architecture.md.
STAGES = [
    ("problem", "timing", "jit", "tables", "memory"),           # what is solved; clocks,
                                                                # backends; TOML table keys
    ("methods", "methods.efg", "methods.mlpg", "scenefile",      # method descriptions, files,
     "gallery"),                                                # canonical specimens
    ("nodes", "search", "quadrature", "fracture"),              # points; fields -> K, J
    ("approx",),                                                # shape functions
    ("system",),                                                # K, f, M; constraints; solvers
    ("methods.discretize", "methods.local", "methods.local_nodes", "methods.local_size", "methods.local_tips",
     "methods.boundary", "methods.size", "methods.crack_choices"),  # scene + method -> discrete
    ("io", "plot", "vtu", "sampling", "sif_plot"),              # files and figures of results
    ("solution", "meshless_solution"),                          # the result contract
    ("static", "explicit", "fem", "loadcases"),                 # drivers and the FE reference
    ("growth",),                                                # step loops over the drivers
    ("study", "cli", "__main__", ""),                           # sweeps; the top
]


def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = list(path.relative_to(PACKAGE).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


MODULES = _modules()


def stage(module: str) -> int:
    """Index in STAGES of the longest prefix matching ``module`` ("" is the package)."""
    best, best_len = None, -1
    for k, prefixes in enumerate(STAGES):
        for p in prefixes:
            if (module == p or (p and module.startswith(p + ".")) or p == "") and len(p) > best_len:
                best, best_len = k, len(p)
    return best


def imports(module: str) -> list[tuple[str, list[str], int]]:
    """(imported efgkit module, names, line) of every import in ``module``, lazy ones too."""
    path = MODULES[module]
    is_package = path.name == "__init__.py"
    base = module.split(".") if module else []
    if not is_package:
        base = base[:-1]
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                parent = base[: len(base) - (node.level - 1)] if node.level > 1 else base
                target = ".".join(parent + ([node.module] if node.module else []))
            elif node.module and (node.module == "efgkit" or node.module.startswith("efgkit.")):
                target = node.module[len("efgkit."):] if node.module != "efgkit" else ""
            else:
                continue
            names = [a.name for a in node.names]
            # "from . import x" / "from .pkg import module": the module itself
            if target in MODULES and all(f"{target}.{n}".strip(".") in MODULES for n in names):
                for n in names:
                    out.append((f"{target}.{n}".strip("."), [], node.lineno))
            else:
                out.append((target, names, node.lineno))
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name == "efgkit" or a.name.startswith("efgkit."):
                    out.append((a.name[len("efgkit."):] if a.name != "efgkit" else "", [],
                                node.lineno))
    return out


def test_every_module_has_a_stage():
    assert [m for m in MODULES if stage(m) is None] == []


def test_imports_resolve_to_modules():
    bad = [(m, t, line) for m in MODULES for t, _, line in imports(m) if t not in MODULES]
    assert bad == []


def test_no_import_upwards():
    up = [f"{m} (stage {stage(m)}) imports {t} (stage {stage(t)}) at line {line}"
          for m in MODULES for t, _, line in imports(m) if stage(t) > stage(m)]
    assert up == []


def test_no_private_name_across_modules():
    private = [f"{m} imports {t}.{n} at line {line}" for m in MODULES
               for t, names, line in imports(m) for n in names
               if n.startswith("_") and not n.endswith("__")]
    assert private == []


def test_no_import_cycles():
    graph = {m: sorted({t for t, _, _ in imports(m) if t != m}) for m in MODULES}
    state, cycles = {}, []

    def visit(m, trail):
        state[m] = "open"
        for t in graph[m]:
            if state.get(t) == "open":
                cycles.append(" -> ".join(trail[trail.index(t):] + [t]) if t in trail
                              else f"{m} -> {t}")
            elif t not in state:
                visit(t, trail + [t])
        state[m] = "done"

    for m in graph:
        if m not in state:
            visit(m, [m])
    assert cycles == []


@pytest.mark.parametrize("module", sorted(MODULES), ids=lambda m: m or "efgkit")
def test_module_size(module):
    """One concept per module: under ~400 lines (a few review-approved exceptions listed)."""
    lines = MODULES[module].read_text().count("\n")
    assert lines <= 420, f"{module} has {lines} lines: split it where a piece has its own name"
