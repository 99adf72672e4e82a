"""A gap between the polls of wgpu-py's per-device poll thread.

wgpu-py 0.32 resolves a device's promises, every readback's buffer map among them, on a
thread of its own (`PollThread`, wgpu-py#778): while a promise is pending, that thread
calls `wgpuDevicePoll(wait=True)` in a loop. `GPUBuffer.map_async` wakes the thread
*before* it asks wgpu-native for the map, and a waiting poll with nothing yet to wait for
returns at once. So the thread polls in a tight loop, and whatever the frame's own thread
asks of wgpu-native for that device meanwhile (the map itself, the depth map after the
colour one, the next frame's submit) waits behind it. Measured on lavapipe, 192 frames of
the dataset benchmark at 256² (docs/performance.md, "The poll thread's tight loop"):
~300 polls a frame, each returning in ~2 µs, `wgpuBufferMapAsync` 0.25 ms on average and
up to 5.6 ms, against 0.05 ms with the gap; the loop itself took ~0.9 ms of CPU a frame.
Changing Python's switch interval did not change it, so the interpreter lock is not what
the frame's thread waits for: a lock of wgpu-native's that the poll thread takes again
as soon as it let it go, before a waiter can (we did not find which; that a waiting poll
keeps other threads from submitting was seen elsewhere too: tracel-ai/burn#2032).

The gap: after a waiting poll that returned at once, the thread sleeps for zero seconds,
which lets go of the interpreter lock and the core for a moment. That is enough for the
frame's thread to get its call in; the next poll then waits for the GPU, as it is meant
to: ~1 poll a frame, and a 256² frame of render_many 13 % faster. A poll that did wait
is followed by no gap. Only the promises' thread changes; a wgpu-py without such a
thread is left alone. WGPU_SHADING_POLL_GAP=0 leaves the thread as wgpu-py made it.
"""

from __future__ import annotations

import os
import threading
import time
from typing import Callable

# A waiting poll that returns sooner than this did not wait (those of the tight loop took
# ~2 µs each; one that waits for a frame, milliseconds).
IMMEDIATE_SECONDS = 50e-6
SWITCH_ENVIRONMENT_VARIABLE = "WGPU_SHADING_POLL_GAP"

_installing = threading.Lock()  # two renderers made at once on one device wrap it once


def with_poll_gap(device, enabled: bool = True) -> bool:
    """Give `device`'s poll thread a gap after each poll that returned at once (module
    docstring), or take it away (`enabled=False`, for comparison). Returns whether the
    thread now has the gap: False where wgpu-py has no poll thread of this kind, or when
    switched off by WGPU_SHADING_POLL_GAP=0. Idempotent; safe while the thread runs (it
    reads the function anew for every poll)."""
    if enabled and os.environ.get(SWITCH_ENVIRONMENT_VARIABLE, "1").strip() == "0":
        enabled = False
    # wgpu-py 0.32's PollThread keeps the function it polls with here (wgpu/backends/
    # wgpu_native/_poller.py); another version may not: then nothing changes.
    poller = getattr(device, "_poller", None)
    poll = getattr(poller, "_poll_func", None)
    if not callable(poll):
        return False
    with _installing:
        poll = poller._poll_func
        original = getattr(poll, "without_gap", poll)
        poller._poll_func = _gapped(original) if enabled else original
    return enabled


def _gapped(poll: Callable[[bool], object]) -> Callable[[bool], object]:
    clock, sleep = time.perf_counter, time.sleep

    def poll_with_gap(wait: bool) -> object:
        if not wait:
            return poll(False)
        start = clock()
        result = poll(True)
        if clock() - start < IMMEDIATE_SECONDS:
            sleep(0)
        return result

    poll_with_gap.without_gap = poll  # type: ignore[attr-defined]
    return poll_with_gap
