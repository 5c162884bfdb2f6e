"""`jaxcontact bench --bem`: the JAX boundary-element solve against ContactMechanics on the same
surfaces, seconds per K(F) point and their ratio measured in one run, peak memory, and the time of
a D, G fit with the boundary-element model."""

from __future__ import annotations

import math
import time

import numpy as np

# The reference surface of docs/model.md §10: L = 100 µm, G = 1e-12 m, E = 210 GPa, D = 1.5, l_min = L/64.
LENGTH, MODULUS, D, G = 100e-6, 210e9, 1.5, 1e-12
F_STAR = (2e-5, 1e-4, 5e-4)  # contact fractions ~0.7-15 %


def _surface(grid: int):
    """The reference's surface of seed 0 on `grid`² as a scene and the BEM model that solves it
    (`rolloff = 0`: the heights of `bem.realisation`)."""
    from .. import BEM, Material, Scene, Surface

    scene = Scene(Surface(D=D, G=G, l_min=LENGTH / 64), Material(E=MODULUS, nu=0.3, H=3e8), LENGTH**2)
    return scene, BEM(grid=grid, realisations=1, rolloff=0.0)


def per_point(grid: int, contactmechanics: bool = True) -> dict:
    """Seconds per K(F) point on `grid`²: JAX (tangent: one solve; secant: three, as the reference)
    after compilation, best of 2, and (`contactmechanics`) ContactMechanics's secant at the same
    penetration tolerance."""
    import jax
    import jax.numpy as jnp

    from ..bem import BEMSettings, bem_stiffness, solve
    from ._bem_fits import surface_map

    scene, model = _surface(grid)
    heights = model.heights(scene)[0]
    loads = np.asarray(F_STAR) * MODULUS * LENGTH**2
    tolerance = BEMSettings().penetration_tolerance / grid  # ContactMechanics's pentol, per rms height
    out = {"grid": grid, "points": len(loads), "device": jax.devices()[0].device_kind}
    for label, secant in (("jax_tangent", 0.0), ("jax_secant", 0.02)):
        run = lambda: solve(heights, LENGTH, MODULUS, jnp.asarray(loads), tolerance=tolerance, secant=secant)  # noqa: E731
        t = time.perf_counter()
        jax.block_until_ready(run().stiffness)
        first = time.perf_counter() - t
        times = []
        for _ in range(2):
            t = time.perf_counter()
            result = run()
            jax.block_until_ready(result.stiffness)
            times.append(time.perf_counter() - t)
        out[label] = {"s_per_point": min(times) / len(loads), "compile_s": max(first - min(times), 0.0)}
        out[label + "_stiffness"] = np.asarray(result.secant_stiffness if secant else result.stiffness).tolist()
    if contactmechanics:
        t = time.perf_counter()
        reference = bem_stiffness(surface_map(scene, model), MODULUS, loads)
        out["contactmechanics"] = {"s_per_point": (time.perf_counter() - t) / len(loads)}
        out["contactmechanics_stiffness"] = reference.stiffness.tolist()
        for label in ("jax_tangent", "jax_secant"):
            out[label]["speedup"] = out["contactmechanics"]["s_per_point"] / out[label]["s_per_point"]
            out[label]["K_over_contactmechanics"] = (
                np.asarray(out[label + "_stiffness"]) / reference.stiffness
            ).tolist()
    return out


def iterations(grid: int, f_star=(1e-4, 3e-4, 1e-3), plain: bool = True, dtype=None) -> dict:
    """The constrained iteration's count and seconds per load on `grid`², preconditioned and (`plain`)
    Polonsky & Keer's: a surface resolved down to 4 grid spacings (l_min = 4L/grid, the reference's
    D and G, synthesised in JAX), loads `f_star` (F*), the tangent; after compilation, best of 2."""
    import jax
    import jax.numpy as jnp

    from .. import BEM, Material, Scene, Surface
    from ..bem import solve

    scene = Scene(Surface(D=D, G=G, l_min=4 * LENGTH / grid), Material(E=MODULUS, nu=0.3, H=3e8), LENGTH**2)
    heights = BEM(grid=grid, realisations=1, rolloff=0.0).heights(scene)[0]
    if dtype is not None:
        heights = heights.astype(dtype)
    loads = jnp.asarray(np.asarray(f_star) * MODULUS * LENGTH**2, heights.dtype)
    out = {"grid": grid, "f_star": list(f_star), "device": jax.devices()[0].device_kind, "dtype": str(heights.dtype)}
    for label, preconditioned in (("preconditioned", True), ("plain", False))[: 2 if plain else 1]:
        times = []
        for _ in range(3):
            t = time.perf_counter()
            result = jax.block_until_ready(solve(heights, LENGTH, MODULUS, loads, preconditioned=preconditioned))
            times.append(time.perf_counter() - t)
        out[label] = {
            "iterations": np.asarray(result.iterations).tolist(),
            "contact_fraction": np.asarray(result.contact_fraction).tolist(),
            "status": np.asarray(result.status).tolist(),
            "s_per_load": min(times[1:]) / len(f_star),
            "compile_s": max(times[0] - min(times[1:]), 0.0),
            "offset": np.asarray(result.offset).tolist(),
        }
    return out


def memory(grid: int) -> dict:
    """The buffers XLA assigns to a solve with the secant on `grid`² (float64, periodic): its
    arguments and its temporaries, MiB (compiled, not run: `Compiled.memory_analysis`); with several
    devices, also the temporaries a device holds with the rows split over all of them
    (`bem.DistributedFFT`)."""
    import jax
    import jax.numpy as jnp
    from jax.sharding import Mesh, NamedSharding, PartitionSpec

    from ..bem import DistributedFFT, LocalFFT, solve

    heights, loads = jnp.zeros((grid, grid)), jnp.asarray([F_STAR[1] * MODULUS * LENGTH**2])

    def analysis(fft, heights):
        program = jax.jit(lambda h, F: solve(h, LENGTH, MODULUS, F, secant=0.02, fft=fft).secant_stiffness)
        return program.lower(heights, loads).compile().memory_analysis()

    mib = 2.0**20
    one = analysis(LocalFFT(), heights)
    out = {
        "grid": grid,
        "arguments_MiB": one.argument_size_in_bytes / mib,
        "temporaries_MiB": one.temp_size_in_bytes / mib,
    }
    devices = jax.devices()
    if len(devices) > 1 and grid % len(devices) == 0:
        mesh = Mesh(np.array(devices), ("rows",))
        split = jax.device_put(heights, NamedSharding(mesh, PartitionSpec("rows", None)))
        out["devices"] = len(devices)
        out["split_temporaries_MiB"] = analysis(DistributedFFT(mesh), split).temp_size_in_bytes / mib
    return out


def fit_time(grid: int = 256, realisations: int = 2, loads: int = 6) -> dict:
    """A D, G fit as users call it (the default method, one start from D = 1.45, G = 2e-12) with the
    BEM model to its own curve (3 % noise), at the fit's default tolerance."""
    import equinox as eqx

    from jaxcontact import fitting

    from .. import BEM, solve

    truth = _surface(grid)[0].with_model(BEM(grid=grid, realisations=realisations))
    F = np.geomspace(5e-5, 1e-3, loads) * MODULUS * LENGTH**2
    K = np.asarray(solve(truth, F).stiffness) * np.exp(0.03 * np.random.default_rng(1).standard_normal(loads))
    start = eqx.tree_at(lambda s: (s.surface.D, s.surface.G), truth, (1.45, 2e-12))
    t = time.perf_counter()
    result = fitting.fit(F, K, start, params=("D", "G"), n_starts=1)
    return {
        "grid": grid,
        "realisations": realisations,
        "loads": loads,
        "seconds": time.perf_counter() - t,
        "D": result.values["D"],
        "G": result.values["G"],
        "ci95": {k: list(v) for k, v in result.ci95.items()},
        "success": bool(result.success),
        "iterations": int(result.iterations),
        "method": result.method,
    }


def run_bem_bench(grids=(256, 512, 1024), memory_grids=(1024, 2048), reference=True, progress=None) -> dict:
    """Each grid's `per_point` (against ContactMechanics where `reference`) and `iterations`, `memory` and
    `fit_time`."""
    steps = [(f"per_point_{g}", lambda g=g: per_point(g, reference)) for g in grids]
    steps += [(f"iterations_{g}", lambda g=g: iterations(g)) for g in grids]
    steps += [(f"memory_{g}", lambda g=g: memory(g)) for g in memory_grids]
    steps.append(("fit", fit_time))
    out = {}
    for name, step in steps if progress is None else progress(steps):
        out[name] = step()
    return out


def format_bem_bench(r: dict) -> str:
    device = next((v["device"] for k, v in r.items() if k.startswith("per_point")), "?")
    lines = [f"boundary-element K(F) per point (3 loads, contact fractions 0.7-15 %), JAX on {device}, compiled:"]
    for key, v in r.items():
        if key.startswith("per_point"):
            t, s = v["jax_tangent"], v["jax_secant"]
            if "contactmechanics" not in v:
                lines.append(f"  {v['grid']}²: JAX tangent {t['s_per_point']:.4f} s, secant {s['s_per_point']:.4f} s")
                continue
            cm = v["contactmechanics"]["s_per_point"]
            lines.append(
                f"  {v['grid']}²: ContactMechanics {cm:.3f} s; JAX tangent {t['s_per_point']:.3f} s "
                f"({t.get('speedup', math.nan):.1f}x), secant {s['s_per_point']:.3f} s "
                f"({s.get('speedup', math.nan):.1f}x); "
                f"K/K_CM tangent {np.round(t.get('K_over_contactmechanics', []), 4).tolist()}, "
                f"secant {np.round(s.get('K_over_contactmechanics', []), 6).tolist()}"
            )
        elif key.startswith("iterations"):
            p, q = v["preconditioned"], v["plain"]
            fractions = ", ".join(f"{100 * f:.1f}" for f in p["contact_fraction"])
            lines.append(
                f"  iterations on {v['grid']}² (l_min = 4 spacings, contact {fractions} %): preconditioned "
                f"{p['iterations']} ({p['s_per_load']:.3g} s a load), plain {q['iterations']} ({q['s_per_load']:.3g} s)"
            )
        elif key.startswith("memory"):
            split = ""
            if "devices" in v:
                split = (
                    f"; split over {v['devices']} devices (bem.DistributedFFT), "
                    f"{v['split_temporaries_MiB']:.0f} MiB temporaries a device"
                )
            lines.append(
                f"  memory of a solve on {v['grid']}²: {v['arguments_MiB'] + v['temporaries_MiB']:.0f} MiB "
                f"({v['temporaries_MiB']:.0f} MiB temporaries, XLA's buffer assignment){split}"
            )
    f = r.get("fit")
    if f:
        lines.append(
            f"D, G fit with BEM(grid={f['grid']}, realisations={f['realisations']}) to {f['loads']} loads: "
            f"{f['seconds']:.1f} s ({f['method']}, {f['iterations']} iterations), "
            f"D = {f['D']:.4f}, G = {f['G']:.4g} m (truth {D}, {G})"
        )
    return "\n".join(lines)
