"""The view options as command-line flags, generated from the one table
(wgpu_shading/scene/view/options.py; docs/view-options.md lists every option's spellings).
`render`, `turntable`, `check`, `shader` and `batch` all add them here, so a flag one of
them accepts the others accept too."""

from __future__ import annotations

import argparse

from ..errors import UsageError
from ..scene.view.options import OPTIONS_BY_NAME, VIEW_OPTIONS, ViewOption, ViewOptions
from ..scene.view.reading import LIGHT_SYNTAX, parse_light

__all__ = ["LIGHT_SYNTAX", "add_view_arguments", "parse_light", "view_options_from_args"]

_GROUPS = {
    "view": "view options (override the scene; batch: defaults for every job)",
    "camera": "camera (f3d's names; applied to scene files and bare meshes)",
    "output": "output",
    "lights": "lights",
}


def _argparse_type(option: ViewOption, flag: str):
    def read(text: str):
        try:
            return option.read(text, flag)
        except UsageError as error:
            raise argparse.ArgumentTypeError(str(error).removeprefix(f"{flag}: ")) from None

    read.__name__ = option.name  # argparse names the type in its messages
    return read


def add_view_arguments(parser: argparse.ArgumentParser) -> None:
    """Every view option's flags, each storing into args.<option name> (None when absent). An
    option's aliases (older spellings) work the same but --help does not show them."""
    groups = {key: parser.add_argument_group(title) for key, title in _GROUPS.items()}
    for option in VIEW_OPTIONS:
        group = groups[option.group]
        if option.flags:
            _add_value_flags(group, option, option.flags, option.help)
        for flag, constant, help_text in option.switches:
            group.add_argument(flag, dest=option.name, action="store_const", const=constant, default=None, help=help_text)
        for alias, current in option.aliases:
            is_switch, constant = option.switch_constant(alias)
            if is_switch:
                group.add_argument(alias, dest=option.name, action="store_const", const=constant, default=None, help=argparse.SUPPRESS)
            else:
                _add_value_flags(group, option, (alias,), argparse.SUPPRESS, errors_name=current)


def _add_value_flags(group, option: ViewOption, flags: tuple[str, ...], help_text: str, errors_name: str | None = None) -> None:
    group.add_argument(
        *flags,
        dest=option.name,
        # a repeated flag's values are read together (view_options_from_args)
        type=str if option.repeated else _argparse_type(option, errors_name or flags[0]),
        action="append" if option.repeated else "store",
        metavar=option.metavar,
        default=None,
        help=help_text,
    )


def view_options_from_args(args: argparse.Namespace) -> ViewOptions:
    """The ViewOptions the flags of `args` (parsed by a parser given add_view_arguments) set."""
    values = {}
    for name in OPTIONS_BY_NAME:
        value = getattr(args, name, None)
        if value is not None:
            option = OPTIONS_BY_NAME[name]
            values[name] = option.read(tuple(value), option.flags[0]) if option.repeated else value
    return ViewOptions(**values)
