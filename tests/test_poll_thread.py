"""wgpu-py's poll thread with a gap after each poll that did not wait (render/poll_thread.py).

Without the gap, the thread that resolves a device's buffer maps called wgpuDevicePoll in
a tight loop, up to hundreds of times a frame, while the frame's own thread waited to ask
for the map. The polls are counted through the function the thread polls with, which
wgpu-py 0.32 keeps on the device's poller (the module says why it is reached there)."""

from __future__ import annotations

import collections

import numpy as np
import pytest

from wgpu_shading import Renderer
from wgpu_shading.dataset import Outputs, mesh_jobs, turntable_views
from wgpu_shading.dataset.views import base_scene, job_scene
from wgpu_shading.render import poll_thread
from wgpu_shading.render.poll_thread import with_poll_gap


def _views(count: int = 24, size: int = 64) -> list:
    """A turntable of the builtin torus as `batch` frames it: each view its own camera."""
    jobs = mesh_jobs(["builtin:torus"], turntable_views(count), Outputs(depth="npy"), {"size": size})
    base = base_scene(jobs[0])
    return [job_scene(base, job) for job in jobs]


def _counted(device, counts: collections.Counter) -> None:
    """Count the waiting polls of the device's poll thread (from here on, gap or not)."""
    poller = device._poller
    poll = poller._poll_func

    def counting(wait: bool):
        counts[wait] += 1
        return poll(wait)

    counting.without_counting = poll
    poller._poll_func = counting


@pytest.fixture
def renderer():
    renderer = Renderer()
    if getattr(renderer.device, "_poller", None) is None:
        pytest.skip("this wgpu-py has no per-device poll thread")
    return renderer


def test_a_renderer_gives_its_devices_the_gap(renderer):
    devices = [worker.device for worker in renderer.parallel_renderers(2)]
    for device in devices:
        assert getattr(device._poller._poll_func, "without_gap", None) is not None
        # asked again (another Renderer on the shared device): wrapped once, not twice
        assert with_poll_gap(device)
        assert not hasattr(device._poller._poll_func.without_gap, "without_gap")


def test_the_poll_thread_no_longer_polls_in_a_tight_loop(renderer):
    scenes = _views()
    list(renderer.render_many(scenes, depth=True))  # pipelines, uploads
    counts: collections.Counter = collections.Counter()
    devices = [worker.device for worker in renderer.parallel_renderers(2)]
    for device in devices:
        with_poll_gap(device, False)
        _counted(device, counts)
        with_poll_gap(device)
    try:
        for _ in range(3):
            list(renderer.render_many(scenes, depth=True))
    finally:
        for device in devices:  # the shared device polls as shipped again, uncounted
            device._poller._poll_func = device._poller._poll_func.without_gap.without_counting
            with_poll_gap(device)
    # Two maps a frame (colour, depth); without the gap this read 0 to ~320 polls a frame
    # on the 2-core VM, at random, and 300 on the dataset benchmark's meshes.
    assert counts[True] / (3 * len(scenes)) <= 5


def test_frames_are_the_same_with_and_without_the_gap(renderer):
    scenes = _views(count=6)
    devices = [worker.device for worker in renderer.parallel_renderers(2)]
    with_gap = list(renderer.render_many(scenes, depth=True))
    for device in devices:
        with_poll_gap(device, False)
    try:
        without = list(renderer.render_many(scenes, depth=True))
    finally:
        for device in devices:
            with_poll_gap(device)
    for a, b in zip(with_gap, without):
        assert np.array_equal(a.color, b.color)
        assert np.array_equal(a.depth, b.depth)


def test_switched_off_by_the_environment(renderer, monkeypatch):
    device = renderer.device
    monkeypatch.setenv(poll_thread.SWITCH_ENVIRONMENT_VARIABLE, "0")
    try:
        assert not with_poll_gap(device)
        assert not hasattr(device._poller._poll_func, "without_gap")
    finally:
        monkeypatch.delenv(poll_thread.SWITCH_ENVIRONMENT_VARIABLE)
        assert with_poll_gap(device)


def test_a_device_without_such_a_thread_is_left_alone():
    class Elsewhere:  # another wgpu-py, another backend
        pass

    device = Elsewhere()
    assert not with_poll_gap(device)
    assert vars(device) == {}
