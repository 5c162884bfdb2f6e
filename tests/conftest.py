"""Settings and fixtures. The tests run in float64 (the library itself never switches x64 on);
what tests share besides fixtures is in helpers.py."""

import importlib.metadata
import os

os.environ.setdefault("JAX_PLATFORMS", "cpu")
# One OpenBLAS thread per worker: the two workers keep both cores busy, and OpenBLAS's threads
# would wait on each other. Read when numpy loads: the workers, started after this file is loaded,
# inherit it.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
# `main()` called in-process keeps no programs in the user's home (~/.cache/jaxcontact): every
# run of the suite compiles what a clean machine compiles. Tests of the kept programs give them
# a temporary directory of their own.
os.environ["JAXCONTACT_CACHE"] = ""
# The suite's cost is XLA compiling the model's programs, most of them run once or a few times, so by
# default it compiles them faster than users' programs are compiled: XLA's classic CPU loop emitters
# (which the fit's own program asks for, `programs.compiling`), LLVM's optimisation level 1 and one
# code-generation part per program (the two workers keep both cores busy). The numbers are the same
# to round-off, and the suite takes about two thirds of the time (docs/accuracy-and-speed.md).
# JAXCONTACT_XLA=default runs it on JAX's default compiler settings, as users' programs are compiled
# (.ci/run does, after the fast run). Level 0 is never used: with the classic emitters, jaxlib
# 0.10.2 gives wrong numbers there (the a_l solve's fallback loop, the E-derivative of K).
JAXLIB = tuple(int(x) for x in importlib.metadata.version("jaxlib").split(".")[:2])
DEFAULT_XLA = os.environ.get("JAXCONTACT_XLA") == "default"
flags = [os.environ.get("XLA_FLAGS")]
if not DEFAULT_XLA:
    flags.append("--xla_cpu_parallel_codegen_split_count=1")
    if JAXLIB >= (0, 10):
        flags += ["--xla_cpu_use_fusion_emitters=false", "--xla_backend_optimization_level=1"]
os.environ["XLA_FLAGS"] = " ".join(filter(None, flags))

# Source locations in traced programs serve XLA's dumps and profiles, which the suite does not
# read, and recording each equation's traceback costs tracing time.
os.environ.setdefault("JAX_INCLUDE_FULL_TRACEBACKS_IN_LOCATIONS", "false")
os.environ.setdefault("JAX_TRACEBACK_IN_LOCATIONS_LIMIT", "0")

import importlib.util  # noqa: E402

import jax  # noqa: E402

jax.config.update("jax_enable_x64", True)
# Strict dtype promotion: a mixed-precision operation in the library (a float32 count beside float64
# values, a real kernel times a complex spectrum) is an error here, not a silent promotion. The library
# runs the third-party code that is not strict-clean under standard promotion (numerics.standard_promotion).
jax.config.update("jax_numpy_dtype_promotion", "strict")

# JAXCONTACT_TYPECHECK=1 checks every annotation of the library as the suite runs it (jaxtyping's
# import hook with beartype, as the anchors run theirs; ints stand for floats as PEP 484 says),
# installed before anything imports jaxcontact. CI's second run does (.ci/run); the README's command
# runs the library as users do, where a wrong type meets the library's own message
# (helpers.refused_type), and keeps the suite's time (the checker costs about 5 %).
if os.environ.get("JAXCONTACT_TYPECHECK") == "1" and importlib.util.find_spec("beartype") is not None:
    from jaxtyping import install_import_hook

    install_import_hook(["jaxcontact"], "beartype.beartype(conf=beartype.BeartypeConf(is_pep484_tower=True))")

import pathlib  # noqa: E402

# One on-disk cache of compiled programs for the session's worker processes: a program that two
# test files (on two workers) both need is compiled once. A clean clone starts with it empty.
jax.config.update(
    "jax_compilation_cache_dir",
    str(pathlib.Path(__file__).resolve().parents[1] / ".pytest_cache" / ("jax-default" if DEFAULT_XLA else "jax")),
)
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.3)

import gc  # noqa: E402

import pytest  # noqa: E402
from helpers import TABLE1, TABLE1_WITHOUT_INTERACTION, make_scene  # noqa: E402

# Tracing the model's programs makes and drops millions of small objects: Python's collector, at its
# default thresholds, walks the long-lived ones (modules, compiled programs) again and again.
gc.freeze()
gc.set_threshold(100_000, 50, 1000)

# Whole files go to the two workers in this order, the longest (measured) first, so that the
# workers finish together: xdist's own order (most tests first) left a few long files of few
# tests for the end, with one worker idle. Files not named follow in their usual order.
LONGEST_FIRST = (
    "test_hard_cases.py",
    "test_bem_model.py",
    "test_bem_scale.py",
    "test_bem_layered.py",
    "test_contract.py",
    "test_bem_jax.py",
    "test_summit_laws.py",
    "test_approach_fit.py",
    "test_interface.py",
    "test_fitting.py",
    "test_dynamics.py",
    "test_programs.py",
    "test_tangential_cycle.py",
    "test_approach.py",
    "test_gradients.py",
    "test_topography_band.py",
    "test_compare_cli.py",
    "test_summit_path.py",
    "test_cli.py",
    "test_topography.py",
    "test_api.py",
    "test_bem_slip.py",
    "test_fit_batch.py",
    "test_posterior.py",
    "test_measured_spectrum.py",
    "test_bem_path.py",
    "test_in_service.py",
    "test_quadrature.py",
    "test_pole_integral.py",
    "test_bem.py",
    "test_bem_robustness.py",
    "test_load_path.py",
    "test_sweep.py",
    "test_reading.py",
    "test_bem_tangential.py",
    "test_measured_asperities.py",
    "test_comparator_fuzz.py",
    "test_inference.py",
    "test_scipy_crosscheck.py",
    "test_accuracy.py",
    "test_equinox.py",
    "test_bem_cache.py",
    "test_load_pieces.py",
    "test_problem.py",
    "test_validation_table.py",
    "test_distribution.py",
    "test_effects.py",
    "test_separate.py",
)


def pytest_unconfigure(config):
    """An xdist worker leaves without freeing its heap: the gigabytes of traced programs and compiled
    executables the suite leaves behind took its interpreter several seconds to free, which the
    controller waited for after the last test. Its results are sent by then (`pytest_sessionfinish`)."""
    if os.environ.get("PYTEST_XDIST_WORKER"):
        import sys

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(0)


def pytest_collection_modifyitems(items):
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(rank)))  # stable: a file's own order kept


@pytest.fixture(scope="session")
def table1_scene():
    return make_scene(**TABLE1)


@pytest.fixture(scope="session")
def dynamics_scene():
    """The embedded scene of `jaxcontact approach` and `jaxcontact dynamics` (Table 1, "paper",
    as the commands read it: the library's tests of the approach and the
    dynamics use it, so that the commands' tests beside them reuse their compiled programs."""
    from jaxcontact.cli._scenefile import DYNAMICS_SCENE, load_scene

    return load_scene(None, default=DYNAMICS_SCENE).scene


@pytest.fixture(scope="session")
def table1_without_interaction():
    """The Table 1 scene without interaction: for gradients through diffrax, whose reverse-mode
    compile with the "paper" interaction inside costs a minute, and for the fits and inference whose
    subject is not the interaction (the interaction's own gradients are checked against finite
    differences in test_gradients.py)."""
    return make_scene(**TABLE1_WITHOUT_INTERACTION)
