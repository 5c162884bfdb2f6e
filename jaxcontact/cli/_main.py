"""The `jaxcontact` command line: run a scene, draw the paper's figures, time the model.

Runs in float64 and keeps a persistent compilation cache, so repeated runs skip compilation.
User mistakes (bad scene files, bad options) end with exit status 2 and one line on stderr.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import pathlib
import re
import sys
import traceback

from ..numerics._compat import avoid_host_callbacks_in_checks
from ..numerics._validate import InputError, MissingExtraError, command_line_spelling
from ._commands import add_dynamics_options, cmd_approach, cmd_dynamics, cmd_run
from ._compare_commands import cmd_compare
from ._compare_table import DEFAULT_COMPARE_SCENE, add_compare_options
from ._cycle_command import add_cycle_options, cmd_cycle
from ._fit_commands import cmd_fit
from ._interface_command import add_interface_options, cmd_interface
from ._output import CommandError
from ._process import command_settings, plotting_imported_while_compiling, warnings_as_lines
from ._spectrum_command import register as register_spectrum_command
from ._study_commands import add_bench_options, cmd_accuracy, cmd_bench, cmd_figures, cmd_sweep
from ._surface_commands import add_topography_options, cmd_surface
from ._topography_run import add_run_topography_options

EXIT_USAGE = 2
EXIT_INTERNAL = 70  # EX_SOFTWARE
# The commands that draw figures with matplotlib.
DRAWING = frozenset(
    {"run", "surface", "approach", "interface", "cycle", "dynamics", "compare", "figures", "fit", "accuracy"}
)
# The commands that time compilations: run without the persistent cache, whose reads they would
# time instead (JAX decides once per process whether to use it, at the first compilation).
TIMING = frozenset({"bench"})


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
        p.add_argument("--format", choices=("table", "json"), default="table", help="output on stdout (default: table)")
        p.add_argument("--out", default=default_out, help=f"output folder (default: {default_out})")
        p.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar (default: shown)")

    def command(name, help):
        """A subcommand whose --help opens with the one line of what it does."""
        return sub.add_parser(name, help=help, description=help[0].upper() + help[1:] + ".")

    def scene_command(name, help, func, out, default_scene="table1_grinding.toml"):
        p = command(name, help)
        p.add_argument("scene", nargs="?", help=f"scene TOML file (default: embedded {default_scene})")
        common(p, out)
        p.set_defaults(func=func)
        return p

    p = scene_command(
        "run", "solve a scene (default: the embedded Table 1 scene), write CSV and plots", cmd_run, "jaxcontact-out"
    )
    p.add_argument("--topography", help="a measured surface file: D, G, l_min from it, K(F) with its 95 %% band")
    add_topography_options(p)
    add_run_topography_options(p)
    p = command("surface", "D, G (both conventions) and l_min of a measured surface, with intervals")
    p.add_argument(
        "file",
        nargs="+",
        help="topography file (any format SurfaceTopography reads); several files of one surface are stitched",
    )
    add_topography_options(p)
    p.add_argument(
        "--accept-mismatch",
        action="store_true",
        help="stitch files that do not join into one power law (their joint D is then not to be trusted)",
    )
    common(p, "jaxcontact-out/surface")
    p.set_defaults(func=cmd_surface)
    scene_command(
        "approach",
        "load–approach curve relative to a preload (scenes with [approach])",
        cmd_approach,
        "jaxcontact-out/approach",
        "table1_dynamics.toml",
    )
    p = scene_command(
        "interface",
        "the joint's interface law per unit area (closure, stiffness against nominal pressure), written as "
        "CSV, as the pressure-overclosure table CalculiX and Abaqus read, and as a plot",
        cmd_interface,
        "jaxcontact-out/interface",
    )
    add_interface_options(p)
    p = scene_command(
        "cycle",
        "the joint in service: friction loops about a preload (--mu; Cattaneo–Mindlin spots, Masing's rules) "
        "and a normal load path (--path; approach, branch stiffness, residual approach), as CSV and plots",
        cmd_cycle,
        "jaxcontact-out/cycle",
    )
    add_cycle_options(p)
    p = scene_command(
        "dynamics",
        "a driven mass on the joint: time history, frequency response, resonance against "
        "preload (scenes with [dynamics])",
        cmd_dynamics,
        "jaxcontact-out/dynamics",
        "table1_dynamics.toml",
    )
    add_dynamics_options(p)
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
    p = command("figures", "reproduce the paper's Figs. 3, 4, 5, 6, 8 and the l_min dependence")
    common(p, "jaxcontact-out/figures")
    p.set_defaults(func=cmd_figures)

    p = command("fit", "fit D and G (or other parameters) to a measured stiffness curve (CSV)")
    p.add_argument("data", help="CSV with columns load_N,stiffness_N_per_m (or F_star,K_star)")
    p.add_argument(
        "--scene", help="scene TOML supplying the parameters that are not fitted (default: the embedded Table 1 scene)"
    )
    p.add_argument("--params", default="D,G", help="comma-separated parameters to fit (default: D,G)")
    p.add_argument("--method", choices=("bfgs", "lbfgs", "lm"), default="bfgs", help="optimiser (default: bfgs)")
    p.add_argument("--starts", type=int, default=12, help="number of starts (default: 12)")
    p.add_argument(
        "--topography",
        help="a measured surface file: its D and ln G with their covariance as the prior (joint inference)",
    )
    add_topography_options(p)
    p.add_argument(
        "--prior",
        action="append",
        metavar="NAME=MEAN:SD|NAME=LOW..HIGH",
        help="a prior on a fitted parameter, e.g. D=1.45:0.05 (Gaussian) or D=1.3..1.6 (bounds); repeatable",
    )
    p.add_argument(
        "--noise",
        type=float,
        help="σ of ln K, which weighs the curve against a prior (default: the residuals' scale of the curve alone)",
    )
    p.add_argument(
        "--posterior",
        action="store_true",
        help="also sample the posterior by NUTS (the bayes extra): 4 chains, corner.png, posterior_band.png",
    )
    p.add_argument("--draws", type=int, help="with --posterior: draws per chain (default: 500)")
    p.add_argument("--seed", type=int, help="with --posterior: the sampler's seed, >= 0 (default: 0)")
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
    p = scene_command(
        "bench", "time the compiled model: speed against scipy, each effect's cost", cmd_bench, "jaxcontact-out"
    )
    add_bench_options(p)
    register_spectrum_command(command, common)
    for command in sub.choices.values():
        command.set_defaults(options_by_name=_options_by_name(command))
    return parser


def writable_folder(option: str, path) -> None:
    """Refuse in one line, before any computing, a folder `path` (an option's) that cannot be written:
    a file in its place, or no permission to write there (or to make it), would lose the work at the end."""
    folder = pathlib.Path(path).absolute()
    existing = next(p for p in (folder, *folder.parents) if p.exists())
    if not existing.is_dir():
        raise CommandError(f"{option} {path}: {existing} is a file, not a folder; name a folder to write into")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise CommandError(f"{option} {path}: no permission to write in {existing}")


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
            for option in ("out", "cache_dir"):
                skipped = option == "cache_dir" and getattr(args, "no_cache", False)
                if getattr(args, option, None) is not None and not skipped:
                    writable_folder(args.options_by_name.get(option, f"--{option}"), getattr(args, option))
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
