"""Adapter selection and embedding: the caller's device is used; a machine without
lavapipe gets an error that says how to install it."""

from __future__ import annotations

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
