"""Partial resets merged by rows give the tensordicts TorchRL's own ``where`` merge gives."""

import dataclasses
import warnings

import pytest
import torch
from tensordict import TensorDict
from torchrl.envs import EnvBase, TransformedEnv

from gvgai_pcg.envs import GVGAIEnv
from gvgai_pcg.envs.difficulty import DifficultyTransform
from gvgai_pcg.envs.level_sources import GeneratedLevels
from gvgai_pcg.envs.reset_rows import RowResetTransformedEnv, check_reset_not_done, merge_reset_rows


class WhereMergedEnv(GVGAIEnv):
    """GVGAIEnv with TorchRL's own partial-reset merge, as the reference."""

    _reset_proc_data = EnvBase._reset_proc_data


def rollout(env, steps: int = 40) -> list:
    generator = torch.Generator().manual_seed(5)
    td = env.reset()
    out = []
    for _ in range(steps):
        td.set("action", torch.randint(0, 5, (env.batch_size[0],), generator=generator))
        stepped, td = env.step_and_maybe_reset(td)
        out += [stepped, td.clone()]
    return out


def test_rows_merged_equal_torchrl_merged_rollouts():
    ours, theirs = (cls("frogs", num_envs=16, levels="human", seed=2) for cls in (GVGAIEnv, WhereMergedEnv))
    for a, b in zip(rollout(ours), rollout(theirs), strict=True):
        assert set(a.keys(True, True)) == set(b.keys(True, True))
        assert (a == b).all()


def test_a_transformed_env_merges_by_rows_too():
    def make(cls):
        source = GeneratedLevels("frogs")
        return cls(GVGAIEnv("frogs", num_envs=8, levels=source, seed=1), DifficultyTransform(mode="ppcg"))

    for a, b in zip(rollout(make(RowResetTransformedEnv)), rollout(make(TransformedEnv)), strict=True):
        assert (a == b).all()


def test_entries_missing_on_one_side_count_as_zeros():
    running = TensorDict({"a": torch.ones(4, 2), "_reset": torch.tensor([True, False, True, False])}, [4])
    fresh = TensorDict({"a": torch.full((4, 2), 5.0), "b": torch.full((4,), 7.0)}, [4])
    shared = running.get("a")
    merged = merge_reset_rows(fresh, running, ["_reset"])
    assert merged.get("a")[:, 0].tolist() == [5.0, 1.0, 5.0, 1.0]
    assert merged.get("b").tolist() == [7.0, 0.0, 7.0, 0.0]
    assert "_reset" not in merged.keys()
    assert shared.eq(1).all()  # replaced, not written in place

    running = TensorDict({"c": torch.ones(2), "_reset": torch.tensor([False, True])}, [2])
    merged = merge_reset_rows(TensorDict({}, [2]), running, ["_reset"])
    assert merged.get("c").tolist() == [1.0, 0.0]


@pytest.mark.parametrize("keys", [["_reset", ("agents", "_reset")], []])
def test_other_reset_layouts_go_to_torchrl(keys, monkeypatch):
    calls = []
    monkeypatch.setattr(
        "gvgai_pcg.envs.reset_rows.torchrl_reset_merge", lambda *args: calls.append(args) or args[1]
    )
    running = TensorDict({"_reset": torch.tensor([True, False])}, [2])
    merge_reset_rows(TensorDict({}, [2]), running, keys)
    assert len(calls) == 1


@pytest.mark.parametrize("game", ["frogs", "zelda"])
def test_outputs_kept_by_the_caller_are_never_overwritten(game):
    # Observations are drawn (and the running ones copied) into recycled buffers, here all of
    # them whatever their size. Every output still held must keep its values.
    env = GVGAIEnv(game, num_envs=32, levels="human", seed=3)
    env.buffers.min_bytes = 0
    # a compiled render returns new tensors; this is about the pool
    env._runner.plan = dataclasses.replace(env.step_plan, fused=False)
    generator, td = torch.Generator().manual_seed(1), env.reset()
    kept, snapshots = [td], [td.clone()]
    for _ in range(30):
        td.set("action", torch.randint(0, 5, (32,), generator=generator))
        stepped, td = env.step_and_maybe_reset(td)
        kept += [stepped, td]
        snapshots += [stepped.clone(), td.clone()]
    for held, snapshot in zip(kept, snapshots, strict=True):  # the loop itself sets "action"
        for key, value in snapshot.exclude("action").items(True, True):
            assert torch.equal(held.get(key), value)
    assert len(env.buffers) == env.buffers.keep  # every buffer held: the pool had to grow


def test_released_observations_are_recycled():
    env = GVGAIEnv("frogs", num_envs=128, levels="human", seed=3)  # 434 KB of tiles: pooled, not compiled
    assert not env.step_plan.fused
    generator, td = torch.Generator().manual_seed(1), env.reset()
    addresses = set()
    for _ in range(30):
        td.set("action", torch.randint(0, 5, (128,), generator=generator))
        stepped, td = env.step_and_maybe_reset(td)
        addresses.add(stepped.get(("next", "tiles")).untyped_storage().data_ptr())
        addresses.add(td.get("tiles").untyped_storage().data_ptr())
    assert len(addresses) <= env.buffers.keep


def test_complete_entries_are_taken_whole_unless_replaced():
    running = TensorDict({"a": torch.zeros(4), "_reset": torch.tensor([False, True, False, True])}, [4])
    fresh = TensorDict({"a": torch.arange(4.0)}, [4])
    merged = merge_reset_rows(fresh, running.clone(), ["_reset"], complete={"a": fresh.get("a")})
    assert merged.get("a") is fresh.get("a")
    stale = {"a": torch.arange(4.0)}  # an entry that is no longer the output's: merged by rows
    merged = merge_reset_rows(fresh, running.clone(), ["_reset"], complete=stale)
    assert merged.get("a").tolist() == [0.0, 1.0, 0.0, 3.0]


def test_a_partial_reset_output_holds_the_running_values_in_the_other_rows():
    """TorchRL and transforms may read every row of a reset's output (its done check copies the
    done entries when the input has none; a VecNorm updates its statistics on them)."""
    env = GVGAIEnv("zelda", num_envs=16, levels="human", seed=0)
    td = env.reset()
    for _ in range(3):
        td.set("action", torch.zeros(16, dtype=torch.int64))  # NIL: nobody finishes
        td = env.step(td).get("next")
    assert not td.get("done").any()
    mask = torch.zeros(16, 1, dtype=torch.bool)
    mask[[0, 5]] = True
    output = env._reset(TensorDict({"_reset": mask}, [16]))
    kept = ~mask.squeeze(-1)
    for key in ("tiles", "score", "won", "difficulty", "level_seed"):
        assert torch.equal(output.get(key)[kept], td.get(key)[kept]), key
    assert not output.get("done").any() and not output.get("terminated").any()
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # TorchRL warns when it sees done rows it was not given
        merged = env.reset(TensorDict({"_reset": mask}, [16]))
    assert not merged.get("done").any()
    assert torch.equal(merged.get("tiles")[kept], td.get("tiles")[kept])


class ZeroTilesEnv(GVGAIEnv):
    """A subclass that replaces an entry of its reset output after GVGAIEnv built it."""

    def _reset(self, tensordict=None, **kwargs):
        out = super()._reset(tensordict, **kwargs)
        out.set("tiles", torch.zeros_like(out.get("tiles")))
        return out


class WhereMergedZeroTilesEnv(ZeroTilesEnv):
    _reset_proc_data = EnvBase._reset_proc_data


def test_an_entry_replaced_after_reset_is_merged_as_torchrl_merges_it():
    ours, theirs = (cls("frogs", num_envs=16, seed=2) for cls in (ZeroTilesEnv, WhereMergedZeroTilesEnv))
    for a, b in zip(rollout(ours), rollout(theirs), strict=True):
        assert (a == b).all()


def test_a_full_reset_keeps_no_reference_to_the_callers_difficulty():
    env = GVGAIEnv("zelda", num_envs=4, levels=GeneratedLevels("zelda"), seed=0)
    requested = torch.full((4, 1), 0.25)
    td = env.reset(TensorDict({"difficulty": requested}, [4]))
    requested.fill_(0.9)  # the caller reuses its tensor
    assert env.rand_step(td).get(("next", "difficulty")).eq(0.25).all()


@pytest.mark.parametrize("done_rows", [[], [0], [1], [0, 2], [1, 3]])
def test_the_done_after_reset_check_agrees_with_torchrl(done_rows):
    env = GVGAIEnv("zelda", num_envs=4, seed=0)
    reset = torch.tensor([False, True, False, False]).unsqueeze(-1)
    done = torch.zeros(4, 1, dtype=torch.bool)
    done[done_rows] = True
    running = TensorDict({key: torch.zeros(4, 1, dtype=torch.bool) for key in env.done_keys}, [4])
    running.set("_reset", reset)
    output = TensorDict({key: done.clone() for key in env.done_keys}, [4])
    outcomes = []
    for check in (check_reset_not_done, EnvBase._reset_check_done):
        try:
            check(env, running.clone(), output.clone())
            outcomes.append("ok")
        except RuntimeError:
            outcomes.append("raised")
    assert outcomes[0] == outcomes[1]
    assert outcomes[0] == ("raised" if 1 in done_rows else "ok")


class TorchRLMaybeResetEnv(GVGAIEnv):
    """GVGAIEnv with TorchRL's own ``maybe_reset``, as the reference."""

    maybe_reset = EnvBase.maybe_reset


def test_maybe_reset_resets_as_torchrls_and_reads_done_once(monkeypatch):
    ours, theirs = (cls("frogs", num_envs=16, seed=2) for cls in (GVGAIEnv, TorchRLMaybeResetEnv))
    for a, b in zip(rollout(ours, 30), rollout(theirs, 30), strict=True):
        assert set(a.keys(True, True)) == set(b.keys(True, True))
        assert (a == b).all()
    tds = [env.reset() for env in (ours, theirs)]  # nobody done: maybe_reset resets nothing
    reads = []
    to_bool = torch.Tensor.__bool__
    monkeypatch.setattr(torch.Tensor, "__bool__", lambda t: reads.append(1) or to_bool(t))
    for env, td in zip((ours, theirs), tds, strict=True):
        assert env.maybe_reset(td) is td and "_reset" not in td.keys()
    assert len(reads) == 3  # ours once, TorchRL's twice
