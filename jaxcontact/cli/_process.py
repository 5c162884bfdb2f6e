"""The process settings of a command: float64, synchronous dispatch, the persistent compilation
cache, matplotlib imported beside the first compile, and the library's warnings as one line each.
Each is restored when the command returns, so that `main()` called in-process changes nothing."""

from __future__ import annotations

import contextlib
import importlib
import os
import pathlib
import sys
import threading

from ._exported import exported_programs

_SETTINGS = (
    "jax_enable_x64",
    "jax_cpu_enable_async_dispatch",
    "jax_compilation_cache_dir",
    "jax_persistent_cache_min_compile_time_secs",
    "jax_persistent_cache_min_entry_size_bytes",
)


@contextlib.contextmanager
def command_settings(persistent_cache: bool = True):
    """The command line's global settings while a command runs; the caller's afterwards.

    float64; compiled calls run on the calling thread; a persistent compilation cache
    (`JAXCONTACT_CACHE`, "" for none; none at all without `persistent_cache`); and the imported
    modules left out of garbage collection. Restored on exit, so that `main()` called in-process
    (tests, notebooks) changes nothing.
    """
    import gc

    import jax

    import jaxcontact  # noqa: F401  (the package and its dependencies, imported before the freeze)

    before = {name: jax.config.values[name] for name in _SETTINGS}
    jax.config.update("jax_enable_x64", True)
    # Handing each compiled call to a worker thread (JAX's default on CPU) costs more than it hides
    # for calls of ~0.1 ms, and the pool's spinning threads compete for the cores (openxla/xla#18608).
    # Sharded (multi-device) computations stay asynchronous.
    jax.config.update("jax_cpu_enable_async_dispatch", False)
    cache = os.environ.get("JAXCONTACT_CACHE", str(pathlib.Path.home() / ".cache" / "jaxcontact" / "xla"))
    cache = cache if persistent_cache else ""
    programs = None
    if cache:
        try:
            pathlib.Path(cache).mkdir(parents=True, exist_ok=True)
            jax.config.update("jax_compilation_cache_dir", cache)
            jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
            jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)
            # Traced programs too (`_exported`): the compilation cache skips XLA, not tracing.
            programs = pathlib.Path(cache) / "exported"
        except OSError:
            pass  # a read-only home: run without the cache
    # The modules just imported live as long as the process: tracing allocates millions of
    # short-lived objects, and each full collection would otherwise walk all of jax, numpy and scipy.
    # Young objects are collected 100x less often too (a cold `run` spent 0.1 s collecting them);
    # memory stays bounded, and array buffers go by reference counting anyway.
    gc.freeze()
    thresholds = gc.get_threshold()
    gc.set_threshold(100 * thresholds[0], *thresholds[1:])
    try:
        with exported_programs(programs):
            yield
    finally:
        gc.set_threshold(*thresholds)
        gc.unfreeze()
        for name, value in before.items():
            jax.config.update(name, value)


@contextlib.contextmanager
def plotting_imported_while_compiling():
    """Import matplotlib (~0.3-0.5 s of a command that draws) on a second thread while XLA compiles;
    yields the thread.

    XLA's compiler releases the GIL, so a command's first solve, which in a new process waits
    seconds on it, leaves a core free for the import; done before (or beside tracing, which holds
    the GIL) it would cost as much as done after. The thread starts at the first lowering long
    enough to announce a real compilation, or when the command ends; the command's own import
    waits for it (Python's module locks) and reports any failure.
    """
    import jax.monitoring

    start = threading.Event()

    def on_event(event, duration, **_):
        if event == "/jax/core/compile/jaxpr_to_mlir_module_duration" and duration > 0.05:
            start.set()

    def load():
        start.wait()
        with contextlib.suppress(Exception):
            for module in ("jaxcontact.cli._plots", "matplotlib.backends.backend_agg"):
                importlib.import_module(module)

    jax.monitoring.register_event_duration_secs_listener(on_event)
    thread = threading.Thread(target=load, name="jaxcontact-import-matplotlib", daemon=True)
    thread.start()
    try:
        yield thread
    finally:
        start.set()
        unregister = getattr(jax.monitoring, "unregister_event_duration_listener", None)
        if unregister is not None:  # older JAX keeps it: a set event is set again, harmlessly
            unregister(on_event)


@contextlib.contextmanager
def warnings_as_lines(command: str):
    """The library's warnings (`warnings.warn`) on stderr as one line each, each message once."""
    import warnings

    from ..numerics import JaxcontactWarning

    seen = set()

    def show(message, category, filename, lineno, file=None, line=None):
        text = " ".join(str(message).split())
        if text not in seen:
            seen.add(text)
            print(f"jaxcontact {command}: warning: {text}", file=sys.stderr)

    with warnings.catch_warnings():
        # Each command shows the library's own warnings, even those an earlier in-process call showed.
        warnings.simplefilter("always", JaxcontactWarning)
        warnings.showwarning = show
        yield
