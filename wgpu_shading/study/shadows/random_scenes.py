"""Random shadowed scenes (docs/shadows.md#random-scenes): the class of scenes the shadow
guarantees are about, not only the catalogue's examples. `random_shadow_scene(seed)` draws
one scene, the same for the same seed on every machine (numpy's PCG64 stream; with
`models=False`, or where ../shared/models is missing, a drawn model is a torus), with labels
saying which classes it belongs to, so that a run over a few hundred seeds can count what
it tried and where it failed (study/shadows/fuzz.py runs and minimises them).

What varies, each independently: a ground plane or none; 1–4 casters (UV spheres of any
tessellation, boxes, tori, zero-thickness quads, the real meshes of ../shared/models when
present) resting on the ground, floating, sunk into it, standing on another caster or
intersecting it, sometimes in a ring around a positional light, sometimes outside the
camera's view; 1–3 lights of every kind (directional at 1°–89° elevation, spot lights with
cutoffs 5°–90°, positional lights near and far, inside a ring of casters and outside);
perspective and orthographic cameras at close-up, middle and far distances, from grazing
to steep views; every shading frequency; image sizes 64–512; scene scales 1e-3 to 1e3;
objects that do not cast (`cast_shadows = false`) or do not receive (`receive_shadows =
false`). The shadow settings are the defaults (`auto`), which the guarantees are about;
`fuzz.py --map-size/--filter` override them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from ...scene import (
    Camera,
    DirectionalLight,
    Material,
    Mesh,
    PositionalLight,
    Scene,
    SceneObject,
    Shading,
    ShadowSettings,
    SpotLight,
    cube,
    plane,
    torus,
    uv_sphere,
)
from .cases import scaled_scene

SIZES = ((64, 64), (96, 96), (128, 128), (128, 96), (160, 120), (192, 192), (256, 256), (320, 240), (384, 384), (512, 512))
SIZE_WEIGHTS = (4, 4, 8, 4, 4, 4, 4, 2, 1, 1)
SHAPES = ("sphere", "low_poly_sphere", "box", "torus", "quad", "model")
PLACEMENTS = ("resting", "floating", "sunk", "on_another", "intersecting")
MODELS = ("stanford-bunny.obj", "suzanne.obj", "teapot.obj", "cow.obj", "spot.obj", "fandisk.obj")


def shared_models() -> Path | None:
    """The real meshes beside the checkout (a folder shared/models above this package), or None."""
    for parent in Path(__file__).resolve().parents:
        if (parent / "shared" / "models").is_dir():
            return parent / "shared" / "models"
    return None


@lru_cache(maxsize=len(MODELS))
def _model(name: str) -> Mesh | None:
    folder = shared_models()
    if folder is None or not (folder / name).is_file():
        return None
    from ...assets.meshes import load_mesh

    return load_mesh(folder / name)


@dataclass(frozen=True)
class RandomShadowScene:
    """A drawn scene and its classes: `labels` maps a class name (ground, shapes, placements,
    lights, elevations, camera, ...) to the value this scene has."""

    seed: int
    scene: Scene
    labels: dict

    @property
    def name(self) -> str:
        return f"random-{self.seed}"


def _material(rng: np.random.Generator, name: str) -> Material:
    diffuse = rng.uniform(0.3, 0.95, 3)
    specular = rng.uniform(0.0, 0.6) * np.ones(3) if rng.random() < 0.6 else np.zeros(3)
    emission = rng.uniform(0.0, 0.08, 3) if rng.random() < 0.2 else np.zeros(3)
    return Material(ambient=tuple(0.25 * diffuse) + (1.0,), diffuse=tuple(diffuse) + (1.0,), specular=tuple(specular) + (1.0,),
                    emission=tuple(emission) + (1.0,), shininess=float(rng.uniform(1.0, 120.0)), name=name)


def _shape(rng: np.random.Generator, shape: str, models: bool = True) -> tuple[Mesh, tuple, tuple, str]:
    """A caster about one unit across: its mesh, rotation (degrees), scale and what it is."""
    turn = tuple(float(v) for v in rng.uniform(-180.0, 180.0, 3)) if rng.random() < 0.6 else (0.0, float(rng.uniform(-180, 180)), 0.0)
    if shape == "sphere":
        slices = int(rng.integers(16, 65))
        return uv_sphere(0.5, slices, max(2, slices // 2)), turn, (1.0, 1.0, 1.0), f"sphere {slices}"
    if shape == "low_poly_sphere":
        slices = int(rng.integers(5, 14))
        return uv_sphere(0.5, slices, int(rng.integers(3, 8))), turn, (1.0, 1.0, 1.0), f"sphere {slices}"
    if shape == "box":
        sides = tuple(float(v) for v in rng.uniform(0.25, 1.2, 3))
        return cube(1.0), turn, sides, "box"
    if shape == "torus":
        minor = float(rng.uniform(0.08, 0.2))
        segments = int(rng.integers(12, 65))
        return torus(0.35, minor, segments, max(6, segments // 2)), turn, (1.0, 1.0, 1.0), "torus"
    if shape == "quad":
        return plane(float(rng.uniform(0.5, 1.3))), tuple(float(v) for v in rng.uniform(-180.0, 180.0, 3)), (1.0, 1.0, 1.0), "quad"
    names = [name for name in MODELS if models and _model(name) is not None]
    if not names:
        return _shape(rng, "torus")
    name = names[int(rng.integers(len(names)))]
    mesh = _model(name)
    lower, upper = mesh.bounds()
    size = 1.0 / float(np.max(upper - lower))
    return mesh, turn, (size, size, size), "model:" + name.removesuffix(".obj")


def _world_y(mesh: Mesh, rotate: tuple, scale: tuple) -> tuple[float, float, np.ndarray]:
    """The lowest and highest world y of the mesh turned and scaled about the origin, and its horizontal centre."""
    points = SceneObject(mesh, rotate=rotate, scale=scale).world_from_model()
    world = mesh.positions.astype(np.float64) @ points[:3, :3].T + points[:3, 3]
    middle = (world.min(axis=0) + world.max(axis=0)) / 2.0
    return float(world[:, 1].min()), float(world[:, 1].max()), middle


def _casters(rng: np.random.Generator, ground: bool, ring: bool, models: bool) -> tuple[list[SceneObject], list[str], list[str]]:
    count = int(rng.integers(3, 6)) if ring else int(rng.integers(1, 5))
    objects, shapes, placements = [], [], []
    tops: list[tuple[np.ndarray, float]] = []  # each caster's horizontal centre and top
    for k in range(count):
        shape = SHAPES[int(rng.choice(len(SHAPES), p=(0.22, 0.12, 0.22, 0.18, 0.12, 0.14)))]
        mesh, rotate, scale, what = _shape(rng, shape, models)
        low, high, middle = _world_y(mesh, rotate, scale)
        if ring:
            angle = 2.0 * math.pi * (k + rng.uniform(-0.2, 0.2)) / count
            where = rng.uniform(1.2, 2.2) * np.array([math.cos(angle), math.sin(angle)])
        else:
            where = rng.uniform(-1.5, 1.5, 2)
        options = PLACEMENTS if (ground and tops) else PLACEMENTS[:3] if ground else ("floating", "on_another", "intersecting") if tops else ("floating",)
        placement = str(rng.choice(options))
        height = high - low
        if placement == "resting":
            y = -low
        elif placement == "floating":
            y = -low + rng.uniform(0.05, 1.5) * max(height, 0.3) + (0.0 if ground else rng.uniform(-1.0, 1.0))
        elif placement == "sunk":
            y = -low - rng.uniform(0.1, 0.45) * height
        else:
            below, top = tops[int(rng.integers(len(tops)))]
            where = below + rng.uniform(-0.25, 0.25, 2)
            y = top - low if placement == "on_another" else top - low - rng.uniform(0.2, 0.5) * height
        translate = (float(where[0] - middle[0]), float(y), float(where[1] - middle[2]))
        obj = SceneObject(mesh, _material(rng, f"caster {k}"), translate=translate, rotate=rotate, scale=scale)
        objects.append(obj)
        shapes.append(what)
        placements.append(placement)
        tops.append((np.array([translate[0] + middle[0], translate[2] + middle[2]]), high + y))
    return objects, shapes, placements


def _direction(elevation: float, azimuth: float) -> np.ndarray:
    """Unit vector from the scene towards the sky at `elevation` (degrees), `azimuth` about +Y."""
    e, a = math.radians(elevation), math.radians(azimuth)
    return np.array([math.cos(e) * math.cos(a), math.sin(e), math.cos(e) * math.sin(a)])


def _elevation(rng: np.random.Generator) -> float:
    """1°–89°, a third of them grazing (below 10°)."""
    return float(rng.uniform(1.0, 10.0) if rng.random() < 0.33 else rng.uniform(10.0, 89.0))


def _light(rng: np.random.Generator, kind: str, centre: np.ndarray, ring: bool, casts: bool) -> tuple[object, str]:
    diffuse = tuple(float(v) for v in rng.uniform(0.35, 1.0, 3)) + (1.0,)
    specular = tuple(float(v) for v in rng.uniform(0.0, 1.0) * np.ones(3)) + (1.0,)
    ambient = (0.03, 0.03, 0.03, 1.0) if rng.random() < 0.3 else (0.0, 0.0, 0.0, 1.0)
    common = dict(diffuse=diffuse, specular=specular, ambient=ambient, shadows=casts)
    elevation = _elevation(rng)
    if kind == "directional":
        travel = -_direction(elevation, float(rng.uniform(0.0, 360.0)))
        return DirectionalLight(direction=tuple(travel), **common), f"directional {elevation:.0f}°"
    near = rng.random() < 0.5
    distance = float(rng.uniform(2.0, 5.0) if near else rng.uniform(12.0, 60.0))
    attenuation = (1.0, 0.0, 0.0) if rng.random() < 0.6 else (1.0, float(rng.uniform(0.0, 0.2)), float(rng.uniform(0.0, 0.05)))
    if kind == "positional" and ring:
        position = centre + np.array([rng.uniform(-0.3, 0.3), rng.uniform(0.2, 1.2), rng.uniform(-0.3, 0.3)])
        return PositionalLight(position=tuple(position), attenuation=attenuation, **common), "positional in ring"
    position = centre + distance * _direction(elevation, float(rng.uniform(0.0, 360.0)))
    if kind == "positional":
        return PositionalLight(position=tuple(position), attenuation=attenuation, **common), f"positional {'near' if near else 'far'}"
    aim = centre + rng.uniform(-1.0, 1.0, 3) * np.array([1.0, 0.3, 1.0])
    cutoff = float(rng.uniform(5.0, 90.0))
    light = SpotLight(position=tuple(position), direction=tuple(aim - position), cutoff=cutoff, exponent=float(rng.uniform(0.0, 20.0)),
                      attenuation=attenuation, **common)
    return light, f"spot {cutoff:.0f}° {'near' if near else 'far'}"


def _camera(rng: np.random.Generator, centre: np.ndarray, ground: bool, ground_size: float) -> tuple[Camera, str]:
    distance_class = str(rng.choice(("close-up", "middle", "far"), p=(0.25, 0.55, 0.2)))
    distance = float({"close-up": rng.uniform(1.2, 2.5), "middle": rng.uniform(3.5, 9.0), "far": rng.uniform(15.0, 50.0)}[distance_class])
    grazing = rng.random() < 0.2
    if grazing:
        elevation = float(rng.uniform(0.5, 6.0))
    else:
        elevation = float(rng.uniform(10.0, 85.0) if ground else rng.uniform(-60.0, 85.0))
    target = centre + rng.uniform(-0.5, 0.5, 3) * np.array([1.0, 0.5, 1.0])
    if ground:
        target[1] = max(target[1], 0.05)
    fov = float(rng.uniform(20.0, 70.0))
    if distance_class == "far":
        fov = float(rng.uniform(5.0, 20.0))
    eye = target + distance * _direction(elevation, float(rng.uniform(0.0, 360.0)))
    orthographic = rng.random() < 0.3
    far = distance + 2.0 * ground_size + 10.0
    camera = Camera(eye=tuple(eye), target=tuple(target), fov_y=fov, near=0.02 * distance, far=far)
    if orthographic:
        camera = replace(camera, projection="orthographic", ortho_height=camera.view_height())
    what = f"{'orthographic' if orthographic else 'perspective'} {distance_class}{' grazing' if grazing else ''}"
    return camera, what


def random_shadow_scene(seed: int, *, size: tuple[int, int] | None = None, models: bool = True) -> RandomShadowScene:
    """One random shadowed scene (see the module); `size` overrides the drawn image size;
    `models=False` draws no real mesh (a torus instead), so the scene does not depend on
    ../shared/models being there (the tests' fixed seeds)."""
    rng = np.random.default_rng(seed)
    ground = rng.random() < 0.8
    light_count = int(rng.integers(1, 4))
    kinds = [str(rng.choice(("directional", "spot", "positional"))) for _ in range(light_count)]
    ring = "positional" in kinds and rng.random() < 0.4
    casters, shapes, placements = _casters(rng, ground, ring, models)
    ground_size = float(rng.uniform(6.0, 80.0))
    objects = list(casters)
    if ground:
        material = Material(ambient=(0.2, 0.2, 0.2, 1.0), diffuse=(0.8, 0.78, 0.74, 1.0), name="ground")
        objects.append(SceneObject(plane(ground_size), material, rotate=(-90.0, 0.0, 0.0)))
    centre = np.mean([o.translate for o in casters], axis=0)
    casting = [rng.random() < 0.85 for _ in kinds]
    casting[int(rng.integers(len(kinds)))] = True
    lights, light_labels = zip(*(_light(rng, kind, centre, ring, casts) for kind, casts in zip(kinds, casting)))
    camera, camera_label = _camera(rng, centre, ground, ground_size)
    outside = False
    if rng.random() < 0.2:  # a caster outside the camera's view, between a light and the scene
        objects, outside = _outside_caster(rng, objects, lights, camera)
    frequency = str(rng.choice(("phong", "gouraud", "flat"), p=(0.5, 0.25, 0.25)))
    reflection = str(rng.choice(("phong", "blinn-phong")))
    drawn_size = SIZES[int(rng.choice(len(SIZES), p=np.array(SIZE_WEIGHTS) / sum(SIZE_WEIGHTS)))]
    image = size or drawn_size  # drawn either way: the rest of the scene stays the same
    objects, switched = _switched(rng, objects)
    scale = 1.0 if rng.random() < 0.4 else float(10.0 ** rng.uniform(-3.0, 3.0))
    scene = Scene(objects=tuple(objects), lights=tuple(lights), camera=camera, size=image,
                  shading=Shading(frequency=frequency, reflection=reflection),
                  shadows=ShadowSettings(), ambient=(0.1, 0.1, 0.1, 1.0))
    scene = scaled_scene(scene, scale) if scale != 1.0 else scene
    labels = {
        "ground": "ground" if ground else "no ground",
        "casters": len(casters),
        "shapes": tuple(shapes),
        "placements": tuple(placements),
        "ring": ring,
        "lights": tuple(light_labels),
        "casting": tuple(casting),
        "camera": camera_label,
        "caster outside view": outside,
        "frequency": frequency,
        "size": f"{image[0]}x{image[1]}",
        "switched off": switched,
        "scale": f"{scale:.3g}",
    }
    return RandomShadowScene(seed, scene, labels)


def _switched(rng: np.random.Generator, objects: list) -> tuple[list, tuple[str, ...]]:
    """Sometimes an object that does not cast or does not receive (never both: it would be
    an object shadows have nothing to do with); what was switched, as labels."""
    if rng.random() >= 0.3:
        return objects, ()
    index = int(rng.integers(len(objects)))
    key = str(rng.choice(("cast_shadows", "receive_shadows")))
    objects = list(objects)
    objects[index] = replace(objects[index], **{key: False})
    return objects, (f"{key}=false ({objects[index].material.name})",)


def _outside_caster(rng: np.random.Generator, objects: list, lights: tuple, camera: Camera) -> tuple[list, bool]:
    """A sphere or box placed towards a light from the target, beyond the camera's view."""
    from ...render.passes.visible_regions import camera_frustum, clipped_box, world_box

    light = lights[int(rng.integers(len(lights)))]
    target = np.asarray(camera.target)
    towards = -np.asarray(light.direction) if isinstance(light, DirectionalLight) else np.asarray(light.position) - target
    reach = float(np.linalg.norm(towards))
    towards = towards / reach
    frustum = camera_frustum(Scene(objects=tuple(objects), camera=camera, size=(64, 64)))
    mesh = uv_sphere(0.4, 24, 12) if rng.random() < 0.5 else cube(0.7)
    for step in np.linspace(0.5, 12.0, 24):
        if not isinstance(light, DirectionalLight) and step > 0.9 * reach:
            break
        where = target + step * towards
        obj = SceneObject(mesh, _material(rng, "outside"), translate=tuple(where))
        if len(clipped_box(world_box(obj), frustum)) == 0:
            return objects + [obj], True
    return objects, False
