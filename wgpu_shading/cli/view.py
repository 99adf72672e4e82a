"""`view`: a live window on a scene or mesh (wgpu_shading/live/, docs/viewer.md)."""

from __future__ import annotations

import argparse

from .arguments import add_view_arguments, view_options_from_args


def command_view(args: argparse.Namespace) -> int:
    from ..live.session import COMPARE_AXES, LiveView
    from ..live.state import help_text
    from ..live.window import glfw_backend, run_window
    from ..render.renderer import Renderer

    glfw_backend()  # a missing [view] extra or display is said before the mesh is read
    live = LiveView(
        args.input, view_options_from_args(args), renderer=Renderer(adapter=args.adapter), compare=args.compare
    )
    if not args.quiet:
        shown = f" ({' | '.join(COMPARE_AXES[args.compare])})" if args.compare else ""
        print(f"viewing {args.input}{shown}; H prints the keys", flush=True)
        if args.keys:
            print(help_text(), flush=True)
    run_window(live)
    return 0


def add_view(commands, gpu: argparse.ArgumentParser) -> None:
    view = commands.add_parser(
        "view",
        parents=[gpu],
        help="open a live window on a scene or mesh (mouse and keys as in f3d; needs the [view] extra)",
        description="Open a window showing what `render` draws with the same options; turn it with the "
        "mouse (left: orbit, right/wheel: zoom, middle: pan) and change it with keys (H lists them; "
        "P prints the `render` command of the current view, S saves NAME-NNN.png). Needs the [view] "
        "extra (`./run extra view`) and a display (`xvfb-run -a` for a virtual one).",
    )
    view.add_argument(
        "input",
        help="a scene file (.toml), a mesh file (OBJ, PLY, STL, OFF, GLB, XYZ), builtin:NAME, or example:NAME",
    )
    view.add_argument(
        "--compare", choices=("frequency", "reflection"),
        help="show every shading frequency (flat | Gouraud | Phong) or reflection model side by side, one camera",
    )
    view.add_argument("--keys", action="store_true", help="print the keys when the window opens")
    view.add_argument("-q", "--quiet", action="store_true", help="print nothing but what S and P print")
    add_view_arguments(view)
    view.set_defaults(handler=command_view)
