"""Plots of a load sweep on the paper's dimensionless axes.

Figures are `matplotlib.figure.Figure` objects written straight to PNG: no pyplot, so that
drawing never selects a backend or touches the caller's matplotlib state.
"""

from __future__ import annotations

import pathlib

import numpy as np
from matplotlib.figure import Figure

from ..core import Solution
from ..quantities import PARAMETERS
from ..studies._plotting import figure, save_figure, subplots
from ._report import flagged_reasons


def _mark_loads(ax, F, mask, label, color="C3"):
    """Loads without a value to draw, as ticks along the bottom of the axes at their loads."""
    if mask.any():
        ax.plot(
            F[mask],
            np.full(mask.sum(), 0.02),
            "|",
            ms=12,
            color=color,
            transform=ax.get_xaxis_transform(),
            label=label,
        )


def _mark_flagged(ax, F, flagged, status):
    """Flagged loads as ticks along the load axis: never at a made-up value."""
    if flagged.any():
        _mark_loads(ax, F, flagged, flagged_reasons(status) + " (no value)")


def plot_sweep(solution: Solution, title: str, out: pathlib.Path) -> list[str]:
    """Stiffness and largest spot against load (and regime shares if computed); returns the paths.

    Only valid points are drawn as values; flagged loads, and loads where K = 0, are marked along
    the load axis.
    """
    out.mkdir(parents=True, exist_ok=True)
    F = np.asarray(solution.load_star)
    status = np.asarray(solution.status)
    ok = status == 0
    paths = []

    fig, ax = subplots(figsize=(6, 4.2))
    K = np.asarray(solution.stiffness_star)
    # K = 0 (every spot plastic, Sec. 4.2) is a valid value that a log axis cannot show.
    positive = ok & (K > 0)
    if positive.any():
        ax.loglog(F[positive], K[positive], "o-", ms=3, label="K*")
    else:
        ax.set_xscale("log")
        ax.text(0.5, 0.5, "no positive stiffness at any load", transform=ax.transAxes, ha="center")
    _mark_flagged(ax, F, ~ok, status)
    _mark_loads(ax, F, ok & (K == 0), "K = 0: every spot plastic", color="C7")
    ax.set(xlabel="F* = F / (E A_a)", ylabel="K* = K / (E sqrt(A_a))", title=title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    paths.append(save_figure(fig, out / "stiffness.png"))

    fig, ax = subplots(figsize=(6, 4.2))
    solved = np.isfinite(np.asarray(solution.a_l))
    if solved.any():
        ax.loglog(F[solved], np.asarray(solution.a_l_star)[solved], "o-", ms=3, label="a_l*")
    else:
        ax.set_xscale("log")
    _mark_flagged(ax, F, ~solved, np.where(solved, 0, status))
    ax.set(xlabel="F*", ylabel="a_l* = a_l / A_a", title="Largest contact spot (Fig. 3)")
    ax.grid(True, which="both", alpha=0.3)
    if (~solved).any():
        ax.legend(fontsize=8)
    paths.append(save_figure(fig, out / "largest_spot.png"))

    if solution.load_share is not None:
        fig, axes = subplots(1, 2, figsize=(10, 4), sharey=True)
        for ax, share, what in (
            (axes[0], solution.load_share, "load"),
            (axes[1], solution.stiffness_share, "stiffness"),
        ):
            valid = np.all(np.isfinite(np.asarray(share)), axis=-1)
            if valid.any():
                ax.stackplot(F[valid], np.asarray(share)[valid].T, labels=solution.regimes, alpha=0.8)
                ax.set_xscale("log")
            ax.set(xlabel="F*", ylabel=f"share of {what}", ylim=(0, 1), title=f"{what} by regime")
        if axes[1].collections:
            axes[1].legend(loc="upper left")
        paths.append(save_figure(fig, out / "regime_shares.png"))
    return paths


def fit_figure(result, loads, stiffness, fine_loads, fitted_stiffness) -> Figure:
    """Data and fitted curve with the fitted values and their 95 % intervals; residuals below; and where
    the fit has profiles, a panel of each parameter's profile likelihood against the parabola."""
    rows = 3 if getattr(result, "profiles", None) else 2
    fig = figure((6.4, 6.0 + 2.4 * (rows - 2)), rows=rows)
    axes = fig.subplots(rows, 1, height_ratios=(3, 1.4, 2)[:rows])
    top, bottom = axes[0], axes[1]
    bottom.sharex(top)
    top.loglog(loads, stiffness, "o", ms=4, label="data")
    if result.describes_data:
        values = [
            f"{name} = {result.values[name]:.4g} [{result.ci95[name][0]:.4g}, {result.ci95[name][1]:.4g}]"
            + PARAMETERS[name].unit_suffix
            for name in result.params
        ]
        label = "fit (95 % CI): " + "; ".join(values)
    else:
        values = [f"{name} = {result.values[name]:.4g}{PARAMETERS[name].unit_suffix}" for name in result.params]
        label = "fit (no CI: the model does not describe the data): " + "; ".join(values)
    top.loglog(fine_loads, fitted_stiffness, "-", label=label)
    top.set(ylabel="stiffness K (N/m)", title=f"Fit of the stiffness curve ({result.method})")
    top.grid(True, which="both", alpha=0.3)
    top.legend(fontsize=7)
    residuals = np.asarray(result.residuals)
    used = np.isfinite(residuals)
    bottom.semilogx(loads[used], residuals[used], "o", ms=4)
    if (~used).any():
        bottom.plot(loads[~used], np.zeros((~used).sum()), "x", color="C3", label="flagged at the optimum")
        bottom.legend(fontsize=7)
    rms = float(np.sqrt(np.mean(residuals[used] ** 2))) if used.any() else float("nan")
    bottom.axhline(0.0, color="k", lw=0.8)
    bottom.axhspan(-2 * rms, 2 * rms, color="C1", alpha=0.15, label=f"±2 rms ({rms:.3g})")
    bottom.set(xlabel="load F (N)", ylabel="ln K_fit − ln K_data")
    bottom.grid(True, which="both", alpha=0.3)
    if rows == 3:
        _profile_panel(axes[2], result)
    return fig


def _profile_panel(ax, result) -> None:
    """Δχ² of each parameter's profile against its distance from the optimum in (parabolic) standard
    errors of its statistical coordinate: a parabola x² where the Gauss–Newton interval holds."""
    for k, (name, prof) in enumerate(result.profiles.items()):
        log = PARAMETERS[name].log
        best = np.log(result.values[name]) if log else result.values[name]
        se = result.stderr[name] / result.values[name] if log else result.stderr[name]
        x = ((np.log(prof.values) if log else prof.values) - best) / se
        ax.plot(x, prof.delta_chi2, "o-", ms=3, color=f"C{k}", label=f"profile of {name}")
    grid = np.linspace(-4, 4, 81)
    ax.plot(grid, grid**2, "k:", lw=1, label="parabola (Gauss–Newton)")
    threshold = next(iter(result.profiles.values())).threshold
    ax.axhline(threshold, color="0.5", lw=0.8, label=f"95 % (Δχ² = {threshold:.2f})")
    ax.set(xlabel="(θ − θ̂) / standard error", ylabel="Δχ²", ylim=(0, max(2.5 * threshold, 12)))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)


def plot_fit(result, loads, stiffness, fine_loads, fitted_stiffness, path: pathlib.Path) -> str:
    """`fit_figure` written to `path`."""
    path.parent.mkdir(parents=True, exist_ok=True)
    return save_figure(fit_figure(result, loads, stiffness, fine_loads, fitted_stiffness), path)


def plot_approach(load_star, approach_m, reference_load, path: pathlib.Path) -> str:
    """The load–approach curve δ(F) − δ(F0) against F* (docs/model.md §6)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = subplots(figsize=(6, 4.2))
    ok = np.isfinite(approach_m)
    ax.semilogx(load_star[ok], 1e9 * approach_m[ok], "o-", ms=3)
    ax.axhline(0.0, color="k", lw=0.8, ls=":")
    ax.set(
        xlabel="F* = F / (E A_a)", ylabel="δ(F) − δ(F0) (nm)", title=f"Load–approach curve (F0 = {reference_load:g} N)"
    )
    ax.grid(True, which="both", alpha=0.3)
    return save_figure(fig, path)


def plot_dynamics(history, sweep_hz, sweep_amplitude, f_linear, preloads, resonance_hz, out: pathlib.Path) -> list[str]:
    """Time history, frequency response and resonance against preload of the dynamic scene."""
    out.mkdir(parents=True, exist_ok=True)
    fig, ax = subplots(figsize=(6, 4.2))
    ax.plot(1e3 * np.asarray(history.t), 1e9 * np.asarray(history.x))
    ax.set(xlabel="t (ms)", ylabel="x (nm)", title="Time history at the drive frequency")
    ax.grid(True, alpha=0.3)
    paths = [save_figure(fig, out / "time_history.png")]
    fig, ax = subplots(figsize=(6, 4.2))
    ax.semilogy(sweep_hz, 1e9 * np.asarray(sweep_amplitude), "o-", ms=3)
    ax.axvline(f_linear, color="k", ls=":", label=f"sqrt(K(F0)/m)/2π = {f_linear:.5g} Hz")
    ax.set(xlabel="drive frequency (Hz)", ylabel="steady amplitude (nm)", title="Frequency response")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    paths.append(save_figure(fig, out / "frequency_response.png"))
    fig, ax = subplots(figsize=(6, 4.2))
    ok = np.isfinite(resonance_hz)
    ax.loglog(preloads[ok], resonance_hz[ok], "o-", ms=3)
    ax.set(xlabel="preload F0 (N)", ylabel="resonance frequency (Hz)", title="Resonance against preload")
    ax.grid(True, which="both", alpha=0.3)
    paths.append(save_figure(fig, out / "resonance_vs_preload.png"))
    return paths


def plot_interface(pressure, closure_m, stiffness, reference, path: pathlib.Path) -> str:
    """The interface law per unit area: closure δ(p) − δ(p0) and k_n against nominal pressure."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, (left, right) = subplots(1, 2, figsize=(10, 4.2))
    ok = np.isfinite(closure_m)
    left.semilogx(pressure[ok], 1e9 * closure_m[ok], "o-", ms=3)
    left.set(
        xlabel="nominal pressure p (Pa)", ylabel="closure δ(p) − δ(p0) (nm)", title=f"Closure (p0 = {reference:g} Pa)"
    )
    right.loglog(pressure[ok], stiffness[ok], "o-", ms=3)
    right.set(xlabel="nominal pressure p (Pa)", ylabel="k_n = K/A_a (Pa/m)", title="Normal stiffness per unit area")
    for ax in (left, right):
        ax.grid(True, which="both", alpha=0.3)
    return save_figure(fig, path)


def plot_cycle(amplitudes, force, damping, fractions, backbone, slip_force, path: pathlib.Path, loop_amplitudes) -> str:
    """Friction loops Q(u) at `loop_amplitudes` (from the `backbone` B at s = (u₀ ± u)/2, Masing's
    rule; one row of `backbone` per loop, at s = u₀ × `fractions`, increasing to 1), and the loop's tip
    Q₀/μF and damping ratio against amplitude."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, (left, right) = subplots(1, 2, figsize=(10, 4.2))
    for u0, rows in zip(loop_amplitudes, backbone):
        if not np.all(np.isfinite(rows)):
            continue
        s = u0 * fractions
        top = rows[-1]
        u = np.concatenate([[-u0], 2 * s - u0, [u0], u0 - 2 * s])
        q = np.concatenate([[-top], -top + 2 * rows, [top], top - 2 * rows])
        left.plot(1e9 * u, q / slip_force, label=f"u0 = {1e9 * u0:.3g} nm")
    left.set(xlabel="tangential displacement u (nm)", ylabel="Q / μF", title="Friction loops (Masing)")
    left.legend(fontsize=8)
    ok = np.isfinite(force)
    right.semilogx(amplitudes[ok], force[ok] / slip_force, "o-", ms=3, label="loop tip Q0 / μF")
    right.semilogx(amplitudes[ok], damping[ok], "s-", ms=3, label="damping ratio ζ")
    right.set(xlabel="amplitude u0 (m)", title="Tip and damping against amplitude")
    right.legend(fontsize=8)
    for ax in (left, right):
        ax.grid(True, which="both", alpha=0.3)
    return save_figure(fig, path)


def plot_path(load, approach, branch, path: pathlib.Path) -> str:
    """The points of a load path on the load–approach plane, marked by branch and numbered in the
    order applied (no lines: a chord between two points is not the curve between them)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = subplots(1, 1, figsize=(5.5, 4.2))
    ok = np.isfinite(approach)
    for code, (name, marker) in enumerate((("loading", "o"), ("unloading", "v"), ("reloading", "^"))):
        on = ok & (branch == code)
        ax.plot(1e9 * approach[on], load[on], marker, ms=5, ls="none", label=name)
    for i in np.flatnonzero(ok):
        ax.annotate(str(i + 1), (1e9 * approach[i], load[i]), textcoords="offset points", xytext=(5, 3), fontsize=7)
    ax.set(xlabel="approach δ − δ(first point) (nm)", ylabel="load F (N)", title="Load path")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return save_figure(fig, path)
