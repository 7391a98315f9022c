"""``ActingRollouts``: a collector's rollout layout, and an update equal to the recomputing one."""

from __future__ import annotations

import torch

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.rl.a2c_loss import A2CLoss
from gvgai_pcg.rl.models import as_tensordict_module, make_actor_critic
from gvgai_pcg.rl.rollout import KEEP_GRAPH_FROM_ENVS, ActingRollouts, keeps_acting_graph


def _setup(num_envs: int = 6, max_steps: int = 7):
    env = GVGAIEnv("zelda", num_envs, "human", "tiles", max_steps=max_steps, seed=3)
    shape = tuple(env.observation_spec["tiles"].shape[-3:])
    net = make_actor_critic("compact", "tiles", shape, env.action_spec.space.n, 32)
    return env, net


def _gradients(net, loss_module, rollout) -> list[torch.Tensor]:
    losses = loss_module(rollout)
    net.zero_grad(set_to_none=True)
    (losses["loss_objective"] + losses["loss_critic"] + losses["loss_entropy"]).backward()
    return [p.grad.clone() for p in net.parameters()]


def test_a_rollout_has_the_collector_layout_and_follows_the_episodes():
    torch.manual_seed(0)
    env, net = _setup()
    rollouts = ActingRollouts(env, net, "tiles", n_steps=5, keep_graph=True)
    first, second = rollouts.collect(), rollouts.collect()
    assert first.batch_size == (6, 5)
    for key in ("tiles", "action", "logits", "state_value"):
        assert key in first.keys()
    for key in ("reward", "done", "terminated", "truncated", "score", "won", "tiles"):
        assert first.get(("next", key)).shape[:2] == (6, 5)
    assert first.get("logits").requires_grad and first.get("state_value").requires_grad
    # a step's next observation is the following step's observation unless the episode ended
    done = first.get(("next", "done")).squeeze(-1)
    for t in range(4):
        going_on = ~done[:, t]
        assert torch.equal(first.get(("next", "tiles"))[going_on, t], first.get("tiles")[going_on, t + 1])
    # the second rollout starts where the first one stopped (max_steps 7 truncates within it)
    assert torch.equal(first.get(("next", "tiles"))[~done[:, -1], -1], second.get("tiles")[~done[:, -1], 0])
    assert second.get(("next", "truncated")).any()


def test_the_update_on_the_acting_graph_equals_the_update_that_recomputes_the_policy():
    torch.manual_seed(1)
    env, net = _setup()
    loss_module = A2CLoss(as_tensordict_module(net, "tiles"))
    rollout = ActingRollouts(env, net, "tiles", n_steps=5, keep_graph=True).collect()
    seen: list[int] = []  # observations the loss passes through the network
    hook = net.register_forward_hook(lambda module, args, out: seen.append(args[0].shape[0]))
    reused = _gradients(net, loss_module, rollout)
    reused_frames, seen[:] = sum(seen), []
    detached = rollout.exclude("logits", "state_value")
    recomputed = _gradients(net, loss_module, detached)
    hook.remove()
    assert reused_frames <= 6 * 2  # the bootstrap pass (and truncated episodes' final observations)
    assert sum(seen) >= 6 * 5  # the recomputing update passes every frame again
    assert any(g.abs().sum() > 0 for g in reused)
    for a, b in zip(reused, recomputed, strict=True):
        torch.testing.assert_close(a, b, rtol=1e-4, atol=1e-6)
    # a rollout whose acting outputs carry no graph (a collector's) is recomputed, not trusted
    with torch.no_grad():
        logits, values = loss_module.policy_outputs(rollout.detach())
    no_graph = rollout.detach()
    assert not no_graph.get("logits").requires_grad
    torch.testing.assert_close(_gradients(net, loss_module, no_graph), recomputed)
    assert logits.shape == (6, 5, env.action_spec.space.n) and values.shape == (6, 5)


def test_small_batches_act_without_a_graph_and_the_update_recomputes_it_equally():
    assert not keeps_acting_graph(12) and keeps_acting_graph(64)
    assert keeps_acting_graph(KEEP_GRAPH_FROM_ENVS) and not keeps_acting_graph(KEEP_GRAPH_FROM_ENVS - 1)
    env, net = _setup()
    loss_module = A2CLoss(as_tensordict_module(net, "tiles"))
    kept, plain = (ActingRollouts(env, net, "tiles", 5, keep_graph=keep) for keep in (True, False))
    assert not ActingRollouts(env, net, "tiles", 5).keep_graph  # 6 envs: the default recomputes
    torch.manual_seed(2)
    with_graph = kept.collect()
    torch.manual_seed(2)
    env.set_seed(3)
    without = plain.collect()
    assert not without.get("logits").requires_grad and not without.get("state_value").requires_grad
    # the same episodes and actions either way, and the same update
    assert torch.equal(with_graph.get("action"), without.get("action"))
    torch.testing.assert_close(with_graph.get("logits").detach(), without.get("logits"))
    seen: list[int] = []
    hook = net.register_forward_hook(lambda module, args, out: seen.append(args[0].shape[0]))
    recomputed = _gradients(net, loss_module, without)
    hook.remove()
    assert sum(seen) >= 6 * 5  # every frame passed through the network again
    for a, b in zip(_gradients(net, loss_module, with_graph), recomputed, strict=True):
        torch.testing.assert_close(a, b, rtol=1e-4, atol=1e-6)
