"""The architecture stays visible in the tree (docs/architecture.md): imports point only
downward through the stages, there are no import circles (type-checking imports count:
they are the design's dependencies too), no module reaches into another module's or
object's `_private` names, and modules stay small."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "wgpu_shading"

# Stage order: a module may import its own stage or a lower one (errors.py: anyone).
STAGE_RANK = {"scene": 0, "assets": 1, "render": 2, "study": 3, "testing": 3, "dataset": 3, "live": 3, "cli": 4}
MAX_MODULE_LINES = 400


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path) -> set[str]:
    """Every wgpu_shading module `path` imports, at module level, inside functions (lazy
    imports count) and under `if TYPE_CHECKING:` (a circle only type checkers see is still
    a circle in the design)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.ImportFrom):
                if child.level:
                    base = package.split(".")
                    base = base[: len(base) - (child.level - 1)]
                    target = ".".join(base + ([child.module] if child.module else []))
                else:
                    target = child.module or ""
                if target.startswith("wgpu_shading"):
                    # `from . import x` may name a submodule: count it when it is one.
                    for alias in child.names:
                        candidate = f"{target}.{alias.name}"
                        found.add(candidate if _exists(candidate) else target)
            elif isinstance(child, ast.Import):
                found.update(a.name for a in child.names if a.name.startswith("wgpu_shading"))
            visit(child)

    visit(ast.parse(path.read_text(encoding="utf-8")))
    found.discard(name)
    return found


def _exists(module: str) -> bool:
    relative = Path(*module.split(".")[1:])
    return (PACKAGE / relative).with_suffix(".py").exists() or (PACKAGE / relative / "__init__.py").exists()


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _stage(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in STAGE_RANK else None


def test_imports_point_only_downward():
    wrong = []
    for name, path in _modules().items():
        stage = _stage(name)
        if stage is None:  # wgpu_shading/__init__ (lazy public API), errors.py
            continue
        for target in _imports(path):
            target_stage = _stage(target)
            if target_stage is None:
                if target not in ("wgpu_shading", "wgpu_shading.errors"):
                    wrong.append(f"{name} -> {target}")
                continue
            if target_stage != stage and STAGE_RANK[target_stage] >= STAGE_RANK[stage]:
                wrong.append(f"{name} ({stage}) -> {target} ({target_stage})")
    assert not wrong, "imports that point up or sideways:\n" + "\n".join(wrong)


# Inside render/ the stages are floors too (docs/architecture.md#render--the-gpu): the feature
# set and the device at the bottom, then what a shader is (shaders/), the GPU objects that
# outlive a frame (gpu/), the passes that draw a frame (passes/), and the Renderer's frame
# API on top. A module imports its own floor or a lower one.
RENDER_FLOORS = {
    "features": 0, "stroke_features": 0, "device": 0, "_prebuilt_ffi": 0, "image_error": 0, "frame_memory": 0,
    "poll_thread": 0,
    "shaders": 1,
    "gpu": 2,
    "passes": 3,
    "renderer": 4, "frames_in_flight": 4,
    "auto_shading": 5,
}


def _render_floor(module: str) -> int | None:
    parts = module.split(".")
    if len(parts) < 3 or parts[1] != "render":
        return None
    return RENDER_FLOORS[parts[2]]


def test_render_floors_point_only_downward():
    wrong = []
    for name, path in _modules().items():
        floor = _render_floor(name)
        if floor is None:
            continue
        for target in _imports(path):
            target_floor = _render_floor(target)
            if target_floor is not None and target_floor > floor:
                wrong.append(f"{name} (floor {floor}) -> {target} (floor {target_floor})")
    assert not wrong, "render/ imports that point up:\n" + "\n".join(wrong)


def test_every_render_module_has_a_floor():
    render = PACKAGE / "render"
    names = {p.stem for p in render.glob("*.py") if p.stem != "__init__"} | {p.name for p in render.iterdir() if (p / "__init__.py").exists()}
    assert names == set(RENDER_FLOORS), "give each render/ module or folder its floor in RENDER_FLOORS (docs/architecture.md)"


def test_every_subpackage_ships():
    """A folder of the package is listed in pyproject.toml's packages, or the wheel lacks it."""
    import tomllib

    listed = set(tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]["packages"])
    folders = {_module_name(p) for p in PACKAGE.rglob("__init__.py")}
    assert folders <= listed, f"add to pyproject.toml [tool.setuptools] packages: {sorted(folders - listed)}"


def test_every_shader_source_ships():
    """Every file of wgsl/ (chunks in subfolders too) matches the wheel's package-data patterns."""
    import tomllib

    root = PACKAGE.parent / "wgsl"
    patterns = tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]["package-data"]["wgpu_shading.wgsl"]
    shipped = {path for pattern in patterns for path in root.glob(pattern)}
    missing = sorted(str(p.relative_to(root)) for p in root.rglob("*.wgsl") if p not in shipped)
    assert not missing, f"add a pattern to pyproject.toml [tool.setuptools.package-data] for: {missing}"


def test_every_import_names_a_module_that_exists():
    """Lazy imports inside functions are not run by importing the package: a module that
    moved must not leave one behind (the `shader` command once imported a moved module)."""
    missing = [f"{name} -> {target}" for name, path in _modules().items() for target in _imports(path) if not _exists(target)]
    assert not missing, "imports of modules that do not exist:\n" + "\n".join(missing)


def test_no_import_cycles():
    graph = {name: {t for t in _imports(path) if t in _modules()} for name, path in _modules().items()}
    # A package's __init__ re-exports its modules: an edge module -> its own package's
    # __init__ (e.g. `from ..scene import X` inside assets) is fine unless the __init__
    # imports back, which the search below finds like any other cycle.
    state: dict[str, int] = {}
    stack: list[str] = []
    cycles: list[list[str]] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                cycles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    # wgpu_shading/__init__ loads names lazily (module __getattr__), and submodules import
    # `__version__` from it; that is not a cycle at import time.
    real = [c for c in cycles if "wgpu_shading" not in c]
    assert not real, "import cycles:\n" + "\n".join(" -> ".join(c) for c in real)


# Underscore members reached on purpose: (module, attribute) → why. Outside the package
# (benchmarks/, tests/) only what a test is about, or a library keeps nowhere else.
FOREIGN_PRIVATE_ACCESS = {
    ("wgpu_shading.assets.mesh_formats.trimesh_reader", "_cache"): "trimesh keeps the normals a file gave only in its cache",
    ("wgpu_shading.render.gpu.cluster_builds", "_register_atexit"): (
        "the standard library's only hook that runs before exit joins worker threads (concurrent.futures uses it too)"
    ),
    ("tests.test_dataset_dask", "_exit"): "os._exit is the standard library's way to die without clean-up",
    ("wgpu_shading.cli.process_end", "_exit"): "os._exit: the standard library's end of a process without Python's teardown",
    ("tests.test_doc_code", "_actions"): "argparse keeps a parser's subcommands only there",
    ("tests.test_memory", "_first_level"): "the test is about this helper: its strips equal the whole image",
    ("wgpu_shading.render.poll_thread", "_poll_func"): (
        "wgpu-py 0.32's poll thread keeps the function it polls a device with only there; the module checks it is there"
    ),
    ("tests.test_poll_thread", "_poller"): "the test counts the polls of wgpu-py's poll thread, which it keeps there",
    ("tests.test_poll_thread", "_poll_func"): "the test counts the polls of wgpu-py's poll thread, which it keeps there",
    ("benchmarks.scripts.ab_issue29", "_poller"): "poll-gap counts the polls of wgpu-py's poll thread, which it keeps there",
    ("benchmarks.scripts.ab_issue29", "_poll_func"): "poll-gap counts the polls of wgpu-py's poll thread, which it keeps there",
    ("benchmarks.scripts.ab_issue29", "_poll_wait"): (
        "the A/B is about waiting with wgpuDevicePoll on our own thread; wgpu-py exposes that poll nowhere else"
    ),
}
# Scripts and tests use the package as users do: its public names only.
OUTSIDE_PACKAGE = ("benchmarks", "tests")


def _is_private(name: str) -> bool:
    # IPython's display protocol (`_repr_png_`) is public by convention.
    return name.startswith("_") and not name.startswith("__") and not (name.startswith("_repr_") and name.endswith("_"))


def _private_reaches(path: Path, name: str | None = None) -> list[str]:
    """`from x import _y` of a package module, and `obj._y` on anything but self/cls."""
    name = name or _module_name(path)
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("wgpu_shading")):
            found += [f"{name}:{node.lineno}: imports {a.name}" for a in node.names if _is_private(a.name) and (name, a.name) not in FOREIGN_PRIVATE_ACCESS]
        elif isinstance(node, ast.Attribute) and _is_private(node.attr):
            owner = node.value
            if isinstance(owner, ast.Name) and owner.id in ("self", "cls"):
                continue
            if (name, node.attr) not in FOREIGN_PRIVATE_ACCESS:
                found.append(f"{name}:{node.lineno}: reaches {ast.unparse(node)}")
    return found


def test_no_module_reaches_into_private_names():
    """A private name is free to change with its module: nothing else may use it (make it
    public, with a name that says what it is, or move the code that needs it)."""
    reaches = [reach for path in _modules().values() for reach in _private_reaches(path)]
    assert not reaches, "private names used from outside:\n" + "\n".join(reaches)


@pytest.mark.parametrize("folder", OUTSIDE_PACKAGE)
def test_benchmarks_and_tests_use_public_names(folder):
    """Benchmarks measure what users can call; a test that needs an internal says why above."""
    root = PACKAGE.parent
    reaches = []
    for path in sorted((root / folder).rglob("*.py")):
        name = ".".join(path.relative_to(root).with_suffix("").parts)
        reaches += _private_reaches(path, name)
    assert not reaches, "private names used from outside the package:\n" + "\n".join(reaches)


def test_the_allowed_private_reaches_still_exist():
    """An entry whose reach is gone is removed, so the list stays the list of exceptions."""
    root = PACKAGE.parent
    for module, attribute in FOREIGN_PRIVATE_ACCESS:
        path = root.joinpath(*module.split(".")).with_suffix(".py")
        assert attribute in path.read_text(encoding="utf-8"), f"{module}: no {attribute} any more; drop its entry"


def test_the_private_name_check_finds_both_kinds(tmp_path, monkeypatch):
    package = tmp_path / "wgpu_shading"
    (package / "render").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "render" / "__init__.py").write_text("")
    (package / "render" / "a.py").write_text("from .b import _helper\n\ndef f(renderer):\n    return renderer._lock, self_like._x\n")
    (package / "render" / "b.py").write_text("class B:\n    def g(self):\n        return self._fine\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", package)
    reaches = [r for path in _modules().values() for r in _private_reaches(path)]
    assert reaches == [
        "wgpu_shading.render.a:1: imports _helper",
        "wgpu_shading.render.a:4: reaches renderer._lock",
        "wgpu_shading.render.a:4: reaches self_like._x",
    ]


def test_type_checking_imports_are_walked(tmp_path, monkeypatch):
    """A circle hidden under `if TYPE_CHECKING:` is found (render_many once hid one)."""
    package = tmp_path / "wgpu_shading"
    (package / "render").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "render" / "__init__.py").write_text("")
    (package / "render" / "a.py").write_text("from .b import x\n")
    (package / "render" / "b.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from .a import y\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", package)
    with pytest.raises(AssertionError, match="render.a -> wgpu_shading.render.b -> wgpu_shading.render.a"):
        test_no_import_cycles()


def test_the_checker_finds_a_cycle(tmp_path, monkeypatch):
    """The cycle search is not vacuous: two modules importing each other are reported."""
    package = tmp_path / "wgpu_shading"
    (package / "scene").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "scene" / "__init__.py").write_text("")
    (package / "scene" / "a.py").write_text("from .b import x\n")
    (package / "scene" / "b.py").write_text("def f():\n    from .a import y\n")
    monkeypatch.setattr(__import__(__name__), "PACKAGE", package)
    with pytest.raises(AssertionError, match="scene.a -> wgpu_shading.scene.b -> wgpu_shading.scene.a"):
        test_no_import_cycles()


@pytest.mark.parametrize("name", sorted(_modules()))
def test_modules_stay_small(name):
    lines = len(_modules()[name].read_text(encoding="utf-8").splitlines())
    assert lines <= MAX_MODULE_LINES, f"{name} has {lines} lines; split it by concept (at most {MAX_MODULE_LINES})"


def test_every_subpackage_is_installed():
    """pyproject.toml lists the packages a wheel holds: a new folder missing there works in a
    checkout and fails once installed."""
    import tomllib

    listed = set(tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["setuptools"]["packages"])
    folders = {_module_name(init) for init in PACKAGE.rglob("__init__.py")}
    assert folders <= listed, f"add to pyproject.toml [tool.setuptools] packages: {sorted(folders - listed)}"


def test_every_public_name_of_the_package_loads():
    """The package's names load lazily from a table of module paths: a module moved without
    its entry there fails only when a user first touches the name."""
    import wgpu_shading

    for name in wgpu_shading.__all__:
        assert getattr(wgpu_shading, name) is not None, name
