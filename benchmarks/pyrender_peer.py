"""pyrender as a peer: what most dataset code uses for offscreen colour and depth.

pyrender (`pyrender-maintained` on PyPI, the maintained fork of pyrender 0.1.45) draws
through PyOpenGL; headless it needs OSMesa (`apt install libosmesa6`) and
`PYOPENGL_PLATFORM=osmesa`, which this module sets unless the caller chose a platform
before. `OffscreenRenderer.render()` returns the colour image and the linear eye depth: the
dataset case, timed against our `render_frame(depth=True)` (benchmarks/depth.py) and as a
mode of the dataset benchmark (benchmarks/dataset.py).

pyrender shades with its own metallic-roughness shader, not Phong, so its image is not
compared pixel for pixel with ours; it draws the same triangles through the same camera,
so the same pixels are covered (tests/test_benchmarks.py checks that on a small case).
"""

from __future__ import annotations

import math
import os

import numpy as np

from wgpu_shading import Renderer, Scene

from .peers import Peer, note_other_gl_context


def _pyrender():
    os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
    import pyrender

    return pyrender


def pyrender_unusable() -> str | None:
    """None when pyrender can render offscreen here, else why not (one line)."""
    try:
        pyrender = _pyrender()
        note_other_gl_context()
        renderer = pyrender.OffscreenRenderer(8, 8)
        renderer.delete()
    except Exception as error:  # not installed, no OSMesa, PyOpenGL platform errors
        text = str(error).splitlines()[0] if str(error) else ""
        return f"{type(error).__name__}: {text}".rstrip(": ")
    return None


def _look_along(direction) -> np.ndarray:
    """A pose whose −z axis points along `direction` (pyrender's lights shine along −z)."""
    forward = -np.asarray(direction, np.float64)
    forward /= np.linalg.norm(forward)
    helper = np.array([0.0, 1.0, 0.0]) if abs(forward[1]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(helper, forward)
    right /= np.linalg.norm(right)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2] = right, np.cross(forward, right), forward
    return pose


class PyrenderScenes:
    """Our Scenes drawn by pyrender: one pyrender mesh per Mesh (kept between calls, like our
    upload cache), camera and lights replaced per call, one OffscreenRenderer per size."""

    def __init__(self):
        self.pyrender = _pyrender()
        note_other_gl_context()
        self._meshes: dict[int, object] = {}
        self._renderers: dict[tuple[int, int], object] = {}
        self._scene = None
        self._key: tuple = ()

    def _mesh(self, obj) -> object:
        pyrender = self.pyrender
        if id(obj.mesh) not in self._meshes:
            material = obj.material or obj.mesh.parts[0].material
            color = material.diffuse if material is not None else (0.8, 0.8, 0.8, 1.0)
            primitive = pyrender.Primitive(
                positions=obj.mesh.positions, normals=obj.mesh.normals, indices=obj.mesh.indices,
                material=pyrender.MetallicRoughnessMaterial(baseColorFactor=np.asarray(color), metallicFactor=0.0, roughnessFactor=0.5),
            )
            self._meshes[id(obj.mesh)] = pyrender.Mesh([primitive])
        return self._meshes[id(obj.mesh)]

    def render(self, scene: Scene, flags: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """Colour (RGB8) and eye depth (float32, 0 where nothing was drawn); `flags`:
        pyrender.RenderFlags (its shadows, benchmarks/shadows.py)."""
        pyrender = self.pyrender
        key = tuple((id(obj.mesh), obj.world_from_model().tobytes()) for obj in scene.objects)
        if key != self._key:  # other meshes or poses: a new pyrender scene (the meshes are kept)
            self._scene = pyrender.Scene(bg_color=(0.0, 0.0, 0.0, 1.0))
            for obj in scene.objects:
                self._scene.add(self._mesh(obj), pose=obj.world_from_model())
            self._key = key
        target = self._scene
        for node in list(target.camera_nodes) + list(target.light_nodes):
            target.remove_node(node)
        target.ambient_light = np.asarray(scene.ambient[:3])
        camera = scene.camera
        width, height = scene.size
        if camera.projection == "orthographic":
            half = camera.view_height() / 2.0
            lens = pyrender.OrthographicCamera(xmag=half * width / height, ymag=half, znear=camera.near, zfar=camera.far)
        else:
            lens = pyrender.PerspectiveCamera(
                yfov=math.radians(camera.fov_y), znear=camera.near, zfar=camera.far, aspectRatio=width / height
            )
        target.add(lens, pose=np.linalg.inv(camera.eye_from_world()))
        for light in scene.lights:
            color = np.asarray(light.diffuse[:3])
            if light.kind == "directional":
                target.add(pyrender.DirectionalLight(color=color, intensity=1.0), pose=_look_along(light.direction))
                continue
            pose = _look_along(getattr(light, "direction", (0.0, 0.0, -1.0)))
            pose[:3, 3] = light.position
            # pyrender's lights fall off with 1/d²: scaled by the squared distance to the
            # camera target, the surface is about as bright as under OpenGL's unattenuated light.
            intensity = 4.0 * math.pi * float(np.sum((np.asarray(light.position) - camera.target) ** 2))
            if light.kind == "spot":
                target.add(pyrender.SpotLight(color=color, intensity=intensity, outerConeAngle=math.radians(light.cutoff)), pose=pose)
            else:
                target.add(pyrender.PointLight(color=color, intensity=intensity), pose=pose)
        if (width, height) not in self._renderers:
            self._renderers[width, height] = pyrender.OffscreenRenderer(width, height)
        return self._renderers[width, height].render(target, flags=flags)

    def close(self) -> None:
        for renderer in self._renderers.values():
            renderer.delete()
        self._renderers.clear()


class PyrenderPeer(Peer):
    """pyrender's OffscreenRenderer: colour and depth per frame."""

    name = "pyrender"

    def __init__(self, scene: Scene):
        self.scene = scene
        self.scenes = PyrenderScenes()
        self.depth: np.ndarray | None = None

    def render(self) -> np.ndarray:
        color, self.depth = self.scenes.render(self.scene)
        return color

    def close(self) -> None:
        self.scenes.close()


class WgpuShadingDepthPeer(Peer):
    """Our colour + eye-space depth, the same product as pyrender's render()."""

    name = "wgpu-shading + depth"

    def __init__(self, scene: Scene, renderer: Renderer):
        self.scene = scene
        self.renderer = renderer
        self.depth: np.ndarray | None = None

    def render(self) -> np.ndarray:
        frame = self.renderer.render_frame(self.scene, depth=True)
        self.depth = frame.depth
        return frame.color
