"""Uniform layouts, derived from the WGSL struct declarations.

`wgsl/structs.wgsl` is the one place a uniform layout is declared. This module reads
the struct declarations of a generated shader and computes WGSL's host-shareable
layout (alignment and size rules of the WGSL spec, §"Memory Layout") as a numpy
structured dtype, so Python fills buffers by field name and can never drift from the
shader. A GPU test (tests/test_layout.py, test_layout_on_the_gpu) proves the offsets by
reading every field back through a compute shader.

Matrices are column-major with each column padded to its vector alignment; numpy sees
matCxR<f32> as shape (C, padded R): store `matrix.T` of a row-major numpy matrix.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

_COMMENTS = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)
_STRUCT = re.compile(r"\bstruct\s+(\w+)\s*\{(.*?)\}", re.S)
_CONST = re.compile(r"\bconst\s+(\w+)\s*:\s*[iu]32\s*=\s*(\d+)[iu]?\s*;")
_ATTRIBUTE = re.compile(r"@\w+(\s*\([^)]*\))?")
_VECTOR = re.compile(r"^vec([234])<\s*(f32|u32|i32)\s*>$")
_MATRIX = re.compile(r"^mat([234])x([234])<\s*f32\s*>$")
_ARRAY = re.compile(r"^array<\s*(.+?)\s*,\s*(\w+)\s*>$")

_SCALARS = {"f32": "<f4", "u32": "<u4", "i32": "<i4"}


class LayoutError(Exception):
    """A struct that cannot be laid out (a bug in the WGSL sources)."""


@dataclass(frozen=True)
class TypeLayout:
    """A WGSL type's host layout: its numpy dtype (with padding), alignment and size in bytes."""

    dtype: np.dtype
    align: int
    size: int


def _round_up(value: int, multiple: int) -> int:
    return (value + multiple - 1) // multiple * multiple


def _split_fields(body: str) -> list[tuple[str, str]]:
    """`name: type` pairs of a struct body; commas inside <...> do not split."""
    fields, depth, current = [], 0, []
    for char in body + ",":
        if char == "<":
            depth += 1
        elif char == ">":
            depth -= 1
        if char == "," and depth == 0:
            text = _ATTRIBUTE.sub("", "".join(current)).strip()
            current = []
            if text:
                name, _, wgsl_type = text.partition(":")
                fields.append((name.strip(), wgsl_type.strip()))
        else:
            current.append(char)
    return fields


class Layouts:
    """All struct layouts of one WGSL module."""

    def __init__(self, source: str):
        text = _COMMENTS.sub("", source)
        self._structs = {name: _split_fields(body) for name, body in _STRUCT.findall(text)}
        self._constants = {name: int(value) for name, value in _CONST.findall(text)}
        self._cache: dict[str, TypeLayout] = {}

    def __contains__(self, name: str) -> bool:
        return name in self._structs

    def dtype(self, struct_name: str) -> np.dtype:
        return self.of(struct_name).dtype

    def of(self, wgsl_type: str) -> TypeLayout:
        wgsl_type = wgsl_type.strip()
        if wgsl_type not in self._cache:
            self._cache[wgsl_type] = self._compute(wgsl_type)
        return self._cache[wgsl_type]

    def _compute(self, wgsl_type: str) -> TypeLayout:
        if wgsl_type in _SCALARS:
            return TypeLayout(np.dtype(_SCALARS[wgsl_type]), 4, 4)
        if match := _VECTOR.match(wgsl_type):
            n = int(match.group(1))
            align = {2: 8, 3: 16, 4: 16}[n]
            return TypeLayout(np.dtype((_SCALARS[match.group(2)], (n,))), align, 4 * n)
        if match := _MATRIX.match(wgsl_type):
            columns, rows = int(match.group(1)), int(match.group(2))
            column_align = {2: 8, 3: 16, 4: 16}[rows]
            padded_rows = column_align // 4
            return TypeLayout(np.dtype(("<f4", (columns, padded_rows))), column_align, columns * column_align)
        if match := _ARRAY.match(wgsl_type):
            element = self.of(match.group(1))
            count_text = match.group(2)
            count = int(count_text) if count_text.isdigit() else self._constants.get(count_text)
            if count is None:
                raise LayoutError(f"array count {count_text!r} is not a known constant")
            stride = _round_up(element.size, element.align)
            if stride % 16:
                # Uniform address space: array strides must be multiples of 16.
                raise LayoutError(f"{wgsl_type}: element stride {stride} is not a multiple of 16")
            element_dtype = element.dtype
            if element_dtype.itemsize != stride:
                element_dtype = np.dtype({"names": ["value"], "formats": [element_dtype], "offsets": [0], "itemsize": stride})
            return TypeLayout(np.dtype((element_dtype, (count,))), element.align, stride * count)
        if wgsl_type in self._structs:
            names, formats, offsets = [], [], []
            offset, align = 0, 1
            previous_was_struct = False
            for name, field_type in self._structs[wgsl_type]:
                member = self.of(field_type)
                member_align = max(member.align, 16) if field_type in self._structs else member.align
                if previous_was_struct:
                    member_align = max(member_align, 16)  # uniform rule: a struct member ends a 16-byte slot
                offset = _round_up(offset, member_align)
                names.append(name)
                formats.append(member.dtype)
                offsets.append(offset)
                offset += member.size
                align = max(align, member_align)
                previous_was_struct = field_type in self._structs
            size = _round_up(offset, align)
            dtype = np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": size})
            return TypeLayout(dtype, align, size)
        raise LayoutError(f"unsupported WGSL type {wgsl_type!r}")


@lru_cache(maxsize=256)
def layouts_for(source: str) -> Layouts:
    return Layouts(source)


def field_offsets(dtype: np.dtype, prefix: str = "") -> dict[str, int]:
    """Flattened byte offsets of every leaf field: {'lights[0].position': 48, ...} style, for docs and tests."""
    result: dict[str, int] = {}
    for name in dtype.names or ():
        field_dtype, offset = dtype.fields[name][:2]
        base = field_dtype.base if field_dtype.subdtype else field_dtype
        if base.names:
            count = field_dtype.shape[0] if field_dtype.shape else 1
            for index in range(count):
                element_name = f"{prefix}{name}[{index}]" if field_dtype.shape else f"{prefix}{name}"
                inner = base
                if inner.names == ("value",):
                    inner = inner.fields["value"][0]
                for key, value in field_offsets(inner, element_name + ".").items():
                    result[key] = offset + index * base.itemsize + value
        else:
            result[f"{prefix}{name}"] = offset
    return result
