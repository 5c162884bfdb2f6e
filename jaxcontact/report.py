"""Tables of a solution: rows as dictionaries, printed as text, JSON or CSV."""

from __future__ import annotations

import csv
import json
import math

import numpy as np

from .asperity import REGIMES
from .solution import Solution
from .status import status_message


def solution_rows(solution: Solution) -> list[dict]:
    """One dictionary per load: F, F*, a_l, K, K*, A_r, status (and regime shares if computed)."""
    rows = []
    for i in range(np.size(solution.load)):
        row = {
            "F_N": float(solution.load[i]),
            "F_star": float(solution.load_star[i]),
            "a_l_m2": float(solution.a_l[i]),
            "K_N_per_m": float(solution.stiffness[i]),
            "K_star": float(solution.stiffness_star[i]),
            "real_area_m2": float(solution.real_area[i]),
            "status": status_message(solution.status[i]),
        }
        if solution.load_share is not None:
            for j, regime in enumerate(REGIMES):
                row[f"load_share_{regime}"] = float(solution.load_share[i, j])
                row[f"stiffness_share_{regime}"] = float(solution.stiffness_share[i, j])
        rows.append(row)
    return rows


def _cell(value) -> str:
    if isinstance(value, str):
        return value
    return "nan" if math.isnan(value) else f"{value:.6g}"


HEADERS = {"F_N": "F (N)", "F_star": "F*", "a_l_m2": "a_l (m²)", "K_N_per_m": "K (N/m)", "K_star": "K*",
           "approach_m": "δ - δ0 (m)"}


def format_table(rows: list[dict], columns=("F_N", "F_star", "a_l_m2", "K_N_per_m", "K_star", "status")) -> str:
    header = [HEADERS.get(c, c) for c in columns]
    cells = [[_cell(r[c]) for c in columns] for r in rows]
    widths = [max(len(h), *(len(c[i]) for c in cells)) for i, h in enumerate(header)]
    lines = ["  ".join(h.rjust(w) for h, w in zip(header, widths))]
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths)) for row in cells]
    return "\n".join(lines)


def to_json(payload) -> str:
    """JSON with NaN written as null (strict JSON has no NaN)."""

    def clean(x):
        if isinstance(x, float) and not math.isfinite(x):
            return None
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [clean(v) for v in x]
        return x

    return json.dumps(clean(payload), indent=2)


def write_csv(rows: list[dict], path) -> None:
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
