"""Compiled programs kept on disk as exported StableHLO, so that a new process need not trace them.

JAX's persistent compilation cache skips XLA's compilation in a new process, but not tracing: the
cache is keyed by the traced program. For the fit's model and Jacobian tracing alone takes ~3 s,
more than the fit itself once compiled. With a directory set (`exported_programs`, which the
command line sets), `program` keeps each program as a `jax.export` artefact: a later process
reads it (~0.1 s) and goes straight to compilation, which the persistent cache then also skips.
Without a directory (the library's default) it is a `jax.jit`. Either way it is compiled for a
short compile time (`compiling.FastCompile`).

An artefact is named by a digest of everything that fixes the program: its name and static
configuration, the shapes and dtypes of its arguments, the JAX version, the backend, the source
of this package and of `fitting`, and the source files of the classes in the trees it closes over
(a model defined elsewhere), so that a changed model never reads an old program.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib.metadata
import importlib.util
import logging
import os
import pathlib
import pickle
import platform
import sys
import threading
from collections.abc import Callable

import jax
import numpy as np
from jax import export  # a submodule that older JAX does not import with `jax`

from ..numerics import cached, register_cache
from ._compiling import FastCompile, compiler_options

logger = logging.getLogger(__name__)
_directory: pathlib.Path | None = None
_source_digest: str | None = None
_keeping: list[threading.Thread] = []  # executables being checked and written (`executable`)


@contextlib.contextmanager
def exported_programs(directory):
    """Keep the programs built by `program` in `directory` while the context is active (`None`: do
    not); on leaving it, every program is on disk."""
    global _directory
    before = _directory
    _directory = None if directory is None else pathlib.Path(directory)
    try:
        yield
    finally:
        while _keeping:
            _keeping.pop().join()
        _directory = before


@register_cache
def _forget_sources() -> None:
    global _source_digest
    _source_digest = None


def _sources() -> str:
    global _source_digest
    if _source_digest is None:
        digest = hashlib.sha256()
        package = pathlib.Path(__file__).resolve().parents[1]
        # `jaxcontact.fitting` installs from a folder of its own (pyproject's package-dir).
        fitting = importlib.util.find_spec("jaxcontact.fitting").submodule_search_locations[0]
        for root in (package, pathlib.Path(fitting).resolve()):
            for path in sorted(root.rglob("*.py")):
                digest.update(str(path.relative_to(root.parent)).encode())
                digest.update(path.read_bytes())
        _source_digest = digest.hexdigest()
    return _source_digest


def _node_types(treedef):
    data = treedef.node_data()
    if data is not None:
        yield data[0]
    for child in treedef.children():
        yield from _node_types(child)


def _classes(treedefs) -> str:
    """The qualified names and source files of the tree nodes' classes: a model defined outside
    this package changes the key when its own file changes."""
    types = {t for treedef in treedefs for t in _node_types(treedef)}
    names = sorted(f"{t.__module__}.{t.__qualname__}" for t in types)
    files = sorted({getattr(sys.modules.get(t.__module__), "__file__", None) or "" for t in types} - {""})
    digest = hashlib.sha256("\n".join(names).encode())
    for file in files:
        digest.update(pathlib.Path(file).read_bytes())
    return digest.hexdigest()


def _key(name: str, static: str, args, closed_over) -> str:
    avals = [(tuple(x.shape), str(x.dtype)) for x in jax.tree_util.tree_leaves(args)]
    treedefs = (jax.tree_util.tree_structure(args), *closed_over)
    parts = (name, static, *map(repr, treedefs), _classes(treedefs), repr(avals), jax.__version__)
    text = "\n".join(parts + (jax.default_backend(), _sources()))
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def active() -> bool:
    """Whether programs are kept on disk (a directory is set by `exported_programs`)."""
    return _directory is not None


def _path(name: str, static: str, args, closed_over, suffix: str) -> pathlib.Path:
    return _directory / f"{name}-{_key(name, static, args, closed_over)}{suffix}"


def program(name: str, static: str, function: Callable, args, closed_over=(), fast_compile: bool = True) -> Callable:
    """`FastCompile(function)` for arguments like `args` (arrays, or pytrees of arrays), read from or
    written to the directory of `exported_programs` when one is set.

    `static` must describe everything `function` closes over that changes the program (the
    fitted parameters' names), and `closed_over` holds the tree structures it closes over (the
    scene's), whose classes' source files join the key. Any failure to read or write an artefact
    falls back to tracing, with a log message. `fast_compile=False`: a plain `jax.jit`, for a
    program whose run time matters more than its compile time.
    """
    make = FastCompile if fast_compile else jax.jit
    jitted = make(function)
    if _directory is None:
        return jitted
    try:
        path = _path(name, static, args, closed_over, ".jaxexport")
        if path.exists():
            exported = export.deserialize(bytearray(path.read_bytes()))
        else:
            exported = export.export(jax.jit(function))(*args)
            _write(path, exported.serialize())
    except Exception as error:  # noqa: BLE001 (a cache must never stop the computation)
        logger.info("exported program %s not used (%s: %s); tracing it", name, type(error).__name__, error)
        return jitted
    return make(exported.call)


def _write(path: pathlib.Path, payload: bytes | bytearray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    partial = path.with_suffix(f".{os.getpid()}.partial")
    partial.write_bytes(payload)
    partial.replace(path)  # atomic: a concurrent reader sees all of it or nothing


@cached
def _host() -> str:
    """A digest of what compiled machine code depends on: the CPU (its feature flags, where the
    system lists them), the platform and jaxlib's version."""
    flags = ""
    with contextlib.suppress(OSError):
        lines = pathlib.Path("/proc/cpuinfo").read_text().splitlines()
        flags = next((line for line in lines if line.startswith(("flags", "Features"))), "")
    parts = (platform.machine(), platform.processor(), flags, importlib.metadata.version("jaxlib"))
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()[:16]


def executable(name: str, static: str, function: Callable, args, closed_over=()) -> Callable:
    """`program(...)` compiled for a short compile time, with the compiled executable itself kept
    in the directory instead, so that a later process neither traces, lowers nor compiles it
    (~0.15 s to load, against ~0.45 s to lower the exported program and fetch it from JAX's cache).

    Only where the short compile options apply: XLA's CPU executables built by its default
    emitters do not survive serialisation, nor do those JAX read from its compilation cache; so an
    executable is kept only after a round trip (serialised, loaded, run on `args`) has given the
    compiled program's own outputs. Where it is not kept, the exported program is (`program`),
    for the next process; a kept one that fails when called later is deleted and the exported
    program used. A new executable is compiled from `function` directly (one trace, one
    lowering), or from the exported program where that is on disk already (no trace). An
    executable is machine code for this host: its file is named by the host's CPU and jaxlib
    (`_host`). Like JAX's own compilation cache, the directory is trusted (the file is a pickle).
    Call the result with concrete arguments only.
    """
    exported_program = functools.partial(program, name, static, function, args, closed_over)
    if _directory is None or not compiler_options():
        return exported_program()
    try:
        path = _path(name, static, args, closed_over, f"-{_host()}.jaxexec")
        if path.exists():
            return _Kept(_load(path.read_bytes()), path, exported_program)
        if _path(name, static, args, closed_over, ".jaxexport").exists():
            compiled = exported_program().top_level.lower(*args).compile()
        else:
            compiled = jax.jit(function, compiler_options=compiler_options()).lower(*args).compile()
    except Exception as error:  # noqa: BLE001 (a cache must never stop the computation)
        logger.info("compiled program %s not read (%s: %s); using the exported one", name, type(error).__name__, error)
        return exported_program()
    # Checked and written on a second thread, mostly outside the GIL: the caller goes on with the
    # results (a cold `jaxcontact run` draws its figures meanwhile); `exported_programs` waits for it.
    keeper = threading.Thread(target=_keep, args=(name, path, compiled, args, exported_program), daemon=True)
    keeper.start()
    _keeping.append(keeper)
    return compiled


def _keep(name: str, path: pathlib.Path, compiled, args, exported_program: Callable) -> None:
    """Write `compiled` to `path` if it survives the round trip; else write its exported program."""
    try:
        payload = pickle.dumps(_serialize(compiled))
        if _round_trips(payload, compiled, args):
            _write(path, payload)
        else:
            logger.info("compiled program %s does not survive serialisation; its exported program kept", name)
            exported_program()
    except Exception as error:  # noqa: BLE001 (a cache must never stop the computation)
        logger.info("compiled program %s not kept (%s: %s)", name, type(error).__name__, error)


def _serialize(compiled):
    from jax.experimental import serialize_executable

    return serialize_executable.serialize(compiled)


def _load(payload: bytes):
    from jax.experimental import serialize_executable

    return serialize_executable.deserialize_and_load(*pickle.loads(payload))


def _round_trips(payload: bytes, compiled, args) -> bool:
    try:
        loaded = jax.tree_util.tree_leaves(_load(payload)(*args))
        expected = jax.tree_util.tree_leaves(compiled(*args))
        return all(np.array_equal(a, b, equal_nan=True) for a, b in zip(loaded, expected, strict=True))
    except Exception:  # noqa: BLE001 (any failure means: do not keep it)
        return False


class _Kept:
    """An executable read from disk; if a call fails, its file is deleted and the program that
    `fallback()` builds used instead."""

    def __init__(self, loaded, path: pathlib.Path, fallback: Callable[[], Callable]):
        self.loaded, self.path, self.fallback = loaded, path, fallback

    def __call__(self, *args):
        if self.loaded is not None:
            try:
                return self.loaded(*args)
            except Exception as error:  # noqa: BLE001 (a cache must never stop the computation)
                logger.info("kept executable %s failed (%s); deleted", self.path.name, error)
                self.loaded = None
                self.path.unlink(missing_ok=True)
                self.fallback = self.fallback()
        return self.fallback(*args)
