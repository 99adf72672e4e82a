"""Adapter selection and embedding: the caller's device is used; a machine without
lavapipe gets an error that says how to install it."""

from __future__ import annotations

import os

import numpy as np
import pytest

from wgpu_shading import DeviceError, Renderer, Scene, SceneObject, load_mesh
from wgpu_shading.render import device as device_module


class FakeAdapter:
    def __init__(self, device: str, backend: str, adapter_type: str):
        self.info = {"device": device, "backend_type": backend, "adapter_type": adapter_type}
        self.summary = f"{device} ({adapter_type}) via {backend}"


def test_no_lavapipe_says_how_to_install_it(monkeypatch):
    monkeypatch.setattr(device_module, "list_adapters", lambda selector=None: [FakeAdapter("SwiftShader", "Vulkan", "CPU")])
    with pytest.raises(DeviceError) as error:
        device_module.select_adapter("lavapipe")
    message = str(error.value)
    assert "no lavapipe (llvmpipe Vulkan) adapter found" in message
    assert "apt-get install mesa-vulkan-drivers" in message and "SwiftShader" in message


def test_unmatched_adapter_suggests_installing_lavapipe_only_when_it_is_missing(monkeypatch):
    monkeypatch.setattr(device_module, "list_adapters", lambda selector=None: [FakeAdapter("llvmpipe", "Vulkan", "CPU")])
    with pytest.raises(DeviceError) as error:
        device_module.select_adapter("nvidia")
    assert "apt-get" not in str(error.value) and "llvmpipe" in str(error.value)
    monkeypatch.setattr(device_module, "list_adapters", lambda selector=None: [FakeAdapter("SwiftShader", "Vulkan", "CPU")])
    with pytest.raises(DeviceError, match="apt-get install mesa-vulkan-drivers"):
        device_module.select_adapter("nvidia")


def test_gpu_selector_prefers_a_discrete_gpu(monkeypatch):
    adapters = [
        FakeAdapter("llvmpipe", "Vulkan", "CPU"),
        FakeAdapter("Intel UHD", "Vulkan", "IntegratedGPU"),
        FakeAdapter("NVIDIA H100", "Vulkan", "DiscreteGPU"),
    ]
    monkeypatch.setattr(device_module, "list_adapters", lambda selector=None: adapters)
    assert device_module.select_adapter("gpu").info["device"] == "NVIDIA H100"
    assert device_module.select_adapter("intel").info["device"] == "Intel UHD"
    assert device_module.select_adapter("lavapipe").info["device"] == "llvmpipe"


def test_environment_variable_selects_the_adapter(monkeypatch):
    monkeypatch.setenv("WGPU_SHADING_ADAPTER", "nvidia")
    assert device_module.requested_adapter() == "nvidia"
    assert device_module.requested_adapter("lavapipe") == "lavapipe"  # the argument wins
    monkeypatch.delenv("WGPU_SHADING_ADAPTER")
    assert device_module.requested_adapter() == "lavapipe"


def test_renderer_uses_the_callers_device(renderer):
    """Embedding: a device the caller created (here a second one on lavapipe) renders the
    same image as the shared default device."""
    adapter = device_module.select_adapter("lavapipe")
    own_device = adapter.request_device_sync(label="the caller's device")
    embedded = Renderer(device=own_device)
    assert embedded.device is own_device and embedded.device is not renderer.device
    scene = Scene(objects=(SceneObject(load_mesh("builtin:sphere?slices=16&stacks=8")),), size=(48, 48))
    np.testing.assert_array_equal(embedded.render(scene), renderer.render(scene))


def test_default_device_is_created_once():
    assert device_module.default_device() is device_module.default_device("lavapipe")
    assert Renderer().device is Renderer().device


# The installed program lets the Vulkan loader load lavapipe's driver only (cli/process_start.py).

def _driver_folder(tmp_path, monkeypatch, *names: str):
    """A driver manifest folder holding `names`, the only one searched."""
    folder = tmp_path / "vulkan" / "icd.d"
    folder.mkdir(parents=True)
    for name in names:
        (folder / name).write_text("{}")
    monkeypatch.setattr(device_module, "driver_manifest_folders", lambda: [str(folder)])
    for variable in ("VK_DRIVER_FILES", "VK_ICD_FILENAMES", "WGPU_SHADING_ADAPTER"):
        # set, then removed: monkeypatch then restores the variable as it was (absent or
        # not) after the test, including what load_only_lavapipe_driver set
        monkeypatch.setenv(variable, "")
        monkeypatch.delenv(variable)
    return folder


def test_driver_manifests_are_searched_where_the_loader_searches(monkeypatch):
    monkeypatch.setenv("XDG_DATA_DIRS", "/opt/a:/opt/b")
    monkeypatch.setenv("XDG_CONFIG_HOME", "/home/me/config")
    folders = device_module.driver_manifest_folders()
    assert folders.index("/home/me/config/vulkan/icd.d") < folders.index("/opt/a/vulkan/icd.d") < folders.index("/opt/b/vulkan/icd.d")
    assert "/etc/vulkan/icd.d" in folders


def test_a_lavapipe_process_loads_lavapipe_s_driver_only(tmp_path, monkeypatch):
    folder = _driver_folder(tmp_path, monkeypatch, "lvp_icd.x86_64.json", "radeon_icd.x86_64.json", "intel_icd.x86_64.json")
    assert device_module.load_only_lavapipe_driver(None)
    for variable in ("VK_DRIVER_FILES", "VK_ICD_FILENAMES"):  # the loader's name, and its older one
        assert os.environ[variable] == str(folder / "lvp_icd.x86_64.json")


@pytest.mark.parametrize("adapter, environment", [
    ("gpu", {}),  # another adapter: every driver, as usual
    ("nvidia", {}),
    (None, {"WGPU_SHADING_ADAPTER": "gpu"}),
    (None, {"VK_DRIVER_FILES": "/mine/driver.json"}),  # the user chose drivers: theirs are kept
    (None, {"VK_ICD_FILENAMES": "/mine/driver.json"}),
])
def test_drivers_are_left_alone_for_other_adapters_and_the_user_s_choice(tmp_path, monkeypatch, adapter, environment):
    _driver_folder(tmp_path, monkeypatch, "lvp_icd.x86_64.json", "radeon_icd.x86_64.json")
    for variable, value in environment.items():
        monkeypatch.setenv(variable, value)
    assert not device_module.load_only_lavapipe_driver(adapter)
    for variable in ("VK_DRIVER_FILES", "VK_ICD_FILENAMES"):
        assert os.environ.get(variable) == environment.get(variable)


def test_without_lavapipe_s_manifest_the_usual_search_reports_what_there_is(tmp_path, monkeypatch):
    _driver_folder(tmp_path, monkeypatch, "radeon_icd.x86_64.json")
    assert not device_module.load_only_lavapipe_driver("lavapipe")
    assert "VK_DRIVER_FILES" not in os.environ and "VK_ICD_FILENAMES" not in os.environ
