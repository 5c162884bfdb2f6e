"""Plots of a load sweep on the paper's dimensionless axes (matplotlib, Agg backend)."""

from __future__ import annotations

import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .asperity import REGIMES  # noqa: E402
from .solution import Solution  # noqa: E402


def save_figure(fig, path) -> str:
    """Lay out, write (PNG, 120 dpi) and close a figure; returns the path."""
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return str(path)


def plot_sweep(solution: Solution, title: str, out: pathlib.Path) -> list[str]:
    """Stiffness and largest spot against load (and regime shares if computed); returns the paths."""
    out.mkdir(parents=True, exist_ok=True)
    F = np.asarray(solution.load_star)
    ok = np.asarray(solution.status) == 0
    flagged = ~ok & np.isfinite(np.asarray(solution.a_l))
    paths = []

    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.loglog(F[ok], np.asarray(solution.stiffness_star)[ok], "o-", ms=3, label="K*")
    if flagged.any():
        ax.plot(F[flagged], np.full(flagged.sum(), np.nanmax(solution.stiffness_star[ok]) if ok.any() else 1.0),
                "x", color="C3", label="flagged (no valid K)")
    ax.set(xlabel="F* = F / (E A_a)", ylabel="K* = K / (E sqrt(A_a))", title=title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    paths.append(save_figure(fig, out / "stiffness.png"))

    fig, ax = plt.subplots(figsize=(6, 4.2))
    solved = np.isfinite(np.asarray(solution.a_l))
    ax.loglog(F[solved], np.asarray(solution.a_l_star)[solved], "o-", ms=3)
    ax.set(xlabel="F*", ylabel="a_l* = a_l / A_a", title="Largest contact spot (Fig. 3)")
    ax.grid(True, which="both", alpha=0.3)
    paths.append(save_figure(fig, out / "largest_spot.png"))

    if solution.load_share is not None:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
        for ax, share, what in ((axes[0], solution.load_share, "load"), (axes[1], solution.stiffness_share, "stiffness")):
            valid = np.all(np.isfinite(np.asarray(share)), axis=-1)
            ax.stackplot(F[valid], np.asarray(share)[valid].T, labels=REGIMES, alpha=0.8)
            ax.set(xscale="log", xlabel="F*", ylabel=f"share of {what}", ylim=(0, 1), title=f"{what} by regime")
        axes[1].legend(loc="upper left")
        paths.append(save_figure(fig, out / "regime_shares.png"))
    return paths


def plot_fit(loads, stiffness, fine_loads, fitted_stiffness, legend_lines, path: pathlib.Path) -> str:
    """Measured points against the fitted curve."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.loglog(loads, stiffness, "o", ms=4, label="data")
    ax.loglog(fine_loads, fitted_stiffness, "-", label="fit: " + "; ".join(s.strip().split("   ")[0] for s in legend_lines))
    ax.set(xlabel="load F (N)", ylabel="stiffness K (N/m)", title="Fit of the stiffness curve")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    return save_figure(fig, path)


def plot_approach(load_star, approach_m, reference_load, path: pathlib.Path) -> str:
    """The load–approach curve δ(F) − δ(F0) against F* (MODEL.md §6)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ok = np.isfinite(approach_m)
    ax.semilogx(load_star[ok], 1e9 * approach_m[ok], "o-", ms=3)
    ax.axhline(0.0, color="k", lw=0.8, ls=":")
    ax.set(xlabel="F* = F / (E A_a)", ylabel="δ(F) − δ(F0) (nm)", title=f"Load–approach curve (F0 = {reference_load:g} N)")
    ax.grid(True, which="both", alpha=0.3)
    return save_figure(fig, path)


def plot_dynamics(history, sweep_hz, sweep_amplitude, f_linear, preloads, resonance_hz, out: pathlib.Path) -> list[str]:
    """Time history, frequency response and resonance against preload of the dynamic scene."""
    out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(1e3 * np.asarray(history.t), 1e9 * np.asarray(history.x))
    ax.set(xlabel="t (ms)", ylabel="x (nm)", title="Time history at the drive frequency")
    ax.grid(True, alpha=0.3)
    paths = [save_figure(fig, out / "time_history.png")]
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.semilogy(sweep_hz, 1e9 * np.asarray(sweep_amplitude), "o-", ms=3)
    ax.axvline(f_linear, color="k", ls=":", label=f"sqrt(K(F0)/m)/2π = {f_linear:.5g} Hz")
    ax.set(xlabel="drive frequency (Hz)", ylabel="steady amplitude (nm)", title="Frequency response")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    paths.append(save_figure(fig, out / "frequency_response.png"))
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ok = np.isfinite(resonance_hz)
    ax.loglog(preloads[ok], resonance_hz[ok], "o-", ms=3)
    ax.set(xlabel="preload F0 (N)", ylabel="resonance frequency (Hz)", title="Resonance against preload")
    ax.grid(True, which="both", alpha=0.3)
    paths.append(save_figure(fig, out / "resonance_vs_preload.png"))
    return paths
