"""The package's shape: layers import downwards only, no import cycle, short modules, private
implementation modules, and methods of equinox modules either abstract or final."""

import ast
import collections
import functools
import importlib
import inspect
import pathlib

import equinox as eqx
import pytest
from helpers import ROOT

# Lowest first. A subpackage imports from its own layer's packages only where listed beside it,
# and from any lower layer; the package's own `__init__` (the public face) sits above the library.
LAYERS = (
    ("numerics",),
    ("programs", "quantities"),
    ("physics",),
    ("models",),
    ("core",),
    ("applications", "topography"),
    ("bem",),
    ("<root>",),
    ("fitting",),
    ("studies",),
    ("cli",),
)
RANK = {package: rank for rank, packages in enumerate(LAYERS) for package in packages}
SIDEWAYS = {("bem", "topography")}
# Each installed package and its folder: `fitting/` installs as `jaxcontact.fitting` (pyproject's package-dir).
FOLDERS = {"jaxcontact.fitting": ROOT / "fitting", "jaxcontact": ROOT / "jaxcontact"}
MAX_LINES = 300


def _path(module: str) -> pathlib.Path:
    """Where `module` lies, without the suffix."""
    for package, folder in FOLDERS.items():
        if module == package or module.startswith(package + "."):
            return folder.joinpath(*module.split(".")[package.count(".") + 1 :])
    return ROOT.joinpath(*module.split("."))


def _modules():
    for package, folder in FOLDERS.items():
        for path in sorted(folder.rglob("*.py")):
            if package == "jaxcontact" and path.is_relative_to(FOLDERS["jaxcontact.fitting"]):
                continue
            parts = [*package.split("."), *path.relative_to(folder).with_suffix("").parts]
            is_package = parts[-1] == "__init__"
            if is_package:
                parts = parts[:-1]
            yield ".".join(parts), path, is_package


def _imports(name: str, path: pathlib.Path, is_package: bool) -> set[str]:
    """The modules of PACKAGES that `name` imports (a `from package import module` counts as the module)."""
    package = name if is_package else name.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            target = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                is_module = _path(sub).with_suffix(".py").exists() or _path(sub).is_dir()
                found.add(sub if is_module else target)
        elif isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
    return {m for m in found if m.split(".")[0] == "jaxcontact"}


MODULES = {name: (path, is_package) for name, path, is_package in _modules()}


@functools.cache
def _graph() -> dict[str, set[str]]:
    """Each module's imports of jaxcontact modules, parsed when a test first asks (both workers
    import every test module; one of them runs these tests)."""
    return {name: _imports(name, path, is_package) for name, (path, is_package) in MODULES.items()}


def _layer(module: str) -> str | None:
    parts = module.split(".")
    if parts[0] != "jaxcontact":
        return None
    return parts[1] if len(parts) > 1 else "<root>"


def test_every_import_goes_to_a_lower_layer():
    upward = []
    for module, targets in _graph().items():
        source = _layer(module)
        for target in targets:
            into = _layer(target)
            if source is None or into is None or source == into or (source, into) in SIDEWAYS:
                continue
            if RANK[into] >= RANK[source]:
                upward.append(f"{module} -> {target}")
    assert upward == []


def test_there_is_no_import_cycle():
    """Between modules (a package's `__init__` counted as a module of its own)."""
    state, cycles = {}, []

    def visit(node, stack):
        state[node] = "open"
        for target in sorted(_graph().get(node, ())):
            if state.get(target) == "open":
                cycles.append(" -> ".join(stack[stack.index(target) :] + [target]))
            elif target not in state:
                visit(target, stack + [target])
        state[node] = "done"

    for module in sorted(_graph()):
        if module not in state:
            visit(module, [module])
    # A package's __init__ re-exporting its own modules is not a cycle unless a module imports it back.
    assert [c for c in cycles if not _only_reexports(c)] == []


def _only_reexports(cycle: str) -> bool:
    steps = cycle.split(" -> ")
    return all(MODULES.get(a, (None, False))[1] and b.startswith(a + ".") for a, b in zip(steps, steps[1:]))


def test_every_module_is_short():
    long = {name: n for name, (path, _) in MODULES.items() if (n := len(path.read_text().splitlines())) > MAX_LINES}
    assert long == {}


def test_implementation_modules_are_private():
    """Every module below a subpackage is `_`-prefixed; its package's `__init__` is its public face."""
    public = [
        name
        for name, (_, is_package) in MODULES.items()
        if not is_package and name.count(".") >= 1 and not name.rsplit(".", 1)[1].startswith("_")
    ]
    assert public == []


def _module_classes():
    for name in MODULES:
        if name.startswith("jaxcontact") and not name.startswith(("jaxcontact.cli", "jaxcontact.studies")):
            module = importlib.import_module(name)
            for cls in vars(module).values():
                if inspect.isclass(cls) and issubclass(cls, eqx.Module) and cls.__module__ == name:
                    yield cls


@pytest.mark.parametrize("cls", sorted(set(_module_classes()), key=lambda c: c.__qualname__), ids=lambda c: c.__name__)
def test_methods_are_abstract_or_final(cls):
    """equinox's rule: a concrete method of a base is never overridden (it is final), and a
    method meant to be replaced is abstract."""
    overridden = collections.defaultdict(list)
    for base in cls.__mro__[1:]:
        if not (issubclass(base, eqx.Module) and base.__module__.startswith("jaxcontact")):
            continue
        for attribute, value in vars(base).items():
            if attribute.startswith("__") or not callable(value) or getattr(value, "__isabstractmethod__", False):
                continue
            mine = vars(cls).get(attribute)
            if mine is not None and mine is not value:
                overridden[attribute].append(base.__qualname__)
    assert dict(overridden) == {}


def test_the_toy_model_is_written_with_exported_names_only():
    """docs/adding-a-model.md's promise: a new model needs nothing beyond `import jaxcontact`."""
    imported = _imports("toy_model", ROOT / "tests" / "toy_model.py", False)
    assert imported == {"jaxcontact"}


def test_fitting_uses_the_public_faces_only():
    private = sorted(
        t
        for m, ts in _graph().items()
        if m.startswith("jaxcontact.fitting")
        for t in ts
        if "._" in t and not t.startswith("jaxcontact.fitting")
    )
    assert private == []


def test_the_readmes_api_example_uses_no_undefined_name(tmp_path):
    """The README's Python block runs as pasted (from the project's folder): ruff finds no name in it
    that the block does not define or import."""
    import re
    import subprocess
    import sys

    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    path = tmp_path / "readme.py"
    path.write_text("\n".join(blocks))
    checked = subprocess.run(
        [sys.executable, "-m", "ruff", "check", "--no-cache", "--isolated", "--select", "F821", str(path)],
        capture_output=True,
        text=True,
    )
    assert checked.returncode == 0, checked.stdout


# Names of 0.4 that 0.5 moved (solve's options, the quadrature's object): no docstring or message may
# still send a user to them.
STALE_NAMES = (
    "Scene.max_steps",
    "Scene.regime_shares",
    "Scene.solver_tolerance",
    "solver_tolerance = {",
    "quadrature_nodes = {",
)


@pytest.mark.parametrize("name", STALE_NAMES)
def test_no_docstring_or_message_names_a_moved_04_name(name):
    sources = [*(ROOT / "jaxcontact").rglob("*.py"), *(ROOT / "fitting").rglob("*.py")]
    assert [str(p.relative_to(ROOT)) for p in sources if name in p.read_text()] == []


def test_the_wheel_installs_jaxcontact_alone():
    """pyproject's package list is every folder of the tree (data folders included, as setuptools
    asks), each under `jaxcontact`: no top-level `fitting` on a user's path."""
    try:
        import tomllib
    except ImportError:  # Python 3.10
        import tomli as tomllib

    listed = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"]
    folders = {
        ".".join([*package.split("."), *path.relative_to(folder).parts])
        for package, folder in FOLDERS.items()
        for path in [folder, *folder.rglob("*")]
        if path.is_dir() and path.name != "__pycache__"
    }
    assert sorted(listed) == sorted(folders)


@pytest.mark.parametrize("package", ["jaxcontact", "jaxcontact.fitting"])
def test_docs_architecture_lists_every_exported_name(package):
    import re

    text = (ROOT / "docs" / "architecture.md").read_text()
    exported = importlib.import_module(package).__all__
    assert [n for n in exported if not re.search(rf"`[^`]*\b{re.escape(n)}\b[^`]*`", text)] == []


def test_every_functools_cache_of_the_library_is_registered_for_clear_caches():
    """A cache made with `functools` directly would survive `jc.clear_caches()`: the library makes
    them with `numerics.cached`."""
    import re

    sources = [path for path, _ in MODULES.values() if path.name != "_caches.py"]
    made = [str(p.relative_to(ROOT)) for p in sources if re.search(r"functools\.(cache|lru_cache)\b", p.read_text())]
    assert made == []


def test_clear_caches_empties_every_registered_cache(monkeypatch):
    import jaxcontact as jc
    from jaxcontact.numerics import _caches

    monkeypatch.setattr(_caches, "_CLEARERS", [])
    calls = []

    @_caches.cached
    def square(x):
        calls.append(x)
        return x * x

    square(3)
    jc.clear_caches()
    square(3)
    assert calls == [3, 3]
