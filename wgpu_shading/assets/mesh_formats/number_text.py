"""Whitespace-separated numbers in text (OBJ's v/vt/vn and f lines), read in C.

Plain decimals (`-0.037830`, `12`, `.5`, `6.14986e-005`) are read as float64 through
integers: the exact value strtod gives, at a third of np.fromstring's time.

np.fromstring(text, float64, sep=" ") takes ~185 ns a number here (20 ms of the Stanford
bunny's 75 ms OBJ load), its integer reading ~20 ns. A decimal with at most 15 digits is
m / 10**k with an integer m < 2**53 and k <= 15: both are exact doubles, and one IEEE
division of exact operands is correctly rounded, so the quotient is the double nearest the
decimal, which is what strtod returns (Clinger's fast path: W. D. Clinger, "How to read
floating point numbers accurately", PLDI 1990). So the digits are read as integers with
the dots removed, and each divided by the power of ten its fraction had. An exponent moves
that power: m * 10**p or m / 10**-p, still one operation on exact doubles while |p| <= 22.

A number with more digits (up to 18: still an exact int64) or a larger power (`8.2e-17`,
which %e writes for a coordinate that is zero but for rounding) is read by float() alone,
the same correctly rounded value, while the rest keep the fast path: one such number no
longer sends its whole block to np.fromstring, ten times slower. Anything else (nan, inf,
a stray character, or many numbers of those) gets None, and the caller reads the text the
usual way.
"""

from __future__ import annotations

import re
import warnings
from typing import Callable, Sequence

import numpy as np

EXACT_DIGITS = 15  # every integer of 15 digits is below 2**53: exact as a double
EXACT_POWER = 22  # 10**22 = 2**22 * 5**22, and 5**22 < 2**53: the largest power of ten that is exact
INTEGER_DIGITS = 18  # every integer of 18 digits is an int64: read as one, then by float() (above)
_POWERS_OF_TEN = np.array([float(10**k) for k in range(EXACT_POWER + 1)])  # exact doubles

BLANK_BYTES = np.zeros(256, bool)  # byte → whether it separates numbers
BLANK_BYTES[[9, 10, 11, 12, 13, 32]] = True  # what str.split() and np.fromstring(sep=" ") skip

_BLANK, _DIGIT, _DOT, _EXPONENT, _MINUS, _PLUS, _OTHER = range(7)
_KIND = np.full(256, _OTHER, np.uint8)
_KIND[BLANK_BYTES] = _BLANK
_KIND[48:58] = _DIGIT
_KIND[ord(".")] = _DOT
_KIND[[ord("e"), ord("E")]] = _EXPONENT
_KIND[ord("-")] = _MINUS
_KIND[ord("+")] = _PLUS
# The same tables for bytes.translate (blank_bytes, _decimals): numpy's indexing of a table by
# the bytes first makes an intp copy of them, 8 bytes a byte of text (the bunny's OBJ: 19 MB,
# whose page faults made its first load in a process 16 ms slower; this: 2 ms).
_BLANK_TABLE = BLANK_BYTES.astype(np.uint8).tobytes()
_KIND_TABLE = _KIND.tobytes()


def parse_numbers(text: str | bytes, dtype) -> np.ndarray | None:
    """Whitespace-separated numbers parsed in C; None when some token is not a number."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)  # "could not be read to its end"
        try:
            return np.fromstring(text, dtype=dtype, sep=" ")
        except (ValueError, DeprecationWarning):
            return None


def parse_floats(text: str | bytes, line_width: int | None = None) -> np.ndarray | None:
    """float64 numbers of `text` (exponents, nan and inf too); None when some token is not
    one, or, with `line_width`, when some line (up to a line break; the last one without
    one too) does not hold exactly that many: in a block of lines whose widths err in
    opposite directions (`v 1 2 3 4` then `v 1 2`) the total is right, and the rows read
    from it would be shifted."""
    text = _ascii(text)
    found = None if text is None else _decimals(text)
    if found is None:
        values = parse_numbers(text, np.float64) if text is not None else None
        starts = None
    else:
        values, starts = found
    if values is not None and line_width is not None and (numbers_per_line(text, starts) != line_width).any():
        return None
    return values


def blank_bytes(data: bytes | np.ndarray) -> np.ndarray:
    """Per byte of `data` (bytes, or uint8): whether it separates numbers (BLANK_BYTES[data])."""
    text = data if isinstance(data, bytes) else np.ascontiguousarray(data, np.uint8).tobytes()
    return np.frombuffer(text.translate(_BLANK_TABLE), bool)


def word_starts(data: bytes | np.ndarray, blank: np.ndarray | None = None) -> np.ndarray:
    """Per byte of `data` (bytes, or uint8): whether a whitespace-separated word begins there
    (`blank`: its blank_bytes, when the caller has them)."""
    blank = blank_bytes(data) if blank is None else blank
    starts = ~blank
    starts[1:] &= blank[:-1]
    return starts


def numbers_per_line(text: bytes, starts: np.ndarray | None = None) -> np.ndarray:
    """How many whitespace-separated words each line of `text` holds (lines end at a line
    break; a last line without one counts); `starts`: where the words begin, when known."""
    data = np.frombuffer(text, np.uint8)
    if starts is None:
        starts = np.flatnonzero(word_starts(text))
    ends = np.flatnonzero(data == 10)
    if len(data) and data[-1] != 10:
        ends = np.append(ends, len(data))
    return np.diff(np.searchsorted(starts, ends), prepend=0)


def _ascii(text: str | bytes) -> bytes | None:
    """`text` as bytes; None for a str with characters beyond ASCII (never a number)."""
    if isinstance(text, bytes):
        return text
    try:
        return text.encode("ascii")
    except UnicodeEncodeError:
        return None


LEADING_COUNT = re.compile(r"[ \t]*(\d+)")  # a line's first number, a count (a PLY or OFF face's corners)
TOKENS_AT_ONCE = 1 << 18  # tokens joined and read together: bounded temporaries


def read_in_blocks(pieces: Sequence, per_block: int, read: Callable[[Sequence], np.ndarray | None], dtype=np.float64) -> np.ndarray | None:
    """read(block) for each block of `per_block` pieces (lines or words), concatenated: the
    temporaries of reading text in C (a few bytes a character) stay bounded however big the
    file. None as soon as one block gives None."""
    blocks = []
    for start in range(0, len(pieces), per_block):
        block = read(pieces[start : start + per_block])
        if block is None:
            return None
        blocks.append(block)
    return blocks[0] if len(blocks) == 1 else np.concatenate(blocks or [np.empty(0, dtype)])


def tokens_as_numbers(tokens: list[str], dtype) -> np.ndarray:
    """float64 or int64 values of number words (from str.split()), the same as
    np.array(tokens, dtype) gives, read in C a block of TOKENS_AT_ONCE words at a time
    (floats through parse_decimals); a block in another form is read the usual way, which
    raises ValueError for a word that is not a number."""
    dtype = np.dtype(dtype)

    def read(block: list[str]) -> np.ndarray:
        text = " ".join(block)
        values = parse_decimals(text) if dtype == np.float64 else parse_numbers(text, dtype)
        return values if values is not None and values.size == len(block) else np.array(block, dtype=dtype)

    return read_in_blocks(tokens, TOKENS_AT_ONCE, read, dtype)


def parse_decimals(text: str | bytes) -> np.ndarray | None:
    """The whitespace-separated numbers of `text` as float64, equal bit for bit to what
    float() gives each (the sign of a zero too), when every one is a plain decimal: an
    optional sign, 1 to INTEGER_DIGITS digits with at most one dot, and optionally an
    exponent (`e` or `E`, an optional sign, 1 to 4 digits) (`6.14986e-005`, as C++ streams
    write small numbers). Those with more than EXACT_DIGITS digits or a power of ten beyond
    ±EXACT_POWER are read by float() one by one, when they are few. None otherwise.
    `text` may be bytes (a reader's block, not decoded: any byte beyond ASCII gives None)."""
    text = _ascii(text)
    found = None if text is None else _decimals(text)
    return None if found is None else found[0]


def _decimals(text: bytes) -> tuple[np.ndarray, np.ndarray] | None:
    """parse_decimals of bytes, and where each number begins in them."""
    data = np.frombuffer(text, np.uint8)
    kind = np.frombuffer(text.translate(_KIND_TABLE), np.uint8)
    if kind.max(initial=_BLANK) == _OTHER:
        return None
    filled = np.zeros(len(data) + 2, bool)  # a blank before and after the text
    np.not_equal(kind, _BLANK, out=filled[1:-1])
    starts = np.flatnonzero(filled[1:] > filled[:-1])  # each number's first character
    ends = np.flatnonzero(filled[:-1] > filled[1:])  # one past its last
    count = len(starts)
    if not count:
        return np.empty(0, np.float64), starts
    mantissa_ends = ends.copy()  # where each number's digits end: its `e`, or its end
    exponents_at = np.flatnonzero(kind == _EXPONENT)
    has_exponent = np.zeros(count, bool)
    exponent_signed = np.zeros(len(exponents_at), bool)
    if len(exponents_at):
        owner = np.searchsorted(starts, exponents_at, "right") - 1
        if len(owner) > 1 and not (np.diff(owner) > 0).all():  # two in one number
            return None
        has_exponent[owner] = True
        mantissa_ends[owner] = exponents_at
        after = data[np.minimum(exponents_at + 1, len(data) - 1)]
        exponent_signed = ((after == ord("-")) | (after == ord("+"))) & (exponents_at + 1 < len(data))
    first = data[starts]
    negative = first == ord("-")
    signed = negative | (first == ord("+"))
    # Signs only at a number's start or right after its `e`: counting those finds any other.
    if np.count_nonzero(kind >= _MINUS) != np.count_nonzero(signed) + np.count_nonzero(exponent_signed):
        return None
    dots = np.flatnonzero(kind == _DOT)
    fraction_digits = np.zeros(count, np.intp)
    has_dot = np.zeros(count, bool)
    if len(dots) == count and ((starts < dots) & (dots < mantissa_ends)).all():  # one in each (most files)
        fraction_digits = mantissa_ends - dots - 1
        has_dot[:] = True
    elif len(dots):
        owner = np.searchsorted(starts, dots, "right") - 1
        if len(owner) > 1 and not (np.diff(owner) > 0).all():  # two in one number
            return None
        if not (dots < mantissa_ends[owner]).all():  # a dot in an exponent
            return None
        fraction_digits[owner] = mantissa_ends[owner] - dots - 1
        has_dot[owner] = True
    digits = mantissa_ends - starts - signed - has_dot
    if digits.min() < 1 or digits.max() > INTEGER_DIGITS:
        return None
    inexact = digits > EXACT_DIGITS  # read by float() below
    if len(exponents_at):
        exponent_digits = ends[has_exponent] - exponents_at - 1 - exponent_signed
        if exponent_digits.min() < 1 or exponent_digits.max() > 4:
            return None
    # The digits as integers, base 10 whatever the leading zeros (`-.5` → `-5`); an exponent
    # becomes a second integer after its number's.
    cleaned = text.replace(b".", b"") if len(dots) else text
    if len(exponents_at):
        cleaned = cleaned.replace(b"e", b" ").replace(b"E", b" ")
    integers = parse_numbers(cleaned, np.int64)
    if integers is None or integers.size != count + len(exponents_at):
        return None
    # One multiplication or division of two exact doubles: correctly rounded (module docstring).
    if not len(exponents_at):
        values = np.abs(integers).astype(np.float64)
        values /= _POWERS_OF_TEN[np.minimum(fraction_digits, EXACT_POWER)]
    else:
        mantissa_index = np.arange(count) + np.concatenate([[0], np.cumsum(has_exponent)[:-1]])
        power = -fraction_digits.astype(np.int64)
        power[has_exponent] += integers[mantissa_index[has_exponent] + 1]
        inexact |= (power < -EXACT_POWER) | (power > EXACT_POWER)
        power = np.clip(power, -EXACT_POWER, EXACT_POWER)
        values = np.abs(integers[mantissa_index]).astype(np.float64)
        np.multiply(values, _POWERS_OF_TEN[np.maximum(power, 0)], out=values, where=power > 0)
        np.divide(values, _POWERS_OF_TEN[np.maximum(-power, 0)], out=values, where=power < 0)
    np.negative(values, out=values, where=negative)  # -0.0 stays negative, as float("-0.0")
    if inexact.any():
        slow = np.flatnonzero(inexact)
        if len(slow) > max(64, count >> 6):
            return None  # (many: np.fromstring reads them all faster)
        values[slow] = [float(text[start:end]) for start, end in zip(starts[slow].tolist(), ends[slow].tolist())]
    return values, starts


def leading_counts(lines: list[str], numbers: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Per line: its first number, a count, and where that is among `numbers` (the lines'
    numbers, in order), or None when a line holds other than its count and that many
    numbers after it (a face line of a PLY or an OFF: `4 a b c d`)."""
    records = counted_lines(lines, numbers)
    if records is None or (records[2] != records[0] + 1).any():
        return None
    return records[0], records[1]


def counted_lines(lines: list[str], numbers: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Per line: its first number, a count (int64), where that is among `numbers` (the
    lines' numbers, in order, int64 or float64), and how many numbers the line holds; None
    when a line's first number is not a whole count or the line holds fewer numbers than
    its count and the count itself (an OFF face line and what follows its indices: `4 a b c d
    r g b`). Each line's numbers are counted from the bytes where numbers begin."""
    per_line = numbers_per_line("\n".join(lines).encode("latin-1"))
    if len(per_line) != len(lines) or per_line.sum() != numbers.size:  # (an empty last line is not counted)
        return None
    first = np.cumsum(per_line) - per_line
    if (per_line < 1).any():
        return None
    counts = numbers[first]
    if counts.dtype != np.int64:
        if not (np.isfinite(counts) & (counts == np.floor(counts)) & (np.abs(counts) < 2**62)).all():
            return None
        counts = counts.astype(np.int64)
    if (per_line < counts + 1).any() or (counts < 0).any():
        return None
    return counts, first, per_line
