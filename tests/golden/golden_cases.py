"""The cases of the golden suite (cases.toml + scenes/), shared by test_golden.py and
benchmarks/golden_noise.py."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
SCENES = HERE / "scenes"
REFERENCES = HERE / "references"
ENVIRONMENT = REFERENCES / "ENVIRONMENT.txt"


@dataclass(frozen=True)
class Case:
    name: str
    scene: Path
    size: tuple[int, int] | None  # None: the scene file's own size

    @property
    def reference(self) -> Path:
        return REFERENCES / f"{self.name}.png"

    def load(self):
        from dataclasses import replace

        from wgpu_shading import load_scene

        scene = load_scene(self.scene)
        return scene if self.size is None else replace(scene, size=self.size)


def cases() -> list[Case]:
    manifest = tomllib.loads((HERE / "cases.toml").read_text())
    examples = manifest["examples"]
    size = tuple(examples["size"])
    found = [Case(name, ROOT / "examples" / f"{name}.toml", size) for name in examples["scenes"]]
    found += [Case(path.stem, path, None) for path in sorted(SCENES.glob("*.toml"))]
    names = [case.name for case in found]
    duplicates = {name for name in names if names.count(name) > 1}
    if duplicates:
        raise ValueError(f"golden cases with the same name: {sorted(duplicates)}")
    return found


def environment_text(device) -> str:
    """What rendered the references: adapter, Mesa/LLVM version, backend, CPU, versions."""
    import platform

    import wgpu

    import wgpu_shading

    info = device.adapter.info
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return (
        "# The references in this folder were rendered by (tests/golden/test_golden.py writes this\n"
        "# file whenever `pytest --update-golden` creates or rewrites a reference):\n"
        f"adapter: {info.get('device', '?')}\n"
        f"driver: {info.get('description', '?')}\n"
        f"backend: {info.get('backend_type', '?')} ({info.get('adapter_type', '?')})\n"
        f"cpu: {cpu} ({platform.machine()})\n"
        f"wgpu-py: {wgpu.__version__}\n"
        f"wgpu-shading: {wgpu_shading.__version__}\n"
    )
