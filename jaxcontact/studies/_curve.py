"""The 200-load curve of `jaxcontact bench`: scipy against each way of calling jaxcontact,
interleaved, timed call by call (median, 90th percentile, best)."""

from __future__ import annotations

import math
import time

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..core import Scene, solve
from ..quantities import Scales
from ._scipy_baseline import BaselineParameters, solve_curve


def best_of(fn, repeats=5) -> float:
    best = math.inf
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(fn())
        best = min(best, time.perf_counter() - t)
    return best


def _arrays(scene: Scene) -> Scene:
    return jax.tree.map(jnp.asarray, scene)


def _baseline(scene: Scene, **changes) -> BaselineParameters:
    s, m = scene.surface, scene.material
    values = dict(
        D=float(s.D),
        G=float(s.G),
        E=float(m.E),
        nu=float(m.nu),
        H=float(m.H),
        area=float(scene.area),
        l_min=float(s.l_min),
        **scene.model.options(),
    )
    values.pop("quadrature", None)
    # The baseline implements the paper's spot stiffness (Eqs. 27-29) only.
    spot = values.pop("spot_stiffness", "paper")
    if spot != "paper":
        raise ValueError(f"spot_stiffness = {spot!r}: the scipy baseline implements 'paper' (Eqs. 27-29) only")
    values.setdefault("interaction", "none")
    return BaselineParameters(**{**values, **changes})


def stats(times) -> dict:
    """Median, 90th percentile and best of a list of times (s)."""
    times = np.asarray(times)
    return {"median_s": float(np.median(times)), "p90_s": float(np.percentile(times, 90)), "best_s": float(times.min())}


def called(fn, repeats: int = 15) -> dict:
    """`stats` of `repeats` calls of `fn` after one that compiles it."""
    jax.block_until_ready(fn())
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(fn())
        times.append(time.perf_counter() - t)
    return stats(times)


def curve(scene: Scene, rounds: int = 10, repeats: int = 30, only: tuple[str, ...] | None = None) -> dict:
    """200 loads over F* = 1e-7 … 1e-4: scipy against jaxcontact's calls, interleaved.

    Each of `rounds` rounds runs the scipy curve once and each jaxcontact call `repeats` times;
    every call is timed (synchronously) and reported as median, 90th percentile and best.
    Interleaving puts all sides in the same spells of the machine's speed (on a shared 2-core
    machine the same compiled call drifts by up to 2x for tens of milliseconds at a time). The
    calls: `solve(scene, loads)` as users make it (eager, on the scene as built); the same inside
    `eqx.filter_jit`; `jax.jit(solve)` on the scene's array leaves (whole `Solution`); the outputs
    the scipy baseline computes (a_l, K, A_r and status: like for like); and the stiffness alone.
    XLA drops whatever a jitted function does not return. `only` names the calls to time (all by
    default); `jit`, the reference of every ratio, is always timed.
    """
    loads = jnp.asarray(np.geomspace(1e-7, 1e-4, 200) * float(Scales.of(scene).load))
    arrays = _arrays(scene)

    def baseline_outputs(s, F):
        solution = solve(s, F)
        return solution.a_l, solution.stiffness, solution.real_area, solution.status

    filter_jitted = eqx.filter_jit(lambda s, F: solve(s, F).stiffness)
    jitted = {
        "jit": jax.jit(solve),
        "jit_baseline_outputs": jax.jit(baseline_outputs),
        "jit_stiffness_only": jax.jit(lambda s, F: solve(s, F).stiffness),
    }
    calls = {
        "plain": lambda: solve(scene, loads).stiffness,
        "filter_jit": lambda: filter_jitted(scene, loads),
        **{name: (lambda run=run: run(arrays, loads)) for name, run in jitted.items()},
    }
    if only is not None:
        calls = {name: call for name, call in calls.items() if name in only or name == "jit"}
    times = {name: [] for name in ("scipy", *calls)}
    for call in calls.values():
        jax.block_until_ready(call())
    for _ in range(rounds):
        t = time.perf_counter()
        solve_curve(_baseline(scene), np.asarray(loads))
        times["scipy"].append(time.perf_counter() - t)
        for name, call in calls.items():
            for _ in range(repeats):
                t = time.perf_counter()
                jax.block_until_ready(call())
                times[name].append(time.perf_counter() - t)
    result = {"points": 200, "rounds": rounds, "repeats": repeats, **{k: stats(v) for k, v in times.items()}}
    scipy = result["scipy"]["median_s"]
    for name in calls:
        result[name]["speedup_median"] = scipy / result[name]["median_s"]
        result[name]["over_jit_median"] = result[name]["median_s"] / result["jit"]["median_s"]
    return result
