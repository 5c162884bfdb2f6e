"""NUTS through blackjax (the `bayes` extra): window adaptation, then several chains in one compiled scan.

Generic over the log density: `jaxcontact.fitting._posterior` gives it the model's, the tests a Gaussian's.
"""

from __future__ import annotations

import dataclasses
import time

import jax
import jax.numpy as jnp
import numpy as np

from jaxcontact.numerics import cached, optional_import, standard_promotion


@dataclasses.dataclass(frozen=True)
class Chains:
    """`positions` (chains, draws, dimension), the `ess` and `rhat` of each dimension (over all chains),
    the mean acceptance, the number of divergent transitions, and the times (s): `adaptation` (with its
    compilation), the sampler's `compilation`, and `sampling` (the compiled run)."""

    positions: np.ndarray
    ess: np.ndarray
    rhat: np.ndarray
    acceptance: float
    divergences: int
    adaptation: float
    compilation: float
    sampling: float


def run_chains(logdensity, initial, *, chains: int = 4, warmup: int = 500, draws: int = 500, seed: int = 0) -> Chains:
    """Adapt NUTS's step size and diagonal mass matrix on one chain from `initial` (blackjax's window
    adaptation), then run `chains` chains of `draws` from the adapted state, each with its own key,
    `vmap`ped over chains inside one `lax.scan`. Seeded and reproducible.

    **Arguments:** `logdensity` (a JAX function of a position vector), `initial` (the start), `chains`,
    `warmup` (adaptation steps), `draws` (per chain), `seed`. **Returns:** `Chains`.
    """
    blackjax = optional_import("blackjax", "sampling a posterior")
    key = jax.random.PRNGKey(seed)
    adapt_key, chain_key = jax.random.split(key)
    initial = jnp.asarray(initial)
    t0 = time.perf_counter()
    adaptation = blackjax.window_adaptation(blackjax.nuts, logdensity)
    # Compiled as one program: run eagerly, its set-up dispatches a hundred small ones.
    adapt = jax.jit(lambda key, position: adaptation.run(key, position, num_steps=warmup)[0])
    with standard_promotion():
        state, parameters = adapt(adapt_key, initial)
    jax.block_until_ready(state.position)
    t1 = time.perf_counter()
    kernel = blackjax.nuts(logdensity, **parameters)
    # Each chain starts from the adapted state; they decorrelate within a few draws (the adapted
    # step explores the posterior) and R-hat over them checks that they agree.
    states = jax.vmap(lambda _: state)(jnp.arange(chains))

    @jax.jit
    def sample(states, key):
        def one_step(states, key):
            keys = jax.random.split(key, chains)
            states, info = jax.vmap(kernel.step)(keys, states)
            return states, (states.position, info.acceptance_rate, info.is_divergent)

        return jax.lax.scan(one_step, states, jax.random.split(key, draws))[1]

    with standard_promotion():
        compiled = sample.lower(states, chain_key).compile()
    t2 = time.perf_counter()
    positions, acceptance, divergent = compiled(states, chain_key)
    jax.block_until_ready(positions)
    t3 = time.perf_counter()
    positions = np.swapaxes(np.asarray(positions), 0, 1)  # (chains, draws, dimension)
    with standard_promotion():
        ess, rhat = (np.asarray(x, dtype=float) for x in _diagnostics(blackjax)(positions))
    return Chains(
        positions=positions,
        ess=ess,
        rhat=rhat,
        acceptance=float(np.mean(acceptance)),
        divergences=int(np.sum(divergent)),
        adaptation=t1 - t0,
        compilation=t2 - t1,
        sampling=t3 - t2,
    )


@cached
def _diagnostics(blackjax):
    """`positions` (chains, draws, dimension) ↦ (ESS, R-hat) per dimension, as one compiled program."""

    def both(positions):
        d = blackjax.diagnostics
        return d.effective_sample_size(positions), d.potential_scale_reduction(positions)

    return jax.jit(jax.vmap(both, in_axes=-1))
