"""Plain text tables of numbers (an x–z profile, x–y–z points, a height matrix), checked before a
reader sees them: SurfaceTopography's text readers take every line above the last one they cannot
parse for a header, so that one bad value among the data silently drops the rows above it."""

from __future__ import annotations

import pathlib
import re

from ..numerics._validate import InputError, decoded_text

# A row's numbers are separated by commas, semicolons, tabs or spaces.
_SEPARATORS = re.compile(r"[,;\s]+")
# Lines a reader skips as comments wherever they stand.
_COMMENTS = ("#", "%", "//", "!")
# Bytes read to tell a binary file (which has NUL bytes) from a text one.
_PROBE = 8192


def _numbers(line: str) -> list[float] | None:
    """The row's numbers, or None if any of its fields is not one."""
    fields = [f for f in _SEPARATORS.split(line.strip()) if f]
    try:
        return [float(f) for f in fields]
    except ValueError:
        return None


def check_text_table(path: pathlib.Path) -> str | None:
    """Raise `InputError` naming the line where a text table of numbers goes wrong: a field that is not
    a number among the data rows (header lines are those above the first row of numbers), a row with
    another number of fields, or, in a two-column x–z profile, an x that does not increase (rows out of
    order, or repeated). Binary files (with NUL bytes) are left to their readers.

    **Returns:** where the text is not UTF-8 (for the message of a reader that then fails), or None.
    """
    data = path.read_bytes()
    if b"\0" in data[:_PROBE]:
        return None
    text, encoding = decoded_text(data)
    width, previous_x, previous_line = None, None, None
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith(_COMMENTS):
            continue
        row = _numbers(stripped)
        if row is None:
            if width is None:
                continue  # a header, above the data
            raise InputError(
                f"topography file {str(path)!r}: line {number} ({stripped[:60]!r}) is not a row of numbers, "
                f"but the data start at an earlier line: correct or remove it (no row is dropped silently)"
            )
        if width is None:
            width = len(row)
        elif len(row) != width:
            raise InputError(
                f"topography file {str(path)!r}: line {number} has {len(row)} values where the rows above have {width}"
            )
        if width == 2:
            if previous_x is not None and not row[0] > previous_x:
                why = (
                    f"repeats x = {row[0]:g} of line {previous_line} (a duplicated row?)"
                    if row[0] == previous_x
                    else f"has x = {row[0]:g}, below line {previous_line}'s {previous_x:g}: the rows are not in x order"
                )
                raise InputError(f"topography file {str(path)!r}: line {number} {why}")
            previous_x, previous_line = row[0], number
    return encoding
