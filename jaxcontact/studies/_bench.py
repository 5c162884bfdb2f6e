"""`jaxcontact bench`: timings of the compiled model, each as a ratio measured in this run.

Against the plain scipy implementation (`scipy_baseline`: quad + brentq, what a user would
otherwise write): a 200-load curve, the gradient of a fitting loss (against finite differences
of the baseline), and a full D/G fit (against `scipy.optimize.least_squares` on the baseline).
Also: compile time, throughput over 1e5 loads with and without interaction, what each effect
costs, an interface law of 1000 pressures per analytic model, a tangential cycle of 50 amplitudes, load–unload
paths of the capped BEM and of measured elastic–plastic summits,
and the persistent compilation cache of the CLI. Times are after compilation, best of
several repeats; nothing here is asserted (timings are not tests).
"""

from __future__ import annotations

import functools
import math
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from scipy import optimize

from ..core import Outputs, Scene, solve
from ..quantities import Scales
from ._bench_paths import bem_path, summit_path
from ._bench_user import curve_as_users_call_it, fit_as_users_call_it
from ._curve import _arrays, _baseline, best_of, called, curve
from ._scipy_baseline import solve_curve

TARGETS = {
    "curve_speedup": 1000.0,
    "gradient_over_forward": 5.0,
    "fit_seconds": 1.0,
    "points_per_s_no_interaction": 1e6,
    "compile_seconds": 3.0,
}


def time_scene(scene: Scene, loads, outputs: Outputs = Outputs()) -> dict:
    """Compile time and run time (s, best of 5) of `jax.jit(solve)` for this scene and these loads."""
    run = jax.jit(functools.partial(solve, outputs=outputs))
    scene, loads = _arrays(scene), jnp.asarray(loads)
    t = time.perf_counter()
    jax.block_until_ready(run(scene, loads))
    first = time.perf_counter() - t
    seconds = best_of(lambda: run(scene, loads))
    return {"compile_s": max(first - seconds, 0.0), "run_s": seconds, "points_per_s": loads.size / seconds}


def _data(scene: Scene, n=30):
    loads = np.geomspace(1e-10, 1e-4, n) * float(Scales.of(scene).load)
    return loads, np.asarray(solve(scene, loads).stiffness) * np.exp(0.05 * np.random.default_rng(0).standard_normal(n))


def _valid_curve(scene: Scene):
    """30 loads (F* from 1e-10 to 1e-5, every point valid on Table 1 with "paper") and their K with
    5 % noise: the curve of the fit's latency goal."""
    from jaxcontact.fitting._synthetic import synthetic_curve

    return synthetic_curve(scene, np.geomspace(1e-10, 1e-5, 30), noise=0.05, seed=1)


def gradient(scene: Scene) -> dict:
    """Loss = mean squared log-stiffness residual over 30 points, as a function of (D, ln G)."""
    loads, K = _data(scene)
    F, log_K = jnp.asarray(loads), jnp.log(jnp.asarray(K))
    base = _arrays(scene)

    def loss(theta):
        s = eqx.tree_at(lambda sc: (sc.surface.D, sc.surface.G), base, (theta[0], jnp.exp(theta[1])))
        r = jnp.log(solve(s, F).stiffness) - log_K
        return jnp.mean(r * r)

    theta = jnp.array([float(scene.surface.D) + 0.01, math.log(float(scene.surface.G)) + 0.1])
    forward, value_and_grad = jax.jit(loss), jax.jit(jax.value_and_grad(loss))
    jax.block_until_ready(forward(theta))
    jax.block_until_ready(value_and_grad(theta))
    forward_s = best_of(lambda: forward(theta))
    grad_s = best_of(lambda: value_and_grad(theta))

    def baseline_loss(th):
        _, K_model, _, _ = solve_curve(_baseline(scene, D=th[0], G=math.exp(th[1])), loads)
        return float(np.mean((np.log(K_model) - np.log(K)) ** 2))

    t = time.perf_counter()
    h = 1e-6
    [baseline_loss(np.asarray(theta) + s * h * e) for e in np.eye(2) for s in (1, -1)]
    baseline_loss(np.asarray(theta))
    fd_s = time.perf_counter() - t
    return {
        "points": 30,
        "forward_s": forward_s,
        "value_and_grad_s": grad_s,
        "gradient_over_forward": grad_s / forward_s,
        "scipy_finite_difference_s": fd_s,
        "speedup": fd_s / grad_s,
    }


def fit(scene: Scene) -> dict:
    from jaxcontact import fitting

    loads, K = _data(scene)
    start = eqx.tree_at(lambda s: (s.surface.D, s.surface.G), scene, (1.5, 1e-9))
    fitting.fit(loads, K, start, method=fitting.LevenbergMarquardt())  # compile
    fitting.fit(loads, K, start, method=fitting.LevenbergMarquardt(), n_starts=1)
    t = time.perf_counter()
    ours = fitting.fit(loads, K, start, method=fitting.LevenbergMarquardt())
    multi_s = time.perf_counter() - t
    t = time.perf_counter()
    fitting.fit(loads, K, start, method=fitting.LevenbergMarquardt(), n_starts=1)
    single_s = time.perf_counter() - t

    def residuals(th):
        _, K_model, _, _ = solve_curve(_baseline(scene, D=th[0], G=math.exp(th[1])), loads)
        return np.log(np.where(np.isfinite(K_model), K_model, 1.0)) - np.log(K)

    t = time.perf_counter()
    ls = optimize.least_squares(
        residuals, [1.5, math.log(1e-9)], bounds=([1.01, math.log(1e-15)], [1.99, math.log(1e-6)]), x_scale="jac"
    )
    scipy_s = time.perf_counter() - t
    return {
        "points": 30,
        "jaxcontact_12_starts_s": multi_s,
        "jaxcontact_1_start_s": single_s,
        "scipy_least_squares_s": scipy_s,
        "speedup_1_start": scipy_s / single_s,
        "D_jaxcontact": ours.values["D"],
        "D_scipy": float(ls.x[0]),
    }


def throughput(scene: Scene, n: int = 100_000) -> dict:
    loads = np.geomspace(1e-7, 1e-4, n) * float(Scales.of(scene).load)
    out = {}
    interaction = scene.model.options().get("interaction", "none")
    for label, choice in (("no_interaction", "none"), ("interaction_" + interaction, interaction)):
        out[label] = time_scene(scene.with_model("xia2024", interaction=choice), loads, Outputs(regime_shares=False))
    return out


def effects_table(scene: Scene, n: int = 20_000) -> list[dict]:
    """The same joint with each effect switched on and off: compile and run time of each variant."""
    loads = np.geomspace(1e-7, 1e-4, n) * float(Scales.of(scene).load)
    variants = [
        ("no interaction, no regime shares", dict(interaction="none"), False),
        ("no interaction", dict(interaction="none"), True),
        ("interaction 'series'", dict(interaction="series"), True),
        ("interaction 'paper'", dict(interaction="paper"), True),
        ("interaction 'paper' + WK distribution", dict(interaction="paper", distribution="wk"), True),
    ]
    rows = []
    for label, kw, shares in variants:
        variant = scene.with_model("xia2024", **kw)
        rows.append({"variant": label, **time_scene(variant, loads, Outputs(regime_shares=shares))})
    return rows


def compilation_cache() -> dict:
    """Wall time of `jaxcontact run` twice, with a fresh persistent cache: cold, then warm."""
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as out:
        env = {**os.environ, "JAXCONTACT_CACHE": cache}
        times = []
        for _ in range(2):
            t = time.perf_counter()
            subprocess.run(
                [sys.executable, "-m", "jaxcontact.cli", "run", "--out", out, "--format", "json", "--no-progress"],
                env=env,
                check=True,
                capture_output=True,
            )
            times.append(time.perf_counter() - t)
        entries = sum(1 for _ in pathlib.Path(cache).rglob("*") if _.is_file())
    return {"cold_s": times[0], "warm_s": times[1], "cache_entries": entries}


# The analytic models an interface law is timed with (`interface`).
INTERFACE_MODELS = ("xia2024", "jzz2010", "gw", "persson")


def interface(scene: Scene, pressures: int = 1000) -> dict:
    """`jc.interface_law(scene, pressures)` as users call it, over four decades of nominal pressure
    from F* = 1e-9, per analytic model: median and best of 15 calls after compilation (s), and the
    median over one `solve` of as many loads (the closure's quadrature and the unloading columns
    on top of the loading curve)."""
    from ..applications import interface_law

    out = {}
    for name in INTERFACE_MODELS:
        variant = scene.with_model(name)
        p = np.geomspace(1e-9, 1e-5, pressures) * float(variant.material.E)
        law = called(lambda: interface_law(variant, p).tangential_stiffness)
        curve_only = called(lambda: solve(variant, p * float(variant.area)).stiffness)
        out[name] = {
            "median_s": law["median_s"],
            "best_s": law["best_s"],
            "over_solve": law["median_s"] / curve_only["median_s"],
        }
    return out


def tangential_cycle(scene: Scene, amplitudes: int = 50) -> dict:
    """`jc.tangential_cycle` of the scene at F* = 1e-6 over `amplitudes` displacement amplitudes
    (0.1 pm to 10 µm), μ = 0.3, as users call it: median and best of 15 calls after compilation (s)."""
    from ..core import tangential_cycle as cycle

    preload = 1e-6 * float(Scales.of(scene).load)
    u = jnp.geomspace(1e-13, 1e-5, amplitudes)
    return called(lambda: cycle(scene, preload, u, 0.3).dissipation)


def measured_spectrum(scene: Scene, bins: int = 200, loads: int = 100) -> dict:
    """Persson on a 200-point table of the scene's own power-law C2D (`MeasuredSpectrum`) against the
    closed-form Persson, `loads` loads from F* = 1e-8 to 1e-3: median and best of 15 eager calls
    after compilation (s) and the ratio of medians (the issue's target: within 2x)."""
    from ..models import Persson
    from ..physics import MeasuredSpectrum
    from ..physics._spectrum import log_areal_prefactor

    side = float(scene.area) ** 0.5
    D, G = float(scene.surface.D), float(scene.surface.G)
    q = np.geomspace(2 * np.pi / side, 2 * np.pi / float(scene.surface.l_min), bins)
    table = MeasuredSpectrum(q, np.exp(float(log_areal_prefactor(D, np.log(G)))) * q ** -(6 - 2 * D))
    F = np.geomspace(1e-8, 1e-3, loads) * float(scene.material.E) * float(scene.area)
    closed = called(lambda: solve(scene.with_model(Persson()), F).stiffness)
    tabulated = called(lambda: solve(scene.with_model(Persson(spectrum=table)), F).stiffness)
    return {"closed": closed, "table": tabulated, "over_closed": tabulated["median_s"] / closed["median_s"]}


def run_all(scene: Scene, progress=None) -> dict:
    """Every timing of the bench. Its compile times are compilations only in a process that keeps
    no persistent compilation cache (the command line runs the bench without one; a process that
    has compiled with one keeps reading it, whatever `jax_enable_compilation_cache` says later).
    The command line's cache is timed in processes of its own (`compilation_cache`)."""
    steps = [
        ("curve", curve),
        ("curve_as_users_call_it", lambda s: curve_as_users_call_it(s, only=("plain", "filter_jit"))),
        ("gradient", gradient),
        ("fit", fit),
        ("fit_as_users_call_it", lambda s: fit_as_users_call_it(s, *_valid_curve(s))),
        ("throughput", throughput),
        ("effects", effects_table),
        ("interface", interface),
        ("tangential_cycle", tangential_cycle),
        ("bem_path", bem_path),
        ("summit_path", summit_path),
        ("measured_spectrum", measured_spectrum),
        ("compilation_cache", lambda s: compilation_cache()),
    ]
    results = {
        "device": str(jax.devices()[0]),
        "devices": len(jax.devices()),
        "async_dispatch": bool(jax.config.read("jax_cpu_enable_async_dispatch")),
    }
    for name, step in steps if progress is None else progress(steps):
        results[name] = step(scene)
    return results
