"""The driven mass on the joint (diffrax) about its preload, by its unloading (dynamic) law and by its
loading law, fitting D and G from resonance against preload, and the command."""

import json

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import ROOT, TABLE1, TABLE1_WITHOUT_INTERACTION, WRONG_START, make_scene

import jaxcontact as jc
from jaxcontact import fitting
from jaxcontact.applications import Drive, frequency_response, resonance_frequency, simulate, steady_amplitude
from jaxcontact.cli import main

MASS, PRELOAD = 1.0, 220.0


@pytest.fixture(scope="module")
def linear_frequency(dynamics_scene):
    f, status = resonance_frequency(dynamics_scene, MASS, jnp.array([PRELOAD]))
    assert int(status[0]) == 0
    return float(f[0])


def drive(f, zeta=0.05, amplitude=0.2):
    return Drive(mass=MASS, damping=2 * zeta * MASS * 2 * np.pi * f, preload=PRELOAD, amplitude=amplitude, frequency=f)


def test_linear_resonance_is_sqrt_K_over_m_with_the_dynamic_stiffness(dynamics_scene, linear_frequency):
    K = float(jc.dynamic_stiffness(dynamics_scene, PRELOAD).stiffness)
    np.testing.assert_allclose(linear_frequency, np.sqrt(K / MASS) / (2 * np.pi), rtol=1e-13)


def test_small_amplitude_response_peaks_at_the_linear_frequency(dynamics_scene, linear_frequency):
    ratios = np.linspace(0.96, 1.03, 8)  # the command's chunk of eight
    amplitudes, status = frequency_response(dynamics_scene, drive(linear_frequency), ratios * linear_frequency)
    assert np.all(np.asarray(status) == 0)
    A = np.log(np.asarray(amplitudes))
    i = int(np.argmax(A))
    assert 0 < i < len(A) - 1
    # Parabola through the three highest points: the resonance frequency.
    a, b, _ = np.polyfit(ratios[i - 1 : i + 2], A[i - 1 : i + 2], 2)
    peak = -b / (2 * a)
    # Damped peak of the linear oscillator: sqrt(1 - 2ζ²) = 0.9975 of the natural frequency.
    assert abs(peak - 1.0) < 0.01, peak
    # ... and its height is the linear one, F1 / (K 2ζ sqrt(1-ζ²)).
    K = float(jc.dynamic_stiffness(dynamics_scene, PRELOAD).stiffness)
    np.testing.assert_allclose(np.exp(A.max()), 0.2 / K / (2 * 0.05), rtol=2e-3)


def test_time_history_by_the_loading_law_is_consistent(table1_without_interaction):
    law, scene = jc.Loading(), table1_without_interaction
    f, _ = resonance_frequency(scene, MASS, jnp.array([PRELOAD]), stiffness=law)
    response = simulate(scene, drive(float(f[0]), amplitude=100.0), stiffness=law, periods=20)
    assert int(response.status) == 0
    F = np.asarray(response.contact_force)
    assert np.all(F > 0)  # a large, still closed, oscillation
    assert abs(F.max() - F.min()) > 50
    # dF_c/dt = K(F_c) v: check at the saved points by finite differences of F_c.
    t, v = np.asarray(response.t), np.asarray(response.v)
    dF = np.gradient(F, t)
    K = np.asarray(jc.solve(scene, jnp.asarray(F)).stiffness)
    np.testing.assert_allclose(dF[5:-5], (K * v)[5:-5], rtol=2e-2, atol=2e-2 * np.abs(K * v).max())


def test_the_unloading_law_of_a_flowing_model_is_linear_about_the_preload(dynamics_scene, linear_frequency):
    # The seed model's spots flow: about the preload the contact force moves with K_u(F0) alone.
    response = simulate(dynamics_scene, drive(linear_frequency, amplitude=100.0), periods=20)
    K = float(jc.dynamic_stiffness(dynamics_scene, PRELOAD).stiffness)
    force = np.asarray(response.contact_force)
    np.testing.assert_allclose(force - PRELOAD, K * np.asarray(response.x), rtol=1e-6, atol=1e-6 * np.ptp(force))


def test_a_fully_plastic_joint_resonates_by_its_dynamic_stiffness():
    # H = 3 GPa on the D = 1.5 surface: every spot flows, the loading K is 0, the unloading one is not.
    scene = make_scene(**dict(TABLE1_WITHOUT_INTERACTION, D=1.5, G=1e-12, l_min=1e-6, H=3e9, area=1e-4))
    loading, status = resonance_frequency(scene, MASS, jnp.array([PRELOAD]), stiffness=jc.Loading())
    assert (int(status[0]), float(loading[0])) == (0, 0.0)
    unloading, status = resonance_frequency(scene, MASS, jnp.array([PRELOAD]))
    assert int(status[0]) == 0 and float(unloading[0]) > 0


def test_a_tangential_law_is_refused_for_a_normal_vibration(dynamics_scene):
    with pytest.raises(ValueError, match="stiffness = TangentialStick"):
        simulate(dynamics_scene, drive(1e3), stiffness=jc.TangentialStick())


def test_gradient_of_steady_amplitude(table1_without_interaction):
    table1_scene = table1_without_interaction
    K = float(jc.solve(table1_scene, PRELOAD).stiffness)
    d = drive(0.97 * np.sqrt(K / MASS) / (2 * np.pi))

    # The scene is an argument of the jitted function, as equinox passes modules: its arrays are
    # traced, not folded into the program as constants.
    @jax.jit
    def amplitude(D, scene):
        return steady_amplitude(eqx.tree_at(lambda s: s.surface.D, scene, D), d, periods=30, rtol=1e-11)[0]

    g = jax.grad(amplitude)(jnp.asarray(TABLE1["D"]), table1_scene)
    h = 1e-5
    fd = (amplitude(TABLE1["D"] + h, table1_scene) - amplitude(TABLE1["D"] - h, table1_scene)) / (2 * h)
    assert abs(float(g)) > 0
    np.testing.assert_allclose(g, fd, rtol=1e-5)


@pytest.mark.parametrize(
    "kw, message",
    [
        (dict(amplitude=300.0), r"amplitude = .* must satisfy 0 < amplitude < preload"),
        (dict(mass=0.0), r"mass .*\(0, inf\)"),
        (dict(damping=-1.0), r"damping .*\[0, inf\)"),
    ],
)
def test_drive_validation(kw, message):
    with pytest.raises(ValueError, match=message):
        Drive(**(dict(mass=1.0, damping=10.0, preload=PRELOAD, amplitude=0.2, frequency=1e4) | kw))


def test_fit_D_and_G_from_resonance_against_preload(table1_without_interaction):
    # The fitting tests' scene and start (their compiled programs): the interaction is not the subject.
    preloads = np.geomspace(1e-10, 1e-4, 30) * TABLE1["E"] * TABLE1["area"]
    # `fit_resonance` fits the loading tangent: resonances of the loading law.
    f, status = resonance_frequency(table1_without_interaction, MASS, preloads, stiffness=jc.Loading())
    assert np.all(np.asarray(status) == 0)
    start = make_scene(**WRONG_START)
    exact = fitting.fit_resonance(preloads, np.asarray(f), MASS, start)
    np.testing.assert_allclose([exact.values["D"], exact.values["G"]], [TABLE1["D"], TABLE1["G"]], rtol=1e-6)
    noisy = np.asarray(f) * np.exp(0.01 * np.random.default_rng(3).standard_normal(f.shape))  # 1 % in frequency
    result = fitting.fit_resonance(preloads, noisy, MASS, start)
    for name in ("D", "G"):
        lo, hi = result.ci95[name]
        assert lo < TABLE1[name] < hi
    assert abs(result.values["D"] - TABLE1["D"]) < 0.01
    with pytest.raises(ValueError, match="mass = 0"):
        fitting.fit_resonance(preloads, np.asarray(f), 0, start)


def test_the_command_on_its_embedded_scene(dynamics_scene, tmp_path, capsys):
    """`jaxcontact dynamics` (a sweep of one chunk): the tests above compiled its programs."""
    scene = tmp_path / "dyn.toml"
    scene.write_text(
        (ROOT / "data" / "scenes" / "table1_dynamics.toml").read_text().replace("sweep_count = 41", "sweep_count = 8")
    )
    assert main(["dynamics", str(scene), "--out", str(tmp_path), "--format", "json", "--no-progress"]) == 0
    payload = json.loads(capsys.readouterr().out)
    K = float(jc.dynamic_stiffness(dynamics_scene, PRELOAD).stiffness)
    np.testing.assert_allclose(payload["linear_resonance_Hz"], np.sqrt(K / MASS) / (2 * np.pi), rtol=1e-12)
    assert len(payload["frequency_response"]) == 8
    assert len(payload["resonance_vs_preload"]) == 31
    assert all(r["status"] == "ok" for r in payload["frequency_response"])
    for name in ("time_history.png", "frequency_response.png", "resonance_vs_preload.png", "time_history.csv"):
        assert (tmp_path / name).stat().st_size > 1000
