"""The text report of `jaxcontact bench`: each measurement, its ratio against the scipy baseline
measured in the same run, and the verdict against its target."""

from __future__ import annotations

CURVE_CALLS = {
    "plain": "jc.solve(scene, loads), as users call it",
    "filter_jit": "eqx.filter_jit(lambda s, F: solve(s, F).stiffness)",
    "jit": "jax.jit(solve) on array leaves, whole Solution",
    "jit_baseline_outputs": "jax.jit, scipy's outputs (a_l, K, A_r, status)",
    "jit_stiffness_only": "jax.jit, stiffness only",
}


def format_results(r: dict) -> str:
    c, g, f, tp = r["curve"], r["gradient"], r["fit"], r["throughput"]
    no_int = tp["no_interaction"]
    with_int = next(v for k, v in tp.items() if k != "no_interaction")

    def verdict(ok):
        return "target met" if ok else "TARGET NOT MET"

    def curve_rows(curve, calls):
        return [
            f"  {CURVE_CALLS[k]:52s} {1e3 * curve[k]['median_s']:7.3f} / {1e3 * curve[k]['p90_s']:7.3f} / "
            f"{1e3 * curve[k]['best_s']:7.3f}  {curve[k]['speedup_median']:6.0f}x  {curve[k]['over_jit_median']:5.2f}x"
            for k in calls
        ]

    def dispatch(asynchronous):
        return "asynchronous" if asynchronous else "synchronous"

    u, fu = r["curve_as_users_call_it"], r["fit_as_users_call_it"]
    lines = [
        f"device: {r['device']} ({r['devices']} device(s)); float64; after compilation (200-load curves: "
        f"{c['rounds']} rounds of scipy once and each jaxcontact call {c['repeats']} times, interleaved; "
        "the rest best of 5)",
        "",
        "200-load curve as users call it (a fresh process, JAX's default settings: "
        f"{dispatch(u['async_dispatch'])} dispatch), scipy median {u['scipy']['median_s']:.3f} s; "
        "jaxcontact (median / p90 / best, ms; speed-up over scipy and time over jax.jit, of the medians):",
        *curve_rows(u, ("plain", "filter_jit", "jit")),
        f"  plain call within 1.25x of jax.jit: {verdict(u['plain']['over_jit_median'] <= 1.25)}",
        f"200-load curve in this process ({dispatch(r['async_dispatch'])} dispatch), "
        f"scipy median {c['scipy']['median_s']:.3f} s:",
        *curve_rows(c, CURVE_CALLS),
        f"  same outputs as scipy >= 1000x faster: {verdict(c['jit_baseline_outputs']['speedup_median'] >= 1000)}",
        f"loss gradient (30 pt): value+grad {1e3 * g['value_and_grad_s']:.2f} ms = "
        f"{g['gradient_over_forward']:.2f}x the forward {1e3 * g['forward_s']:.2f} ms "
        f"(target <= 5x: {verdict(g['gradient_over_forward'] <= 5)}); "
        f"scipy finite differences {g['scipy_finite_difference_s']:.3f} s: {g['speedup']:.0f}x",
        f"D/G fit (30 pt):      jaxcontact {f['jaxcontact_1_start_s']:.3f} s (1 start), "
        f"{f['jaxcontact_12_starts_s']:.3f} s "
        f"(12 starts, vmapped); scipy least_squares {f['scipy_least_squares_s']:.2f} s: {f['speedup_1_start']:.0f}x "
        f"(target < 1 s: {verdict(f['jaxcontact_12_starts_s'] < 1)})",
        f"D/G fit (30 pt) as users call it (a fresh process, fitting.fit's defaults): first "
        f"{fu['first_s']:.2f} s (target < 3 s: {verdict(fu['first_s'] < 3)}), then {fu['median_s']:.3f} s median, "
        f"{fu['best_s']:.3f} s best (target < 0.1 s: {verdict(fu['median_s'] < 0.1)})",
        f"throughput, 1e5 loads: {no_int['points_per_s']:.3g} points/s without interaction "
        f"(target >= 1e6: {verdict(no_int['points_per_s'] >= 1e6)}), {with_int['points_per_s']:.3g} with",
        f"compile time:          {no_int['compile_s']:.2f} s without interaction, {with_int['compile_s']:.2f} s with "
        f"(target < 3 s: {verdict(max(no_int['compile_s'], with_int['compile_s']) < 3)})",
        f"CLI persistent compilation cache: `jaxcontact run` cold {r['compilation_cache']['cold_s']:.2f} s, warm "
        f"{r['compilation_cache']['warm_s']:.2f} s",
        *_interface_lines(r.get("interface"), verdict),
        *_cycle_lines(r.get("tangential_cycle"), verdict),
        *_path_lines(r.get("bem_path"), verdict, BEM_PATH, 1.5, "s"),
        *_path_lines(r.get("summit_path"), verdict, SUMMIT_PATH, 3.0, "ms"),
        *_spectrum_lines(r.get("measured_spectrum"), verdict),
        "",
        "what each effect costs (20000 loads):",
        f"{'variant':40s} {'compile (s)':>11s} {'run (ms)':>9s} {'vs leanest':>10s} {'points/s':>10s}",
    ]
    base = r["effects"][0]["run_s"]
    for e in r["effects"]:
        lines.append(
            f"{e['variant']:40s} {e['compile_s']:11.2f} {1e3 * e['run_s']:9.3f} {e['run_s'] / base:9.2f}x "
            f"{e['points_per_s']:10.3g}"
        )
    return "\n".join(lines)


def _interface_lines(timings: dict | None, verdict) -> list[str]:
    """The interface law's line of the report (none where the run did not time it)."""
    if not timings:
        return []
    cells = ", ".join(
        f"{name} {1e3 * t['median_s']:.1f} / {1e3 * t['best_s']:.1f} ms ({t['over_solve']:.1f}x its solve)"
        for name, t in timings.items()
    )
    slowest = max(t["median_s"] for t in timings.values())
    return [f"interface law, 1000 pressures (median / best): {cells} (target < 10 ms: {verdict(slowest < 0.01)})"]


def _cycle_lines(timing: dict | None, verdict) -> list[str]:
    """The tangential cycle's line of the report (none where the run did not time it)."""
    if not timing:
        return []
    return [
        f"tangential cycle, 50 amplitudes (median / best): {1e3 * timing['median_s']:.2f} / "
        f"{1e3 * timing['best_s']:.2f} ms (target < 10 ms: {verdict(timing['median_s'] < 0.01)})"
    ]


def _against(timing: dict | None, verdict, what: tuple[str, str], names: tuple[str, str, str], target, unit):
    """One line of the report: a call against its reference, median / best each, their ratio against
    `target` (none where the run did not time it). `what`: the call's and the reference's labels;
    `names`: their keys in `timing` and the ratio's; `unit`: "s" or "ms"."""
    if not timing:
        return []
    scale = 1e3 if unit == "ms" else 1.0
    call, reference = (timing[name] for name in names[:2])
    ratio = timing[names[2]]

    def pair(t):
        return f"{t['median_s'] * scale:.3f} / {t['best_s'] * scale:.3f} {unit}"

    return [
        f"{what[0]} (median / best): {pair(call)}; {what[1]} {pair(reference)}; "
        f"{ratio:.2f}x (target <= {target:g}x: {verdict(ratio <= target)})"
    ]


BEM_PATH = ("capped BEM 256², 10-point load–unload path", "bem.solve of the same loads")
SUMMIT_PATH = ("measured Kogut–Etsion summits, 200-point load–unload–reload path", "solve of the same loads")


def _path_lines(timing: dict | None, verdict, what: tuple[str, str], target: float, unit: str) -> list[str]:
    """A load path's line of the report: the path and the solve of the same loads (`what`, their
    labels), their ratio against `target`."""
    return _against(timing, verdict, what, ("path", "solve", "over_solve"), target, unit)


def _spectrum_lines(timing: dict | None, verdict) -> list[str]:
    """Persson on a measured spectrum's line of the report."""
    what = ("Persson on a 200-point measured spectrum, 100 loads", "closed form")
    return _against(timing, verdict, what, ("table", "closed", "over_closed"), 2.0, "ms")


def format_markdown(r: dict, machine: str, date: str) -> str:
    """The table of measured figures in docs/accuracy-and-speed.md, as this run measured them."""
    c, u, fu, g, f, tp, cache = (
        r["curve"],
        r["curve_as_users_call_it"],
        r["fit_as_users_call_it"],
        r["gradient"],
        r["fit"],
        r["throughput"],
        r["compilation_cache"],
    )
    no_int = tp["no_interaction"]
    with_int = next(v for k, v in tp.items() if k != "no_interaction")

    def ms(x):
        return f"{1e3 * x['median_s']:.3f} ms"

    rows = [
        (
            "200-load curve, like for like (a_l, K, A_r, status), `jax.jit`",
            f"{ms(c['jit_baseline_outputs'])}: {c['jit_baseline_outputs']['speedup_median']:.0f}× scipy "
            f"({1e3 * c['scipy']['median_s']:.0f} ms)",
            "≥ 1000× scipy",
        ),
        (
            "200-load curve, `jc.solve(scene, loads)` as users call it (JAX's default settings)",
            f"{ms(u['plain'])}: {u['plain']['over_jit_median']:.2f}× `jax.jit` ({ms(u['jit'])})",
            "≤ 1.25× `jax.jit`",
        ),
        (
            "gradient of a 30-point fitting loss",
            f"{g['gradient_over_forward']:.2f}× the forward; {g['speedup']:.0f}× scipy finite differences",
            "≤ 5× the forward",
        ),
        (
            "D, G fit to 30 points (LM, warm)",
            f"{f['jaxcontact_1_start_s']:.3f} s (1 start), "
            f"{f['jaxcontact_12_starts_s']:.3f} s (12 starts); scipy least_squares {f['scipy_least_squares_s']:.2f} s",
            "< 1 s",
        ),
        (
            "D, G fit to 30 points as users call it (a fresh process, `fitting.fit`'s defaults: BFGS, 12 starts)",
            f"first {fu['first_s']:.2f} s; then {fu['median_s']:.3f} s median ({fu['best_s']:.3f} s best)",
            "first < 3 s; then < 0.1 s",
        ),
        (
            "throughput, 10⁵ loads",
            f"{no_int['points_per_s']:.2g} points/s without interaction, {with_int['points_per_s']:.2g} with",
            "≥ 10⁶ without",
        ),
        (
            "compile time (no persistent cache)",
            f"{no_int['compile_s']:.2f} s without interaction, {with_int['compile_s']:.2f} s with",
            "< 3 s",
        ),
        (
            "`jaxcontact run` (persistent cache)",
            f"cold {cache['cold_s']:.2f} s, warm {cache['warm_s']:.2f} s",
            "cold < 4 s, warm < 2 s",
        ),
    ]
    lines = [
        f"*Measured by `jaxcontact bench` on {machine}, {date}; float64, after compilation; the 200-load "
        "curves are medians of interleaved rounds (scipy once, each call 30 times).*",
        "",
        "| what | measured | target |",
        "|---|---|---|",
        *(f"| {a} | {b} | {t} |" for a, b, t in rows),
    ]
    return "\n".join(lines)
