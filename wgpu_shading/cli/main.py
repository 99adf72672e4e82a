"""The `wgpu-shading` command line.

    wgpu-shading render SCENE.toml -o out.png
    wgpu-shading render MESH -o out.png [--frequency F] [--reflection R] [--material M] ...
    wgpu-shading turntable MESH -o spin.gif [--frames 360] [--fps 30]   a turning view
    wgpu-shading check SCENE.toml --ref golden.png [--update]   golden-image test (exit 0/1)
    wgpu-shading render SCENE --shading auto --max-error E   cheapest shading within E/255
    wgpu-shading bench accuracy [--quick] [--out DIR]       the accuracy/time study
    wgpu-shading batch MANIFEST.csv -o DIR  a dataset: one folder per mesh (docs/datasets.md)
    wgpu-shading batch --meshes 'dir/*.obj' --views 24 --size 256 -o DIR [--workers N]
    wgpu-shading shader SCENE.toml          print the generated WGSL
    wgpu-shading materials                  the material table
    wgpu-shading examples                   the example scenes and sample meshes (example:NAME)
    wgpu-shading info                       adapters and versions
    wgpu-shading view MESH [--compare frequency]   a live window (mouse and keys as in f3d)

Errors a user can cause (missing file, bad key, bad value, no adapter) print one line on
stderr and exit with status 2; no traceback.
"""

from __future__ import annotations

import argparse
import logging
import os
import re
import signal
import sys
import threading
import warnings
from typing import NoReturn, Sequence

from .. import __version__
from ..errors import WgpuShadingError, shorten
from .process_end import EXIT_BROKEN_PIPE, end_process
from .process_start import command_starts, start_process

EXIT_USAGE = 2
EXIT_INTERNAL = 3


_INNERMOST = "wgpu_shading_parser"  # the (sub)command parser that read the arguments
# A value that starts with a minus sign: a number (-2, -.5, -1e3, -inf, -nan), an axis (-Z),
# or a vector whose first component is one (-1,2,3).
NEGATIVE_VALUE = re.compile(r"^-((\d+\.?\d*|\.\d+)(e[-+]?\d+)?|inf(inity)?|nan|[xyz])(,.*)?$", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    """argparse with one-line usage errors (its own put the whole usage text first): the
    same "wgpu-shading: error: ..." line and exit status 2 as every other bad input. A
    mistyped flag, command or choice is answered with the closest spelling and the help of
    the command it was given to: `render --sise 64` → "unknown option --sise: did you mean
    --size? (see `wgpu-shading render --help`)"."""

    def __init__(self, *args, **kwargs):
        # A prefix of a flag (--transp) is not another spelling of it: abbreviations accept
        # typos silently and change meaning when a flag that shares the prefix is added.
        kwargs.setdefault("allow_abbrev", False)
        super().__init__(*args, **kwargs)
        # What argparse takes for a value although it starts with "-": its own negative
        # numbers (-30, -.5) and also -1e3, -inf, axes (--up -Z) and vectors (-1,2,3), which
        # it took for unknown options ("--up: expected one argument"). No flag looks like
        # these; set before any argument is added (argparse checks each flag against it).
        self._negative_number_matcher = NEGATIVE_VALUE

    def error(self, message: str):  # type: ignore[override]
        # "argument --size/--resolution: ..." → "--size: ...", as the errors raised later name flags
        message = re.sub(r"^argument ([^/:\s]+)(/[^:\s]+)*: ", r"\1: ", message)
        choice = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)", message)
        if choice:
            message += _did_you_mean(choice.group(1), re.findall(r"'([^']*)'", choice.group(2)))
        self.exit(EXIT_USAGE, f"wgpu-shading: error: {shorten(message)} (see `{self.prog} --help`)\n")

    def parse_known_args(self, args=None, namespace=None):
        namespace, extras = super().parse_known_args(args, namespace)
        if not hasattr(namespace, _INNERMOST):  # a subcommand's parser finishes before its parent's
            setattr(namespace, _INNERMOST, self)
        return namespace, extras

    def parse_args(self, args=None, namespace=None):
        namespace, extras = self.parse_known_args(args, namespace)
        parser = getattr(namespace, _INNERMOST, self)
        delattr(namespace, _INNERMOST)
        if extras:  # argparse would say "unrecognized arguments" for the whole command line
            parser.reject(extras[0])
        return namespace

    def reject(self, word: str):
        """Exit with one line about the first word this (sub)command does not take."""
        if word.startswith("-"):
            flag = word.split("=", 1)[0]
            self.error(f"unknown option {flag}" + _did_you_mean(flag, self.visible_flags()))
        self.error(f"unexpected argument {word!r}")

    def visible_flags(self) -> list[str]:
        """The long flags --help shows (older spellings, hidden there, are not suggested)."""
        return [flag for action in self._actions if action.help != argparse.SUPPRESS for flag in action.option_strings if flag.startswith("--")]


def _did_you_mean(word: str, candidates) -> str:
    import difflib  # (imported on a mistake only: ~2 ms of every start)
    close = difflib.get_close_matches(word, list(candidates), n=1, cutoff=0.6)
    return f": did you mean {close[0]}?" if close else ""


class _Ignored:
    """Stands for the parser of a command this command line does not run: every method
    call (add_argument, groups, set_defaults, nested subcommands) is accepted and dropped."""

    def __getattr__(self, name: str):
        return lambda *args, **kwargs: self


class _OnlyCommand:
    """The subcommands as the add_* functions below see them when the command line names
    one: that command's parser is built in full; every other command is registered by
    name and help only (enough for `--help` and for suggesting a mistyped command), and
    its arguments are not added. Adding the ~470 arguments of every command cost each
    start ~10 ms (docs/performance.md, "Cold start")."""

    def __init__(self, commands, wanted: str):
        self.commands, self.wanted = commands, wanted

    def add_parser(self, name: str, **kwargs):
        if name == self.wanted:
            return self.commands.add_parser(name, **kwargs)
        self.commands.add_parser(name, help=kwargs.get("help"), description=kwargs.get("description"))
        return _Ignored()


def _named_command(argv: Sequence[str] | None) -> str | None:
    """The command a command line names: its first word that is not an option."""
    words = sys.argv[1:] if argv is None else argv
    return next((word for word in words if not word.startswith("-")), None)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The whole command line's parser; with `command`, only that command's arguments."""
    parser = _Parser(
        prog="wgpu-shading",
        description="Classic local lighting (Phong/Blinn-Phong; flat, Gouraud, Phong shading) rendered offscreen with wgpu.",
    )
    parser.add_argument("--version", action="version", version=f"wgpu-shading {__version__}")
    # Options of every command that uses the GPU.
    gpu = argparse.ArgumentParser(add_help=False)
    gpu.add_argument(
        "--adapter", help="lavapipe (default), gpu, or part of an adapter's name; also WGPU_SHADING_ADAPTER"
    )
    # Imported here, not at the top: start_process sets the environment before numpy loads.
    from . import batch, bench, check, info, render, view

    commands = parser.add_subparsers(dest="command", metavar="COMMAND")
    commands.required = True
    if command is not None:
        commands = _OnlyCommand(commands, command)

    render.add_render(commands, gpu)
    check.add_check(commands, gpu)
    bench.add_bench(commands, gpu)
    batch.add_batch(commands, gpu)
    render.add_shader(commands, gpu)
    info.add_info(commands, gpu)
    view.add_view(commands, gpu)
    return parser


def _one_line_warning(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"wgpu-shading: warning: {message}", file=sys.stderr)


def _option_name(destination: str) -> str:
    return "input" if destination in ("input", "manifest") else "--" + destination.replace("_", "-")


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that every clean-up runs (a file being written is left
    as it was: its temporary is removed; see assets/atomic.py). Python's default for SIGTERM
    is to die at once, leaving temporaries and child processes behind."""


def _terminate(signum, frame) -> None:
    raise Terminated()


def unraisable_hook(unraisable) -> None:
    """sys.unraisablehook while the CLI runs.

    A signal's exception raised while a destructor runs (a wgpu object's __del__, called by
    the garbage collector between any two lines) is swallowed there ("Exception ignored in
    ..."), and the command went on: a turntable of 1,000,000 frames kept rendering after
    SIGTERM. The signal is raised again, so its handler runs again: from a helper thread, a
    moment later, so that it lands in ordinary code and not in this hook (should it land in
    a destructor again, this hook sends it again).

    A wgpu object whose __init__ the signal interrupted is half made, and wgpu-py 0.32's
    GPUObjectBase.__del__ reads what __init__ had not set yet (`_internal`, a buffer's
    `_mapped_memoryviews`: wgpu/_classes.py, wgpu/backends/wgpu_native/_api.py `_release`),
    which printed "Exception ignored ... AttributeError" under `wgpu-shading: interrupted`.
    That one is not printed: the process is ending, and it frees what the object held.
    Any other error in a destructor is printed as Python does."""
    error = unraisable.exc_value
    if isinstance(error, KeyboardInterrupt):  # Terminated too
        signum = signal.SIGTERM if isinstance(error, Terminated) else signal.SIGINT
        resend = threading.Timer(0.01, os.kill, (os.getpid(), signum))
        resend.daemon = True
        resend.start()
    elif not _half_made_wgpu_object(unraisable):
        sys.__unraisablehook__(unraisable)


def _half_made_wgpu_object(unraisable) -> bool:
    error, where = unraisable.exc_value, unraisable.object
    return (
        isinstance(error, AttributeError)
        and getattr(where, "__name__", "") == "__del__"
        and getattr(where, "__module__", "").startswith("wgpu.")
        and type(error.obj).__module__.startswith("wgpu.")
    )


def console_main() -> NoReturn:
    """The `wgpu-shading` program (pyproject's [project.scripts]): what the process sets for
    itself (process_start.py), one command, then the end of the process (process_end.py).
    main() is the same command for callers in-process."""
    start_process()
    end_process(main(owns_process=True))


def main(argv: Sequence[str] | None = None, *, owns_process: bool = False) -> int:
    """Run one command line; its exit status. `owns_process`: the caller is the installed
    program, whose process runs this command only (process_start.py)."""
    if threading.current_thread() is not threading.main_thread():
        return _main(argv, owns_process)
    previous = signal.signal(signal.SIGTERM, _terminate)
    previous_hook, sys.unraisablehook = sys.unraisablehook, unraisable_hook
    try:
        return _main(argv, owns_process)
    except Terminated:  # arrived after _main's own handlers
        print("wgpu-shading: terminated", file=sys.stderr)
        return 143
    finally:
        signal.signal(signal.SIGTERM, previous)
        sys.unraisablehook = previous_hook


def _main(argv: Sequence[str] | None, owns_process: bool) -> int:
    parser = build_parser(_named_command(argv))
    try:
        args = parser.parse_args(argv)
    except SystemExit as exit_:  # a usage error, printed already (--help and --version exit 0)
        if not exit_.code:
            raise
        return EXIT_USAGE
    args.command_line = list(argv if argv is not None else sys.argv[1:])  # as typed (check --report repeats it)
    # trimesh logs file problems it works around (e.g. a PLY's missing texture image) with
    # tracebacks through Python's last-resort handler; the CLI reports files its own way.
    trimesh_log = logging.getLogger("trimesh")
    if not trimesh_log.handlers:
        trimesh_log.addHandler(logging.NullHandler())
    for name, value in vars(args).items():
        # No file name or value holds a NUL character; os calls would raise ValueError deep inside.
        for text in value if isinstance(value, list) else [value]:
            if isinstance(text, str) and "\x00" in text:
                print(f"wgpu-shading: error: {_option_name(name)} {shorten(repr(text), 80)} contains a NUL character", file=sys.stderr)
                return EXIT_USAGE
    try:
        with warnings.catch_warnings():
            # A file's problems that do not stop the render (a missing texture or .mtl):
            # one line each, like errors, instead of Python's two lines with source code.
            warnings.simplefilter("always", UserWarning)
            warnings.showwarning = _one_line_warning
            if owns_process:
                command_starts(args.command, getattr(args, "adapter", None))
            return args.handler(args)
    except WgpuShadingError as error:
        print(f"wgpu-shading: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except BrokenPipeError:
        # The reader of a text command's output went away (`wgpu-shading shader … | head`):
        # stop quietly as text tools do, pointing stdout at /dev/null so that the flush at
        # exit cannot fail a second time (docs.python.org/3/library/signal.html#note-on-sigpipe).
        # `-o -` raises its own UsageError instead: a PNG cut short is an error worth a line.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
        return EXIT_BROKEN_PIPE
    except OSError as error:  # unwritable output, full disk, ...
        print(f"wgpu-shading: error: {error}", file=sys.stderr)
        return EXIT_USAGE
    except Terminated:
        print("wgpu-shading: terminated", file=sys.stderr)
        return 143  # 128 + SIGTERM, as a shell reports a process it killed
    except KeyboardInterrupt:
        print("wgpu-shading: interrupted", file=sys.stderr)
        return 130
    except Exception as error:  # a bug, not bad input: still one line, the traceback on request
        if os.environ.get("WGPU_SHADING_DEBUG"):
            raise
        print(
            f"wgpu-shading: internal error: {type(error).__name__}: {error} "
            "(set WGPU_SHADING_DEBUG=1 for the traceback, and please report it)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
