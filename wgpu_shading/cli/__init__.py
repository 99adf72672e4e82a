"""The `wgpu-shading` command line: one module per command group, each thin over the library."""

from .main import build_parser, console_main, main

__all__ = ["build_parser", "console_main", "main"]
