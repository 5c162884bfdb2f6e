"""Tables of a solution: rows as dictionaries, printed as text, JSON or CSV."""

from __future__ import annotations

import csv
import json
import math

import jax
import numpy as np

from ..core import Solution
from ..quantities import PARAMETERS, status_message


def solution_rows(solution: Solution) -> list[dict]:
    """One dictionary per load: F, F*, a_l, K, K*, A_r, status, whether every spot is plastic
    (K = 0 with status ok), and the regime shares if computed."""
    solution = jax.tree.map(np.asarray, solution)  # on the host: one transfer per field, not per row

    def flat(values):
        return np.broadcast_to(values, solution.load.shape).reshape(-1)

    quantities = {
        "F_N": solution.load,
        "F_star": solution.load_star,
        "a_l_m2": solution.a_l,
        "K_N_per_m": solution.stiffness,
        "K_star": solution.stiffness_star,
        "real_area_m2": solution.real_area,
    }
    quantities = {name: flat(values) for name, values in quantities.items()}
    shares = {}
    if solution.load_share is not None:
        for j, regime in enumerate(solution.regimes):
            shares[f"load_share_{regime}"] = flat(solution.load_share[..., j])
            shares[f"stiffness_share_{regime}"] = flat(solution.stiffness_share[..., j])
    status, fully_plastic = flat(solution.status), flat(solution.fully_plastic)
    rows = []
    for i in range(status.size):
        row = {name: float(values[i]) for name, values in quantities.items()}
        row["status"] = status_message(status[i])
        row["fully_plastic"] = bool(fully_plastic[i])
        row.update((name, float(values[i])) for name, values in shares.items())
        rows.append(row)
    return rows


def flagged_reasons(status) -> str:
    """Why points are flagged, by count, e.g. "3 interaction_breakdown, 1 load_out_of_range"."""
    status = np.asarray(status).reshape(-1)
    codes, counts = np.unique(status[status != 0], return_counts=True)
    return ", ".join(f"{n} {status_message(c)}" for c, n in zip(codes, counts))


def flagged_summary(status) -> str:
    """How many points are flagged and why, e.g. "3 of 41 loads flagged: 3 interaction_breakdown"."""
    status = np.asarray(status).reshape(-1)
    flagged = int(np.sum(status != 0))
    if not flagged:
        return f"0 of {status.size} loads flagged"
    return f"{flagged} of {status.size} loads flagged: {flagged_reasons(status)}"


def _cell(value) -> str:
    if isinstance(value, str):
        return value
    return "nan" if math.isnan(value) else f"{value:.6g}"


HEADERS = {
    "F_N": "F (N)",
    "F_star": "F*",
    "a_l_m2": "a_l (m²)",
    "K_N_per_m": "K (N/m)",
    "K_star": "K*",
    "approach_m": "δ - δ0 (m)",
}


def _status_cell(row: dict) -> str:
    return "ok (K = 0: every spot plastic)" if row.get("fully_plastic") else row["status"]


def _header(column: str) -> str:
    """`K_<what>_N_per_m` as `K <what> (N/m)`, `status_<model>` as `<model> status`; other columns by
    their own name."""
    if column.startswith("K_") and column.endswith("_N_per_m"):
        return f"K {column[2:-8].replace('_', ' ')} (N/m)"
    if column.startswith("status_"):
        return f"{column[7:]} status"
    return column


def format_table(rows: list[dict], columns=("F_N", "F_star", "a_l_m2", "K_N_per_m", "K_star", "status")) -> str:
    header = [HEADERS.get(c, _header(c)) for c in columns]
    cells = [[_status_cell(r) if c == "status" else _cell(r[c]) for c in columns] for r in rows]
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


def scene_record(spec) -> dict:
    """Everything that made a result: the scene's parameters (SI), its model and settings, the
    loads' source and the version, so that a result file can be reproduced on its own."""
    import jaxcontact

    scene = spec.scene
    parameters = {name: float(p.get(scene)) for name, p in PARAMETERS.items()}
    finder = getattr(scene.model, "root_finder", None)
    settings = dict(regime_shares=spec.outputs.regime_shares, stiffness=spec.outputs.stiffness.name)
    if finder is not None:
        settings.update(max_steps=finder.max_steps, solver_tolerance=finder.tolerance)
    return {
        "jaxcontact": jaxcontact.__version__,
        "title": spec.title,
        "source": spec.source,
        "parameters_SI": parameters,
        "model": scene.model.options(),
        "settings": settings,
    }


def record_comments(record: dict) -> list[str]:
    """`scene_record` as comment lines for a CSV file."""
    parameters = ", ".join(f"{k} = {v:.10g}{PARAMETERS[k].unit_suffix}" for k, v in record["parameters_SI"].items())
    choices = ", ".join(f"{k} = {v}" for k, v in {**record["model"], **record["settings"]}.items())
    return [f"jaxcontact {record['jaxcontact']}: {record['title']} ({record['source']})", parameters, choices]


def write_csv(rows: list[dict], path, comments=()) -> None:
    """Rows as CSV, after `comments` as `# ` lines (which `fitting.load_curve` and pandas'
    `comment="#"` skip)."""
    with open(path, "w", newline="") as f:
        for line in comments:
            f.write(f"# {line}\n")
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
