"""The architecture stays visible in the tree (docs/architecture.md): imports point only
downward through the stages, there are no import circles, and modules stay small."""

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


def _is_type_checking_block(node: ast.AST) -> bool:
    return isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test)


def _imports(path: Path) -> set[str]:
    """Every wgpu_shading module `path` imports, at module level or inside functions
    (lazy imports count), except under `if TYPE_CHECKING:` (never executed)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()

    def visit(node: ast.AST) -> None:
        for child in ast.iter_child_nodes(node):
            if _is_type_checking_block(child):
                continue
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
