"""MTL material libraries → classic Materials (the conventions are in docs/real-world-files.md).

- Ka, Kd, Ks, Ke, Ns map one to one onto OpenGL's ambient, diffuse, specular, emission,
  shininess (Ka absent: OpenGL's default 0.2 ambient; Kd absent: 0.8, or 1 under a map_Kd).
- `Ns 0` (or absent) with a non-zero Ks: no highlight. x^0 = 1 would light every lit
  point with Ks (a white blow-out); Blender's importer maps Ns 0 to roughness 1 (matte)
  and f3d ignores Ks, so the file's author saw no highlight. `illum 0` / `illum 1` (no
  specular by the MTL definition) also drop Ks.
- `d` (dissolve) is the alpha; without `d`, `Tr` (transparency) gives alpha 1 − Tr.
  Alpha below 1 makes the material blend (docs/conventions.md#the-lighting-equation). `Tr 1` without `d` is read as
  opaque, with a warning: MeshLab (VCG) writes `Tr 1.000000` into every MTL it exports,
  meaning the alpha, and 1 − Tr would make those files invisible; f3d shows them opaque.
  An explicit `d 0` is kept (the author asked for it) but warned about: nothing is drawn.
- `map_Kd`: options (-s, -o, -bm, ...) are skipped and the rest of the line is the file
  name, spaces included. A missing image is a warning naming it; the part is untextured.
- Maps (scene/maps.py): `map_Ks` specular, `map_Ns` shininess, `map_Ke` emissive, `map_d`
  alpha (its alpha channel, else its luminance; the material blends), `norm` a tangent-space
  normal map, `map_Bump`/`bump` by what the image is (`classify_bump_image`): a normal map,
  a height map (bump map), or neither (a colour photo: ignored with a warning). `-bm` is
  the normal scale or bump depth. Ks / Ke absent under their map: 1 (like Kd under map_Kd).
"""

from __future__ import annotations

import warnings
from pathlib import Path


from ...errors import MeshError, SceneError
from ...scene.maps import alpha_pixels, classify_bump_image
from ...scene.material import Material, Texture
from ..textures import load_texture

# MTL map statements → the Material field they fill (bump maps are classified first).
_MAP_KEYS = {"map_ks": "specular_map", "map_ns": "shininess_map", "map_ke": "emissive_map", "map_d": "alpha_map",
             "norm": "normal_map", "map_bump": "bump", "bump": "bump"}

# map_* options and how many values follow each (-o/-s/-t take 1 to 3 numbers);
# -colorspace is a newer exporter extension (tinyobjloader issue 184).
_OPTION_VALUES = {"-colorspace": 1, "-blendu": 1, "-blendv": 1, "-cc": 1, "-clamp": 1, "-texres": 1, "-bm": 1, "-boost": 1,
                  "-imfchan": 1, "-type": 1, "-mm": 2, "-o": 3, "-s": 3, "-t": 3}


def _map_file(tokens: list[str]) -> str:
    index = 0
    while index < len(tokens) and tokens[index].lower() in _OPTION_VALUES:
        count = _OPTION_VALUES[tokens[index].lower()]
        index += 1
        taken = 0
        while taken < count and index < len(tokens):
            try:
                float(tokens[index])
            except ValueError:
                if count == 1:  # -blendu on, -imfchan r, -type sphere
                    index += 1
                break
            index += 1
            taken += 1
    return " ".join(tokens[index:])


def _bump_multiplier(tokens: list[str]) -> float:
    """The `-bm` value of a map statement (1 when absent or malformed)."""
    lowered = [token.lower() for token in tokens]
    if "-bm" in lowered:
        try:
            return float(tokens[lowered.index("-bm") + 1])
        except (IndexError, ValueError):
            pass
    return 1.0


def _load_map(fields: dict, key: str, base: Path, name: str, where: str) -> Texture | None:
    """The image a map statement names, or None with a warning when it cannot be read."""
    file_name = fields[key][0]
    image_path = base / file_name.replace("\\", "/")
    if not image_path.is_file():
        warnings.warn(f"{where}: material {name!r}: {key} image {file_name!r} not found (looked for {image_path}); ignored", stacklevel=3)
        return None
    try:
        return load_texture(image_path)
    except SceneError as error:
        warnings.warn(f"{where}: material {name!r}: {key}: {error}; ignored", stacklevel=3)
        return None


def _maps(fields: dict, base: Path, name: str, where: str) -> dict:
    """Material map fields from the MTL's map statements (module docstring)."""
    found: dict = {}
    for key, field in _MAP_KEYS.items():
        if key not in fields or field in found or (field == "bump" and "bump_map" in found):
            continue
        texture = _load_map(fields, key, base, name, where)
        if texture is None:
            continue
        multiplier = fields[key][1]
        if field == "bump":
            kind = classify_bump_image(texture.pixels)
            if kind == "other":
                warnings.warn(f"{where}: material {name!r}: {key} image {fields[key][0]!r} is neither a height map (grey) "
                              "nor a tangent-space normal map (bluish); ignored", stacklevel=2)
                continue
            field = "bump_map" if kind == "height" else "normal_map"
            if field in found:
                continue
        if field == "alpha_map":
            texture = Texture(alpha_pixels(texture.pixels), name=texture.name, encoding="linear")
        found[field] = texture
        if field == "normal_map":
            found["normal_scale"] = multiplier
        elif field == "bump_map":
            found["bump_scale"] = multiplier
    return found


def _numbers(tokens: list[str], where: str, count: int) -> tuple[float, ...]:
    try:
        values = [float(t) for t in tokens]
    except ValueError:
        raise MeshError(f"{where}: expected numbers, got {' '.join(tokens)!r}") from None
    if not values:
        raise MeshError(f"{where}: expected {count} number(s)")
    if len(values) == 1 and count == 3:
        values *= 3
    return tuple(values[:count])


def _material(name: str, fields: dict, base: Path, where: str) -> Material:
    texture = None
    if "map_kd" in fields:
        file_name = fields["map_kd"]
        image_path = base / file_name.replace("\\", "/")
        if image_path.exists():
            texture = load_texture(image_path)
        else:
            warnings.warn(f"{where}: material {name!r}: texture {file_name!r} not found (looked for {image_path}); drawn untextured", stacklevel=2)
    dissolve = fields.get("d")
    if dissolve is None and "tr" in fields:
        dissolve = 1.0 - fields["tr"]
        if dissolve <= 0.0:  # MeshLab's `Tr 1` means opaque, see the module docstring
            warnings.warn(f"{where}: material {name!r}: 'Tr {fields['tr']:g}' without 'd' would make it invisible; "
                          "read as opaque (MeshLab writes Tr 1 for opaque materials)", stacklevel=2)
            dissolve = 1.0
    elif dissolve is not None and dissolve <= 0.0:
        warnings.warn(f"{where}: material {name!r}: 'd {dissolve:g}' makes it fully transparent; its faces draw nothing", stacklevel=2)
    maps = _maps(fields, base, name, where)
    alpha = min(max(dissolve, 0.0), 1.0) if dissolve is not None else 1.0
    diffuse = fields.get("kd", (1.0, 1.0, 1.0) if texture is not None else (0.8, 0.8, 0.8))
    ambient = fields.get("ka", (0.2, 0.2, 0.2))
    specular = fields.get("ks", (1.0, 1.0, 1.0) if "specular_map" in maps else (0.0, 0.0, 0.0))
    shininess = fields.get("ns", 0.0)
    if shininess <= 0.0 or fields.get("illum", 2) in (0, 1):
        specular = (0.0, 0.0, 0.0)  # Ns 0 (or illum 0/1): no highlight, see the module docstring
    return Material(
        ambient=tuple(max(c, 0.0) for c in ambient) + (alpha,),
        diffuse=tuple(max(c, 0.0) for c in diffuse) + (alpha,),
        specular=tuple(max(c, 0.0) for c in specular) + (alpha,),
        emission=tuple(max(c, 0.0) for c in fields.get("ke", (1.0, 1.0, 1.0) if "emissive_map" in maps else (0.0, 0.0, 0.0))) + (1.0,),
        shininess=min(max(shininess, 0.0), 1e6),
        texture=texture,
        name=name,
        alpha_mode="blend" if alpha < 1.0 or "alpha_map" in maps else "opaque",
        **maps,
    )


def read_mtl(path: Path) -> dict[str, Material]:
    materials: dict[str, Material] = {}
    current: str | None = None
    fields: dict = {}
    text = path.read_text(encoding="utf-8-sig", errors="replace")  # -sig: a BOM would hide the first newmtl
    start_line = 0

    def finish() -> None:
        if current is not None:
            materials[current] = _material(current, fields, path.parent, f"{path}:{start_line}")

    for number, raw in enumerate(text.splitlines(), start=1):
        tokens = raw.split()
        if not tokens or tokens[0].startswith("#"):
            continue
        key = tokens[0].lower()
        where = f"{path}:{number}"
        if key == "newmtl":
            finish()
            current, fields, start_line = " ".join(tokens[1:]), {}, number
        elif key in ("ka", "kd", "ks", "ke"):
            if len(tokens) > 1 and tokens[1].lower() in ("spectral", "xyz"):
                continue  # rare CIE/spectral forms: keep the defaults
            fields[key] = _numbers(tokens[1:], where, 3)
        elif key in ("ns", "d", "tr"):
            fields[key] = _numbers(tokens[1:], where, 1)[0]
        elif key == "illum":
            fields[key] = int(_numbers(tokens[1:], where, 1)[0])
        elif key == "map_kd":
            fields[key] = _map_file(tokens[1:])
        elif key in _MAP_KEYS and len(tokens) > 1:
            fields[key] = (_map_file(tokens[1:]), _bump_multiplier(tokens[1:]))
    finish()
    return materials


def read_mtl_files(libraries: list[str], base: Path, obj_name: str) -> dict[str, Material]:
    """Every `mtllib` of an OBJ (a missing library is a warning: parts get no material)."""
    materials: dict[str, Material] = {}
    # `mtllib a.mtl b.mtl` names several libraries (the MTL spec); a name with spaces that
    # exists as a whole is one file.
    libraries = [name for library in libraries
                 for name in ([library] if (base / library).exists() or len(library.split()) == 1 else library.split())]
    for library in libraries:
        path = base / library
        if not path.is_file():  # missing, a folder, a dangling or looping link
            warnings.warn(f"{obj_name}: material library {library!r} not found (looked for {path}); parts drawn without it", stacklevel=2)
            continue
        try:
            materials.update(read_mtl(path))
        except OSError as error:  # permissions, I/O errors: a sentence naming both files
            raise MeshError(f"{obj_name}: material library {library!r} cannot be read ({error.strerror or error})") from None
    return materials
