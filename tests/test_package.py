"""The package's shape: version, layers that import only downward, no import circles."""

import ast
from pathlib import Path

import railwear

ROOT = Path(railwear.__file__).resolve().parent
# layer of each top-level module or subpackage (docs/architecture.md); within layer 1, geometry
# and wear may use contact
LAYER = {"errors": 0, "units": 0, "registry": 0, "textfiles": 0, "checkpoints": 0, "_numba_cache": 0, "contact": 1, "geometry": 1, "wear": 1, "dynamics": 2, "track": 2,
         "pde": 2, "longterm": 3, "scenario": 4, "results": 4, "plots": 4, "sweep": 4, "analysis": 4,
         "forecast": 4, "api": 4, "measured": 4, "report": 4, "maintenance": 4, "cli": 5, "__main__": 6, "__init__": 6}


def _module(path):
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports():
    """``{module: {imported railwear modules}}``, function-level imports included."""
    modules = {_module(p): p for p in ROOT.rglob("*.py")}
    out = {}
    for name, path in modules.items():
        found = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("railwear"):
                found |= {f"{node.module}.{a.name}" if f"{node.module}.{a.name}" in modules else node.module
                          for a in node.names}
            elif isinstance(node, ast.Import):
                found |= {a.name for a in node.names if a.name.startswith("railwear")}
        out[name] = {m for m in found if m in modules and m != name and not name.startswith(m + ".")}
    return out


def test_version_is_set():
    assert railwear.__version__.count(".") >= 2


def test_layers_import_only_downward():
    def layer(module):
        return LAYER[(module.split(".") + ["__init__"])[1]]

    upward = [(m, t) for m, targets in _imports().items() for t in targets if layer(t) > layer(m)]
    assert not upward


def test_no_import_circles():
    graph, seen, circles = _imports(), {}, []

    def visit(node, path):
        seen[node] = "open"
        for nxt in graph[node]:
            if seen.get(nxt) == "open":
                circles.append(path[path.index(nxt):] + [nxt])
            elif nxt not in seen:
                visit(nxt, path + [nxt])
        seen[node] = "done"

    for start in graph:
        if start not in seen:
            visit(start, [start])
    assert not circles
