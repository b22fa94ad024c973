"""The architecture as a test: no import from a higher layer, no circle, heavy libraries only where they are wrapped."""

from __future__ import annotations

import ast
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import pytest

from orc_rpl.layers import HEAVY_LIBRARIES, TIERS, may_import

PACKAGE = Path(__file__).resolve().parents[2] / "orc_rpl"


@dataclass(frozen=True)
class Import:
    """One import statement of a module (TYPE_CHECKING imports, used only in annotations, are left out)."""

    importer: str        #: dotted module name that imports
    imported: str        #: dotted module name imported (a submodule where `from pkg import sub` names one)
    line: int
    in_function: bool

    def where(self) -> str:
        return f"{self.importer.replace('.', '/')}.py:{self.line}"


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _imports_of(path: Path) -> list[Import]:
    module = _module_name(path)
    is_package = path.name == "__init__.py"
    found: list[Import] = []

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and _is_type_checking(child.test):
                for other in child.orelse:
                    visit(other, in_function)
                continue
            nested = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
            if isinstance(child, ast.Import):
                found.extend(Import(module, alias.name, child.lineno, in_function) for alias in child.names)
            elif isinstance(child, ast.ImportFrom):
                base = child.module or ""
                if child.level:  # relative import
                    anchor = module.split(".") if is_package else module.split(".")[:-1]
                    anchor = anchor[: len(anchor) - child.level + 1]
                    base = ".".join([*anchor, base] if base else anchor)
                for alias in child.names:
                    candidate = f"{base}.{alias.name}"
                    target = candidate if _module_path(candidate) is not None else base
                    found.append(Import(module, target, child.lineno, in_function))
            visit(child, nested)

    visit(ast.parse(path.read_text(encoding="utf-8")), False)
    return found


def _module_path(name: str) -> Path | None:
    if not name.startswith("orc_rpl"):
        return None
    relative = Path(*name.split(".")[1:])
    for candidate in (PACKAGE / relative.with_suffix(".py"), PACKAGE / relative / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


@cache
def all_imports() -> tuple[Import, ...]:
    return tuple(i for path in sorted(PACKAGE.rglob("*.py")) for i in _imports_of(path))


def _package_of(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def test_every_package_has_a_tier() -> None:
    packages = {p.stem if p.is_file() else p.name for p in PACKAGE.iterdir()
                if (p.is_dir() and (p / "__init__.py").is_file()) or (p.suffix == ".py" and p.name != "__init__.py")}
    placed = {name for tier in TIERS for name in tier}
    assert packages <= placed, f"packages missing from orc_rpl/layers.py TIERS: {sorted(packages - placed)}"


def test_no_module_imports_from_a_higher_or_the_same_layer() -> None:
    wrong = [f"{i.where()}: {_package_of(i.importer)} imports {i.imported} ({_package_of(i.imported)} is not below it)"
             for i in all_imports()
             if i.imported.startswith("orc_rpl.") and _package_of(i.importer) != "__init__"
             and not may_import(_package_of(i.importer), _package_of(i.imported))]
    assert not wrong, "imports against the layer order (orc_rpl/layers.py):\n" + "\n".join(wrong)


def test_heavy_libraries_are_imported_only_in_the_package_that_wraps_them() -> None:
    wrong = [f"{i.where()}: imports {i.imported} (only orc_rpl.{HEAVY_LIBRARIES[i.imported.split('.')[0]]} may)"
             for i in all_imports()
             if i.imported.split(".")[0] in HEAVY_LIBRARIES
             and _package_of(i.importer) != HEAVY_LIBRARIES[i.imported.split(".")[0]]]
    assert not wrong, "\n".join(wrong)


def test_no_circle_of_imports_even_through_imports_inside_functions() -> None:
    graph: dict[str, set[str]] = {}
    lines: dict[tuple[str, str], Import] = {}
    for i in all_imports():
        if i.imported.startswith("orc_rpl") and i.imported != i.importer:
            graph.setdefault(i.importer, set()).add(i.imported)
            lines.setdefault((i.importer, i.imported), i)
    # A package's __init__ imports its submodules; a submodule that imports its own package's __init__
    # is a circle only when that __init__ (transitively) imports the submodule back: the search finds it.
    cycles: list[list[str]] = []
    state: dict[str, int] = {}
    stack: list[str] = []

    def search(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                cycles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in state:
                search(nxt)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            search(node)
    described = [" -> ".join(f"{a} ({lines[(a, b)].where()})" for a, b in zip(c, c[1:])) for c in cycles]
    assert not cycles, "import circles (an import inside a function does not hide one):\n" + "\n".join(described)


@pytest.mark.parametrize("tier", TIERS, ids=lambda t: "+".join(t))
def test_tiers_name_each_package_once(tier: tuple[str, ...]) -> None:
    others = [name for other in TIERS if other is not tier for name in other]
    assert not set(tier) & set(others), f"{tier} shares a package with another tier"


def test_docs_architecture_draws_the_same_tiers() -> None:
    text = (PACKAGE.parent / "docs" / "architecture.md").read_text(encoding="utf-8")
    block = text.split("## Layers", 1)[1].split("```", 2)[1]
    drawn = tuple(tuple(name.strip() for name in line.split("|")) for line in block.strip().splitlines())
    assert drawn == TIERS, "docs/architecture.md's layer block differs from orc_rpl/layers.py TIERS"
