"""Timings of the compiled model: what each effect costs, and the speed against the scipy baseline.

Every figure is measured in this run on this machine, after compilation, as the best of
several repeats; ratios are printed rather than asserted (timings are not tests).
"""

from __future__ import annotations

import time

import jax
import numpy as np

from .scene import Scene
from .scipy_baseline import BaselineParameters, solve_curve
from .solve import solve


def _best_of(fn, repeats=5):
    best = np.inf
    for _ in range(repeats):
        t = time.perf_counter()
        jax.block_until_ready(fn())
        best = min(best, time.perf_counter() - t)
    return best


def time_scene(scene: Scene, loads) -> dict:
    """Compile time and run time (s) of `solve` for this scene and these loads."""
    loads = np.asarray(loads, dtype=float)
    t = time.perf_counter()
    jax.block_until_ready(solve(scene, loads))
    first = time.perf_counter() - t
    run = _best_of(lambda: solve(scene, loads))
    return {"compile_s": first - run, "run_s": run, "points_per_s": loads.size / run}


def _baseline_params(scene: Scene) -> BaselineParameters:
    s, m = scene.surface, scene.material
    return BaselineParameters(float(s.D), float(s.G), float(m.E), float(m.nu), float(m.H), float(scene.area),
                              float(s.l_min), scene.model, scene.interaction, scene.distribution)


def effects_table(scene: Scene, loads) -> list[dict]:
    """The same joint with each effect switched on and off: compile and run time of each variant."""
    variants = [("no interaction, no regime shares", dict(interaction="none", regime_shares=False)),
                ("no interaction", dict(interaction="none")),
                ("interaction 'series'", dict(interaction="series")),
                ("interaction 'paper'", dict(interaction="paper")),
                ("interaction 'paper' + WK distribution", dict(interaction="paper", distribution="wk"))]
    rows = []
    for label, kw in variants:
        variant = Scene(scene.surface, scene.material, scene.area, model="xia2024",
                        **{"distribution": "mb", "regime_shares": True, **kw})
        rows.append({"variant": label, **time_scene(variant, loads)})
    return rows


def baseline_ratio(scene: Scene, loads) -> dict:
    """One load curve: jaxcontact (compiled) against the plain scipy implementation."""
    params = _baseline_params(scene)
    t = time.perf_counter()
    solve_curve(params, loads)
    scipy_s = time.perf_counter() - t
    jax_s = time_scene(scene, loads)["run_s"]
    return {"points": int(np.size(loads)), "scipy_s": scipy_s, "jaxcontact_s": jax_s, "speedup": scipy_s / jax_s}
