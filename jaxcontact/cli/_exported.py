"""The command line's store of compiled programs (`programs.AbstractProgramStore`): on disk, as exported
StableHLO, so that a new process need not trace them.

JAX's persistent compilation cache skips XLA's compilation in a new process, but not tracing: the
cache is keyed by the traced program. For the fit's model and Jacobian tracing alone takes ~3 s,
more than the fit itself once compiled. Within `exported_programs(directory)` (which the command line
enters), `DiskStore.program` keeps each program as a `jax.export` artefact: a later process reads it
(~0.1 s) and goes straight to compilation, which the persistent cache then also skips. Either way it
is compiled for a short compile time (`programs.FastCompile`).

An artefact is named by a digest of everything that fixes the program: its name and static
configuration, the shapes and dtypes of its arguments, the JAX version, the backend, the installed
jaxcontact (its version; for an editable install, which runs its source as it is edited, the digest
of that source), and the source files of the classes in the trees it closes over (a model defined
elsewhere), so that a changed model never reads an old program.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib.metadata
import importlib.util
import json
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

from ..applications import CHUNK
from ..numerics import cached
from ..programs import AbstractProgramStore, FastCompile, compiler_options, kept_in

logger = logging.getLogger(__name__)


@contextlib.contextmanager
def exported_programs(directory):
    """Keep the programs the library builds in `directory` while the context is active (`None`: in
    this process); on leaving it, every program is on disk."""
    with kept_in(None if directory is None else DiskStore(pathlib.Path(directory))):
        yield


@cached
def installed() -> str:
    """What identifies the installed jaxcontact's code: its version, and for an editable install (whose
    source runs as it is edited) a digest of the source of its packages, found by their import names."""
    distribution = importlib.metadata.distribution("jaxcontact")
    direct = json.loads(distribution.read_text("direct_url.json") or "{}")
    identity = f"jaxcontact {distribution.version}"
    if not direct.get("dir_info", {}).get("editable", False):
        return identity
    digest = hashlib.sha256(identity.encode())
    for name in ("jaxcontact", "jaxcontact.fitting"):
        for root in importlib.util.find_spec(name).submodule_search_locations:
            root = pathlib.Path(root).resolve()
            for path in sorted(root.rglob("*.py")):
                digest.update(str(path.relative_to(root)).encode())
                digest.update(path.read_bytes())
    return digest.hexdigest()


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
    text = "\n".join(parts + (jax.default_backend(), installed()))
    return hashlib.sha256(text.encode()).hexdigest()[:32]


class DiskStore(AbstractProgramStore):
    """Programs kept in `directory` between processes: exported (`program`), and for a short
    compile time also as executables (`executable`). Solves of fewer loads than the command line's
    chunk are compiled for a short compile time (`short_compile_below`): a process of the command
    line makes a few calls per program."""

    short_compile_below = CHUNK

    def __init__(self, directory: pathlib.Path):
        self.directory = directory
        self.keeping: list[threading.Thread] = []  # executables being checked and written

    def path(self, name: str, static: str, args, closed_over, suffix: str) -> pathlib.Path:
        return self.directory / f"{name}-{_key(name, static, args, closed_over)}{suffix}"

    def program(self, name, static, function, args, closed_over=(), fast_compile=True):
        return program(self, name, static, function, args, closed_over, fast_compile)

    def executable(self, name, static, function, args, closed_over=()):
        return executable(self, name, static, function, args, closed_over)

    def close(self) -> None:
        while self.keeping:
            self.keeping.pop().join()


def program(
    store: DiskStore, name: str, static: str, function: Callable, args, closed_over=(), fast_compile: bool = True
) -> Callable:
    """`FastCompile(function)` for arguments like `args` (arrays, or pytrees of arrays), read from or
    written to the store's directory.

    `static` must describe everything `function` closes over that changes the program (the
    fitted parameters' names), and `closed_over` holds the tree structures it closes over (the
    scene's), whose classes' source files join the key. Any failure to read or write an artefact
    falls back to tracing, with a log message. `fast_compile=False`: a plain `jax.jit`, for a
    program whose run time matters more than its compile time.
    """
    make = FastCompile if fast_compile else jax.jit
    jitted = make(function)
    try:
        path = store.path(name, static, args, closed_over, ".jaxexport")
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


def executable(store: DiskStore, name: str, static: str, function: Callable, args, closed_over=()) -> Callable:
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
    exported_program = functools.partial(program, store, name, static, function, args, closed_over)
    if not compiler_options():
        return exported_program()
    try:
        path = store.path(name, static, args, closed_over, f"-{_host()}.jaxexec")
        if path.exists():
            return _Kept(_load(path.read_bytes()), path, exported_program)
        if store.path(name, static, args, closed_over, ".jaxexport").exists():
            compiled = exported_program().top_level.lower(*args).compile()
        else:
            compiled = jax.jit(function, compiler_options=compiler_options()).lower(*args).compile()
    except Exception as error:  # noqa: BLE001 (a cache must never stop the computation)
        logger.info("compiled program %s not read (%s: %s); using the exported one", name, type(error).__name__, error)
        return exported_program()
    # Checked and written on a second thread, mostly outside the GIL: the caller goes on with the
    # results (a cold `jaxcontact run` draws its figures meanwhile); the store's `close` waits for it.
    keeper = threading.Thread(target=_keep, args=(name, path, compiled, args, exported_program), daemon=True)
    keeper.start()
    store.keeping.append(keeper)
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
