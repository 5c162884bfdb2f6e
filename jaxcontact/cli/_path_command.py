"""The normal load path of `jaxcontact cycle --path` (`jc.solve_path`): a CSV and the load–approach loop."""

from __future__ import annotations

import pathlib

COLUMNS = (
    "load_N",
    "approach_m",
    "stiffness_N_per_m",
    "unloading_stiffness_N_per_m",
    "real_area_m2",
    "branch",
    "status",
)


def run_path(spec, loads, out: pathlib.Path) -> tuple[list[dict], list[str], str]:
    """The joint of `spec` along `loads` (N): its rows, the files written and a summary line."""
    import numpy as np

    from ..applications import solve_path
    from ..quantities import Branch, status_message
    from ._plots import plot_path
    from ._report import record_comments, scene_record, write_csv

    path = solve_path(spec.scene, np.asarray(loads, dtype=float))
    values = [
        np.asarray(getattr(path, name))
        for name in ("load", "approach", "stiffness", "unloading_stiffness", "real_area")
    ]
    rows = [
        dict(zip(COLUMNS[:5], (float(x[i]) for x in values)))
        | {"branch": Branch(int(path.branch[i])).name.lower(), "status": status_message(int(path.status[i]))}
        for i in range(len(loads))
    ]
    csv = str(out / "path.csv")
    residual = float(path.residual_approach)
    comments = record_comments(scene_record(spec)) + [f"residual approach after a full unload = {residual:.10g} m"]
    write_csv(rows, csv, comments=comments)
    figure = plot_path(values[0], values[1], np.asarray(path.branch), out / "path.png")
    text = f"load path of {len(loads)} points: residual approach after a full unload {residual:.4g} m"
    return rows, [csv, figure], text


def add_path_option(p) -> None:
    p.add_argument(
        "--path",
        type=float,
        nargs="+",
        metavar="F",
        help="a normal load path (N) in the order applied (default: the scene's [path] loads): the approach, "
        "the stiffness on each branch and the residual approach (elastic models and the BEM model)",
    )
