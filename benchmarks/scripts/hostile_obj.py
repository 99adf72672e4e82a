"""Time and peak memory of the CLI on hostile OBJ files of few bytes and many corners, each
written here (docs/reliability.md, "Limits", quotes the result):

    python benchmarks/scripts/hostile_obj.py [--smoke] [FOLDER]

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

SQUARE = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"


def files(scale: int) -> dict:
    """label → a function writing that file (its repeats divided by `scale`)."""
    return {
        "one face of 24M repeated corners": lambda f: f.write(SQUARE + "f" + " 1 2 3 4" * (6_000_000 // scale) + "\n"),
        "24 faces of 1M repeated corners": lambda f: f.write(SQUARE + ("f" + " 1 2 3 4" * (250_000 // scale) + "\n") * 24),
        "one `l` record of 24M vertices": lambda f: f.write(SQUARE + "l" + " 1 2 3 4" * (6_000_000 // scale) + "\n"),
        "40 faces of 1M corners (40M triangles)": lambda f: f.write(SQUARE + ("f 1" + " 2 3 4 2" * (250_000 // scale) + "\n") * 40),
        "a concave face through one point, 8,000 corners": lambda f: f.write(SQUARE + "f 1" + " 2 3 4 2" * max(2_000 // scale, 100) + "\n"),
    }


def main() -> None:
    arguments = [a for a in sys.argv[1:] if a != "--smoke"]
    scale = 1000 if "--smoke" in sys.argv[1:] else 1
    folder = Path(arguments[0]) if arguments else Path(tempfile.mkdtemp(prefix="hostile-obj-"))
    folder.mkdir(parents=True, exist_ok=True)
    cli = str(Path(sys.executable).with_name("wgpu-shading"))
    print("| file | MB | exit | last line | wall s | peak RSS MB |\n|---|---:|---:|---|---:|---:|")
    try:
        for index, (label, write) in enumerate(files(scale).items()):
            path = folder / f"hostile{index}.obj"
            with open(path, "w") as file:
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
