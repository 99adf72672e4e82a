"""Numbers read from text (assets/mesh_formats/number_text.py): the fast decimal reading is
checked bit for bit against Python's float() (correctly rounded, an independent reference),
and everything outside its form must be refused so the caller reads it the usual way."""

import numpy as np
import pytest

from wgpu_shading.assets.mesh_formats.number_text import EXACT_DIGITS, parse_decimals, parse_floats


def _bits(values) -> np.ndarray:
    return np.asarray(values, np.float64).view(np.int64)


def _random_decimals(rng, count: int) -> list[str]:
    tokens = []
    for _ in range(count):
        digits = "".join(rng.choice(list("0123456789"), int(rng.integers(1, EXACT_DIGITS + 1))))
        dot = int(rng.integers(0, len(digits) + 1))
        number = digits[:dot] + "." + digits[dot:] if rng.random() < 0.9 else digits  # `.5`, `5.`, `12`
        tokens.append(str(rng.choice(["", "-", "+"], p=[0.5, 0.4, 0.1])) + number)
    return tokens


def test_plain_decimals_are_what_float_gives_bit_for_bit():
    rng = np.random.default_rng(29)
    tokens = _random_decimals(rng, 50_000)
    separators = rng.choice([" ", "  ", "\n", "\t", " \r\n"], len(tokens))
    text = "".join(f"{token}{separator}" for token, separator in zip(tokens, separators))
    values = parse_decimals(text)
    assert values is not None
    assert np.array_equal(_bits(values), _bits([float(token) for token in tokens]))


def test_what_exporters_write():
    rng = np.random.default_rng(7)
    coordinates = rng.normal(0.0, 10.0, 30_000)
    for style in ("%.6f", "%.4f", "%.9f", "%g"):
        tokens = [style % value for value in coordinates]
        values = parse_floats(" ".join(tokens))
        assert np.array_equal(_bits(values), _bits([float(token) for token in tokens])), style


def test_signed_zeros_and_short_forms():
    values = parse_decimals("  -0.0 +0 5. .5 -.5 007 -000.000100\n")
    assert np.array_equal(_bits(values), _bits([-0.0, 0.0, 5.0, 0.5, -0.5, 7.0, -0.0001]))
    assert parse_decimals("").size == 0 and parse_decimals(" \n ").size == 0


@pytest.mark.parametrize("text", [
    "1e5", "1.5E-3", "nan", "-inf", "1.2.3", "--1", "1-2", "+-1", ".", "-", "+", "1 . 2",
    "1" * (EXACT_DIGITS + 1), "0." + "0" * EXACT_DIGITS, "0x10", "1,2", "\uff11", "1 2 x",
])
def test_other_forms_are_refused(text):
    assert parse_decimals(text) is None


def test_other_forms_are_read_the_usual_way():
    text = "1e-3 2.5 -7E2 " + "1" * 17 + ".5 nan"
    assert np.array_equal(parse_floats(text), np.fromstring(text, np.float64, sep=" "), equal_nan=True)
    assert parse_floats("1 two 3") is None
