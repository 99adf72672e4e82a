"""The benchmarks do not rot, and the benchmark peers draw what they claim to (so the
comparisons are fair).

`python -m benchmarks --smoke` runs every benchmark once on tiny inputs (~10-20 s); the
tests below check that it ran each one and printed sensible numbers. Nothing is timed
against a target. The wgpu-based peers run everywhere; moderngl and pygfx come with the
[bench] extra only, so their tests skip without it (and the smoke run leaves them out).
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))  # the repository's benchmarks/ package

from benchmarks.peers import RawWgslPeer, WgpuShadingPeer  # noqa: E402
from benchmarks.scenes import geometry_draw, torus_scene  # noqa: E402


@pytest.fixture(scope="module")
def small_torus():
    return replace(torus_scene(512), size=(96, 96))  # square, like every benchmark image


def covered(image: np.ndarray) -> np.ndarray:
    return (image[:, :, :3] > 0).any(axis=2)


def test_raw_wgsl_peers_cover_the_same_pixels_as_the_renderer(renderer, small_torus):
    ours = WgpuShadingPeer(small_torus, renderer).render()
    draw = geometry_draw(small_torus, "torus")
    floor = RawWgslPeer(small_torus, renderer, draw, "floor").render()
    limit = RawWgslPeer(small_torus, renderer, draw, "limit").render()
    seed = RawWgslPeer(small_torus, renderer, draw, "seed").render()
    assert not covered(floor).any()  # no draw at all
    assert covered(ours).mean() > 0.1
    np.testing.assert_array_equal(covered(limit), covered(ours))
    np.testing.assert_array_equal(covered(seed), covered(ours))
    # The seed's shader, ported to WGSL, computes the same lighting as ours for this scene.
    assert np.abs(seed.astype(int) - ours.astype(int)).max() <= 2


def test_moderngl_peer_matches_the_seed_port(renderer, small_torus):
    pytest.importorskip("moderngl")
    from benchmarks.peers import ModernGLPeer

    draw = geometry_draw(small_torus, "torus")
    try:
        peer = ModernGLPeer(draw)
    except Exception as error:  # no EGL/llvmpipe OpenGL on this machine
        pytest.skip(f"no headless OpenGL: {error}")
    image = peer.render()
    peer.close()
    seed = RawWgslPeer(small_torus, renderer, draw, "seed").render()
    assert image.shape == seed.shape
    differs = np.abs(image.astype(int) - seed.astype(int)).max(axis=2) > 2
    assert differs.mean() < 0.01  # same pixels, same colors (but rasterization-edge rounding)


def test_pygfx_peer_draws_the_mesh_on_lavapipe(renderer, small_torus):
    pytest.importorskip("pygfx")
    from benchmarks.peers import PygfxPeer

    draw = geometry_draw(small_torus, "torus")
    peer = PygfxPeer(draw, lean=True)
    image = peer.render()
    peer.close()
    assert image.shape[:2] == (96, 96)
    overlap = covered(image) & covered(renderer.render(small_torus))
    assert overlap.sum() > 0.9 * covered(image).sum()  # the same silhouette, give or take edges


# --------------------------------------------------------------------------- python -m benchmarks --smoke

SMOKE_STEPS = (
    "warm", "depth", "breakdown", "cold", "batch", "memory", "scaling", "dataset", "specialization", "reference",
    "golden_noise", "gif_palette", "loading", "antialiasing", "live", "callgrind", "ab_issue21", "ab_issue29", "ab_issue29_start_up", "ab_issue29_frame_plans", "ab_issue29_turned_away", "ab_issue29_chunks", "ab_issue29_batch_parts", "ab_issue29_kept_frames", "ab_issue29_fresh_meshes", "ab_issue29_frames_in_flight", "ab_issue29_chunk_order", "ab_issue29_thread_cpu", "ab_issue29_output_folders", "ab_issue29_crease_split", "ab_issue29_encoder_threads", "ab_issue29_dask_saturation", "ab_issue29_dask_client", "ab_issue29_per_mesh", "ab_issue29_files_beside", "ab_issue29_spread_folders", "ab_issue29_poll_gap", "ab_issue29_vertex_cache", "ab_issue29_mesh_cache", "ab_issue29_mesh_cache_many", "frame_timeline", "hostile_files", "shadows",
    "report",
)


@pytest.fixture(scope="module")
def smoke() -> str:
    """The stdout of one `python -m benchmarks --smoke`, as a person runs it."""
    result = subprocess.run(
        [sys.executable, "-m", "benchmarks", "--smoke"], cwd=REPO, capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 0, f"smoke run failed:\n{result.stdout[-3000:]}\n{result.stderr[-5000:]}"
    return result.stdout


def _section(output: str, name: str) -> str:
    """What the smoke run printed for one step (between its marker and the next)."""
    start = output.index(f"<!-- smoke: {name} -->")
    end = output.find("<!-- smoke:", start + 1)
    return output[start : end if end >= 0 else len(output)]


def _tables(text: str) -> list[list[dict[str, str]]]:
    """Every markdown table in text, as rows of {column: cell}."""
    tables, block = [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|"):
            block.append([cell.strip() for cell in line.strip().strip("|").split("|")])
            continue
        if len(block) >= 2:
            tables.append([dict(zip(block[0], row)) for row in block[2:]])
        block = []
    return tables


def _number(cell: str) -> float:
    """The first number in a cell: '1,234.5', '0.39×', '**2.81×**', '12 ms', 'nan×'; a dash
    ('–', what a step prints for a peer that is not installed) is nan."""
    if cell.lstrip("*").startswith("nan") or cell.strip("* ") in ("–", "—", "-"):
        return math.nan
    match = re.search(r"-?\d[\d,]*(?:\.\d+)?", cell)
    assert match, f"no number in {cell!r}"
    return float(match.group().replace(",", ""))


def _positive(cell: str) -> bool:
    value = _number(cell)
    return math.isfinite(value) and value > 0


def _moderngl_usable() -> bool:
    try:
        import moderngl

        moderngl.create_standalone_context(backend="egl", require=430).release()
    except Exception:
        return False
    return True


def test_smoke_mode_is_declared_with_no_output_into_docs():
    from benchmarks.__main__ import SECTIONS, SMOKE, SMOKE_SCRIPTS

    assert set(SECTIONS) | set(SMOKE_SCRIPTS) | {"report"} == set(SMOKE_STEPS)
    assert all("--output" not in args for args in SMOKE_SCRIPTS.values())  # would rewrite docs/specialization.md
    assert max(SMOKE.warm_sizes) <= 64 and SMOKE.memory_triangles <= 2_000 and SMOKE.tiny


def test_smoke_runs_every_benchmark_and_says_so(smoke):
    summary = next(line for line in smoke.splitlines() if line.startswith("smoke: ran "))
    for step in SMOKE_STEPS:
        assert re.search(rf"\b{step} \(\d+\.\d s\)", summary), f"{step} missing from {summary!r}"
    seconds = float(re.search(r"in (\d+\.\d) s", summary).group(1))
    assert seconds < 120, f"the smoke run took {seconds} s: inputs no longer tiny?"
    assert "smoke: all ran; results.md and results.json written to a temporary folder, removed" in smoke
    skipped = next(line for line in smoke.splitlines() if line.startswith("smoke: skipped: "))
    for peer, usable in (("moderngl", _moderngl_usable()), ("pygfx", _importable("pygfx")), ("pyrender", _pyrender_usable())):
        assert (f"the {peer} peer" in skipped) != usable, skipped


def _pyrender_usable() -> bool:
    if not _importable("pyrender"):
        return False
    from benchmarks.pyrender_peer import pyrender_unusable

    return pyrender_unusable() is None


def test_smoke_depth_times_colour_and_depth_against_pyrender(smoke):
    (rows,) = _tables(_section(smoke, "depth"))
    assert [(row["scene"], row["size"]) for row in rows] == [("torus 128", "64²"), ("sphere 20K", "64²")]
    for row in rows:
        assert _positive(row["wgpu-shading"]) and _positive(row["wgpu-shading + depth"])
        assert _positive(row["every triangle"]) and row["culling: CPU ratio"].endswith("×")  # the A/B of the clusters
        assert _positive(row["pyrender (colour + depth)"]) == _pyrender_usable()


def test_smoke_shadows_times_a_shadowed_frame_against_pyrender_and_pygfx(smoke):
    frames, by_size = _tables(_section(smoke, "shadows"))
    assert [(row["light"], row["size"]) for row in frames] == [("directional light", "64²"), ("spot light", "64²")]
    for row in frames:
        assert all(_positive(row[name].split()[0]) for name in ("wgpu-shading (maps drawn)", "maps reused", "no shadows"))
        assert _positive(row["pyrender"].split()[0]) == _pyrender_usable()
        assert _positive(row["pygfx lean"].split()[0]) == _importable("pygfx")
    assert [row["map"] for row in by_size] == ["none", "256", "512"]  # the smoke run's sizes
    assert all(_positive(row["frame"]) for row in by_size)


def _importable(name: str) -> bool:
    import importlib.util

    return importlib.util.find_spec(name) is not None


def test_smoke_warm_and_breakdown_print_medians_and_ratios(smoke):
    (warm,) = _tables(_section(smoke, "warm"))
    assert [(row["scene"], row["size"]) for row in warm] == [("torus 128", "64²"), ("sphere 20K", "64²")]
    for row in warm:
        assert _positive(row["wgpu-shading"]) and _positive(row["limit"]) and _positive(row["ours ÷ limit"])
        if "moderngl" in row:
            assert _positive(row["ours ÷ moderngl (≤ 1.0)"])
    medians, threads = _tables(_section(smoke, "breakdown"))
    assert [row["scene"] for row in medians] == ["torus 128", "sphere 20K"]
    for row in medians:
        assert all(_positive(row[name]) for name in ("floor", "limit", "gouraud", "phong", "seed WGSL", "phong ÷ seed WGSL"))
    assert {row["renderer"] for row in threads} >= {"phong", "seed WGSL"}
    assert all(math.isfinite(_number(row["total"])) for row in threads)


def test_smoke_cold_start_times_every_variant_and_phase(smoke):
    variants, phases = _tables(_section(smoke, "cold"))
    names = {row["variant"] for row in variants}
    assert names >= {
        "wgpu-shading CLI", "CLI, prebuilt FFI off (wgpu-py's own cffi start-up)", "wgpu floor + prebuilt FFI",
        "CLI with Python's own exit (main() after start_process())",
        "wgpu floor (plain wgpu-py)", "python + import numpy", "CLI, fresh caches (first run ever)",
        "CLI, no bytecode cache (a source tree with PYTHONDONTWRITEBYTECODE)",
    }
    assert all(_positive(row["median s"]) and _positive(row["CPU median s"]) for row in variants)  # CPU beside wall
    steps = {row["phase"]: row for row in phases}
    assert "PNG write (as the CLI does it)" in steps and "first draw + readback (LLVM JIT of shader variants)" in steps
    assert _positive(steps["**sum**"]["now"]) and _positive(steps["**sum**"]["prebuilt FFI off (≈ before)"])
    assert _positive(steps["**sum**"]["CPU now"])


def test_smoke_batch_renders_and_writes_the_turntable(smoke):
    text = _section(smoke, "batch")
    (modes,) = _tables(text)
    assert len(modes) == 3 and all(_positive(row["frames/s (median pass)"]) for row in modes)
    assert all(_positive(row["cores we used"]) for row in modes)  # process CPU ÷ wall: this process did work
    assert "frames identical to render(): True" in text
    assert re.search(r"turntable cube -o spin.gif --frames 5 .*: [\d.]+ s, 5 frames written", text)


def test_smoke_memory_and_scaling_print_their_tables(smoke):
    memory, file_rows = _tables(_section(smoke, "memory"))
    assert [row["variant"] for row in memory] == ["default", "LP_NUM_THREADS=0 (no binning queue)"]
    # the large-file rows: the same torus as an STL, a PLY, three OBJs, a GLB, an embedded glTF, a PLY with face uvs, and PLY and OFF
    # files of quads and triangles, a COFF, and cubes as an STL, each loaded, then rendered; both peaks measured above the same baseline
    assert [row["file"] for row in file_rows] == [
        "binary STL", "binary PLY", "OBJ", "OBJ, `vt` and `vn` numbered on their own (as Blender writes it)",
        "OBJ of `v`, `vt` and `f v/vt` with UV seams and no normals (as Agisoft Metashape writes it)", "glTF (GLB)",
        "glTF, its buffer embedded as base64 (a `glTF-Embedded` file)",
        "binary STL of separate cubes, every vertex on a crease (a voxel model)",
        "binary PLY with a `texcoord` list on every face (as MeshLab and Agisoft Metashape export a textured mesh)",
        "binary PLY of quads and triangles, with texture coordinates (as Blender writes it)",
        "ASCII PLY of quads and triangles", "OFF of quads and triangles",
        "COFF: an OFF with a colour on every vertex line (as MeshLab writes it)"]
    for file_row in file_rows:
        assert file_row["triangles"] == ("1,992" if "cubes" in file_row["file"] else "1,922") and _positive(file_row["baseline MiB"])
        assert _number(file_row["load + render peak ÷ mesh arrays (< 3)"]) >= _number(file_row["load peak ÷ mesh arrays"]) > 0
    assert all(row["triangles"] == "1,980" and _positive(row["baseline MiB"]) for row in memory)
    # our share counts the mesh's arrays once plus their GPU copy: above 1× of them
    assert all(float(row["ours (mesh + GPU copy) ÷ mesh arrays"].rstrip("×")) > 1.0 for row in memory)
    triangles, pixels = _tables(_section(smoke, "scaling"))
    assert [row["triangles (sphere, 64²)"] for row in triangles] == ["196", "1,980"]
    assert [row["pixels (torus 128)"] for row in pixels] == ["1,024", "4,096"]
    assert all(_positive(row["wgpu-shading"]) and _positive(row["limit"]) for row in triangles + pixels)


def test_smoke_runs_the_standalone_benchmarks(smoke):
    (specialization,) = _tables(_section(smoke, "specialization"))
    assert len(specialization) == 3
    assert all(_positive(row["uber / specialized"]) and _positive(row["specialized frame"]) for row in specialization)

    reference = _section(smoke, "reference").splitlines()
    rows = [line.split() for line in reference if re.match(r"\s+\d+\s+(flat|gouraud|phong)\s", line)]
    assert [(r[0], r[1]) for r in rows] == [(n, f) for n in ("20", "196") for f in ("flat", "gouraud", "phong")]
    assert all(float(r[2]) >= 0 and int(r[3]) > 0 for r in rows)

    noise, defects, whole = _tables(_section(smoke, "golden_noise"))
    assert [row["setting"] for row in noise] == ["run-to-run #1"]
    assert re.fullmatch(r"\d/2", noise[0]["cases not bit-identical"])
    assert len(defects) == 6 and all(row["gold_torus_phong"] for row in defects)
    assert all(row["gold_torus_phong"].startswith("caught") for row in whole)  # shift, swap, no highlight

    live = _section(smoke, "live")  # a closed sphere's first frames, its clusters built on the worker meanwhile
    assert re.search(r"first 20 frames of a drag.*\n  wall ms: median \d+, worst \d+", live)
    assert re.search(r"during the build: median \d+\.\d+ ms", live)

    (hostile,) = _tables(_section(smoke, "hostile_files"))  # a thousandth of each file: read and drawn
    assert len(hostile) == 7 and all(row["exit"] == "0" and row["last line"].startswith("wrote ") for row in hostile)

    (gif,) = _tables(_section(smoke, "gif_palette"))
    assert len(gif) == 7 and gif[-1]["method"].startswith("**chosen")
    assert all(_positive(row["KiB/frame"]) and len(row["error mean R/G/B"].split(" / ")) == 3 for row in gif)


def test_smoke_dataset_times_every_mode_and_the_dask_overhead(smoke):
    fps, inside_outside, cpu, stages = _tables(_section(smoke, "dataset"))
    (row,) = fps
    assert row["size"] == "32²"
    for mode in ("naive", "in-process", "in-process, 1 device", "dask 1 worker", "dask 2 workers", "naive, colour + depth",
                 "batch, colour + depth", "batch, colour + depth, first run"):
        assert _positive(row[mode]), mode
    assert _positive(row["pyrender, colour + depth"]) == _pyrender_usable()
    assert _positive(row["in-process ÷ naive"]) and re.search(r"ms \([+-]?[\d.]+ %\)", row["Dask overhead per frame"])
    assert all(_positive(cell) for cell in list(inside_outside[0].values())[1:])
    # pyrender's column is a dash where pyrender is not installed (the test extra does not have it)
    assert all(_positive(cell) == (_pyrender_usable() or "pyrender" not in mode) for mode, cell in list(cpu[0].items())[1:])
    (stage_row,) = stages  # every stage of the colour + depth batch, wall / CPU, and the batch beside them
    for stage in ("load", "scenes", "render", "render, one at a time", "encode", "write", "sum of stages"):
        wall, cpu_ms = stage_row[stage].split(" / ")
        assert _positive(wall) and _positive(cpu_ms), stage
    assert _positive(stage_row["batch inside chunks"]) and _positive(stage_row["inside chunks ÷ render + readback (≤ 1.5)"])
    assert _positive(stage_row["first run inside chunks"]) and _positive(stage_row["first run ÷ render + readback"])
    # the denominator: render + readback of the same scenes, timed in the same rotation as the batch
    wall, cpu_ms = stage_row["render + readback, same passes"].split(" / ")
    assert _positive(wall) and _positive(cpu_ms)


def test_pyrender_peer_covers_the_same_pixels_and_returns_eye_depth(renderer, small_torus):
    pytest.importorskip("pyrender")
    from benchmarks.pyrender_peer import PyrenderPeer, WgpuShadingDepthPeer, pyrender_unusable

    reason = pyrender_unusable()
    if reason is not None:
        pytest.skip(f"pyrender cannot render offscreen here (apt install libosmesa6): {reason}")
    peer = PyrenderPeer(small_torus)
    image = peer.render()
    depth = peer.depth
    peer.close()
    ours = WgpuShadingDepthPeer(small_torus, renderer)
    ours_image = ours.render()
    assert image.shape[:2] == (96, 96)
    seen = depth > 0  # pyrender: 0 where nothing was drawn
    assert seen.mean() > 0.1
    assert (seen != np.isfinite(ours.depth)).mean() < 0.02  # the same silhouette, give or take edges
    assert (covered(image) == covered(ours_image)).mean() > 0.98
    both = seen & np.isfinite(ours.depth)
    np.testing.assert_allclose(depth[both], ours.depth[both], rtol=1e-3)  # both are eye-space distances
