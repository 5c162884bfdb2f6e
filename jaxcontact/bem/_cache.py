"""Boundary-element results kept on disk, each entry saying what it answers and verified on read.

An entry is one JSON object: `describes` (everything that determines the result: a hash of the
heights, the grid, the sizes, the modulus, the substrate, the solver settings and the load),
`row` (the result) and `checksum` (SHA-256 of the other two). A file whose description is not the
one asked for (an entry copied over another), whose checksum does not match (an edited number), or
whose row is not a valid result (NaN where the status says ok, a string where a number belongs) is
never served: the caller recomputes it and reports it once (`CacheWarning`).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import pathlib
import tempfile
import warnings

import numpy as np

from ..numerics import JaxcontactWarning
from ..quantities import Status

# Part of every description: a result computed under other rules is never reused.
CACHE_FORMAT = 2


class CacheWarning(JaxcontactWarning):
    """A cache entry was invalid and has been recomputed (the message names the file and why)."""


def default_directory() -> pathlib.Path:
    """`$JAXCONTACT_CACHE_DIR/bem`, else `~/.cache/jaxcontact/bem` (XDG_CACHE_HOME honoured)."""
    root = os.environ.get("JAXCONTACT_CACHE_DIR")
    if root:
        return pathlib.Path(root) / "bem"
    base = os.environ.get("XDG_CACHE_HOME") or pathlib.Path.home() / ".cache"
    return pathlib.Path(base) / "jaxcontact" / "bem"


@dataclasses.dataclass(frozen=True)
class EntryKey:
    """Where an entry lives (`name`, a hash) and what it must describe (`describes`, JSON values)."""

    name: str
    describes: dict


def _digest(value) -> str:
    return hashlib.sha256(json.dumps(value, sort_keys=True, allow_nan=True).encode()).hexdigest()


def _row_problem(row) -> str | None:
    """Why `row` is not a boundary-element result (None if it is one)."""
    if not isinstance(row, dict):
        return f"its result is a {type(row).__name__}, not an object"
    expected = {"stiffness", "offset", "fraction", "status", "iterations"}
    if set(row) != expected:
        return f"its result has the fields {sorted(row)}, not {sorted(expected)}"
    for name in ("status", "iterations"):
        if isinstance(row[name], bool) or not isinstance(row[name], int):
            return f"its {name} is {row[name]!r}, not an integer"
    for name in ("stiffness", "offset", "fraction"):
        if isinstance(row[name], bool) or not isinstance(row[name], (int, float)):
            return f"its {name} is {row[name]!r}, not a number"
    if row["status"] not in {int(s) for s in Status} or row["iterations"] < 0:
        return f"its status {row['status']} or iteration count {row['iterations']} is not a valid one"
    if row["status"] == Status.OK:
        finite = all(math.isfinite(row[name]) for name in ("stiffness", "offset", "fraction"))
        if not finite or not row["stiffness"] > 0 or not 0 <= row["fraction"] <= 1:
            return f"its status is ok but its stiffness, offset or contact fraction is not valid ({row})"
    return None


class ResultCache:
    """One JSON file per (surface, modulus, load, substrate, settings), in `directory`.

    The key hashes the heights' bytes, so a measured map and a synthesised one are treated alike;
    a repeated study reads its loads back instead of solving them again. Writes go to a temporary
    file of the writer's own and replace the entry atomically, so concurrent writers never see a
    half-written entry.
    """

    def __init__(self, directory: str | os.PathLike | None = None):
        self.directory = pathlib.Path(directory) if directory is not None else default_directory()

    @staticmethod
    def surface_key(heights, sizes, modulus, substrate, settings) -> dict:
        """The description that every load on one surface shares: the heights hashed once per surface."""
        heights = np.ascontiguousarray(heights, dtype=np.float64)
        return {
            "format": CACHE_FORMAT,
            "heights_sha256": hashlib.sha256(heights.tobytes()).hexdigest(),
            "grid": [int(n) for n in heights.shape],
            "size_m": [float(s) for s in sizes],
            "modulus_Pa": float(modulus),
            "substrate": substrate.name,
            "settings": repr(settings),
        }

    @staticmethod
    def key(surface_key: dict, load) -> EntryKey:
        describes = {**surface_key, "load_N": float(load)}
        return EntryKey(_digest(describes), describes)

    def path(self, key: EntryKey) -> pathlib.Path:
        return self.directory / f"{key.name}.json"

    def lookup(self, key: EntryKey) -> tuple[dict | None, str | None]:
        """`(row, None)` for a valid entry, `(None, None)` for none, `(None, why)` for an invalid one."""
        try:
            text = self.path(key).read_text()
        except FileNotFoundError:
            return None, None
        except (OSError, UnicodeDecodeError) as exc:
            return None, f"it cannot be read ({exc})"
        try:
            entry = json.loads(text)
        except ValueError:
            return None, "it is not valid JSON"
        if not isinstance(entry, dict) or set(entry) != {"describes", "row", "checksum"}:
            return None, "it is not a cache entry of this version"
        if entry["describes"] != key.describes:
            return None, "it describes another surface, load or setting"
        if entry["checksum"] != _digest({"describes": entry["describes"], "row": entry["row"]}):
            return None, "its checksum does not match its content"
        problem = _row_problem(entry["row"])
        return (None, problem) if problem else (entry["row"], None)

    def get(self, key: EntryKey) -> dict | None:
        """The entry's result, or None where there is none or it is invalid."""
        return self.lookup(key)[0]

    def put(self, key: EntryKey, row: dict) -> None:
        row = {k: (int(v) if k in ("status", "iterations") else float(v)) for k, v in row.items()}
        entry = {"describes": key.describes, "row": row}
        entry["checksum"] = _digest(entry)
        self.directory.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=self.directory, prefix=f".{key.name}.", suffix=".tmp")
        try:
            with os.fdopen(handle, "w") as file:
                json.dump(entry, file)
            os.replace(temporary, self.path(key))
        except BaseException:
            pathlib.Path(temporary).unlink(missing_ok=True)
            raise

    def report_invalid(self, key: EntryKey, why: str) -> None:
        """Say once that an invalid entry was recomputed (a `CacheWarning`)."""
        warnings.warn(f"cache entry {self.path(key)} was invalid ({why}); recomputed", CacheWarning, stacklevel=3)
