"""Adapter and device selection.

By default the renderer runs on Mesa's lavapipe (the "llvmpipe" Vulkan adapter), so
results are the same on every machine that has it. Another adapter is chosen with the
`adapter=` argument or the WGPU_SHADING_ADAPTER environment variable:

    lavapipe / llvmpipe   the software Vulkan rasterizer (default)
    gpu                   the first hardware adapter (discrete before integrated)
    any other text        the first adapter whose description contains it (case-insensitive)

The default device for each selector is created once per process (about 0.5 s on
lavapipe) and reused while it lives: once it is lost (destroyed, driver reset), the next
Renderer() gets a fresh one. A caller can also hand its own wgpu device to the Renderer.
"""

from __future__ import annotations

import os
import threading
from contextlib import contextmanager

from ..errors import DeviceError, WgpuShadingError

ADAPTER_ENVIRONMENT_VARIABLE = "WGPU_SHADING_ADAPTER"
DEFAULT_ADAPTER = "lavapipe"
_SOFTWARE_NAMES = {"lavapipe", "llvmpipe", "software", "cpu"}

INSTALL_HINT = (
    "install Mesa's lavapipe (software Vulkan): `sudo apt-get install mesa-vulkan-drivers` on "
    "Debian/Ubuntu, `sudo dnf install mesa-vulkan-drivers` on Fedora; or choose another adapter "
    f"with --adapter / {ADAPTER_ENVIRONMENT_VARIABLE} (see `wgpu-shading info`)"
)


def requested_adapter(adapter: str | None = None) -> str:
    """The selector in effect: the argument, else the environment variable, else lavapipe."""
    return (adapter or os.environ.get(ADAPTER_ENVIRONMENT_VARIABLE) or DEFAULT_ADAPTER).strip()


def _prepare_instance(selector: str) -> None:
    from ._prebuilt_ffi import load_wgpu_native

    # Before anything imports wgpu's backend: skips ~2 s of C-header parsing per process.
    load_wgpu_native()
    import wgpu.backends.wgpu_native.extras as extras

    # Mesa's device-select Vulkan layer only reorders GPUs (we pick adapters ourselves) and
    # prints "XDG_RUNTIME_DIR is invalid" on headless machines; its documented off switch:
    os.environ.setdefault("NODEVICE_SELECT", "1")
    # lavapipe is a Vulkan driver: enumerating only Vulkan skips probing EGL/OpenGL, which is
    # slow and noisy on a headless machine. Any other selector may need any backend.
    backends = ["Vulkan"] if selector.lower() in _SOFTWARE_NAMES else ["All"]
    try:
        extras.set_instance_extras(backends=backends)
    except RuntimeError:
        pass  # the process already created the wgpu instance (e.g. the caller used wgpu first)


# The Vulkan loader's own variables for the drivers it loads (VK_ICD_FILENAMES is the older
# name), and where it looks for driver manifests on Linux; lavapipe's is lvp_icd.<arch>.json.
# https://vulkan.lunarg.com/doc/sdk/latest/linux/LoaderDriverInterface.html#driver-discovery-on-linux
_DRIVER_VARIABLES = ("VK_DRIVER_FILES", "VK_ICD_FILENAMES")


def driver_manifest_folders() -> list[str]:
    """Where the Vulkan loader looks for driver manifests on Linux, in its order."""
    home = os.path.expanduser("~")
    config = [os.environ.get("XDG_CONFIG_HOME") or os.path.join(home, ".config")]
    config += (os.environ.get("XDG_CONFIG_DIRS") or "/etc/xdg").split(":") + ["/usr/local/etc", "/etc"]
    data = [os.environ.get("XDG_DATA_HOME") or os.path.join(home, ".local", "share")]
    data += (os.environ.get("XDG_DATA_DIRS") or "/usr/local/share:/usr/share").split(":")
    return [os.path.join(folder, "vulkan", "icd.d") for folder in config + data if folder]


def load_only_lavapipe_driver(adapter: str | None = None) -> bool:
    """For a process that renders with one selector only (the CLI): when that selector is
    lavapipe, tell the Vulkan loader to load lavapipe's driver and no other, instead of
    every installed driver (Intel's, AMD's, ...) that adapter enumeration otherwise loads:
    ~5 ms of every start (docs/performance.md, "Cold start"). Call it before the wgpu
    instance exists. Nothing changes when the user chose drivers already (the loader's
    variables are set), when lavapipe's manifest is not found (the usual search then
    reports what there is), or for another selector. Not for a library: a process may ask
    for another adapter later, which this would hide. True when it was applied."""
    if requested_adapter(adapter).lower() not in _SOFTWARE_NAMES or any(os.environ.get(v) for v in _DRIVER_VARIABLES):
        return False
    manifests = []
    for folder in driver_manifest_folders():
        try:
            names = sorted(os.listdir(folder))
        except OSError:
            continue
        manifests += [os.path.join(folder, name) for name in names if name.startswith("lvp_icd.") and name.endswith(".json")]
    if not manifests:
        return False
    for variable in _DRIVER_VARIABLES:
        os.environ[variable] = os.pathsep.join(manifests)
    return True


def _matches(adapter: object, selector: str) -> bool:
    info = adapter.info  # type: ignore[attr-defined]
    key = selector.lower()
    if key in _SOFTWARE_NAMES:
        return "llvmpipe" in info.get("device", "").lower() and info.get("backend_type") == "Vulkan"
    if key == "gpu":
        return info.get("adapter_type") in ("DiscreteGPU", "IntegratedGPU")
    return key in adapter.summary.lower()  # type: ignore[attr-defined]


def list_adapters(adapter: str | None = None) -> list:
    """Every adapter wgpu can see (for `wgpu-shading info`)."""
    import wgpu

    _prepare_instance(requested_adapter(adapter))
    return list(wgpu.gpu.enumerate_adapters_sync())


def select_adapter(adapter: str | None = None):
    """The wgpu adapter for a selector, or a DeviceError that says how to get one."""
    selector = requested_adapter(adapter)
    adapters = list_adapters(selector)
    candidates = [a for a in adapters if _matches(a, selector)]
    if selector.lower() == "gpu":
        candidates.sort(key=lambda a: a.info.get("adapter_type") != "DiscreteGPU")
    if not candidates:
        seen = "; ".join(a.summary for a in adapters) or "none"
        if selector.lower() in _SOFTWARE_NAMES:
            raise DeviceError(f"no lavapipe (llvmpipe Vulkan) adapter found (adapters seen: {seen}); {INSTALL_HINT}")
        if any(_matches(a, DEFAULT_ADAPTER) for a in adapters):
            # lavapipe is there: installing it would not help; say what can be chosen.
            raise DeviceError(
                f"no adapter matches {selector!r} (adapters seen: {seen}); choose one by part of its name, "
                f"'gpu' for hardware, or leave --adapter / {ADAPTER_ENVIRONMENT_VARIABLE} unset for lavapipe"
            )
        raise DeviceError(f"no adapter matches {selector!r} (adapters seen: {seen}); {INSTALL_HINT}")
    return candidates[0]


_devices: dict[str, object] = {}  # selector → the shared default device
_devices_lock = threading.Lock()


def default_device(adapter: str | None = None):
    """The shared wgpu device for a selector: created on first use, then reused while it
    is alive (a lost device is replaced by a new one)."""
    selector = requested_adapter(adapter).lower()
    with _devices_lock:
        device = _devices.get(selector)
        if device is None or not _alive(device):
            device = _devices[selector] = _device_for(selector)
        return device


def _alive(device) -> bool:
    """False when the device is lost: creating even a tiny buffer then fails ("Parent
    device is lost"). wgpu-py 0.32 has no device.lost promise to ask instead."""
    import wgpu

    try:
        device.create_buffer(size=4, usage=wgpu.BufferUsage.COPY_DST)
    except Exception as error:
        if device_lost(error):
            return False
        raise
    return True


def device_lost(error: BaseException) -> bool:
    """True when a wgpu error says that its device is lost or destroyed."""
    text = str(error).lower()
    return "device is lost" in text or "device lost" in text or "device was lost" in text


@contextmanager
def lost_device_errors(device):
    """Inside: an error that says `device` is lost becomes a DeviceError, and the device
    leaves the default-device cache, so that the next Renderer() gets a fresh one."""
    try:
        yield
    except WgpuShadingError:
        raise
    except Exception as error:
        if device_lost(error):
            forget_device(device)
            raise DeviceError(
                f"the wgpu device was lost ({str(error).strip().splitlines()[-1].strip()}); create a new Renderer to continue"
            ) from None
        raise


def forget_device(device) -> None:
    """Drop `device` from the default-device cache (it was lost): the next default_device()
    call creates a new one. Devices the caller handed in are not in the cache."""
    with _devices_lock:
        for selector, cached in list(_devices.items()):
            if cached is device:
                del _devices[selector]


# On a CPU adapter every buffer lives in host memory anyway; letting mesh buffers be mapped
# directly spares wgpu a staging copy of each mesh upload (peak memory of a big mesh drops
# from 3x to 2x its arrays: numpy's copy and the driver's). Not used on GPUs, where
# mappable vertex buffers would be slow.
DIRECT_UPLOAD_FEATURE = "mappable-primary-buffers"


def uses_direct_upload(device) -> bool:
    """True when the renderer may create mesh buffers mapped, without a staging copy."""
    return DIRECT_UPLOAD_FEATURE in device.features and device.adapter.info.get("adapter_type") == "CPU"


# Alpha-blended materials drawn into the float32 target (`render --float`, .npy) blend into
# an rgba32float attachment, which WebGPU allows only with this feature (lavapipe has it).
FLOAT32_BLENDING_FEATURE = "float32-blendable"


def _device_for(selector: str):
    chosen = select_adapter(selector)
    features = []
    if chosen.info.get("adapter_type") == "CPU" and DIRECT_UPLOAD_FEATURE in chosen.features:
        features.append(DIRECT_UPLOAD_FEATURE)
    if FLOAT32_BLENDING_FEATURE in chosen.features:
        features.append(FLOAT32_BLENDING_FEATURE)
    try:
        return chosen.request_device_sync(label=f"wgpu-shading on {chosen.summary}", required_features=features)
    except Exception as error:  # wgpu raises plain RuntimeErrors here
        raise DeviceError(f"could not create a device on {chosen.summary}: {error}") from None


def describe_device(device) -> str:
    info = device.adapter.info
    return f"{info.get('device', '?')} ({info.get('backend_type', '?')}, {info.get('description', '')})".strip()
