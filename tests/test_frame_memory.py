"""The driver's per-frame scratch memory stays mapped between frames (render/frame_memory.py).

Measured by the kernel's count of minor page faults in a fresh process (the allocator's
thresholds depend on what a process freed before), over warm frames of the 10K torus at
512², every triangle drawn: lavapipe bins each frame into ~2.4 MB of scratch; given back to the kernel after
every frame, it is faulted in again by the next (~600 faults a frame on Mesa 22.3)."""

from __future__ import annotations

import os
import platform
import subprocess
import sys

import pytest

from wgpu_shading.render.frame_memory import SWITCH_ENVIRONMENT_VARIABLE, keep_frame_memory_mapped

WARM_FRAME_FAULTS = """
import resource
from dataclasses import replace
from wgpu_shading import Renderer, load_scene
from wgpu_shading.assets import load_mesh

scene = load_scene("examples/gold_torus_phong.toml")
(obj,) = scene.objects
mesh = load_mesh("builtin:torus?major=0.5&minor=0.2&segments=72")
# Lit on both sides: every triangle is binned (seen from outside, the closed torus would be
# drawn with its far side culled, turned_away.py, and bin about half the scratch).
scene = replace(scene, objects=(replace(obj, mesh=mesh),), size=(512, 512), shading=replace(scene.shading, two_sided=True))
renderer = Renderer()
for _ in range(5):
    renderer.render(scene)
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(20):
    renderer.render(scene)
print((resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before) / 20)
"""

GLIBC = sys.platform.startswith("linux") and platform.libc_ver()[0] == "glibc"


def _faults_per_frame(switch: str) -> float:
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    environment = {**os.environ, SWITCH_ENVIRONMENT_VARIABLE: switch}
    result = subprocess.run(
        [sys.executable, "-c", WARM_FRAME_FAULTS], capture_output=True, text=True, timeout=120, cwd=root, env=environment
    )
    assert result.returncode == 0, result.stderr
    return float(result.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(not GLIBC, reason="glibc's dynamic malloc thresholds")
def test_warm_frames_fault_in_no_fresh_memory():
    primed = _faults_per_frame("1")
    # A few dozen at most (a heap extended now and then: 32 faults a frame in some
    # layouts, measured); the 512² image alone is 256 pages, the scratch ~600.
    assert primed < 60, f"{primed} page faults a warm frame"
    switched_off = _faults_per_frame("0")
    if switched_off < 200:
        pytest.skip(f"this driver's frames do not give their scratch back ({switched_off} faults a frame without)")
    assert primed < switched_off / 5


def test_the_switch_leaves_the_allocator_alone(monkeypatch):
    monkeypatch.setenv(SWITCH_ENVIRONMENT_VARIABLE, "0")
    assert keep_frame_memory_mapped() is False
    monkeypatch.setenv(SWITCH_ENVIRONMENT_VARIABLE, "1")
    assert keep_frame_memory_mapped() is GLIBC
