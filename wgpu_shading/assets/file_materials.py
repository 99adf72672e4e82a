"""The materials that mesh files carry (OBJ/MTL, glTF) as classic Material objects."""

from __future__ import annotations

import numpy as np

from ..scene.material import Material, Texture


def _mtl_numbers(kwargs: dict, key: str, count: int) -> tuple[float, ...] | None:
    """Exact float values of an MTL key as trimesh kept them (it quantizes its own colors to 8 bits)."""
    raw = kwargs.get(key)
    if raw is None:
        return None
    values = [raw] if isinstance(raw, (int, float)) else list(raw)
    try:
        numbers = tuple(float(v) for v in values)
    except (TypeError, ValueError):
        return None
    if len(numbers) == 1 and count > 1:
        numbers = numbers * count
    return numbers[:count] if len(numbers) >= count else None


def material_from_trimesh(part: object, source: str) -> Material | None:
    """The material a mesh file carries (OBJ/MTL Ka, Kd, Ks, Ns, Ke, d, map_Kd; glTF base color).

    Returns None when the file has no material of its own.
    """
    visual = getattr(part, "visual", None)
    file_material = getattr(visual, "material", None)
    if file_material is None:
        return None
    kwargs = {k.lower(): v for k, v in (getattr(file_material, "kwargs", None) or {}).items()}
    image = getattr(file_material, "image", None)
    if image is None:
        image = getattr(file_material, "baseColorTexture", None)
    is_pbr = hasattr(file_material, "baseColorFactor")
    # trimesh invents a placeholder material (a 2×2 image, no MTL values) for any mesh with
    # UVs; only an MTL's values, an MTL's map_Kd (which records its file_path) or a glTF
    # material count as the file's own.
    image_from_file = image is not None and (is_pbr or "file_path" in getattr(image, "info", {}))
    if not kwargs and not image_from_file and not is_pbr:
        return None
    if not image_from_file:
        image = None
    texture = None
    if image is not None:
        texture = Texture(np.asarray(image.convert("RGBA")), name=f"{source}:{getattr(file_material, 'name', '')}")
    name = str(getattr(file_material, "name", "") or "")
    if is_pbr:  # glTF PBR: keep its colour, light it classically
        factor = getattr(file_material, "baseColorFactor", None)
        base = tuple(float(c) / (255.0 if np.asarray(factor).dtype.kind in "iu" else 1.0) for c in factor) if factor is not None else (1.0, 1.0, 1.0, 1.0)
        return Material(ambient=base, diffuse=base, texture=texture, name=name)
    diffuse = _mtl_numbers(kwargs, "kd", 3)
    ambient = _mtl_numbers(kwargs, "ka", 3)
    specular = _mtl_numbers(kwargs, "ks", 3)
    emission = _mtl_numbers(kwargs, "ke", 3)
    shininess = _mtl_numbers(kwargs, "ns", 1)
    dissolve = _mtl_numbers(kwargs, "d", 1)
    if diffuse is None and ambient is None and specular is None and texture is None:
        return None
    alpha = (min(max(dissolve[0], 0.0), 1.0),) if dissolve else (1.0,)
    defaults = Material()
    return Material(
        ambient=(ambient + alpha) if ambient else defaults.ambient,
        diffuse=(diffuse + alpha) if diffuse else (defaults.diffuse[:3] + alpha),
        specular=(specular + alpha) if specular else defaults.specular,
        emission=(emission + (1.0,)) if emission else defaults.emission,
        shininess=min(max(shininess[0], 0.0), 1e6) if shininess else defaults.shininess,
        texture=texture,
        name=name,
    )
