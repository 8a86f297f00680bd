"""No import cycle inside scripts/rtbench: the modules' imports of each other,
read from the source (function-level imports too, which a cycle hides in),
form a graph without a cycle, so every module can be read, tested and
imported on top of the ones below it."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = "rtbench"


def package_modules(package_dir: Path) -> dict[str, Path]:
    return {path.stem: path for path in sorted(package_dir.glob("*.py"))}


def imported_names(node: ast.AST) -> list[str]:
    """The dotted names an import statement may bring in, relative imports
    resolved against the package (a module of it is one level down)."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if not isinstance(node, ast.ImportFrom):
        return []
    base = PACKAGE if node.level else node.module or ""
    if node.level and node.module:
        base = f"{PACKAGE}.{node.module}"
    return [base, *(f"{base}.{alias.name}" for alias in node.names)]


def package_imports(source: str, modules: set[str]) -> set[str]:
    """The modules of the package that `source` imports, anywhere in it."""
    found = set()
    for node in ast.walk(ast.parse(source)):
        for name in imported_names(node):
            top, _, rest = name.partition(".")
            module = rest.split(".")[0]
            if top == PACKAGE and module in modules:
                found.add(module)
    return found


def import_graph(package_dir: Path) -> dict[str, set[str]]:
    modules = package_modules(package_dir)
    return {
        name: package_imports(path.read_text(encoding="utf-8"), set(modules)) - {name} for name, path in modules.items()
    }


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of the graph as [a, b, ..., a], or None: a depth-first
    search that meets a module still on its path has gone round."""
    done: set[str] = set()
    path: list[str] = []

    def visit(module: str) -> list[str] | None:
        if module in path:
            return [*path[path.index(module) :], module]
        if module in done:
            return None
        path.append(module)
        for imported in sorted(graph.get(module, ())):
            cycle = visit(imported)
            if cycle:
                return cycle
        path.pop()
        done.add(module)
        return None

    for module in sorted(graph):
        cycle = visit(module)
        if cycle:
            return cycle
    return None


def test_the_search_finds_a_cycle_through_a_function_level_import(tmp_path):
    """The shape the compare command once had: a module that imports, inside
    a function, a module that imports it back at the top."""
    (tmp_path / "model.py").write_text("def main():\n    from rtbench import output\n")
    (tmp_path / "output.py").write_text("from rtbench.model import Comparison\n")
    (tmp_path / "leaf.py").write_text("import json\nfrom . import model\n")
    graph = import_graph(tmp_path)
    assert graph == {"leaf": {"model"}, "model": {"output"}, "output": {"model"}}
    assert find_cycle(graph) == ["model", "output", "model"]
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None


def test_rtbench_has_no_import_cycle(repo_root):
    graph = import_graph(repo_root / "scripts" / PACKAGE)
    assert {"bench", "compare", "compare_output", "cli", "load"} <= set(graph)  # the package was read
    assert graph["compare_output"] >= {"compare"}  # and its imports
    assert find_cycle(graph) is None
