"""Whitespace-separated numbers in text (OBJ's v/vt/vn and f lines), read in C.

Plain decimals (`-0.037830`, `12`, `.5`) are read as float64 through integers: the exact
value strtod gives, at a third of np.fromstring's time.

np.fromstring(text, float64, sep=" ") takes ~185 ns a number here (20 ms of the Stanford
bunny's 75 ms OBJ load), its integer reading ~20 ns. A decimal with at most 15 digits is
m / 10**k with an integer m < 2**53 and k <= 15: both are exact doubles, and one IEEE
division of exact operands is correctly rounded, so the quotient is the double nearest the
decimal, which is what strtod returns (Clinger's fast path: W. D. Clinger, "How to read
floating point numbers accurately", PLDI 1990). So the digits are read as integers with
the dots removed, and each divided by the power of ten its fraction had.

Anything else (an exponent, more digits, nan, inf, a stray character) gets None, and the
caller reads the text the usual way.
"""

from __future__ import annotations

import warnings

import numpy as np

EXACT_DIGITS = 15  # every integer of 15 digits is below 2**53: exact as a double
_POWERS_OF_TEN = np.array([float(10**k) for k in range(EXACT_DIGITS + 1)])  # exact doubles

_BLANK, _DIGIT, _DOT, _MINUS, _PLUS, _OTHER = range(6)
_KIND = np.full(256, _OTHER, np.uint8)
_KIND[[9, 10, 11, 12, 13, 32]] = _BLANK  # what str.split() and np.fromstring(sep=" ") skip
_KIND[48:58] = _DIGIT
_KIND[ord(".")] = _DOT
_KIND[ord("-")] = _MINUS
_KIND[ord("+")] = _PLUS


def parse_numbers(text: str, dtype) -> np.ndarray | None:
    """Whitespace-separated numbers parsed in C; None when some token is not a number."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)  # "could not be read to its end"
        try:
            return np.fromstring(text, dtype=dtype, sep=" ")
        except (ValueError, DeprecationWarning):
            return None


def parse_floats(text: str) -> np.ndarray | None:
    """float64 numbers of `text` (exponents, nan and inf too); None when some token is not one."""
    values = parse_decimals(text)
    return values if values is not None else parse_numbers(text, np.float64)


def parse_decimals(text: str) -> np.ndarray | None:
    """The whitespace-separated numbers of `text` as float64, equal bit for bit to what
    float() gives each (the sign of a zero too), when every one is a plain decimal: an
    optional sign, digits with at most one dot, 1 to EXACT_DIGITS digits. None otherwise."""
    try:
        data = np.frombuffer(text.encode("ascii"), np.uint8)
    except UnicodeEncodeError:
        return None
    kind = np.take(_KIND, data)
    if kind.max(initial=_BLANK) == _OTHER:
        return None
    filled = np.zeros(len(data) + 2, bool)  # a blank before and after the text
    np.not_equal(kind, _BLANK, out=filled[1:-1])
    starts = np.flatnonzero(filled[1:] > filled[:-1])  # each number's first character
    ends = np.flatnonzero(filled[:-1] > filled[1:])  # one past its last
    if not len(starts):
        return np.empty(0, np.float64)
    digits = ends - starts
    first = data[starts]
    negative = first == ord("-")
    signed = negative | (first == ord("+"))
    if np.count_nonzero(kind >= _MINUS) != np.count_nonzero(signed):  # a sign after a number's start
        return None
    digits -= signed
    dots = np.flatnonzero(kind == _DOT)
    fraction_digits = np.zeros(len(starts), np.intp)
    if len(dots) == len(starts) and ((starts < dots) & (dots < ends)).all():  # one in each (most files)
        fraction_digits = ends - dots - 1
        digits -= 1
    elif len(dots):
        owner = np.searchsorted(starts, dots, "right") - 1
        if len(owner) > 1 and not (np.diff(owner) > 0).all():  # two dots in one number
            return None
        fraction_digits[owner] = ends[owner] - dots - 1
        digits[owner] -= 1
    if (digits.min() < 1 or digits.max() > EXACT_DIGITS):
        return None
    # Base 10 whatever the leading zeros; a sign before the digits (`-.5` → `-5`) is read too.
    mantissas = parse_numbers(text.replace(".", "") if len(dots) else text, np.int64)
    if mantissas is None or mantissas.size != len(starts):
        return None
    values = np.abs(mantissas).astype(np.float64) / _POWERS_OF_TEN[fraction_digits]
    np.negative(values, out=values, where=negative)  # -0.0 stays negative, as float("-0.0")
    return values
