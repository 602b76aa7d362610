"""The validation suite's packages import one way (issue 35), read from the
imports themselves with `ast` (top-level and inside functions, absolute and
relative):

* `validation.shared` (references, drivers of the other codes, the systems
  they are compared on, output readers, the check record) imports nothing
  else of `validation`;
* `validation.longrun` (the long-run studies) imports `shared` only;
* `validation.checks` and `validation.bench` import `shared` and `longrun`,
  never each other; `validation.fixtures` imports `shared` only;
* the report (`validation/report.py`, `report_html.py`) imports `checks`,
  `longrun` and `shared`, never `bench` or `fixtures`;
* the tests may import anything.

And no two module files under `validation/` share a name (``__init__.py`` and
``__main__.py`` aside), so a name says which module it is; and every module
imports, the entry points of `make bench` and `make fixtures` included, which
no other test runs."""

import ast
import importlib
from collections import defaultdict
from pathlib import Path

import pytest

VALIDATION = Path(__file__).resolve().parents[1]

#: Layer -> the layers it may import (a layer is a package of `validation`;
#: "report" stands for the modules at the root of `validation/`).
ALLOWED = {
    "shared": {"shared"},
    "longrun": {"shared", "longrun"},
    "checks": {"shared", "longrun", "checks"},
    "bench": {"shared", "longrun", "bench"},
    "fixtures": {"shared", "fixtures"},
    "report": {"shared", "longrun", "checks", "report"},
}
#: Files whose names may repeat: a package's own files.
SPECIAL = {"__init__.py", "__main__.py"}


def _layer(root: Path, name: str) -> str:
    """The layer of `validation.<name>...`: its package, or "report" for a root module."""
    return name if (root / name).is_dir() else "report"


def imported_layers(root: Path, path: Path) -> set[str]:
    """The layers of `validation` that the file `path` (under `root`, the
    `validation/` folder) imports."""
    package = ["validation", *path.relative_to(root).parent.parts]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            modules = [alias.name.split(".") for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = base + (node.module.split(".") if node.module else [])
            # `from validation import x` (or `from .. import x` at depth 1) names the layer in `x`.
            modules = [module + [alias.name] for alias in node.names] if module == ["validation"] else [module]
        else:
            continue
        found |= {_layer(root, m[1]) for m in modules if m[0] == "validation" and len(m) > 1}
    return found


def violations(root: Path) -> list[str]:
    """Every import that runs against `ALLOWED`, as "file imports layer"."""
    out = []
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root).parts
        layer = parts[0] if len(parts) > 1 else "report"
        if layer == "tests":
            continue
        for target in sorted(imported_layers(root, path) - ALLOWED[layer]):
            out.append(f"{path.relative_to(root)} ({layer}) imports validation.{target}")
    return out


def shared_names(root: Path) -> dict[str, list[str]]:
    """Module file names found more than once under `root`, with their places."""
    places = defaultdict(list)
    for path in sorted(root.rglob("*.py")):
        if path.name not in SPECIAL:
            places[path.name].append(str(path.relative_to(root)))
    return {name: where for name, where in places.items() if len(where) > 1}


def module_names(root: Path) -> list[str]:
    """Every module of `validation` outside its tests, as a dotted name."""
    paths = [p for p in sorted(root.rglob("*.py")) if p.relative_to(root).parts[0] != "tests"]
    return [".".join(("validation", *p.relative_to(root).with_suffix("").parts)).removesuffix(".__init__") for p in paths]


@pytest.mark.parametrize("name", module_names(VALIDATION))
def test_every_module_imports(name):
    importlib.import_module(name)


def test_every_package_has_a_layer():
    packages = {p.parent.name for p in VALIDATION.glob("*/*.py")} - {"tests"}
    assert packages == set(ALLOWED) - {"report"}


def test_imports_run_one_way():
    assert violations(VALIDATION) == []


def test_no_two_modules_share_a_name():
    assert shared_names(VALIDATION) == {}


def test_the_reader_sees_every_form_of_import(tmp_path):
    """A planted tree: each kind of import running the wrong way is reported,
    so an empty list above means no such import, not an unread one."""
    for package in ("shared", "checks", "bench", "longrun"):
        (tmp_path / package).mkdir()
        (tmp_path / package / "__init__.py").write_text("")
    (tmp_path / "report.py").write_text("")
    (tmp_path / "checks" / "a.py").write_text("import validation.bench.x\n")
    (tmp_path / "bench" / "a.py").write_text("def f():\n    from ..checks import y\n")
    (tmp_path / "longrun" / "b.py").write_text("from validation import checks, shared\n")
    (tmp_path / "shared" / "c.py").write_text("from validation.report import main\nfrom . import d\n")
    (tmp_path / "shared" / "d.py").write_text("from validation.shared.c import x\n")
    assert violations(tmp_path) == [
        "bench/a.py (bench) imports validation.checks",
        "checks/a.py (checks) imports validation.bench",
        "longrun/b.py (longrun) imports validation.checks",
        "shared/c.py (shared) imports validation.report",
    ]
    assert shared_names(tmp_path) == {"a.py": ["bench/a.py", "checks/a.py"]}
