"""The library's packages import in one direction only (the order in seasonloop/__init__.py), the
library imports nothing outside it (stage scripts, tools, benchmarks), and the benchmarks and tools
import nothing of the tests."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from seasonloop import FOUNDATION, PACKAGES

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "seasonloop"

# Lowest first: a module may import its own package and those before it (the library's own list,
# seasonloop.PACKAGES, is highest first). The foundation modules import nothing of seasonloop.
LAYERS = ("foundation", *reversed(PACKAGES))


def layer_of(dotted: str) -> str:
    """The layer of a seasonloop module: its package under seasonloop, or foundation for a top-level module."""
    parts = dotted.split(".")
    return parts[1] if len(parts) > 2 or (SRC / parts[1]).is_dir() else "foundation"


def module_name(path: Path) -> str:
    return ".".join(("seasonloop", *path.relative_to(SRC).with_suffix("").parts)).removesuffix(".__init__")


def imports_of(path: Path) -> list[str]:
    """The seasonloop modules a file imports, resolved to dotted names (relative imports included)."""
    found = []
    package = module_name(path).split(".")[:-1] if path.name != "__init__.py" else module_name(path).split(".")
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package[: len(package) - node.level + 1] + ([base] if base else []))
            found.append(base)
    outside = ("_common", "_datasets", "_ground_truth", "stages", "tools", "benchmarks", "workspaces")
    return [name for name in found if name.split(".")[0] in ("seasonloop", *outside)]


MODULES = sorted(SRC.rglob("*.py"))


def test_every_package_is_a_layer_and_every_top_level_module_a_foundation_module() -> None:
    packages = {path.name for path in SRC.iterdir() if (path / "__init__.py").is_file()}
    assert packages == set(PACKAGES)
    assert {path.stem for path in SRC.glob("*.py")} - {"__init__"} == set(FOUNDATION)


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(SRC)))
def test_imports_point_down(path: Path) -> None:
    own = layer_of(module_name(path)) if path.parent != SRC else "foundation"
    for name in imports_of(path):
        assert name.split(".")[0] == "seasonloop", f"{path.name} imports {name}, which is not the library"
        target = layer_of(name)
        assert own != "foundation", f"{module_name(path)} is a foundation module but imports {name}"
        assert LAYERS.index(target) <= LAYERS.index(own), (
            f"{module_name(path)} ({own}) imports {name} ({target}): packages import only those below them"
        )


def test_the_check_catches_an_upward_import(tmp_path: Path) -> None:
    # the derivation itself: an evaluation module importing reporting is found and rejected
    assert layer_of("seasonloop.reporting.summary") == "reporting"
    assert layer_of("seasonloop.io") == "foundation" and layer_of("seasonloop.data") == "data"
    assert LAYERS.index(layer_of("seasonloop.reporting.summary")) > LAYERS.index(
        layer_of("seasonloop.evaluation.metrics")
    )


@pytest.mark.parametrize(
    "path",
    sorted([*(ROOT / "benchmarks").rglob("*.py"), *(ROOT / "tools").rglob("*.py")]),
    ids=lambda p: str(p.relative_to(ROOT)),
)
def test_benchmarks_and_tools_import_nothing_of_the_tests(path: Path) -> None:
    tree = ast.parse(path.read_text())
    imported = {
        alias.name.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names
    }
    imported |= {(node.module or "").split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    assert not imported & {"workspaces", "conftest", "tests"}, (
        f"{path.name} imports {imported & {'workspaces', 'conftest', 'tests'}}"
    )
    assert '"tests"' not in path.read_text(), f"{path.name} reaches into tests/"


def import_graph() -> dict[str, set[str]]:
    """seasonloop module -> the seasonloop modules it imports (anywhere in the file, deferred
    imports included; a `from package import name` counts as importing the package)."""
    names = {module_name(path) for path in MODULES}

    def resolve(dotted: str) -> str:
        while dotted and dotted not in names:
            dotted = dotted.rpartition(".")[0]
        return dotted

    graph = {}
    for path in MODULES:
        own = module_name(path)
        graph[own] = {resolve(name) for name in imports_of(path)} - {own, "seasonloop", ""}
    return graph


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import circles of `graph`: its strongly connected components of two or more modules."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import connected_components

    order = sorted(graph)
    index = {name: i for i, name in enumerate(order)}
    edges = [(index[a], index[b]) for a, targets in graph.items() for b in targets if b in index]
    rows, cols = zip(*edges) if edges else ((), ())
    matrix = csr_matrix(([1] * len(edges), (rows, cols)), shape=(len(order), len(order)))
    _, labels = connected_components(matrix, directed=True, connection="strong")
    groups: dict[int, list[str]] = {}
    for name, label in zip(order, labels):
        groups.setdefault(int(label), []).append(name)
    return [group for group in groups.values() if len(group) > 1]


def test_no_module_imports_itself_through_others() -> None:
    # a circle (a imports b, b imports a, even deferred) makes the house's order meaningless inside it
    assert circles(import_graph()) == []
    # the derivation itself: a circle of three is found
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


def test_params_reaches_nothing_above_it_by_name() -> None:
    # the ground floor checks params.yaml without the registries; what names a registry entry is
    # checked above them (seasonloop.registries): no module imported by a string the drawing misses
    for path in sorted((SRC / "params").glob("*.py")):
        assert "importlib" not in path.read_text(), f"{path.name} imports by name"
