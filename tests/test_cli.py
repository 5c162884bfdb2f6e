"""The command line: the main job on the default scene, JSON output, figures, one-line errors."""

import csv
import gc
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from helpers import ROOT, TABLE1, make_scene

import jaxcontact as jc
from jaxcontact import fitting
from jaxcontact.cli import main


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
    assert abs(float(rows[i]["K_star"]) - 1.04576) < 5e-6  # docs/model.md §7
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
        "spot_stiffness": "paper",
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
        (
            "[surface]\nD = 1.5\nG = 3e-10\n[material]\nE = 2e11\nnu = 0.3\nH = 4e9\n[joint]\narea = 0\n"
            "[loads]\nvalues = [1.0]\n",
            "error: area (nominal contact area, m²) = 0 is outside its valid range",
        ),
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
    thresholds = gc.get_threshold()
    assert main(["run", "--out", str(tmp_path), "--no-progress", "--format", "json"]) == 0
    capsys.readouterr()
    assert [jax.config.values[n] for n in names] == before
    assert gc.get_threshold() == thresholds  # the command's rarer collections end with it


def test_matplotlib_is_imported_once_a_compilation_begins_not_before():
    import jax.monitoring

    from jaxcontact.cli._main import plotting_imported_while_compiling

    with plotting_imported_while_compiling() as thread:
        thread.join(0.2)
        assert thread.is_alive()  # waiting: tracing holds the GIL, an import beside it gains nothing
        jax.monitoring.record_event_duration_secs("/jax/core/compile/jaxpr_to_mlir_module_duration", 0.5)
        thread.join(30)
        assert not thread.is_alive()


def test_the_background_import_leaves_no_listener_behind():
    from jax._src import monitoring

    from jaxcontact.cli._main import plotting_imported_while_compiling

    before = list(monitoring._event_duration_secs_listeners)
    with plotting_imported_while_compiling():
        pass
    assert monitoring._event_duration_secs_listeners == before


_DIFFRAX_PROGRAM = """
import diffrax, jax, jax.numpy as jnp
from jaxcontact.numerics._compat import avoid_host_callbacks_in_checks
def solve(t1):
    saveat = diffrax.SaveAt(ts=jnp.linspace(0.0, 1.0, 3) * t1)
    controller = diffrax.PIDController(rtol=1e-6, atol=1e-9)
    return diffrax.diffeqsolve(
        diffrax.ODETerm(lambda t, y, args: -y), diffrax.Tsit5(), 0.0, t1, None, 1.0,
        saveat=saveat, stepsize_controller=controller, throw=False,
    ).ys
{setting}
print("callback" in jax.jit(solve).lower(1.0).as_text())
"""


def _host_callback_in_a_diffrax_program(setting: str) -> str:
    code = _DIFFRAX_PROGRAM.format(setting=setting)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()


def test_the_executable_compiles_diffrax_solves_without_host_callbacks():
    """Diffrax checks traced save times through a host callback, which keeps a program out of
    JAX's persistent cache: `approach` and `dynamics` compiled their solves on every run."""
    assert _host_callback_in_a_diffrax_program("avoid_host_callbacks_in_checks()") == "False"


def test_without_the_executables_setting_diffrax_keeps_its_host_callback():
    assert _host_callback_in_a_diffrax_program("") == "True"


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


def test_console_script_output_through_a_pipe_is_complete(tmp_path):
    from jaxcontact import topography as tp

    # The executable leaves without the interpreter's teardown: a piped (block-buffered) stdout
    # must still arrive whole.
    data = tmp_path / "map.txt"
    np.savetxt(data, tp.areal_map(1.5, 1e-10, 1e-3, 512, seed=0).heights())
    out = subprocess.run(
        [sys.executable, "-m", "jaxcontact.cli", "surface", str(data), "--size", "1e-3", "1e-3"]
        + ["--out", str(tmp_path / "o"), "--format", "json"],
        capture_output=True,
        text=True,
        env={**{k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}, "JAXCONTACT_CACHE": ""},
    )
    assert out.returncode == 0
    assert 1.3 < json.loads(out.stdout)["psd"]["D"] < 1.7


def test_log_axes_are_labelled_with_decades_in_plain_text(tmp_path):
    from jaxcontact.cli._plots import save_figure, subplots

    fig, ax = subplots()
    ax.loglog([1e-7, 1e-4], [1.0, 10.0])
    save_figure(fig, tmp_path / "decades.png")
    assert [t.get_text() for t in ax.get_xticklabels()] == ["10⁻⁸", "10⁻⁷", "10⁻⁶", "10⁻⁵", "10⁻⁴", "10⁻³"]
    np.testing.assert_allclose(ax.xaxis.get_minorticklocs()[:4], [2e-8, 5e-8, 2e-7, 5e-7])


def test_figures(tmp_path, capsys, monkeypatch):
    from jaxcontact.studies import _figures as figures

    drawn = []
    save = figures.save_figure
    monkeypatch.setattr(figures, "save_figure", lambda fig, path: drawn.append(fig) or save(fig, path))
    assert main(["figures", "--out", str(tmp_path), "--format", "json", "--no-progress"]) == 0
    for fig in drawn:
        ax = fig.axes[0]
        # Every figure states its conditions, and its curves differ in line style and marker (print).
        assert "l_min" in ax.get_title()
        curves = [line for line in ax.lines if line.get_label() and not line.get_label().startswith("default")]
        looks = {(str(line.get_linestyle()), line.get_marker()) for line in curves}
        assert len(looks) == len(curves), ax.get_title()
    captured = capsys.readouterr()
    assert "warning" not in captured.err  # the paper's own material (H = 120 GPa) is reproduced, not warned of
    files = json.loads(captured.out)["files"]
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


@pytest.mark.parametrize("command", ["approach", "dynamics"])
def test_only_scenes_that_ask_run_the_effect(tmp_path, capsys, command):
    assert main([command, str(ROOT / "data" / "scenes" / "table1_grinding.toml"), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "does not ask for this effect" in err
    assert len(err.splitlines()) == 1


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
    from jaxcontact.cli import _plots as plots

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


def test_a_zero_stiffness_is_marked_on_the_load_axis_not_drawn_on_the_log_axis(tmp_path, monkeypatch):
    import warnings

    import equinox as eqx

    from jaxcontact.cli import _plots as plots

    figures = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path: figures.append(fig) or str(path))
    loads = np.array([1e-6, 1e-5, 1e-4]) * TABLE1["E"] * TABLE1["area"]
    solution = jc.solve(make_scene(**TABLE1), loads)
    # Every spot plastic at the first load (K = 0 is a valid value, Sec. 4.2).
    solution = eqx.tree_at(lambda s: s.stiffness, solution, solution.stiffness.at[0].set(0.0))
    with warnings.catch_warnings():
        # What matplotlib says when a log axis is given only non-positive values.
        warnings.filterwarnings("error", message="Data has no positive values")
        plots.plot_sweep(solution, "t", tmp_path)
        figures[0].canvas.draw()
    values, marks = figures[0].axes[0].lines
    np.testing.assert_allclose(values.get_ydata(), np.asarray(solution.stiffness_star)[1:])
    np.testing.assert_allclose(marks.get_xdata(), np.asarray(solution.load_star)[:1])


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.strip() == f"jaxcontact {jc.__version__}"


def test_an_internal_error_is_not_reported_as_a_user_mistake(tmp_path, capsys, monkeypatch):
    """A bug (here a numpy broadcasting error inside the run) says so, with its traceback; exit 70."""
    from jaxcontact.cli import _report as report

    def broken(*args, **kwargs):
        raise ValueError("operands could not be broadcast together with shapes (4097,) (2,)")

    monkeypatch.setattr(report, "solution_rows", broken)
    assert main(["run", "--out", str(tmp_path), "--no-progress"]) == 70
    err = capsys.readouterr().err
    assert "Traceback" in err
    assert "internal error (a bug in jaxcontact, not in your input)" in err


def test_bench_writes_its_report_to_out(tmp_path, capsys, monkeypatch):
    """`bench --out` leaves the report (text and JSON, with the scene) where it was asked to."""
    from jaxcontact.studies import _bench as bench
    from jaxcontact.studies import _bench_report as bench_report

    monkeypatch.setattr(bench, "run_all", lambda scene, progress=None: {"curve": {"speedup": 1234.0}})
    monkeypatch.setattr(bench_report, "format_results", lambda results: "200-load curve: 1234x")
    monkeypatch.setattr(bench_report, "format_markdown", lambda results, machine, date: "| table |")
    assert main(["bench", "--out", str(tmp_path), "--no-progress"]) == 0
    capsys.readouterr()
    assert (tmp_path / "bench.txt").read_text().splitlines()[1] == "200-load curve: 1234x"
    saved = json.loads((tmp_path / "bench.json").read_text())
    assert (tmp_path / "bench.md").read_text() == "| table |\n"
    assert saved["curve"]["speedup"] == 1234.0
    assert saved["scene"]["parameters_SI"]["D"] == TABLE1["D"]


_BEM_BENCH = {
    "per_point_256": {
        "grid": 256,
        "points": 3,
        "device": "cpu",
        "jax_tangent": {"s_per_point": 0.1, "compile_s": 2.0, "speedup": 9.0, "K_over_contactmechanics": [1.001]},
        "jax_secant": {"s_per_point": 0.3, "compile_s": 2.0, "speedup": 3.0, "K_over_contactmechanics": [1.0]},
        "contactmechanics": {"s_per_point": 0.9},
    },
    "memory_1024": {"grid": 1024, "arguments_MiB": 8.0, "temporaries_MiB": 73.0},
    "memory_2048": {
        "grid": 2048,
        "arguments_MiB": 32.0,
        "temporaries_MiB": 300.0,
        "devices": 4,
        "split_temporaries_MiB": 107.0,
    },
}


def test_bench_bem_writes_its_report_to_out(tmp_path, capsys, monkeypatch):
    """`bench --bem` reports each grid's speed-up over ContactMechanics and the memory, as text and JSON."""
    from jaxcontact.studies import _bem_bench

    monkeypatch.setattr(_bem_bench, "run_bem_bench", lambda *args, **kwargs: _BEM_BENCH)
    assert main(["bench", "--bem", "--out", str(tmp_path), "--no-progress"]) == 0
    capsys.readouterr()
    lines = (tmp_path / "bench_bem.txt").read_text().splitlines()
    assert "256²: ContactMechanics 0.900 s; JAX tangent 0.100 s (9.0x)" in lines[1]
    assert lines[2] == "  memory of a solve on 1024²: 81 MiB (73 MiB temporaries, XLA's buffer assignment)"
    assert lines[3].endswith("; split over 4 devices (bem.DistributedFFT), 107 MiB temporaries a device")
    assert json.loads((tmp_path / "bench_bem.json").read_text())["per_point_256"]["jax_tangent"]["speedup"] == 9.0


def test_bench_bem_without_contactmechanics_times_the_jax_solve_alone(tmp_path, capsys, monkeypatch):
    """Where ContactMechanics is missing (a GPU machine, say) the grids asked for are timed without it."""
    import sys

    from jaxcontact.studies import _bem_bench

    asked = {}
    alone = {"per_point_512": {k: v for k, v in _BEM_BENCH["per_point_256"].items() if k != "contactmechanics"}}
    alone["per_point_512"]["grid"] = 512
    monkeypatch.setitem(sys.modules, "ContactMechanics", None)
    monkeypatch.setattr(_bem_bench, "run_bem_bench", lambda *a, **k: asked.update(a=a, k=k) or alone)
    assert main(["bench", "--bem", "--bem-grids", "512", "--out", str(tmp_path), "--no-progress"]) == 0
    assert "the JAX solve is timed alone" in capsys.readouterr().err
    assert asked == {"a": ((512,),), "k": {"reference": False, "progress": None}}
    lines = (tmp_path / "bench_bem.txt").read_text().splitlines()
    assert lines[1] == "  512²: JAX tangent 0.1000 s, secant 0.3000 s"


def test_bench_bem_refuses_a_grid_that_is_not_a_power_of_two(capsys):
    assert main(["bench", "--bem", "--bem-grids", "300", "--no-progress"]) == 2
    assert "power of two" in capsys.readouterr().err


_FIT_BENCH = {
    "device": "cpu",
    "curves": 1000,
    "points": 30,
    "batch_first_call_s": 190.0,
    "batch_compile_s": 75.0,
    "batch_s": {"median": 110.0, "best": 100.0},
    "loop_per_curve_s": {"median": 0.08, "best": 0.04},
    "loop_s_scaled": {"median": 80.0, "best": 40.0},
    "ratio": {"median": 80.0 / 110.0, "best": 0.4},
    "success": 1.0,
    "max_abs_D_difference": 3e-6,
    "batch_loss_excess": {"max": 2e-6, "min": -4e-4},
}


def test_bench_fit_batch_reports_the_ratio_to_the_loop(tmp_path, capsys, monkeypatch):
    from jaxcontact.studies import _fit_bench

    monkeypatch.setattr(_fit_bench, "run_fit_bench", lambda scene, curves: dict(_FIT_BENCH, curves=curves))
    assert main(["bench", "--fit-batch", "1000", "--out", str(tmp_path), "--no-progress"]) == 0
    capsys.readouterr()
    lines = (tmp_path / "bench_fit_batch.txt").read_text().splitlines()
    assert lines[3].startswith("  ratio (loop / batch): 0.727× (median), 0.4× (best)")


def test_bench_fit_batch_says_which_fits_better_where_the_two_differ(tmp_path, capsys, monkeypatch):
    from jaxcontact.studies import _fit_bench

    monkeypatch.setattr(_fit_bench, "run_fit_bench", lambda scene, curves: dict(_FIT_BENCH, curves=curves))
    assert main(["bench", "--fit-batch", "1000", "--out", str(tmp_path), "--no-progress"]) == 0
    capsys.readouterr()
    line = (tmp_path / "bench_fit_batch.txt").read_text().splitlines()[3]
    assert line.endswith("the batch's loss relative to the loop's -0.0004 to +2e-06")


def test_bench_fit_batch_refuses_no_curves(tmp_path, capsys):
    assert main(["bench", "--fit-batch", "0", "--out", str(tmp_path)]) == 2
    assert "--fit-batch 0 must be a number of curves >= 1" in capsys.readouterr().err


def test_bench_compiles_without_the_persistent_cache(tmp_path, capsys, monkeypatch):
    """The bench's compile times are compilations, not reads of `JAXCONTACT_CACHE`."""
    import jax

    from jaxcontact.studies import _bench as bench
    from jaxcontact.studies import _bench_report as bench_report

    seen = []
    monkeypatch.setenv("JAXCONTACT_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr(
        bench, "run_all", lambda scene, progress=None: seen.append(jax.config.values["jax_compilation_cache_dir"]) or {}
    )
    monkeypatch.setattr(bench_report, "format_results", lambda results: "")
    monkeypatch.setattr(bench_report, "format_markdown", lambda results, machine, date: "")
    main(["bench", "--out", str(tmp_path / "out"), "--no-progress"])
    capsys.readouterr()
    assert seen and seen[0] != str(tmp_path / "cache")


def test_approach_refuses_a_preload_outside_the_model(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    text = (ROOT / "data" / "scenes" / "table1_dynamics.toml").read_text()
    scene.write_text(
        text.replace("[approach]\n", "[approach]\nreference_load = 1e9\n", 1).replace("reference_load = 220.0", "", 1)
    )
    assert main(["approach", str(scene), "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        "jaxcontact approach: error: approach.reference_load = 1e+09 N is outside the model (load_out_of_range): "
        "choose a preload where the stiffness is valid (see jaxcontact run on this scene)"
    )


def test_the_fit_figure_shows_the_values_their_intervals_and_the_residuals():
    from types import SimpleNamespace

    from jaxcontact.cli._plots import fit_figure

    loads = np.geomspace(1.0, 100.0, 5)
    result = SimpleNamespace(
        params=("D", "G"),
        values={"D": 1.40475, "G": 1.98e-10},
        ci95={"D": (1.40208, 1.40742), "G": (1.66e-10, 2.35e-10)},
        residuals=np.array([0.01, -0.02, np.nan, 0.03, -0.01]),
        method="lm",
        describes_data=True,
    )
    fig = fit_figure(result, loads, 1e8 * loads, loads, 1e8 * loads)
    top, bottom = fig.axes
    legend = [t.get_text() for t in top.get_legend().get_texts()]
    assert legend[1] == "fit (95 % CI): D = 1.405 [1.402, 1.407]; G = 1.98e-10 [1.66e-10, 2.35e-10] m"
    residual_points = bottom.lines[0]
    np.testing.assert_allclose(residual_points.get_ydata(), [0.01, -0.02, 0.03, -0.01])


def test_values_in_the_wrong_unit_are_warned_about(tmp_path, capsys):
    """E and H typed in GPa, the area in mm²: the run goes on, and says what looks like a unit mistake."""
    scene = tmp_path / "gpa.toml"
    scene.write_text(
        "[surface]\nD = 1.4058\nG = 2.2826e-10\n[material]\nE = 220\nnu = 0.25\nH = 100\n[joint]\narea = 100\n"
        "[loads]\nvalues = [1e-3]\n"
    )
    assert main(["run", str(scene), "--out", str(tmp_path / "o"), "--no-progress"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err == [
        "jaxcontact run: warning: E = 220 Pa is far outside what engineering surfaces have (1e+08–2e+12 Pa): "
        "given in GPa or MPa instead of Pa? The model runs with it as it is.",
        "jaxcontact run: warning: H = 100 Pa is far outside what engineering surfaces have (1e+07–1e+11 Pa): "
        "given in GPa or MPa instead of Pa? The model runs with it as it is.",
        "jaxcontact run: warning: area = 100 m² is far outside what engineering surfaces have (1e-10–1 m²): "
        "given in mm² instead of m²? The model runs with it as it is.",
    ]


def test_the_table_says_why_a_stiffness_is_zero():
    from jaxcontact.cli._report import format_table

    row = dict(F_N=1.0, F_star=1e-6, a_l_m2=1e-10, K_N_per_m=0.0, K_star=0.0, status="ok", fully_plastic=True)
    assert format_table([row]).splitlines()[1].endswith("ok (K = 0: every spot plastic)")


def test_run_with_more_loads_than_one_chunk(tmp_path, capsys):
    """4097 loads: two chunks of 4096, the second padded; every row is there and right."""
    scene = tmp_path / "many.toml"
    scene.write_text(
        "[surface]\nD = 1.4058\nG = 2.2826e-10\n[material]\nE = 220e9\nnu = 0.25\nH = 100e9\n[joint]\narea = 1e-4\n"
        '[effects]\nregime_shares = false\n[loads]\nunit = "F_star"\nrange = [1e-7, 1e-4]\ncount = 4097\n'
    )
    assert main(["run", str(scene), "--out", str(tmp_path / "o"), "--no-progress", "--format", "json"]) == 0
    rows = json.loads(capsys.readouterr().out)["rows"]
    assert len(rows) == 4097
    F = np.array([r["F_N"] for r in rows])
    K = np.asarray(jc.solve(make_scene(**TABLE1), F[[0, 4095, 4096]]).stiffness)
    np.testing.assert_allclose([rows[i]["K_N_per_m"] for i in (0, 4095, 4096)], K, rtol=1e-12)


def test_a_modulus_that_overflows_every_load_is_flagged_not_plotted_as_an_error(tmp_path, capsys):
    """Issue 18.9: E = 1e-300 Pa puts F* beyond float64; the run says so per load and in a warning,
    and its plots do not fail on a log axis with nothing finite to show."""
    scene = tmp_path / "tiny_E.toml"
    scene.write_text(
        "[surface]\nD = 1.5\nG = 3e-10\n[material]\nE = 1e-300\nnu = 0.3\nH = 4e9\n[joint]\narea = 1e-4\n"
        "[loads]\nvalues = [1.0, 10.0]\n"
    )
    assert main(["run", str(scene), "--out", str(tmp_path / "o"), "--format", "json", "--no-progress"]) == 0
    captured = capsys.readouterr()
    assert [row["status"] for row in json.loads(captured.out)["rows"]] == ["invalid_parameters"] * 2
    assert captured.err.startswith("jaxcontact run: warning: E = 1e-300 Pa is far outside")


@pytest.mark.parametrize("starts", ["-3", "0"])
def test_a_number_of_starts_below_one_is_one_line_with_exit_2(tmp_path, capsys, starts):
    data = ROOT / "data" / "table1_grinding_generated.csv"
    assert main(["fit", str(data), "--starts", starts, "--out", str(tmp_path), "--no-progress"]) == 2
    assert capsys.readouterr().err == f"jaxcontact fit: error: --starts {starts} must be an integer in [1, 1024]\n"


def test_every_subcommands_help_opens_with_what_it_does():
    from jaxcontact.cli._main import build_parser

    commands = next(a for a in build_parser()._actions if a.dest == "command").choices
    described = {name: bool(p.description) and "\n" not in p.description for name, p in commands.items()}
    assert described == dict.fromkeys(commands, True)


def test_the_bench_table_for_the_docs_states_each_figure_and_its_machine():
    from jaxcontact.studies._bench_report import format_markdown

    timing = {"median_s": 1e-4, "speedup_median": 1300.0, "over_jit_median": 1.4}
    results = {
        "curve": {"jit_baseline_outputs": timing, "scipy": {"median_s": 0.13}},
        "curve_as_users_call_it": {"plain": timing, "jit": {"median_s": 0.7e-4}},
        "gradient": {"gradient_over_forward": 2.5, "speedup": 1000.0},
        "fit": {"jaxcontact_1_start_s": 0.007, "jaxcontact_12_starts_s": 0.08, "scipy_least_squares_s": 1.2},
        "fit_as_users_call_it": {"first_s": 2.61, "median_s": 0.118, "best_s": 0.1},
        "throughput": {
            "no_interaction": {"points_per_s": 1.5e7, "compile_s": 1.4},
            "paper": {"points_per_s": 8e6, "compile_s": 2.5},
        },
        "compilation_cache": {"cold_s": 3.2, "warm_s": 1.6},
    }
    table = format_markdown(results, "x86_64, 2 cores", "2026-11-25").splitlines()
    assert table[0].startswith("*Measured by `jaxcontact bench` on x86_64, 2 cores, 2026-11-25;")
    assert table[4] == (
        "| 200-load curve, like for like (a_l, K, A_r, status), `jax.jit` | 0.100 ms: 1300× scipy (130 ms) "
        "| ≥ 1000× scipy |"
    )
    assert table[8] == (
        "| D, G fit to 30 points as users call it (a fresh process, `fitting.fit`'s defaults: BFGS, 12 starts) "
        "| first 2.61 s; then 0.118 s median (0.100 s best) | first < 3 s; then < 0.1 s |"
    )


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--draws", "100"], "--draws 100 applies with --posterior only"),
        (["--seed", "3"], "--seed 3 applies with --posterior only"),
        (["--posterior", "--seed", "-1"], "--seed -1 must be an integer >= 0"),
        (["--prior", "D=1.4:0.1", "--prior", "D=1.5:0.1"], "D has a prior already; give one per parameter"),
        (["--prior", "D=1.45:-0.05"], "--prior D=1.45:-0.05: Normal: sd = -0.05 must be > 0"),
    ],
)
def test_fit_options_that_would_be_ignored_are_one_line_with_exit_2(tmp_path, capsys, extra, message):
    data = ROOT / "data" / "table1_grinding_generated.csv"
    assert main(["fit", str(data), *extra, "--out", str(tmp_path), "--no-progress"]) == 2
    assert message in capsys.readouterr().err


def test_a_scene_file_with_a_latin1_comment_is_read(tmp_path, capsys):
    path = tmp_path / "scene.toml"
    scene = "[surface]\nD = 1.5\nG = 3e-10\n[material]\nE = 2e11\nnu = 0.3\nH = 4e9\n[joint]\narea = 1e-4\n"
    path.write_bytes("# Messung é\n".encode("latin-1") + (scene + "[loads]\nvalues = [1.0]\n").encode())
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--format", "json", "--no-progress"]) == 0
    assert json.loads(capsys.readouterr().out)["rows"][0]["status"] == "ok"


def test_a_curve_file_with_a_latin1_comment_is_read(tmp_path):
    path = tmp_path / "curve.csv"
    path.write_bytes("# Messung é\n".encode("latin-1") + (ROOT / "data" / "table1_grinding_generated.csv").read_bytes())
    assert fitting.load_curve(path, make_scene(**TABLE1)).loads.size == 40


def test_an_interrupted_posterior_keeps_the_least_squares_fit(tmp_path, capsys, monkeypatch):
    def interrupted(*_, **__):
        raise KeyboardInterrupt

    monkeypatch.setattr(fitting, "sample", interrupted)
    data = ROOT / "data" / "table1_grinding_generated.csv"
    assert main(["fit", str(data), "--posterior", "--out", str(tmp_path), "--no-progress"]) == 130
    assert "fit by bfgs" in capsys.readouterr().out
