"""Boundary-element results kept on disk, keyed by everything that determines them."""

from __future__ import annotations

import hashlib
import json
import os
import pathlib

import numpy as np

# Part of every key: a result computed under other rules is never reused.
CACHE_FORMAT = 1


def default_directory() -> pathlib.Path:
    """`$JAXCONTACT_CACHE_DIR/bem`, else `~/.cache/jaxcontact/bem` (XDG_CACHE_HOME honoured)."""
    root = os.environ.get("JAXCONTACT_CACHE_DIR")
    if root:
        return pathlib.Path(root) / "bem"
    base = os.environ.get("XDG_CACHE_HOME") or pathlib.Path.home() / ".cache"
    return pathlib.Path(base) / "jaxcontact" / "bem"


class ResultCache:
    """One JSON file per (surface, modulus, load, substrate, settings), in `directory`.

    The key hashes the heights' bytes, so a measured map and a synthesised one are treated alike;
    a repeated study reads its loads back instead of solving them again.
    """

    def __init__(self, directory: str | os.PathLike | None = None):
        self.directory = pathlib.Path(directory) if directory is not None else default_directory()

    @staticmethod
    def surface_key(heights, sizes, modulus, substrate, settings) -> str:
        """The part of a key that every load on one surface shares: hashed once per surface."""
        digest = hashlib.sha256(np.ascontiguousarray(heights, dtype=np.float64).tobytes())
        described = (
            CACHE_FORMAT,
            tuple(map(float, sizes)),
            np.shape(heights),
            float(modulus),
            substrate,
            repr(settings),
        )
        digest.update(repr(described).encode())
        return digest.hexdigest()

    @staticmethod
    def key(surface_key: str, load) -> str:
        return hashlib.sha256(f"{surface_key}:{float(load)!r}".encode()).hexdigest()

    def get(self, key: str) -> dict | None:
        path = self.directory / f"{key}.json"
        try:
            return json.loads(path.read_text())
        except (OSError, ValueError):
            return None

    def put(self, key: str, row: dict) -> None:
        self.directory.mkdir(parents=True, exist_ok=True)
        path = self.directory / f"{key}.json"
        temporary = path.with_suffix(".tmp")
        temporary.write_text(
            json.dumps({k: (int(v) if k in ("status", "iterations") else float(v)) for k, v in row.items()})
        )
        temporary.replace(path)
