"""Numbers read from text (assets/mesh_formats/number_text.py): the fast decimal reading is
checked bit for bit against Python's float() (correctly rounded, an independent reference),
and everything outside its form must be refused so the caller reads it the usual way."""

import numpy as np
import pytest

from wgpu_shading.assets.mesh_formats.number_text import (
    EXACT_DIGITS, EXACT_POWER, INTEGER_DIGITS, blank_bytes, parse_decimals, parse_floats, tokens_as_numbers, word_starts,
)


def _bits(values) -> np.ndarray:
    return np.asarray(values, np.float64).view(np.int64)


def _random_decimals(rng, count: int, exponents: bool = False) -> list[str]:
    tokens = []
    for _ in range(count):
        digits = "".join(rng.choice(list("0123456789"), int(rng.integers(1, EXACT_DIGITS + 1))))
        dot = int(rng.integers(0, len(digits) + 1))
        number = digits[:dot] + "." + digits[dot:] if rng.random() < 0.9 else digits  # `.5`, `5.`, `12`
        if exponents and rng.random() < 0.7:  # e-005, E+3, e7: the power of ten kept within ±EXACT_POWER
            fraction = len(digits) - dot
            power = int(rng.integers(-EXACT_POWER + fraction, EXACT_POWER - len(digits) + 1)) if fraction < EXACT_POWER else 0
            exponent = power + 0
            number += str(rng.choice(["e", "E"])) + str(rng.choice(["", "+", "-"] if exponent >= 0 else ["-"])) + str(abs(exponent)).zfill(int(rng.integers(1, 4)))
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


def test_exponents_are_what_float_gives_bit_for_bit():
    rng = np.random.default_rng(2029)
    tokens = _random_decimals(rng, 50_000, exponents=True)
    values = parse_decimals(" ".join(tokens))
    assert values is not None
    assert np.array_equal(_bits(values), _bits([float(token) for token in tokens]))
    edges = ["6.14986e-005", "-0e5", "1e22", "1e-22", "123456789012345e7", "0.00000000000001e-7", "9.99E+1"]
    assert np.array_equal(_bits(parse_decimals(" ".join(edges))), _bits([float(token) for token in edges]))


def test_what_exporters_write():
    rng = np.random.default_rng(7)
    coordinates = rng.normal(0.0, 10.0, 30_000)
    coordinates[::7] *= 1e-6  # small ones: %g writes them with exponents
    for style in ("%.6f", "%.4f", "%.9f", "%g", "%.6g", "%e", "%.3e"):
        tokens = [style % value for value in coordinates]
        values = parse_floats(" ".join(tokens))
        assert np.array_equal(_bits(values), _bits([float(token) for token in tokens])), style


def test_signed_zeros_and_short_forms():
    values = parse_decimals("  -0.0 +0 5. .5 -.5 007 -000.000100\n")
    assert np.array_equal(_bits(values), _bits([-0.0, 0.0, 5.0, 0.5, -0.5, 7.0, -0.0001]))
    assert parse_decimals("").size == 0 and parse_decimals(" \n ").size == 0


@pytest.mark.parametrize("text", [
    "nan", "-inf", "1.2.3", "--1", "1-2", "+-1", ".", "-", "+", "1 . 2",
    "1" * (INTEGER_DIGITS + 1), "0." + "0" * INTEGER_DIGITS, "0x10", "1,2", "\uff11", "1 2 x",
    "e5", "1e", "1e+", "1e5e5", "1e5.0", "1e--5", "1e-5-", ".e5", "1e00001",
])
def test_other_forms_are_refused(text):
    assert parse_decimals(text) is None


def test_a_few_long_or_far_numbers_are_read_by_float_and_the_rest_the_fast_way():
    """More digits than a double holds exactly, or a power of ten beyond ±22 (`8.266366e-17`,
    as %e writes a coordinate that is zero but for rounding): float()'s value, bit for bit,
    without sending the whole text to np.fromstring; many of them do go there (None)."""
    rng = np.random.default_rng(9)
    few = ["1" * (EXACT_DIGITS + 1), "0." + "0" * EXACT_DIGITS + "1", "-" + "9" * INTEGER_DIGITS, "1e23", "1e-23",
           "-1.5e-30", "8.266366e-17", "-0.000000e-40", "4.9e-324", "1.7976931348623157e308"]
    tokens = _random_decimals(rng, 2000, exponents=True) + few
    rng.shuffle(tokens)
    assert np.array_equal(_bits(parse_decimals(" ".join(tokens))), _bits([float(token) for token in tokens]))
    assert parse_decimals(" ".join(few * 20)) is None  # (200 of 200: np.fromstring's work)


def test_other_forms_are_read_the_usual_way():
    text = "1e-3 2.5 -7E2 1e300 " + "1" * 17 + ".5 nan"
    assert np.array_equal(parse_floats(text), np.fromstring(text, np.float64, sep=" "), equal_nan=True)
    assert parse_floats("1 two 3") is None


def test_tokens_are_read_as_numpy_reads_them():
    """OFF's words (str.split()): the same values as np.array(tokens, dtype), a block at a time."""
    rng = np.random.default_rng(5)
    tokens = _random_decimals(rng, 3000, exponents=True)
    assert np.array_equal(_bits(tokens_as_numbers(tokens, np.float64)), _bits(np.array(tokens, dtype=np.float64)))
    mixed = tokens[:100] + ["nan", "1e300", "1_000"] + tokens[100:200]  # a block np.array reads: the usual way
    assert np.array_equal(tokens_as_numbers(mixed, np.float64), np.array(mixed, dtype=np.float64), equal_nan=True)
    integers = [str(value) for value in rng.integers(-10**12, 10**12, 5000)] + ["+7", "007"]
    assert np.array_equal(tokens_as_numbers(integers, np.int64), np.array(integers, dtype=np.int64))
    with pytest.raises(ValueError):
        tokens_as_numbers(["1.5", "x"], np.float64)
    with pytest.raises(ValueError):
        tokens_as_numbers(["1", "2.0"], np.int64)


def test_bytes_read_as_their_text_does():
    """A reader's block of bytes (never decoded: obj_blocks.py) gives what its text gives,
    bit for bit, including numbers read by float() one by one; bytes beyond ASCII refuse."""
    rng = np.random.default_rng(18)
    tokens = _random_decimals(rng, 5_000, exponents=True) + ["8.266366e-17", "12345678901234567", "-0.0"]
    text = " ".join(tokens)
    from_text, from_bytes = parse_decimals(text), parse_decimals(text.encode())
    assert from_text is not None and np.array_equal(_bits(from_bytes), _bits(from_text))
    assert np.array_equal(_bits(parse_floats(b"1 2.5\n-3e400")[:2]), _bits([1.0, 2.5]))  # (the usual way for inf)
    assert parse_decimals("1 2 é".encode()) is None and parse_decimals("1 2 é") is None


def test_blank_bytes_and_word_starts_are_what_bytes_split_sees():
    """Every byte value, given as bytes and as a uint8 array: blank where bytes.split() splits
    (what np.fromstring skips too), and a word starting after each run of blanks."""
    data = bytes(range(256)) * 3 + b"  v 1.5\t-2\r\n\x0b\x0c f 1 2 3"
    blank = np.array([bytes([byte]).isspace() for byte in data])
    expected = [i for i in range(len(data)) if not blank[i] and (i == 0 or blank[i - 1])]
    assert len(expected) == len(data.split())
    for given in (data, np.frombuffer(data, np.uint8)):
        np.testing.assert_array_equal(blank_bytes(given), blank)
        np.testing.assert_array_equal(np.flatnonzero(word_starts(given)), expected)
