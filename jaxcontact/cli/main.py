"""The `jaxcontact` command line: run a scene, draw the paper's figures, time the model.

Runs in float64 and keeps a persistent compilation cache, so repeated runs skip compilation.
User mistakes (bad scene files, bad options) end with exit status 2 and one line on stderr.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import os
import pathlib
import re
import sys
import threading
import traceback

from ..core.exported import exported_programs
from ..numerics.compat import avoid_host_callbacks_in_checks
from ..numerics.validate import InputError, MissingExtraError, command_line_spelling
from .commands import CommandError, cmd_approach, cmd_dynamics, cmd_fit, cmd_run
from .compare_commands import DEFAULT_COMPARE_SCENE, add_compare_options, cmd_compare
from .study_commands import cmd_accuracy, cmd_bench, cmd_figures, cmd_sweep
from .surface_commands import add_topography_options, cmd_surface

EXIT_USAGE = 2
EXIT_INTERNAL = 70  # EX_SOFTWARE
# The commands that draw figures with matplotlib.
DRAWING = frozenset({"run", "surface", "approach", "dynamics", "compare", "figures", "fit", "accuracy"})
# The commands that time compilations: run without the persistent cache, whose reads they would
# time instead (JAX decides once per process whether to use it, at the first compilation).
TIMING = frozenset({"bench"})


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
            # Traced programs too (`core.exported`): the compilation cache skips XLA, not tracing.
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


def _version() -> str:
    from .. import __version__

    return __version__


class Parser(argparse.ArgumentParser):
    """argparse, with "-1e-3" read as a number (argparse's own pattern misses exponents), so that a
    negative value reaches its option and is refused there by name; errors in one line."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")

    def error(self, message):
        """One line, as every other mistake in the input (`--help` shows the usage)."""
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message}\n")


def _options_by_name(parser) -> dict[str, str]:
    """{argument name: "--option"} for the options of a (sub)command, for messages in its spelling."""
    return {a.dest: max(a.option_strings, key=len) for a in parser._actions if a.option_strings}


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="jaxcontact", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"jaxcontact {_version()}")
    sub = parser.add_subparsers(dest="command", required=True)

    def common(p, default_out):
        p.add_argument("--format", choices=("table", "json"), default="table", help="output format on stdout")
        p.add_argument("--out", default=default_out, help=f"output folder (default: {default_out})")
        p.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")

    def scene_command(name, help, func, out, default_scene="table1_grinding.toml"):
        p = sub.add_parser(name, help=help)
        p.add_argument("scene", nargs="?", help=f"scene TOML file (default: embedded {default_scene})")
        common(p, out)
        p.set_defaults(func=func)
        return p

    p = scene_command(
        "run", "solve a scene (default: the embedded Table 1 scene), write CSV and plots", cmd_run, "jaxcontact-out"
    )
    p.add_argument("--topography", help="a measured surface file: D, G, l_min from it, K(F) with its 95 %% band")
    add_topography_options(p)
    p = sub.add_parser("surface", help="D, G (both conventions) and l_min of a measured surface, with intervals")
    p.add_argument("file", help="topography file (any format SurfaceTopography reads)")
    add_topography_options(p)
    common(p, "jaxcontact-out/surface")
    p.set_defaults(func=cmd_surface)
    scene_command(
        "approach",
        "load–approach curve relative to a preload (scenes with [approach])",
        cmd_approach,
        "jaxcontact-out/approach",
        "table1_dynamics.toml",
    )
    scene_command(
        "dynamics",
        "a driven mass on the joint: time history, frequency response, resonance against "
        "preload (scenes with [dynamics])",
        cmd_dynamics,
        "jaxcontact-out/dynamics",
        "table1_dynamics.toml",
    )
    p = scene_command(
        "compare",
        "every model beside an elastic boundary-element reference on synthesised (or, with "
        "--topography, measured) surfaces; CSV, plot and K_model/K_BEM table",
        cmd_compare,
        "jaxcontact-out/compare",
        DEFAULT_COMPARE_SCENE,
    )
    p.add_argument("--topography", help="a measured areal map: BEM on its heights, models on its D, G, l_min")
    add_topography_options(p)
    add_compare_options(p)
    p = sub.add_parser("figures", help="reproduce the paper's Figs. 3, 4, 5, 6, 8 and the l_min dependence")
    common(p, "jaxcontact-out/figures")
    p.set_defaults(func=cmd_figures)

    p = sub.add_parser("fit", help="fit D and G (or other parameters) to a measured stiffness curve (CSV)")
    p.add_argument("data", help="CSV with columns load_N,stiffness_N_per_m (or F_star,K_star)")
    p.add_argument("--scene", help="scene TOML supplying the parameters that are not fitted (default: embedded)")
    p.add_argument("--params", default="D,G", help="comma-separated parameters to fit (default: D,G)")
    p.add_argument("--method", choices=("bfgs", "lbfgs", "lm"), default="bfgs", help="optimiser (default: bfgs)")
    p.add_argument("--starts", type=int, default=12, help="number of starts (default: 12)")
    common(p, "jaxcontact-out")
    p.set_defaults(func=cmd_fit)

    p = scene_command(
        "sweep", "D × G × load grid, sharded across all JAX devices; CSV output", cmd_sweep, "jaxcontact-out"
    )
    p.add_argument("--D", default="1.3:1.7:5", help="fractal dimensions LOW:HIGH:COUNT, linear (default 1.3:1.7:5)")
    p.add_argument(
        "--G", default="1e-11:1e-9:5", help="roughness (m) LOW:HIGH:COUNT, log-spaced (default 1e-11:1e-9:5)"
    )
    p.add_argument("--distributed", action="store_true", help="call jax.distributed.initialize() (multi-host runs)")
    scene_command(
        "accuracy", "error against time for every accuracy knob (reference: mpmath)", cmd_accuracy, "jaxcontact-out"
    )
    scene_command(
        "bench", "time the compiled model: speed against scipy, each effect's cost", cmd_bench, "jaxcontact-out"
    )
    for command in sub.choices.values():
        command.set_defaults(options_by_name=_options_by_name(command))
    return parser


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
            for module in ("jaxcontact.cli.plots", "matplotlib.backends.backend_agg"):
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

    from ..numerics.validate import JaxcontactWarning

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


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    drawing = plotting_imported_while_compiling() if args.command in DRAWING else contextlib.nullcontext()
    try:
        with (
            command_settings(persistent_cache=args.command not in TIMING),
            drawing,
            warnings_as_lines(args.command),
            command_line_spelling(args.options_by_name),
        ):
            return args.func(args)
    except (
        InputError,
        CommandError,
        MissingExtraError,
        FileNotFoundError,
        IsADirectoryError,
        NotADirectoryError,
        PermissionError,
    ) as exc:  # the user's to fix (a missing extra too): SceneFileError and DataError are InputErrors
        print(f"jaxcontact {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except Exception:  # anything else is a bug, not a mistake in the input: say so, with the traceback
        traceback.print_exc()
        print(
            f"jaxcontact {args.command}: internal error (a bug in jaxcontact, not in your input): please "
            "report it with the traceback above",
            file=sys.stderr,
        )
        return EXIT_INTERNAL
    except KeyboardInterrupt:
        print("jaxcontact: interrupted", file=sys.stderr)
        return 130


def console() -> None:
    """The `jaxcontact` executable: `main()`, then an exit that skips the interpreter's teardown.

    Once a command has written its files, tearing down JAX's runtime and every module's objects
    costs ~0.6 s, a sixth of a warm `jaxcontact run`. Output streams are flushed and `atexit`
    handlers run first (logging, JAX's own), so nothing written is lost.
    """
    import atexit

    # JAX keeps no program holding a host callback in its persistent cache, and diffrax checks its
    # save times through one: `approach` and `dynamics` compiled their solves on every run. Every
    # solve here runs with `throw=False` and flags failures in its status.
    avoid_host_callbacks_in_checks()
    code = main()
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):  # a closed pipe must not change the exit status
            stream.flush()
    atexit._run_exitfuncs()
    os._exit(code)


if __name__ == "__main__":
    console()
