"""Compiled programs: one per static configuration, load arrays padded to a few bucket lengths, and
(where the command line asks for it) kept on disk between processes (`exported_programs`)."""

from ._compiling import FastCompile, compiler_options
from ._exported import executable, exported_programs, program
from ._programs import bucket, call, edge_padded, padded, unpadded

__all__ = [
    "bucket",
    "call",
    "compiler_options",
    "edge_padded",
    "executable",
    "exported_programs",
    "FastCompile",
    "padded",
    "program",
    "unpadded",
]
