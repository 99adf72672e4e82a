"""Fuzz test (hypothesis): scene files, mesh files and command lines, valid and hostile.

Every input must end in one of two ways: accepted, and then rendered to finite values with
no blank picture where the float64 reference sees the object; or refused with a
WgpuShadingError whose message is one short line (the CLI: exit 2, that line, no
traceback). Anything else (another exception, exit 3, a traceback, NaN, a blank image) is
a failure that hypothesis shrinks to a minimal input.

The suite runs a fast profile (FAST_EXAMPLES per test, derandomized: a few seconds).
`./run fuzz` runs the long one: WGPU_SHADING_FUZZ_EXAMPLES per test (default 3,400: over
10,000 in all), random seeds, and a JSON report (WGPU_SHADING_FUZZ_REPORT) with the counts
that docs/reliability.md quotes.
"""

from __future__ import annotations

import io
import json
import math
import os
from collections import Counter
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from wgpu_shading import WgpuShadingError, load_mesh, load_scene
from wgpu_shading.assets.mesh_scene import mesh_scene
from wgpu_shading.cli.main import main
from wgpu_shading.study.reference import render_reference

FAST_EXAMPLES = 12
LONG = "WGPU_SHADING_FUZZ_EXAMPLES" in os.environ
EXAMPLES = int(os.environ.get("WGPU_SHADING_FUZZ_EXAMPLES", FAST_EXAMPLES))
FUZZ = settings(
    max_examples=EXAMPLES,
    deadline=None,
    derandomize=not LONG,
    database=None,
    suppress_health_check=list(HealthCheck),
    print_blob=True,
)
EXAMPLES_DIR = Path(__file__).resolve().parent.parent / "examples"
SIZE = (32, 24)

STATS: Counter = Counter()


@pytest.fixture(scope="module", autouse=True)
def report():
    yield
    path = os.environ.get("WGPU_SHADING_FUZZ_REPORT")
    if path:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        Path(path).write_text(json.dumps(dict(sorted(STATS.items())), indent=2) + "\n")


# --------------------------------------------------------------------------- values


def _finite(low: float, high: float):
    return st.floats(low, high, allow_nan=False, allow_infinity=False)


text = st.text(st.characters(blacklist_categories=("Cs",)), max_size=12)  # TOML cannot hold lone surrogates
hostile_scalar = st.one_of(
    st.floats(),  # nan, inf, 1e308, -0.0, subnormals
    st.sampled_from([1e39, -1e39, 1e-39, 1e-300, 1e300, 3.5e38, 1e15, 1e16, 0.0, -1.0, 2.0]),
    st.integers(-(10**30), 10**30),
    st.booleans(),
    text,
)
hostile_value = st.recursive(
    hostile_scalar,
    lambda children: st.one_of(st.lists(children, max_size=5), st.dictionaries(text, children, max_size=3)),
    max_leaves=12,
)


def rarely(probability: float):
    """True with about this probability. (The window sits mid-range: hypothesis draws the
    ends of an integer range far more often than the middle.)"""
    return st.integers(0, 999).map(lambda n: 300 <= n < 300 + 1000 * probability)


def maybe(good, hostile=hostile_value, p_hostile: float = 0.04):
    """Mostly a valid value, sometimes anything at all (a scene has a dozen such values,
    so about a third of the documents hold at least one hostile value)."""
    return rarely(p_hostile).flatmap(lambda bad: hostile if bad else good)


def vec3(low: float, high: float):
    return st.tuples(_finite(low, high), _finite(low, high), _finite(low, high)).map(list)


def color(high: float = 1.0):
    return st.one_of(vec3(0.0, high), st.tuples(_finite(0, high), _finite(0, high), _finite(0, high), _finite(0, 1)).map(list))


good_builtin = st.sampled_from(
    ["builtin:sphere?slices=10&stacks=6", "builtin:torus?segments=10", "builtin:cube", "builtin:plane", "builtin:sphere?radius=0.7&slices=8&stacks=5"]
)
hostile_builtin = st.builds(
        lambda name, key, value: f"builtin:{name}?{key}={value}",
        st.sampled_from(["sphere", "torus", "cube", "plane", "cone", ""]),
        st.sampled_from(["slices", "stacks", "radius", "size", "segments", "rings", "major", "minor", "subdivisions", "x"]),
    st.one_of(st.integers(-10, 10**7).map(str), st.floats().map(repr), text),
)
builtin_mesh = maybe(good_builtin, hostile_builtin, p_hostile=0.1)


@st.composite
def light(draw):
    kind = draw(st.sampled_from(["directional", "positional", "spot"]))
    table = {"type": draw(maybe(st.just(kind), p_hostile=0.05))}
    if kind != "positional":
        table["direction"] = draw(maybe(vec3(-1, 1).filter(lambda v: math.hypot(*v) > 1e-3)))
    if kind != "directional":
        table["position"] = draw(maybe(vec3(-6, 6)))
        if draw(st.booleans()):
            table["attenuation"] = draw(maybe(vec3(0, 1)))
    if kind == "spot":
        table["cutoff"] = draw(maybe(_finite(0, 90)))
        table["exponent"] = draw(maybe(_finite(0, 200)))
    for key in ("ambient", "diffuse", "specular"):
        if draw(st.booleans()):
            table[key] = draw(maybe(color(3.0)))
    if draw(rarely(0.03)):
        table[draw(text.filter(bool))] = draw(hostile_value)
    return table


@st.composite
def scene_object(draw):
    table = {"mesh": draw(maybe(builtin_mesh, p_hostile=0.02))}
    material = draw(
        maybe(st.one_of(
            st.none(),
            st.sampled_from(["gold", "ruby", "pearl", "chrome", "no such material"]),
            st.fixed_dictionaries(
                {},
                optional={
                    "base": maybe(st.sampled_from(["gold", "jade", "silver"])),
                    "diffuse": maybe(color(1.0)),
                    "specular": maybe(color(1.0)),
                    "emission": maybe(color(0.5)),
                    "shininess": maybe(_finite(0, 300)),
                },
            ),
        ))
    )
    if material is not None:
        table["material"] = material
    if draw(st.booleans()):
        table["translate"] = draw(maybe(vec3(-0.5, 0.5)))
    if draw(st.booleans()):
        table["rotate"] = draw(maybe(vec3(-360, 360)))
    if draw(st.booleans()):
        table["scale"] = draw(maybe(st.one_of(vec3(0.4, 1.2), vec3(-1.2, -0.4))))
    return table


@st.composite
def scene_document(draw) -> dict:
    document: dict = {"output": {"size": list(SIZE)}}
    if draw(st.booleans()):
        document["output"]["background"] = draw(maybe(color(1.0)))
    if draw(st.booleans()):
        document["shading"] = draw(
            st.fixed_dictionaries(
                {},
                optional={
                    "frequency": maybe(st.sampled_from(["flat", "gouraud", "phong"])),
                    "reflection": maybe(st.sampled_from(["phong", "blinn-phong"])),
                    "blinn_exponent_scale": maybe(_finite(0, 4)),
                    "local_viewer": maybe(st.booleans()),
                    "two_sided": maybe(st.booleans()),
                },
            )
        )
    if draw(st.booleans()):
        document["camera"] = draw(
            st.fixed_dictionaries(
                {},
                optional={
                    "eye": maybe(st.tuples(_finite(-1, 1), _finite(-1, 1), _finite(2.5, 5)).map(list)),
                    "up": maybe(vec3(-0.3, 0.3).map(lambda v: [v[0], 1.0, v[2]])),
                    "fov_y": maybe(_finite(30, 70)),
                    "near": maybe(_finite(0.01, 0.5)),
                    "far": maybe(_finite(20, 1000)),
                },
            )
        )
    if draw(st.booleans()):
        document["ambient"] = {"color": draw(maybe(color(1.0)))}
    document["lights"] = draw(st.lists(light(), max_size=3))
    document["objects"] = draw(st.lists(scene_object(), min_size=1, max_size=2))
    if draw(rarely(0.04)):  # a section of the wrong type, or an unknown one
        document[draw(st.sampled_from(["output", "camera", "lights", "objects", "extra"]))] = draw(hostile_value)
    return document


# --------------------------------------------------------------------------- TOML


def _toml_key(key: str) -> str:
    return json.dumps(key, ensure_ascii=False)


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(type(value))


def to_toml(document: dict) -> str:
    lines = []
    for key, value in document.items():
        if not isinstance(value, (dict, list)) or (isinstance(value, list) and not all(isinstance(v, dict) for v in value)):
            lines.append(f"{_toml_key(key)} = {_toml_value(value)}")
    for key, value in document.items():
        if isinstance(value, dict):
            lines.append(f"[{_toml_key(key)}]")
            lines += [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items()]
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for table in value:
                lines.append(f"[[{_toml_key(key)}]]")
                lines += [f"{_toml_key(k)} = {_toml_value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- checks


def _one_line(error: BaseException) -> str:
    message = str(error)
    assert "\n" not in message and 0 < len(message) <= 600, f"not one short line: {message[:300]!r}"
    assert "Traceback" not in message
    return message


def check_rendered(renderer, scene, what: str) -> None:
    """Finite float values in [0, 1]; where the float64 reference covers pixels well inside
    an object, the GPU covers them too (no blank image) and does not leave them black where
    the reference is lit."""
    frame = renderer.render_frame(scene, float32=True, depth=True)
    color = frame.color
    assert np.isfinite(color).all(), f"{what}: NaN or inf in the float output"
    assert color.min() >= 0.0 and color.max() <= 1.0, f"{what}: values outside [0, 1]"
    STATS["rendered"] += 1
    reference = render_reference(scene)
    inside = reference.covered & (reference.edge_margin >= 1.0)
    if not inside.any():
        STATS["rendered, reference sees no object pixel"] += 1
        return
    gpu_covered = np.isfinite(frame.depth)
    assert gpu_covered[inside].any(), f"{what}: blank image: the reference covers {inside.sum()} pixels, the GPU none"
    STATS["rendered, compared with the reference"] += 1
    missing = inside & ~gpu_covered
    assert missing.mean() <= 0.02 * max(inside.mean(), 1e-9) + 2 / inside.size, f"{what}: the GPU misses {missing.sum()} covered pixels"
    lit = inside & (reference.color[:, :, :3].max(axis=2) > 0.05)
    dark = lit & (color[:, :, :3].max(axis=2) == 0.0)
    assert dark.sum() <= max(1, 0.01 * lit.sum()), f"{what}: {dark.sum()} pixels black where the reference is lit"


# --------------------------------------------------------------------------- tests


@FUZZ
@given(document=scene_document())
def test_fuzz_scene_files(renderer, tmp_path_factory, document):
    folder = tmp_path_factory.mktemp("scene", numbered=True)
    path = folder / "scene.toml"
    path.write_text(to_toml(document), encoding="utf-8")
    STATS["scene files"] += 1
    try:
        scene = load_scene(path)
    except WgpuShadingError as error:
        message = _one_line(error)
        assert str(path) in message, f"the message does not name the file: {message}"
        STATS["scene files refused"] += 1
        if STATS["scene files refused"] % 8 == 1:  # the CLI prints the same line, exit 2
            code, err = _cli("render", str(path), "-o", str(folder / "out.png"))
            assert code == 2 and err.strip() == f"wgpu-shading: error: {message}", err
        return
    STATS["scene files accepted"] += 1
    try:
        check_rendered(renderer, scene, f"scene {to_toml(document)!r}")
    except WgpuShadingError as error:  # e.g. an adapter limit found at render time
        _one_line(error)
        STATS["scene files refused by the renderer"] += 1


number_text = st.one_of(
    _finite(-3, 3).map(lambda v: f"{v:.6g}"),
    st.sampled_from(["nan", "inf", "-inf", "1e39", "1e-39", "1e300", "-0", "0", "1e-20", "3.4e38"]),
    st.integers(-(10**12), 10**12).map(str),
    st.text(alphabet="0123456789.-+eE", max_size=10),
)


@st.composite
def mesh_file(draw) -> tuple[str, bytes]:
    suffix = draw(st.sampled_from([".obj", ".ply", ".stl", ".off"]))
    style = draw(st.sampled_from(["valid"] * 5 + ["hostile", "hostile", "garbage", "truncated"]))
    if style == "garbage":
        return suffix, draw(st.binary(max_size=400))
    if style == "hostile":
        vertices = draw(st.lists(st.tuples(number_text, number_text, number_text), min_size=0, max_size=8))
        faces = draw(st.lists(st.lists(st.integers(-3, 10), min_size=1, max_size=5), max_size=8))
    else:
        count = draw(st.integers(3, 8))
        coordinate = _finite(-1, 1).map(lambda v: f"{v:.6g}")
        vertices = draw(st.lists(st.tuples(coordinate, coordinate, coordinate), min_size=count, max_size=count))
        index = st.integers(0, count - 1)
        faces = draw(st.lists(st.lists(index, min_size=3, max_size=4), min_size=1, max_size=8))
        if suffix == ".obj":
            faces = [[i + 1 for i in face] for face in faces]  # OBJ counts from 1
    declared_vertices = draw(st.one_of(st.just(len(vertices)), st.just(len(vertices)), st.integers(0, 10**10)))
    declared_faces = draw(st.one_of(st.just(len(faces)), st.just(len(faces)), st.integers(0, 10**10)))
    comment = draw(st.sampled_from(["", "", "# café\n", "# \xff\xfe\n", "# " + "x" * 2000 + "\n"]))
    if suffix == ".obj":
        text = comment + "".join(f"v {x} {y} {z}\n" for x, y, z in vertices)
        text += "".join("f " + " ".join(str(i) for i in face) + "\n" for face in faces)
    elif suffix == ".off":
        text = f"OFF\n{comment}{declared_vertices} {declared_faces} 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in vertices)
        text += "".join(f"{len(face)} " + " ".join(str(i) for i in face) + "\n" for face in faces)
    elif suffix == ".ply":
        text = (
            f"ply\nformat ascii 1.0\n{comment.replace('#', 'comment')}element vertex {declared_vertices}\n"
            "property float x\nproperty float y\nproperty float z\n"
            f"element face {declared_faces}\nproperty list uchar int vertex_indices\nend_header\n"
        )
        text += "".join(f"{x} {y} {z}\n" for x, y, z in vertices)
        text += "".join(f"{len(face)} " + " ".join(str(i) for i in face) + "\n" for face in faces)
    else:
        text = "solid fuzz\n" + comment
        for face in faces:
            text += "facet normal 0 0 1\nouter loop\n"
            for index in face[:3]:
                x, y, z = vertices[index % len(vertices)] if vertices else ("0", "0", "0")
                text += f"vertex {x} {y} {z}\n"
            text += "endloop\nendfacet\n"
        text += "endsolid fuzz\n"
    data = text.encode("latin-1", errors="replace")
    if style == "truncated" and data:
        data = data[: draw(st.integers(0, len(data)))]
    return suffix, data


@FUZZ
@given(file=mesh_file())
def test_fuzz_mesh_files(renderer, tmp_path_factory, file):
    suffix, data = file
    path = tmp_path_factory.mktemp("mesh", numbered=True) / f"fuzz{suffix}"
    path.write_bytes(data)
    STATS["mesh files"] += 1
    # a numpy warning that would reach a user's stderr is a failure (numpy ignores underflow)
    with np.errstate(over="raise", divide="raise", invalid="raise", under="ignore"):
        try:
            load_mesh(path)
            scene = mesh_scene(str(path), SIZE, None)
        except WgpuShadingError as error:
            _one_line(error)
            STATS["mesh files refused"] += 1
            return
    STATS["mesh files accepted"] += 1
    check_rendered(renderer, scene, f"mesh {data[:200]!r}")


def _cli(*argv: str, cwd: Path | None = None) -> tuple[int, str]:
    """main(argv) in-process: exit status and stderr. In `cwd` (commands without -o write
    INPUT.png into the current folder)."""
    out, err = io.StringIO(), io.StringIO()
    previous = os.getcwd()
    if cwd is not None:
        os.chdir(cwd)
    try:
        with redirect_stdout(out), redirect_stderr(err):
            try:
                code = main(list(argv))
            except SystemExit as exit_:  # argparse's usage errors
                code = exit_.code if isinstance(exit_.code, int) else 2
    finally:
        os.chdir(previous)
    return code, err.getvalue()


@st.composite
def command_line(draw, folder: Path) -> list[str]:
    command = draw(st.sampled_from(["render", "render", "turntable", "shader", "check"]))
    source = draw(
        st.one_of(
            builtin_mesh,
            st.sampled_from([str(EXAMPLES_DIR / "gold_torus_phong.toml"), str(EXAMPLES_DIR / "two_lights.toml"), "missing.toml", "missing.obj", ""]),
            text,
        )
    )
    argv = [command, source]
    options = {
        "--size": st.one_of(st.sampled_from(["16", "16x12", "12×16"]), st.text(max_size=8), st.integers(-5, 10**6).map(str)),
        "--frequency": st.one_of(st.sampled_from(["flat", "gouraud", "phong"]), st.text(max_size=6)),
        "--reflection": st.one_of(st.sampled_from(["phong", "blinn-phong"]), st.text(max_size=6)),
        "--material": st.one_of(st.sampled_from(["gold", "jade"]), st.text(max_size=10)),
        "--blinn-exponent-scale": number_text,
    }
    if command == "turntable":
        options.update(
            {
                "--frames": st.one_of(st.integers(-3, 3).map(str), st.text(max_size=5)),
                "--degrees": number_text,
                "--fps": number_text,
                "-o": st.sampled_from(["spin.gif", "spin.png", "spin", "nodir/spin.gif"]),
            }
        )
    elif command == "render":
        options["-o"] = st.sampled_from(["out.png", "out.npy", "out.jpg", "out.gif", "nodir/out.png", "out"])
    elif command == "check":
        options["--ref"] = st.sampled_from(["ref.png", "ref.jpg", "missing/ref.png"])
    chosen = draw(st.lists(st.sampled_from(sorted(options)), unique=True, max_size=4))
    for option in chosen:
        value = draw(options[option])
        if option in ("-o", "--ref"):
            value = str(folder / value)
        argv += [option, value]
    if command in ("render", "turntable") and "--size" not in chosen:
        argv += ["--size", "16"]
    if command == "turntable" and "--frames" not in chosen:
        argv += ["--frames", "2"]
    if draw(st.booleans()):
        argv.append(draw(st.sampled_from(["--two-sided", "--infinite-viewer", "--float", "-q", "--bogus", "--update"])))
    return argv


@FUZZ
@given(data=st.data())
def test_fuzz_command_lines(renderer, tmp_path_factory, data):
    folder = tmp_path_factory.mktemp("cli", numbered=True)
    argv = data.draw(command_line(folder))
    STATS["command lines"] += 1
    code, err = _cli(*argv, cwd=folder)
    assert code in (0, 1, 2), f"exit {code} for {argv}: {err[-500:]}"
    assert "internal error" not in err and "Traceback" not in err, f"{argv}: {err[-500:]}"
    if code == 2:
        lines = err.strip().splitlines()
        assert lines, f"{argv}: exit 2 without a message"
        assert len(lines) == 1 and len(lines[0]) <= 700, f"{argv}: {err[:500]}"
        assert lines[0].startswith("wgpu-shading") and ": error: " in lines[0], f"{argv}: {err[:500]}"
        STATS["command lines refused"] += 1
    else:
        STATS["command lines accepted"] += 1
