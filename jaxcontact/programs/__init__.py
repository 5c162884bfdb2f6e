"""Compiled programs: one per static configuration, load arrays padded to a few bucket lengths, built in
the current store (`kept_in`: this process by default; the command line keeps them on disk)."""

from ._compiling import FastCompile, compiler_options
from ._programs import bucket, call, edge_padded, padded, unpadded
from ._store import AbstractProgramStore, InProcess, current_store, executable, keeping, kept_in, program

__all__ = [
    "AbstractProgramStore",
    "current_store",
    "InProcess",
    "kept_in",
    "keeping",
    "bucket",
    "call",
    "compiler_options",
    "edge_padded",
    "executable",
    "FastCompile",
    "padded",
    "program",
    "unpadded",
]
