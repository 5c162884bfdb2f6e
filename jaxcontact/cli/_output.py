"""What every command shares: how a mistake is reported, how results are printed, progress bars."""

from __future__ import annotations

# Exit status of a command that ran and wrote its output, but whose result is not usable (a fit
# that did not converge, or whose model does not describe the data); 2 is a mistake in the input.
EXIT_NOT_USABLE = 1


class CommandError(Exception):
    """A user mistake to report in one line."""


def implausible_values(spec) -> list[str]:
    """The scene's implausible values (likely unit mistakes), for the JSON output; building the
    scene has already warned of them (`PlausibilityWarning`, shown on stderr by `main`)."""
    from ..quantities import implausible

    return implausible(spec.scene)


def progress_bar(enabled: bool, desc: str, unit: str):
    """`items ↦ items` wrapped in a tqdm bar, or None when progress is off."""
    if not enabled:
        return None
    from tqdm.auto import tqdm

    return lambda items: tqdm(items, desc=desc, unit=unit)


def print_result(payload, fmt: str, text: str) -> None:
    from ._report import to_json

    print(to_json(payload) if fmt == "json" else text)


def add_log_range(p, option: str, what: str, default: str, points: int) -> None:
    """`--OPTION LOW HIGH` (log-spaced `what` from LOW to HIGH, `default` when not given) and
    `--points N` (`points` by default): the sweep of a command."""
    p.add_argument(
        f"--{option}",
        nargs=2,
        type=float,
        metavar=("LOW", "HIGH"),
        help=f"{what}, log-spaced from LOW to HIGH (default: {default})",
    )
    p.add_argument("--points", type=int, default=points, help=f"number of {option} (default: {points})")
