"""The command line: the main job on the default scene, JSON output, figures, one-line errors."""

import csv
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT, TABLE1, make_scene

import jaxcontact as jc
from jaxcontact.cli import main


@pytest.fixture(autouse=True)
def no_cache(monkeypatch):
    monkeypatch.setenv("JAXCONTACT_CACHE", "")


def test_run_default_scene(tmp_path, capsys):
    assert main(["run", "--out", str(tmp_path), "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "Table 1 grinding surface" in text
    assert "interaction_breakdown" in text
    lines = (tmp_path / "results.csv").read_text().splitlines()
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    assert len(rows) == 41
    F_star = np.array([float(r["F_star"]) for r in rows])
    sol = jc.solve(make_scene(**TABLE1), F_star * TABLE1["E"] * TABLE1["area"])
    K_csv = np.array([float(r["K_N_per_m"]) for r in rows])
    np.testing.assert_allclose(K_csv, np.asarray(sol.stiffness), rtol=1e-12)  # nan where flagged
    i = int(np.argmin(abs(F_star - 1e-6)))
    assert abs(float(rows[i]["K_star"]) - 1.04576) < 5e-6  # MODEL.md §7
    assert rows[-1]["status"] == "interaction_breakdown"
    assert rows[-1]["K_N_per_m"] == "nan"
    for png in ("stiffness.png", "largest_spot.png", "regime_shares.png"):
        assert (tmp_path / png).stat().st_size > 10_000


def test_results_record_the_scene_they_came_from(tmp_path, capsys):
    """The CSV's header comments and the JSON carry the scene's parameters, model and version."""
    assert main(["run", "--out", str(tmp_path), "--no-progress", "--format", "json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["scene"]["parameters_SI"] == {k: TABLE1[k] for k in jc.PARAMETERS}
    assert payload["scene"]["model"] == {
        "model": "xia2024",
        "interaction": "paper",
        "distribution": "mb",
        "quadrature": "power-series",
    }
    comments = [line for line in (tmp_path / "results.csv").read_text().splitlines() if line.startswith("#")]
    assert comments[1] == (
        "# D = 1.4058, G = 2.2826e-10 m, l_min = 1e-09 m, E = 2.2e+11 Pa, nu = 0.25, H = 1e+11 Pa, area = 0.0001 m²"
    )


def test_run_json(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(
        "[surface]\nD = 1.5\nG = 3e-10\n[material]\nE = 1.13e11\nnu = 0.3\nH = 4e9\n"
        "[joint]\narea = 1e-4\n[effects]\nregime_shares = false\n[loads]\nvalues = [1.13, 1130.0, 1e9]\n"
    )
    assert main(["run", str(scene), "--out", str(tmp_path / "o"), "--format", "json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert [r["status"] for r in payload["rows"]] == ["ok", "interaction_breakdown", "load_out_of_range"]
    assert payload["rows"][1]["K_N_per_m"] is None
    assert payload["rows"][0]["K_N_per_m"] > 0
    np.testing.assert_allclose(payload["rows"][0]["a_l_m2"], 4.842854262e-11, rtol=1e-6)  # checkpoints.csv


@pytest.mark.parametrize(
    "content, message",
    [
        (None, "does not exist"),
        ("[surface\nD = 1.4", "is not valid TOML"),
        ("[surface]\nD = 1.4\n", "missing key surface.G"),
        ("[surface]\nD = 1.4\nG = 1e-10\nroughness = 2\n", "unknown key surface.roughness"),
    ],
)
def test_errors_are_one_line_with_exit_2(tmp_path, capsys, content, message):
    path = tmp_path / "scene.toml"
    if content is not None:
        path.write_text(content)
    assert main(["run", str(path), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err
    assert len(err.splitlines()) == 1
    assert "Traceback" not in err


def test_main_restores_the_callers_jax_settings(tmp_path, capsys):
    import jax

    names = ("jax_enable_x64", "jax_cpu_enable_async_dispatch", "jax_compilation_cache_dir")
    before = [jax.config.values[n] for n in names]
    assert main(["run", "--out", str(tmp_path), "--no-progress", "--format", "json"]) == 0
    capsys.readouterr()
    assert [jax.config.values[n] for n in names] == before


def test_accuracy_without_mpmath_is_a_one_line_error(tmp_path):
    code = (
        "import sys; sys.modules['mpmath'] = None; from jaxcontact.cli import main; "
        f"sys.exit(main(['accuracy', '--out', {str(tmp_path)!r}]))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        timeout=120,
        env={**os.environ, "JAXCONTACT_CACHE": ""},
    )
    assert out.returncode == 2
    assert out.stderr.strip().splitlines() == [
        "jaxcontact accuracy: error: the accuracy study needs mpmath for its reference: "
        "pip install 'jaxcontact[studies]'"
    ]


def test_console_script_reports_bad_value_without_traceback(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(
        "[surface]\nD = 2.5\nG = 1e-10\n[material]\nE = 2e11\nnu = 0.3\nH = 1e9\n[joint]\narea = 1e-4\n"
        "[loads]\nvalues = [1.0]\n"
    )
    out = subprocess.run(
        [sys.executable, "-m", "jaxcontact.cli", "run", str(bad), "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        env={"JAX_PLATFORMS": "cpu", "JAXCONTACT_CACHE": "", "PATH": ""},
    )
    assert out.returncode == 2
    assert out.stderr.strip() == (
        "jaxcontact run: error: D (fractal dimension) = 2.5 is outside its valid range (1, 2)"
    )


def test_figures(tmp_path, capsys):
    assert main(["figures", "--out", str(tmp_path), "--format", "json", "--no-progress"]) == 0
    files = json.loads(capsys.readouterr().out)["files"]
    names = sorted(p.split("/")[-1] for p in files)
    assert names == sorted(
        [
            "fig3_largest_spot.png",
            "fig4_stiffness_vs_D.png",
            "fig5_stiffness_vs_G.png",
            "fig6_interaction.png",
            "fig8_models.png",
            "l_min_dependence.png",
        ]
    )
    assert all((tmp_path / n).stat().st_size > 10_000 for n in names)


def test_approach_command_on_the_embedded_dynamics_scene(tmp_path, capsys):
    assert main(["approach", "--out", str(tmp_path), "--format", "json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    rows = payload["rows"]
    assert payload["reference_load_N"] == 220.0
    assert len(rows) == 31
    delta = np.array([r["approach_m"] for r in rows])
    assert np.all(np.diff(delta) > 0)
    assert delta[0] < 0 < delta[-1]
    scene = make_scene(**TABLE1)
    np.testing.assert_allclose(
        delta, np.asarray(jc.approach(scene, np.array([r["F_N"] for r in rows]), 220.0).approach), rtol=1e-12
    )
    assert (tmp_path / "approach.png").stat().st_size > 10_000


def test_dynamics_command(tmp_path, capsys):
    scene = tmp_path / "dyn.toml"
    scene.write_text(
        (ROOT / "data" / "scenes" / "table1_dynamics.toml").read_text().replace("sweep_count = 41", "sweep_count = 8")
    )
    assert main(["dynamics", str(scene), "--out", str(tmp_path), "--format", "json", "--no-progress"]) == 0
    payload = json.loads(capsys.readouterr().out)
    K = float(jc.solve(make_scene(**TABLE1), 220.0).stiffness)
    np.testing.assert_allclose(payload["linear_resonance_Hz"], np.sqrt(K) / (2 * np.pi), rtol=1e-12)
    assert len(payload["frequency_response"]) == 8
    assert len(payload["resonance_vs_preload"]) == 31
    assert all(r["status"] == "ok" for r in payload["frequency_response"])
    for name in ("time_history.png", "frequency_response.png", "resonance_vs_preload.png", "time_history.csv"):
        assert (tmp_path / name).stat().st_size > 1000


@pytest.mark.parametrize("command", ["approach", "dynamics"])
def test_only_scenes_that_ask_run_the_effect(tmp_path, capsys, command):
    assert main([command, str(ROOT / "data" / "scenes" / "table1_grinding.toml"), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "does not ask for this effect" in err
    assert len(err.splitlines()) == 1


def test_run_adds_the_approach_only_when_asked(tmp_path, capsys):
    assert main(["run", "--out", str(tmp_path / "a"), "--format", "json"]) == 0
    assert "approach_m" not in json.loads(capsys.readouterr().out)["rows"][0]
    assert (
        main(
            [
                "run",
                str(ROOT / "data" / "scenes" / "table1_dynamics.toml"),
                "--out",
                str(tmp_path / "b"),
                "--format",
                "json",
            ]
        )
        == 0
    )
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert all(np.isfinite(r["approach_m"]) for r in rows)


ALL_OUT_OF_RANGE = (
    "[surface]\nD = 1.5\nG = 3e-10\n[material]\nE = 1.13e11\nnu = 0.3\nH = 4e9\n[joint]\narea = 1e-4\n"
    "[loads]\nvalues = [1e9, 2e9, 3e9]\n"
)


def test_a_run_where_every_load_is_flagged_says_so(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text(ALL_OUT_OF_RANGE)
    assert main(["run", str(scene), "--out", str(tmp_path / "o"), "--no-progress"]) == 0
    assert "3 of 3 loads flagged: 3 load_out_of_range" in capsys.readouterr().out
    assert (tmp_path / "o" / "stiffness.png").stat().st_size > 10_000


def test_flagged_loads_are_marked_on_the_load_axis_not_drawn_as_values(tmp_path, monkeypatch):
    from jaxcontact.cli import plots

    figures = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path: figures.append(fig) or str(path))
    loads = np.array([1e-6, 1e-5, 1e-3]) * TABLE1["E"] * TABLE1["area"]  # the last past breakdown
    solution = jc.solve(make_scene(**TABLE1), loads)
    plots.plot_sweep(solution, "t", tmp_path)
    ax = figures[0].axes[0]
    values, marks = ax.lines
    np.testing.assert_allclose(values.get_ydata(), np.asarray(solution.stiffness_star)[:2])
    assert marks.get_transform() == ax.get_xaxis_transform()
    np.testing.assert_allclose(marks.get_xdata(), np.asarray(solution.load_star)[2:])
