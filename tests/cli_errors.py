"""The command line's answer to bad input as the tests check it (docs/reliability.md): exit
status 2 and one line on standard error that names the file, key or flag."""

from __future__ import annotations

import warnings

from wgpu_shading.cli.main import main


def run_cli(capsys, *args: str) -> tuple[int, str]:
    """`wgpu-shading ARGS` in this process: (exit status, standard error). A warning is an
    error here, so no numpy RuntimeWarning can leak onto standard error unnoticed."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code = main(list(args))
    return code, capsys.readouterr().err


def one_line_error(code: int, err: str, *words: str) -> str:
    """Assert exit status 2 and a single line containing every one of `words`; return it."""
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]
