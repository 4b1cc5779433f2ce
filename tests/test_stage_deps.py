"""dvc.yaml declares everything each stage's result depends on, so a cached result cannot go stale.

For every stage DVC resolves from dvc.yaml (matrix stages expanded for every learner and season
of params.yaml), the stage script's source is read (never run) to find:
- the library modules it imports, transitively: seasonloop.* and the stage helpers stages/_*.py.
  The learner lookup (seasonloop.models.core.lookup) imports a learner's module only when asked
  for it, so a stage that uses the lookup depends on the modules of the learners it can ask
  for (LEARNERS_ASKED_FOR: fit@pca asks for pca only) and on what those import. The params check
  every stage starts with (seasonloop.registries.choices, CHECK) imports the registries and the
  learner modules to read their names and declared params: not followed and not a dep, since a
  check only stops a stage and never shapes what it writes;
- the params it reads: literal keys of param(params, "a.b"), load_params("a", ...) and
  params["a"], and the section "x" of XConfig.from_params(params) (a seasonloop.params.settings class
  whose NAME is "x"), in the script and in the stages/_common.py helpers it calls; each must also
  be among the keys its load_params call checks before work starts.
Each must be covered by a declared dep (a file, or a folder above it) or a declared param (the
key or a parent of it; `params.yaml:` alone covers every key).
"""

from __future__ import annotations

import ast
import shlex
from collections.abc import Callable, Iterable
from functools import cache
from pathlib import Path
from typing import Any

import pytest
import yaml

from seasonloop.params.settings import SECTIONS

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src"
STAGES = ROOT / "stages"
# the stage helpers a stage script imports as `from _common import ...`
HELPERS = {path.stem: path for path in STAGES.glob("_*.py")}
LOOKUP = SRC / "seasonloop" / "models" / "core" / "lookup.py"
CHECK = SRC / "seasonloop" / "registries" / "choices.py"  # the whole-file params check: not followed
MODELS = SRC / "seasonloop" / "models"

# _common functions whose string arguments are param keys -> index of the first such argument:
# param(params, "a.b") reads a key; load_params("a", "b.c") checks (and so reads) them
PARAM_READERS = {"param": 1, "load_params": 0}

# Param reads whose key is computed at run time: what each can read, from the stage's command-line
# arguments and params.yaml. A dynamic read not listed here fails the test, so none goes unchecked.
DYNAMIC_READS: dict[tuple[str, str], Callable[[list[str], dict[str, Any]], list[str]]] = {
    # fit@<learner> reads its learner's section
    ("stages/fit.py", "param(params, name)"): lambda argv, params: [argv[0]],
    # the ablation fits every learner of ablation.learners
    ("stages/training_seasons_fit.py", "param(params, learner)"): lambda argv, params: [argv[0]],
}

# The learners whose modules a stage script can import through the lookup, from its arguments and
# params.yaml. A stage that reaches the lookup without an entry here fails the test.
LEARNERS_ASKED_FOR: dict[str, Callable[[list[str], dict[str, Any]], list[str]]] = {
    "stages/fit.py": lambda argv, params: [argv[0]],
    "stages/features.py": lambda argv, params: [argv[0]],
    "stages/training_seasons_fit.py": lambda argv, params: [argv[0]],
    # the pipeline's own CAE, loaded from models/cae
    "stages/cae_widths.py": lambda argv, params: ["cae"],
    # seasonloop.reporting.figures asks every learner of the run which figures it draws
    "stages/figures.py": lambda argv, params: list(params["learners"]),
}


@cache
def config_sections() -> dict[str, str]:
    """seasonloop.params.settings class name -> the params section it reads (its NAME)."""
    return {section.__name__: section.NAME for section in SECTIONS}


def rel(path: Path) -> str:
    return path.resolve().relative_to(ROOT).as_posix()


def module_path(dotted: str) -> Path | None:
    """The source file of a seasonloop module or package, or None when it is not one."""
    base = SRC.joinpath(*dotted.split("."))
    if base.with_suffix(".py").is_file():
        return base.with_suffix(".py")
    if (base / "__init__.py").is_file():
        return base / "__init__.py"
    return None


def package_of(path: Path) -> str:
    """Dotted package of a file under src/ ('seasonloop.models' for models/pca.py)."""
    parts = path.resolve().relative_to(SRC).with_suffix("").parts
    return ".".join(parts[:-1])


@cache
def direct_imports(path: Path) -> frozenset[Path]:
    """The seasonloop modules and stage helpers (stages/_*.py) that `path` imports (anywhere in the file)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    found: set[Path] = set()

    def add(dotted: str) -> None:
        if dotted in HELPERS:
            found.add(HELPERS[dotted])
        elif dotted.split(".")[0] == "seasonloop":
            target = module_path(dotted)
            assert target is not None, f"{rel(path)}: cannot resolve import of {dotted}"
            found.add(target)

    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                add(alias.name)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                package = package_of(path).split(".")
                base = ".".join(package[: len(package) - node.level + 1] + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            if base in HELPERS or base.split(".")[0] == "seasonloop":
                add(base)
                # `from seasonloop.models import pca` imports a module, not a name
                for alias in node.names:
                    if base not in HELPERS and module_path(f"{base}.{alias.name}") is not None:
                        add(f"{base}.{alias.name}")
    return frozenset(found)


def enclosing_inits(path: Path) -> list[Path]:
    """The __init__.py of every package above a module under src/: importing it runs them first."""
    if SRC not in path.resolve().parents:
        return []
    return [
        folder / "__init__.py"
        for folder in path.resolve().parents
        if SRC in folder.parents and (folder / "__init__.py").is_file()
    ]


def runs_code(init: Path) -> bool:
    """Whether a package __init__ does more than hold a docstring and assignments (it re-exports)."""
    return any(isinstance(node, ast.ImportFrom) for node in ast.parse(init.read_text()).body)


def module_closure(script: Path, learners: Iterable[str] = ()) -> set[Path]:
    """Every module `script` imports, transitively, plus the script itself; `learners`: the learner
    modules the lookup may import for it."""
    seen: set[Path] = set()
    todo = [script]
    while todo:
        path = todo.pop()
        if path in seen or path == CHECK:
            continue
        seen.add(path)
        todo.extend(direct_imports(path))
        # `import a.b.c` runs a/__init__.py and a/b/__init__.py, and whatever they import
        todo.extend(enclosing_inits(path))
        if path == LOOKUP:
            # the lookup imports a learner's module by name, when asked for it
            todo.extend(MODELS / f"{name}.py" for name in learners)
    # an __init__ holding only a docstring runs nothing (test_package_inits_hold_no_code checks it)
    return {path for path in seen if path.name != "__init__.py" or runs_code(path)}


def checked_keys(script: Path) -> set[str]:
    """The keys a stage script checks up front: the literal arguments of its load_params call."""
    return {
        arg.value
        for node in ast.walk(ast.parse(script.read_text()))
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "load_params"
        for arg in node.args
        if isinstance(arg, ast.Constant) and isinstance(arg.value, str)
    }


def _reads_in(tree: ast.AST, file: str) -> tuple[set[str], set[str], set[str]]:
    """(literal param keys, dynamic reads as source text, names of functions called) in `tree`."""
    keys: set[str] = set()
    dynamic: set[str] = set()
    calls: set[str] = set()
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Attribute)
            and node.func.attr == "from_params"
            and isinstance(node.func.value, ast.Name)
        ):
            # SplitConfig.from_params(params) reads (and checks) section "split"
            section = config_sections().get(node.func.value.id)
            assert section is not None, f"{file}: {ast.unparse(node)}: not a seasonloop.params.settings section"
            keys.add(section)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            calls.add(node.func.id)
            if node.func.id in PARAM_READERS:
                for arg in node.args[PARAM_READERS[node.func.id] :]:
                    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                        keys.add(arg.value)
                    elif isinstance(arg, ast.Starred) or not isinstance(arg, ast.Constant):
                        dynamic.add(ast.unparse(node))
        elif isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name) and node.value.id == "params":
            if isinstance(node.slice, ast.Constant) and isinstance(node.slice.value, str):
                keys.add(node.slice.value)
            else:
                dynamic.add(ast.unparse(node))
    return keys, dynamic, calls


@cache
def common_reads() -> dict[str, tuple[frozenset[str], frozenset[str]]]:
    """function name in the stage helpers (stages/_*.py) -> (param keys, dynamic reads) it reads, transitively."""
    functions = {
        node.name: (node, helper)
        for helper in HELPERS.values()
        for node in ast.parse(helper.read_text()).body
        if isinstance(node, ast.FunctionDef)
    }
    direct = {name: _reads_in(node, rel(helper)) for name, (node, helper) in functions.items()}
    result = {}
    for name in functions:
        keys: set[str] = set()
        dynamic: set[str] = set()
        seen, todo = set(), [name]
        while todo:
            current = todo.pop()
            if current in seen:
                continue
            seen.add(current)
            k, d, calls = direct[current]
            keys |= k
            # param() itself reads its argument: the caller's literal is what counts
            dynamic |= set() if current in PARAM_READERS else d
            todo.extend(call for call in calls if call in functions)
        result[name] = (frozenset(keys), frozenset(dynamic))
    return result


def script_reads(script: Path) -> tuple[set[str], set[str]]:
    """(literal param keys, dynamic reads) of a stage script, through the _common helpers it calls."""
    keys, dynamic, calls = _reads_in(ast.parse(script.read_text()), str(script))
    helpers = common_reads()
    for call in calls & set(helpers):
        if call not in PARAM_READERS:
            keys |= helpers[call][0]
            dynamic |= helpers[call][1]
    return keys, dynamic


@cache
def resolved_stages() -> list[dict[str, Any]]:
    """Each stage as DVC resolves it: name, script, arguments, dep paths, declared params (None: all)."""
    from dvc.repo import Repo

    stages = []
    with Repo(str(ROOT)) as repo:
        for stage in repo.index.stages:
            argv = shlex.split(stage.cmd)
            assert argv[0] == "python" and argv[1].startswith("stages/"), (
                f"{stage.addressing}: unexpected cmd {stage.cmd}"
            )
            deps, params = [], []
            for dep in stage.deps:
                if hasattr(dep, "params"):
                    # `params.yaml:` with no keys tracks the whole file
                    params = None if not dep.params else params + list(dep.params)
                else:
                    deps.append(Path(dep.def_path).as_posix())
            stages.append(
                {"name": stage.addressing, "script": argv[1], "argv": argv[2:], "deps": deps, "params": params}
            )
    return stages


def uncovered_modules(required: Iterable[str], deps: list[str]) -> list[str]:
    return sorted(
        path for path in required if not any(path == dep or path.startswith(dep.rstrip("/") + "/") for dep in deps)
    )


def uncovered_params(required: Iterable[str], declared: list[str] | None) -> list[str]:
    if declared is None:
        return []
    return sorted(key for key in required if not any(key == d or key.startswith(d + ".") for d in declared))


def params_yaml() -> dict[str, Any]:
    return yaml.safe_load((ROOT / "params.yaml").read_text())


def learners_asked_for(stage: dict[str, Any]) -> list[str]:
    """The learners whose modules the stage can import through the lookup (none if it never reaches it)."""
    if LOOKUP not in module_closure(ROOT / stage["script"]):
        return []
    resolver = LEARNERS_ASKED_FOR.get(stage["script"])
    assert resolver is not None, (
        f"{stage['script']} imports the learner lookup; add which learners it asks "
        "for to LEARNERS_ASKED_FOR in tests/test_stage_deps.py"
    )
    return resolver(stage["argv"], params_yaml())


def stage_ids() -> list[str]:
    return [stage["name"] for stage in resolved_stages()]


@pytest.mark.parametrize("name", stage_ids())
def test_stage_declares_every_module_it_imports(name: str) -> None:
    stage = next(s for s in resolved_stages() if s["name"] == name)
    required = {rel(path) for path in module_closure(ROOT / stage["script"], learners_asked_for(stage))}
    missing = uncovered_modules(required, stage["deps"])
    assert not missing, f"dvc.yaml stage {name}: imports {', '.join(missing)} not listed in its deps"


@pytest.mark.parametrize("name", stage_ids())
def test_stage_declares_every_param_it_reads(name: str) -> None:
    stage = next(s for s in resolved_stages() if s["name"] == name)
    keys, dynamic = script_reads(ROOT / stage["script"])
    for read in sorted(dynamic):
        resolver = DYNAMIC_READS.get((stage["script"], read))
        assert resolver is not None, (
            f"{stage['script']}: param read `{read}` has a computed key; "
            "add what it can read to DYNAMIC_READS in tests/test_stage_deps.py"
        )
        keys |= set(resolver(stage["argv"], params_yaml()))
    missing = uncovered_params(keys, stage["params"])
    assert not missing, f"dvc.yaml stage {name}: reads param {', '.join(missing)} not listed in its params"
    # what it reads it checks before starting work (learner sections: the learner classes check them)
    literal, _ = script_reads(ROOT / stage["script"])
    unchecked = uncovered_params(literal, sorted(checked_keys(ROOT / stage["script"])))
    assert not unchecked, f"{stage['script']}: reads {', '.join(unchecked)} without checking it in load_params(...)"


def test_every_stage_is_checked() -> None:
    # the stage list comes from DVC's own resolution of dvc.yaml: one fit per learner of params.yaml
    names = stage_ids()
    for learner in params_yaml()["learners"]:
        assert f"fit@{learner}" in names


def test_package_inits_hold_no_code() -> None:
    # module_closure follows a package __init__'s relative re-exports (`from .video import
    # render_route`) whenever a module inside the package is imported; anything else would run unseen
    for init in SRC.rglob("__init__.py"):
        for node in ast.parse(init.read_text()).body:
            is_docstring = isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)
            is_reexport = isinstance(node, ast.ImportFrom) and node.level > 0
            assert is_docstring or is_reexport or isinstance(node, ast.Assign), (
                f"{rel(init)}: holds code; list it as a dep or move it"
            )


def test_the_checks_see_what_they_should() -> None:
    # the derivation itself: known imports and reads are found
    fit = {rel(p) for p in module_closure(ROOT / "stages/fit.py", ["ica"])}
    assert {
        "stages/_common.py",
        "stages/_datasets.py",
        "src/seasonloop/models/ica.py",
        "src/seasonloop/models/core/fastica.py",
        "src/seasonloop/models/core/lookup.py",
        "src/seasonloop/io.py",
    } <= fit
    # the lookup imports only the learner asked for, and the stage not the whole-file check
    assert "src/seasonloop/registries/choices.py" not in fit
    assert "src/seasonloop/models/pca.py" not in fit and "src/seasonloop/models/cae.py" not in fit
    # importing a module inside a package runs the package's __init__ and what it re-exports
    inner = {rel(p) for p in module_closure(SRC / "seasonloop/data/synthetic/layout.py")}
    assert {"src/seasonloop/data/synthetic/__init__.py", "src/seasonloop/data/synthetic/video.py"} <= inner
    keys, _ = script_reads(ROOT / "stages/fit.py")
    assert {"seed", "train.seasons", "data.seasons", "train.augmented"} <= keys
    # a typed config built from params reads its whole section
    keys, _ = script_reads(ROOT / "stages/preprocess.py")
    assert "preprocess" in keys
    assert uncovered_modules(["src/seasonloop/models/pca.py"], ["src/seasonloop/models"]) == []
    assert uncovered_modules(["src/seasonloop/models_x.py"], ["src/seasonloop/models"]) == [
        "src/seasonloop/models_x.py"
    ]
    assert uncovered_params(["evaluate.metric"], ["evaluate"]) == []
    assert uncovered_params(["evaluate_x"], ["evaluate"]) == ["evaluate_x"]


def test_config_reads_count_as_section_reads(tmp_path: Path) -> None:
    # XConfig.from_params(params) reads section x: dvc.yaml must declare it, load_params must check it
    script = tmp_path / "stage.py"
    script.write_text(
        'params = load_params("data.seasons", "split")\n'
        "config = SplitConfig.from_params(params)\n"
        "evaluate = EvaluateConfig.from_params(params)\n"
    )
    keys, dynamic = script_reads(script)
    assert {"split", "evaluate", "data.seasons"} <= keys and not dynamic
    assert uncovered_params(keys, ["data.seasons", "split"]) == ["evaluate"]
    assert uncovered_params(keys, ["data", "split", "evaluate"]) == []
    assert uncovered_params(keys, sorted(checked_keys(script))) == ["evaluate"]
    # every settings class is known, by the section it reads
    assert config_sections()["SplitConfig"] == "split" and config_sections()["ReportConfig"] == "report"


def test_bytecode_is_no_part_of_a_source_dependency() -> None:
    """Python writes __pycache__/*.pyc beside the modules a stage imports (unless
    PYTHONDONTWRITEBYTECODE is set): DVC must not hash them into the source folders the stages
    depend on (src/seasonloop/params, ...), or a run would change its own and other stages' deps
    and a fresh clone's first `dvc repro` would rerun what the committed dvc.lock says is done."""
    from dvc.repo import Repo

    root = Path(__file__).resolve().parents[1]
    with Repo(str(root)) as repo:
        ignored = [
            repo.dvcignore.is_ignored_file(str(root / path))
            for path in (
                "src/seasonloop/params/__pycache__/schema.cpython-311.pyc",
                "src/seasonloop/evaluation/__pycache__/metrics.cpython-311.pyc",
                "stages/_common.pyc",
                "src/seasonloop/params/schema.py",
            )
        ]
    assert ignored == [True, True, True, False]
