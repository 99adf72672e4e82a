"""What the accuracy/time study measures: its scene (a gold sphere under one positional light),
the grid `StudyConfig` of shading `Variant`s (frequency × reflection model × k_blinn, the
points `--shading auto` chooses among: render/auto_shading.py) with its checks, and the
`QUICK` grid."""

from __future__ import annotations

from dataclasses import dataclass

from ...errors import AccuracyError
from ...render.auto_shading import Variant
from ...scene import FREQUENCIES, Camera, Material, PositionalLight, Scene, SceneObject


# --------------------------------------------------------------------------- the study's scene

# A gold-like, fairly glossy material under one white positional light: the highlight
# stays just below saturation (so clamping hides no error) and is well inside the disc.
STUDY_MATERIAL = Material(
    ambient=(0.45, 0.34, 0.15, 1.0),
    diffuse=(0.45, 0.34, 0.15, 1.0),
    specular=(0.45, 0.45, 0.45, 1.0),
    shininess=80.0,
    name="study-gold",
)
STUDY_LIGHT = PositionalLight(position=(3.0, 3.0, 5.0))
STUDY_CAMERA = Camera(eye=(0.0, 0.0, 3.2), target=(0.0, 0.0, 0.0), fov_y=45.0, near=0.5, far=10.0)
STUDY_ROTATION = (25.0, 35.0, 0.0)  # no vertex or pole sits exactly under the highlight


def study_scene(mesh, size: int, variant: Variant, material: Material = STUDY_MATERIAL) -> Scene:
    """The study's scene: a unit sphere mesh at the origin, rotated, seen from z = 3.2."""
    return Scene(
        objects=(SceneObject(mesh, material, rotate=STUDY_ROTATION),),
        lights=(STUDY_LIGHT,),
        camera=STUDY_CAMERA,
        shading=variant.shading(),
        ambient=(0.2, 0.2, 0.2, 1.0),
        size=(size, size),
        background=(0.0, 0.0, 0.0, 1.0),
    )


# --------------------------------------------------------------------------- the grid

FULL_TRIANGLES = (20, 80, 320, 1_280, 5_120, 20_480, 81_920, 327_680, 1_000_000)
BLINN_KS = (1.0, 3.0, 4.0)


@dataclass(frozen=True)
class StudyConfig:
    """The grid of the study. `reflections` are (model, k_blinn) pairs; the figures use the
    first size and the `figure_triangles` (which must be in `triangles`)."""

    triangles: tuple[int, ...] = FULL_TRIANGLES
    sizes: tuple[int, ...] = (256, 512)
    frequencies: tuple[str, ...] = FREQUENCIES
    reflections: tuple[tuple[str, float], ...] = (("phong", 1.0),) + tuple(("blinn-phong", k) for k in BLINN_KS)
    frames: int = 5  # timed frames per variant at least (after one warm-up frame)
    min_seconds: float = 2.0  # more frames (up to 5 × frames) until a block has been timed this long
    same_mesh: bool = True
    figure_triangles: tuple[int, ...] = (80, 1_280, 20_480)
    figure_size: int = 256

    def __post_init__(self) -> None:
        if not self.triangles or not self.sizes or not self.frequencies or not self.reflections:
            raise AccuracyError("the study needs at least one tessellation, size, frequency and reflection")
        for n in self.triangles:
            if not 8 <= n <= 20_000_000:
                raise AccuracyError(f"triangles: {n} is outside 8..20,000,000")
        for s in self.sizes:
            if not 16 <= s <= 4096:
                raise AccuracyError(f"sizes: {s} is outside 16..4096 pixels")
        for f in self.frequencies:
            if f not in FREQUENCIES:
                raise AccuracyError(f"frequencies: unknown frequency {f!r}")
        for model, k in self.reflections:
            if model not in ("phong", "blinn-phong") or not k > 0:
                raise AccuracyError(f"reflections: bad reflection model {model!r} with k_blinn {k}")
        if self.frames < 1:
            raise AccuracyError("frames must be at least 1")
        if ("phong", 1.0) not in self.reflections:
            raise AccuracyError("reflections must include Phong reflection (the models are compared with it)")

    @property
    def variants(self) -> list[Variant]:
        return [Variant(f, model, k) for model, k in self.reflections for f in self.frequencies]

    @property
    def figure_points(self) -> tuple[int, ...]:
        return tuple(n for n in self.figure_triangles if n in self.triangles)


QUICK = StudyConfig(
    triangles=(20, 320, 5_120),
    sizes=(128,),
    reflections=(("phong", 1.0), ("blinn-phong", 4.0)),
    frames=2,
    min_seconds=0.0,
    figure_triangles=(20, 320, 5_120),
    figure_size=128,
)
