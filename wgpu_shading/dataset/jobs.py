"""Dataset jobs: plain data describing one view of one mesh or scene, and what to write.

A Job is what travels to a worker (pickled by Dask): file names, numbers and strings only,
never a Scene or a Mesh. The worker loads the mesh once per chunk of jobs and keeps the
upload on its warm Renderer; shipping Scene objects would defeat that cache (an unpickled
Mesh is a new object, uploaded again: 71 ms a task instead of 16 ms for a textured scene).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field
from typing import Any

from ..assets.image_writers import PNG_LEVEL
from ..errors import UsageError
from ..scene.view.options import VIEW_OPTIONS, ViewOptions

COLOR_FORMATS = ("png", "png16", "none")
DEPTH_FORMATS = ("none", "npy", "png16")
NORMAL_SPACES = ("none", "eye", "world")

# Where a job keeps each view option (scene/view/options.py): the image size; the camera
# under the scene file's [camera] names; the turns about the target; the rest (material,
# shading, lights, ...) under the option's name. Stable names keep the digests of rows
# written before the options were unified, so reruns still skip their finished jobs.
CAMERA_FIELDS = {
    "camera_position": "eye", "camera_focal_point": "target", "camera_view_up": "up", "camera_view_angle": "fov_y",
    "camera_near": "near", "camera_far": "far", "camera_projection": "projection", "camera_ortho_height": "ortho_height",
}
ORBIT_FIELDS = {"camera_azimuth": "azimuth", "camera_elevation": "elevation", "camera_distance": "distance"}
# The options that decide what is loaded (one mesh load and upload per distinct key).
LOAD_OPTIONS = tuple(option.name for option in VIEW_OPTIONS if option.load)

@dataclass(frozen=True)
class Outputs:
    """Which files each view gets.

    color: "png" (8-bit RGBA, the pixels of `wgpu-shading render`), "png16" (16-bit RGBA from
           the float32 target) or "none"
    depth: "npy" (float32 eye-space distance along the view axis, inf = background) or
           "png16" (16-bit gray: 0 = background, 1..65535 = near..far linearly) or "none"
    normals: "eye" or "world" (float32 (H, W, 3) .npy, unit vectors, 0 = background) or "none"
    ids: a 16-bit gray PNG: 0 = background, k = the scene's object k-1 (a segmentation mask)
    compress_level: zlib level of every PNG (0 = none .. 9 = smallest); the default is
           `render`'s (assets/image_writers.PNG_LEVEL: 1, which ISA-L encodes 10-20x faster
           than level 6, for files about a third larger).
    """

    color: str = "png"
    depth: str = "none"
    normals: str = "none"
    ids: bool = False
    compress_level: int = PNG_LEVEL

    def __post_init__(self) -> None:
        for name, value, allowed in (
            ("color", self.color, COLOR_FORMATS),
            ("depth", self.depth, DEPTH_FORMATS),
            ("normals", self.normals, NORMAL_SPACES),
        ):
            if value not in allowed:
                raise UsageError(f"outputs.{name}: expected one of {', '.join(allowed)}, got {value!r}")
        if not (isinstance(self.compress_level, int) and 0 <= self.compress_level <= 9):
            raise UsageError(f"outputs.compress_level: expected an integer 0..9, got {self.compress_level!r}")
        if self.color == "none" and self.depth == "none" and self.normals == "none" and not self.ids:
            raise UsageError("outputs: nothing to write (color, depth, normals and ids are all off)")

    def file_names(self, name: str) -> list[str]:
        """The files a view called `name` gets, in its mesh's folder."""
        files = []
        if self.color != "none":
            files.append(f"{name}.png")
        if self.depth != "none":
            files.append(f"{name}_depth.{'npy' if self.depth == 'npy' else 'png'}")
        if self.normals != "none":
            files.append(f"{name}_normals_{self.normals}.npy")
        if self.ids:
            files.append(f"{name}_ids.png")
        return files


@dataclass(frozen=True)
class Job:
    """One view of one mesh (or scene file) and the files to write for it.

    source: a mesh file, builtin:NAME, or a scene .toml (absolute path, or relative to the
            current folder of the worker)
    folder/name: outputs go to OUTPUT/folder/name*.png|npy, plus name.json (camera, row hash)
    size: (width, height); None = the scene file's size, or 512² for a mesh (like `render`)
    camera: scene-file camera keys (eye, target, up, fov_y, near, far, projection, ortho_height)
    orbit: azimuth, elevation (degrees), distance (see scene/view/apply.py place_camera)
    overrides: the other view options by name (material, frequency, lights, ...)
    Together they are the job's ViewOptions (view_options()): what `render` would be given.
    """

    id: str
    source: str
    folder: str
    name: str
    size: tuple[int, int] | None = None
    camera: dict[str, Any] = field(default_factory=dict)
    orbit: dict[str, float] = field(default_factory=dict)
    overrides: dict[str, Any] = field(default_factory=dict)
    outputs: Outputs = field(default_factory=Outputs)

    @classmethod
    def with_view(cls, options: ViewOptions, **fields: Any) -> "Job":
        """A job rendering `options` (each option stored where Job keeps it)."""
        camera, orbit, overrides = {}, {}, {}
        size = None
        for name, value in options.given().items():
            if name == "size":
                size = value
            elif name in CAMERA_FIELDS:
                camera[CAMERA_FIELDS[name]] = value
            elif name in ORBIT_FIELDS:
                orbit[ORBIT_FIELDS[name]] = value
            else:
                overrides[name] = value
        return cls(size=size, camera=camera, orbit=orbit, overrides=overrides, **fields)

    def view_options(self) -> ViewOptions:
        """The options `wgpu-shading render SOURCE` needs to draw this job's view (read once:
        checking every value costs ~0.15 ms, a small frame's tenth)."""
        cached = self.__dict__.get("_view_options")
        if cached is None:
            cached = self._read_view_options()
            object.__setattr__(self, "_view_options", cached)  # not a field: digest and == ignore it
        return cached

    def _read_view_options(self) -> ViewOptions:
        values: dict[str, Any] = dict(self.overrides)
        values.update({name: self.camera[key] for name, key in CAMERA_FIELDS.items() if key in self.camera})
        values.update({name: self.orbit[key] for name, key in ORBIT_FIELDS.items() if key in self.orbit})
        if self.size is not None:
            values["size"] = self.size
        if "infinite_viewer" in values:  # a Job made before local_viewer was its name
            values["local_viewer"] = not values.pop("infinite_viewer")
        return ViewOptions(**values)

    def load_key(self) -> tuple:
        """Jobs with the same key share one loaded base scene (one mesh load and upload)."""
        options = self.view_options()
        return (self.source, *(getattr(options, name) for name in LOAD_OPTIONS))

    def digest(self) -> str:
        """A hash of everything that decides this job's files: a rerun skips the job only
        when the stored digest matches (a changed manifest row renders again). Computed
        once (the skip check and the writer each ask; a job is frozen)."""
        cached = self.__dict__.get("_digest")
        if cached is None:
            data = asdict(self)
            data.pop("id")
            text = json.dumps(data, sort_keys=True, default=list)
            cached = hashlib.sha256(text.encode()).hexdigest()[:32]
            object.__setattr__(self, "_digest", cached)  # not a field, like _view_options
        return cached

    def files(self) -> list[str]:
        return [f"{self.folder}/{file}" for file in self.outputs.file_names(self.name)]

    def record_path(self) -> str:
        return f"{self.folder}/{self.name}.json"


def chunks(jobs: list[Job], size: int) -> list[list[Job]]:
    """Jobs grouped by what they load (one mesh load per chunk), at most `size` per chunk,
    in manifest order of each group's first job."""
    if size < 1:
        raise UsageError(f"chunk size must be at least 1, got {size}")
    groups: dict[tuple, list[Job]] = {}
    for job in jobs:
        groups.setdefault(job.load_key(), []).append(job)
    return [group[i : i + size] for group in groups.values() for i in range(0, len(group), size)]
