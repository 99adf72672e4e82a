"""Time and peak memory of the CLI on hostile mesh files (OBJ, PLY) of few bytes and many
corners, each written here (docs/reliability.md, "Limits", quotes the result):

    python benchmarks/scripts/hostile_files.py [--smoke] [FOLDER]

Each file is rendered by `wgpu-shading render FILE -o out.png --size 64` in a fresh
process; the table gives its exit status, the last line it printed, wall seconds and the
process's peak resident memory (os.wait4's usage of that child). FOLDER (default: a temporary one,
removed after) holds the files, 48-80 MB each. --smoke: the same files a thousandth the
size, under every limit (the test suite's run: each is read and drawn, exit 0).
"""

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"


def _ply_header(encoding: str) -> bytes:
    """A PLY of the square's 4 vertices and one face, as `list int int` (counts up to 2^31)."""
    return (f"ply\nformat {encoding} 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list int int vertex_indices\nend_header\n").encode()


def _repeated(file, piece: bytes, times: int) -> None:
    """`piece` written `times` times, 65,536 at a time: the files are never whole in this
    process (a child process starts with its parent's peak resident memory as its own,
    across exec, and the table gives the child's)."""
    for start in range(0, times, 1 << 16):
        file.write(piece * min(1 << 16, times - start))


def _obj(*lines: tuple[bytes, bytes, int]):
    """An OBJ of the square's vertices, then lines of a prefix and a piece repeated."""
    def write(file):
        file.write(SQUARE.encode())
        for prefix, piece, times in lines:
            file.write(prefix)
            _repeated(file, piece, times)
            file.write(b"\n")
    return write


def _one_face_ply(corners: int, binary: bool):
    def write(file):
        file.write(_ply_header("binary_little_endian" if binary else "ascii"))
        if binary:
            file.write(np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], "<f4").tobytes() + np.int32(corners).tobytes())
            _repeated(file, np.arange(4, dtype="<i4").tobytes(), corners // 4)
        else:
            file.write(b"0 0 0\n1 0 0\n1 1 0\n0 1 0\n" + str(corners).encode())
            _repeated(file, b" 0 1 2 3", corners // 4)
            file.write(b"\n")
    return write


def files(scale: int) -> dict:
    """label → (file suffix, a function writing the file), its repeats divided by `scale`."""
    return {
        "one face of 24M repeated corners": (".obj", _obj((b"f", b" 1 2 3 4", 6_000_000 // scale))),
        "24 faces of 1M repeated corners": (".obj", _obj(*[(b"f", b" 1 2 3 4", 250_000 // scale)] * 24)),
        "one `l` record of 24M vertices": (".obj", _obj((b"l", b" 1 2 3 4", 6_000_000 // scale))),
        "40 faces of 1M corners (40M triangles)": (".obj", _obj(*[(b"f 1", b" 2 3 4 2", 250_000 // scale)] * 40)),
        "a concave face through one point, 8,000 corners": (".obj", _obj((b"f 1", b" 2 3 4 2", max(2_000 // scale, 100)))),
        "a binary PLY of one face of 12M corners": (".ply", _one_face_ply(12_000_000 // scale, binary=True)),
        "an ASCII PLY of one face of 12M corners": (".ply", _one_face_ply(12_000_000 // scale, binary=False)),
    }


def main() -> None:
    arguments = [a for a in sys.argv[1:] if a != "--smoke"]
    scale = 1000 if "--smoke" in sys.argv[1:] else 1
    folder = Path(arguments[0]) if arguments else Path(tempfile.mkdtemp(prefix="hostile-files-"))
    folder.mkdir(parents=True, exist_ok=True)
    cli = str(Path(sys.executable).with_name("wgpu-shading"))
    print("| file | MB | exit | last line | wall s | peak RSS MB |\n|---|---:|---:|---|---:|---:|")
    try:
        for index, (label, (suffix, write)) in enumerate(files(scale).items()):
            path = folder / f"hostile{index}{suffix}"
            with open(path, "wb") as file:
                write(file)
            start = time.perf_counter()
            with tempfile.TemporaryFile("w+") as output:
                child = subprocess.Popen([cli, "render", str(path), "-o", str(folder / "out.png"), "--size", "64"],
                                         stdout=output, stderr=subprocess.STDOUT)
                _, status, usage = os.wait4(child.pid, 0)  # this child's own peak, not the largest so far
                child.returncode = os.waitstatus_to_exitcode(status)
                wall = time.perf_counter() - start
                output.seek(0)
                last = output.read().strip().splitlines()[-1][:110].replace("|", "/")
            print(f"| {label} | {path.stat().st_size / 1e6:.2f} | {child.returncode} | {last} | {wall:.1f} | "
                  f"{usage.ru_maxrss / 1024:.0f} |", flush=True)
            path.unlink()
    finally:
        if not arguments:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
