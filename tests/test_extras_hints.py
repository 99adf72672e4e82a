"""Optional extras: a missing one is named with the command that installs it into the
environment running now (not a `pip install wgpu-shading[x]` that asks PyPI for a package it
does not have, nor one that lands in another Python), and what can run without it does."""

from __future__ import annotations

import shlex
import sys

from wgpu_shading.cli import main
from wgpu_shading.errors import install_hint


def test_hint_names_this_interpreter_and_the_extras_packages():
    assert install_hint("plots") == (
        f"install the [plots] extra into this environment: {shlex.quote(sys.executable)} -m pip install 'matplotlib>=3.7'"
    )
    assert "'imageio-ffmpeg>=0.5'" in install_hint("video")


def test_bench_accuracy_without_matplotlib_writes_all_but_the_plot(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib now fails
    out = tmp_path / "study"
    assert main(["bench", "accuracy", "--quick", "--frames", "1", "-q", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert "the Pareto plot needs matplotlib" in err and "-m pip install 'matplotlib" in err
    written = {p.name for p in out.iterdir()}
    assert {"results.csv", "results.json", "table.md"} <= written and not any("pareto" in name for name in written)
