"""What accuracy costs in time: every numerical knob against a high-precision reference.

Error is the maximum relative error in K over a load sweep, against `reference.stiffness`
(mpmath, 30 digits); time is per 1000-load curve after compilation (best of 5, `jax.jit`).
The knobs: the interaction remainder summed as a power series (the default) against
Gauss–Legendre with 4 … 256 nodes and adaptive quadax Gauss–Kronrod,
the a_l solver tolerance, float32 against float64. Points on the Pareto front (no other point is
both faster and more accurate) are marked, and so is the default.
"""

from __future__ import annotations

import dataclasses
import time

import jax
import numpy as np

from ..core import Scene, solve
from ..numerics import x64
from ..quantities import Scales
from . import _reference as reference
from ._curve import best_of

CURVE = 1000
ERROR_POINTS = 12


@dataclasses.dataclass
class Knob:
    """One setting of the study: the model's options by name (`Scene.with_model`, its root finder's
    `solver_tolerance` among them), float32."""

    label: str
    group: str
    options: dict
    float32: bool = False
    default: bool = False


def knobs(quick: bool = False) -> list[Knob]:
    nodes = (4, 16, 32) if quick else (4, 8, 12, 16, 24, 32, 64, 128, 256)
    out = [
        Knob("power series of the pole term (no nodes)", "power series", dict(quadrature="power-series"), default=True)
    ]
    out += [
        Knob(f"Gauss–Legendre, {n} nodes", "quadrature nodes", dict(quadrature="gauss-legendre", quadrature_nodes=n))
        for n in nodes
    ]
    if quick:
        return out
    out += [
        Knob(
            f"adaptive quadax quadgk, rtol {tol:g}",
            "adaptive quadrature",
            dict(quadrature="adaptive", quadrature_tolerance=tol),
        )
        for tol in (1e-4, 1e-8, 1e-12)
    ]
    out += [
        Knob(f"solver tolerance {tol:g}", "a_l solver tolerance", dict(solver_tolerance=tol))
        for tol in (1e-3, 1e-5, 1e-7, 1e-9)
    ]
    out += [Knob("float32 (default settings)", "precision", {}, float32=True)]
    return out


def study(scene: Scene, F_star_range=(1e-7, 9.81e-4), quick: bool = False, progress=None) -> dict:
    """Run the study on `scene` (xia2024, "mb"); returns the reference and one row per knob.

    The default sweep ends at 0.9998 of the Table 1 surface's interaction breakdown (F* = 9.812e-4), where
    the interaction integrand is sharpest and the quadrature has the most to do.
    """
    s, m = scene.surface, scene.material
    E, area = float(m.E), float(scene.area)
    loads = np.geomspace(*F_star_range, CURVE) * float(Scales.of(scene).load)
    pick = np.linspace(0, CURVE - 1, ERROR_POINTS).astype(int)
    exact = np.array(
        [
            reference.stiffness(
                float(s.D),
                float(s.G),
                E,
                float(m.nu),
                float(m.H),
                area,
                float(s.l_min),
                float(F),
                scene.model.interaction.name,
            )[0]
            for F in loads[pick]
        ]
    )
    rows = []
    items = knobs(quick)
    for knob in items if progress is None else progress(items):
        variant = scene.with_model("xia2024", interaction=scene.model.interaction.name, **knob.options)
        with x64(not knob.float32):
            F = loads.astype(np.float32 if knob.float32 else np.float64)
            run = jax.jit(solve)
            t = time.perf_counter()
            K = np.asarray(jax.block_until_ready(run(variant, F)).stiffness, dtype=float)
            compile_s = time.perf_counter() - t
            best = best_of(lambda: run(variant, F))
        error = float(np.max(np.abs(K[pick] / exact - 1)))
        rows.append(
            dict(
                knob=knob.label,
                group=knob.group,
                default=knob.default,
                max_rel_error=error,
                ms_per_1000_loads=1e3 * best * 1000 / CURVE,
                compile_s=compile_s - best,
            )
        )
    for r in rows:
        r["pareto"] = not any(_dominates(o, r) for o in rows if o is not r)
    return {"loads_F_star": list(F_star_range), "reference": "mpmath, 30 digits", "rows": rows}


ROUND_OFF = 1e-14  # errors below this are all "at round-off": equal for the Pareto front


def _dominates(a: dict, b: dict) -> bool:
    """a is at least as fast and as accurate as b, and strictly better in one."""
    ea, eb = max(a["max_rel_error"], ROUND_OFF), max(b["max_rel_error"], ROUND_OFF)
    ta, tb = a["ms_per_1000_loads"], b["ms_per_1000_loads"]
    return ta <= tb and ea <= eb and (ta < tb or ea < eb)


def format_study(result: dict) -> str:
    lines = [
        f"max relative error in K over F* {result['loads_F_star'][0]:g} … {result['loads_F_star'][1]:g} "
        f"(reference: {result['reference']}); time per 1000-load curve after compilation",
        "",
        f"{'knob':42s} {'max rel error':>13s} {'ms/1000 loads':>13s}  ",
    ]
    for r in result["rows"]:
        marks = ("default " if r["default"] else "") + ("pareto" if r["pareto"] else "")
        lines.append(f"{r['knob']:42s} {r['max_rel_error']:13.2e} {r['ms_per_1000_loads']:13.3f}  {marks}")
    return "\n".join(lines)


def plot_study(result: dict, path) -> str:
    from ._plotting import save_figure, subplots

    fig, ax = subplots(figsize=(7, 4.8))
    groups = sorted({r["group"] for r in result["rows"]})
    for i, g in enumerate(groups):
        rs = [r for r in result["rows"] if r["group"] == g]
        ax.loglog(
            [r["ms_per_1000_loads"] for r in rs],
            [max(r["max_rel_error"], 1e-17) for r in rs],
            "o",
            color=f"C{i}",
            label=g,
        )
    front = sorted((r for r in result["rows"] if r["pareto"]), key=lambda r: r["ms_per_1000_loads"])
    ax.loglog(
        [r["ms_per_1000_loads"] for r in front],
        [max(r["max_rel_error"], 1e-17) for r in front],
        "k--",
        lw=1,
        label="Pareto front",
    )
    for r in result["rows"]:
        if r["default"]:
            ax.plot(r["ms_per_1000_loads"], max(r["max_rel_error"], 1e-17), "r*", ms=14, label="default")
    ax.set(
        xlabel="ms per 1000-load curve (after compilation)",
        ylabel="max relative error in K",
        title="What accuracy costs",
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path)
