"""`jaxcontact bench --fit-batch`: many curves fitted in one batch (`fitting.fit_batch`) against looping
`fitting.fit`, as users call both: medians and bests of repeated calls, and their ratio."""

from __future__ import annotations

import statistics
import time

import numpy as np


def run_fit_bench(scene, curves: int = 1000, points: int = 30, looped: int = 20, repeats: int = 2) -> dict:
    """Seed-model curves of `scene` (F* = 1e-10…1e-4, 5 % noise, one seed each); the batch timed
    `repeats` times after its first (compiling) call; `fitting.fit` on `looped` of them after a first
    (compiling) fit, its per-curve times scaled to `curves`."""
    import jax

    from jaxcontact import fitting
    from jaxcontact.fitting._synthetic import synthetic_curve

    F_star = np.geomspace(1e-10, 1e-4, points)
    loads, K = (np.array(a) for a in zip(*(synthetic_curve(scene, F_star, noise=0.05, seed=s) for s in range(curves))))
    first = time.perf_counter()
    batch = fitting.fit_batch(loads, K, scene, n_starts=4)
    first = time.perf_counter() - first
    batch_times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fitting.fit_batch(loads, K, scene, n_starts=4)
        batch_times.append(time.perf_counter() - t0)
    fitting.fit(loads[0], K[0], scene, n_starts=4)  # compiles the loop's program
    loop_times, agreement, excess = [], [], []
    for i in range(looped):
        t0 = time.perf_counter()
        result = fitting.fit(loads[i], K[i], scene, n_starts=4)
        loop_times.append(time.perf_counter() - t0)
        agreement.append(abs(result.values["D"] - batch.values["D"][i]))
        # Where the two end in different local optima (the loss has kinks), which one fits better.
        excess.append((batch.loss[i] - result.loss) / result.loss)
    per_curve = (statistics.median(loop_times), min(loop_times))
    batched = (statistics.median(batch_times), min(batch_times))
    return {
        "device": jax.devices()[0].device_kind,
        "curves": curves,
        "points": points,
        "batch_first_call_s": first,
        "batch_compile_s": batch.compile_time,
        "batch_s": {"median": batched[0], "best": batched[1]},
        "loop_per_curve_s": {"median": per_curve[0], "best": per_curve[1]},
        "loop_s_scaled": {"median": per_curve[0] * curves, "best": per_curve[1] * curves},
        "ratio": {"median": per_curve[0] * curves / batched[0], "best": per_curve[1] * curves / batched[1]},
        "success": float(np.mean(batch.success)),
        "max_abs_D_difference": float(max(agreement)),
        "batch_loss_excess": {"max": float(max(excess)), "min": float(min(excess))},
    }


def format_fit_bench(r: dict) -> str:
    return "\n".join(
        [
            f"{r['curves']} curves of {r['points']} points on {r['device']}, 4 starts each",
            f"  fit_batch: {r['batch_s']['median']:.3g} s (best {r['batch_s']['best']:.3g} s) per call; first call "
            f"{r['batch_first_call_s']:.3g} s, of which compiling {r['batch_compile_s']:.3g} s; "
            f"{100 * r['success']:.1f} % converged",
            f"  fitting.fit in a loop: {r['loop_per_curve_s']['median']:.3g} s per curve (best "
            f"{r['loop_per_curve_s']['best']:.3g} s), {r['loop_s_scaled']['median']:.4g} s for {r['curves']}",
            f"  ratio (loop / batch): {r['ratio']['median']:.3g}× (median), {r['ratio']['best']:.3g}× (best); "
            f"largest |ΔD| between the two {r['max_abs_D_difference']:.2g}; the batch's loss relative to the "
            f"loop's {r['batch_loss_excess']['min']:+.2g} to {r['batch_loss_excess']['max']:+.2g}",
        ]
    )
