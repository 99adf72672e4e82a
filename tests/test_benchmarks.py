"""The benchmark peers draw what they claim to (so the comparisons are fair). Nothing timed.

The wgpu-based peers run everywhere; moderngl and pygfx come with the [bench] extra only,
so their tests skip without it.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository's benchmarks/ package

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
