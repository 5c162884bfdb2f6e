"""Measured stiffness curves from CSV.

A header row is required; lines starting with `#` before it are comments (used to label
generated data). Columns: `load_N,stiffness_N_per_m`, or the dimensionless `F_star,K_star`
(converted with the scene's E and nominal area).
"""

from __future__ import annotations

import csv
import dataclasses
import math
import pathlib

import numpy as np

import jaxcontact as jc
from jaxcontact import InputError
from jaxcontact.numerics import decoded_text

COLUMN_SETS = (("load_N", "stiffness_N_per_m"), ("F_star", "K_star"))


class DataError(InputError):
    """A curve file that cannot be used; the message says where and why."""


@dataclasses.dataclass(frozen=True)
class Curve:
    """A stiffness-vs-load curve in SI units."""

    loads: np.ndarray
    stiffness: np.ndarray
    source: str = "<array>"


def parse_curve(text: str, scene: jc.Scene, source: str = "<text>") -> Curve:
    """A curve from CSV text; errors name the file's own line numbers (comments and blank lines count)."""
    numbered = [
        (number, line)
        for number, line in enumerate(text.lstrip("\ufeff").splitlines(), start=1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not numbered:
        raise DataError(f"{source}: no header row and no data")
    (_, header_line), *data = numbered
    header = [h.strip() for h in next(csv.reader([header_line]))]
    columns = next((c for c in COLUMN_SETS if all(k in header for k in c)), None)
    if columns is None:
        raise DataError(
            f"{source}: header {','.join(header)!r} lacks the columns 'load_N,stiffness_N_per_m' (or 'F_star,K_star')"
        )
    where = [header.index(k) for k in columns]
    x, y = [], []
    for number, line in data:
        fields = next(csv.reader([line]))
        if len(fields) != len(header):
            raise DataError(f"{source}: line {number} has {len(fields)} fields, the header has {len(header)}")
        pair = []
        for key, i in zip(columns, where):
            raw = fields[i].strip()
            try:
                value = float(raw)
            except ValueError:
                raise DataError(f"{source}: line {number}, column {key}: {raw!r} is not a number") from None
            if not (math.isfinite(value) and value > 0):
                raise DataError(f"{source}: line {number}, column {key}: {raw} must be a positive finite number")
            pair.append(value)
        x.append(pair[0])
        y.append(pair[1])
    if len(x) < 3:
        raise DataError(f"{source}: {len(x)} data rows; a fit needs at least 3")
    loads, stiffness = np.asarray(x), np.asarray(y)
    if columns[0] == "F_star":
        scales = jc.Scales.of(scene)
        loads, stiffness = loads * float(scales.load), stiffness * float(scales.stiffness)
    return Curve(loads, stiffness, source)


def load_curve(path, scene: jc.Scene) -> Curve:
    path = pathlib.Path(path)
    if path.is_dir():
        raise DataError(f"data file {str(path)!r} is a directory, not a CSV file")
    if not path.is_file():
        raise DataError(f"data file {str(path)!r} does not exist")
    return parse_curve(decoded_text(path.read_bytes())[0], scene, str(path))


def write_curve(path, loads, stiffness, comments=()) -> None:
    with open(path, "w", newline="") as f:
        for c in comments:
            f.write(f"# {c}\n")
        f.write("load_N,stiffness_N_per_m\n")
        for F, K in zip(loads, stiffness):
            f.write(f"{float(F):.10g},{float(K):.10g}\n")
