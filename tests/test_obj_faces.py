"""OBJ face lines read at once in numpy (assets/mesh_formats/obj_faces.fans_at_once) against
the plainest reading of the same lines: each line split into tokens, each token into up to
three numbers at its slashes (an empty one absent, 0), each polygon cut into its fan from
its first corner. Random lines of every corner form (`a`, `a/b`, `a//c`, `a/b/c`), sizes
3-6, blanks and tabs, and now and then a form mixed into a run, a bad number or a face of
two corners (then the vectorised reading must decline: None)."""

from __future__ import annotations

import numpy as np
import pytest

from wgpu_shading.assets.mesh_formats.obj_faces import fans_at_once

FORMS = ("{v}", "{v}/{t}", "{v}//{n}", "{v}/{t}/{n}")


def _reference(lines: list[str]) -> tuple[np.ndarray, np.ndarray] | None:
    triangles, polygon = [], []
    for number, line in enumerate(lines):
        corners = []
        for token in line.split()[1:]:
            parts = (token.split("/") + ["", ""])[:3]
            if len(token.split("/")) > 3 or not all(part == "" or part.lstrip("-").isdigit() for part in parts):
                return None
            corners.append([int(part) if part else 0 for part in parts])
        if len(corners) < 3:
            return None
        for k in range(1, len(corners) - 1):
            triangles.append([corners[0], corners[k], corners[k + 1]])
            polygon.append(number)
    return np.array(triangles, np.int64).reshape(-1, 3, 3), np.array(polygon)


def _lines(rng) -> list[str]:
    form = str(rng.choice(FORMS))
    lines = []
    for _ in range(int(rng.integers(1, 40))):
        size = 3 if rng.random() < 0.7 else int(rng.integers(2 if rng.random() < 0.05 else 3, 7))
        corner_form = form if rng.random() < 0.97 else str(rng.choice(FORMS))
        tokens = [corner_form.format(v=int(rng.integers(1, 99)), t=int(rng.integers(1, 99)), n=int(rng.integers(1, 99))) for _ in range(size)]
        if rng.random() < 0.02:
            tokens[int(rng.integers(0, size))] = "x"
        blank = " " if rng.random() < 0.8 else str(rng.choice(["  ", "\t", " \t "]))
        lines.append("f" + blank + blank.join(tokens) + (" " if rng.random() < 0.1 else "") + ("\r" if rng.random() < 0.05 else ""))
    return lines


@pytest.mark.parametrize("seed", range(6))
def test_face_lines_read_at_once_are_the_plain_reading(seed):
    rng = np.random.default_rng(seed)
    declined = 0
    for _ in range(100):
        lines = _lines(rng)
        fast, expected = fans_at_once(lines), _reference(lines)
        if fast is None:
            declined += 1
            continue
        assert expected is not None, lines
        np.testing.assert_array_equal(fast[0], expected[0], err_msg="\n".join(lines))
        np.testing.assert_array_equal(fast[1], expected[1])
    assert declined < 100
