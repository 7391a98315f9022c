"""The private torch, tensordict and TorchRL APIs of gvgai_pcg/_private_apis.py still exist and
behave as the package relies on. A failure here after an upgrade names the API and the pinned
versions: fix its wrapper in gvgai_pcg/_private_apis.py (or pin the old version)."""

from __future__ import annotations

import inspect
import re
from contextlib import contextmanager
from pathlib import Path

import pytest
import tensordict
import torch
import torchrl
from tensordict import TensorDict
from torchrl.data import Categorical, Composite, Unbounded
from torchrl.envs import EnvBase, TransformedEnv

import gvgai_pcg
from gvgai_pcg import _private_apis as private
from gvgai_pcg._private_apis import PINNED, CompleteStepHook, ResetMergeHook

# Every private name the package may use, only in gvgai_pcg/_private_apis.py.
PRIVATE_NAMES = (
    "_storage_Use_Count",
    "_cdata",
    "_assert_async",
    "_new_unsafe",
    "._tensordict",
    "_reset_proc_data",
    "_step_proc_data",
    "_reset_check_done",
    "_complete_done",
    "_allow_done_after_reset",
    "_update_during_reset",
)


@contextmanager
def relied_on(api: str):
    """Turn any failure inside into one that names ``api`` and the versions."""
    try:
        yield
    except Exception as error:  # noqa: BLE001  (whatever changed, say which API it was)
        pytest.fail(
            f"{api} no longer exists or behaves as gvgai_pcg relies on. Installed: torch "
            f"{torch.__version__}, torchrl {torchrl.__version__}, tensordict {tensordict.__version__}; "
            f"pinned: {PINNED}. See gvgai_pcg/_private_apis.py for why it is used and adapt its "
            f"wrapper there.\n{type(error).__name__}: {error}"
        )


def parameters(function) -> list[str]:
    return list(inspect.signature(function).parameters)


class TinyEnv(EnvBase):
    """Four envs with one observation; done after every step, never after a reset."""

    def __init__(self, **kwargs) -> None:
        super().__init__(batch_size=torch.Size([4]), **kwargs)
        self.observation_spec = Composite(obs=Unbounded((4, 1)), shape=(4,))
        self.action_spec = Categorical(2, shape=(4,))
        self.reward_spec = Unbounded((4, 1))
        self.resets = 0

    def _reset(self, tensordict):
        self.resets += 1
        obs = torch.full((4, 1), float(self.resets))
        return TensorDict({"obs": obs, "done": torch.zeros(4, 1, dtype=torch.bool)}, [4])

    def _step(self, tensordict):
        done = torch.ones(4, 1, dtype=torch.bool)
        return TensorDict(
            {"obs": torch.zeros(4, 1), "reward": torch.zeros(4, 1), "done": done, "terminated": done}, [4]
        )

    def _set_seed(self, seed):
        return seed


class HookedEnv(ResetMergeHook, TinyEnv):
    def merge_reset(self, tensordict, tensordict_reset):
        self.merged = (tensordict, tensordict_reset)
        return tensordict_reset.set("merged_by", torch.ones(4))


class HookedTransformedEnv(ResetMergeHook, TransformedEnv):
    def merge_reset(self, tensordict, tensordict_reset):
        return tensordict_reset.set("merged_by", torch.full((4,), 2.0))


def test_only_the_private_api_module_names_private_apis():
    package = Path(gvgai_pcg.__file__).parent
    pattern = re.compile("|".join(re.escape(name) for name in PRIVATE_NAMES))
    named = [
        f"{path.relative_to(package)}: {match.group()}"
        for path in sorted(package.rglob("*.py"))
        if path.name != "_private_apis.py"
        for match in pattern.finditer(path.read_text())
    ]
    assert not named, f"use the wrappers of gvgai_pcg/_private_apis.py instead: {named}"


def test_storage_use_count_counts_the_tensors_on_a_storage():
    with relied_on("torch._C._storage_Use_Count"):
        assert private.HAS_STORAGE_USE_COUNT
        buffer = torch.empty(1000)
        alone = private.storage_use_count(buffer.untyped_storage())
        view = buffer[10:]
        assert private.storage_use_count(buffer.untyped_storage()) == alone + 1
        array = view.numpy()
        assert private.storage_use_count(buffer.untyped_storage()) == alone + 2
        del view, array
        assert private.storage_use_count(buffer.untyped_storage()) == alone


def test_assert_async_raises_the_message_where_the_condition_is_false():
    with relied_on("torch._assert_async"):
        private.assert_async(torch.tensor(True), "never")
        with pytest.raises(RuntimeError, match="the log table is full"):
            private.assert_async(torch.tensor(False), "the log table is full")


def test_new_unsafe_takes_the_entries_as_they_are():
    with relied_on("tensordict.TensorDict._new_unsafe"):
        assert {"source", "batch_size", "device"} <= set(parameters(TensorDict._new_unsafe))
        x, nested = torch.arange(6).view(3, 2), TensorDict({"y": torch.zeros(3, 5)}, [3, 5])
        td = private.unchecked_tensordict({"x": x, "table": nested}, torch.Size([3]), torch.device("cpu"))
        assert type(td) is TensorDict and td.batch_size == torch.Size([3])
        assert td.device == torch.device("cpu")
        assert td.get("x") is x  # not copied
        assert td.get("table").batch_size == torch.Size([3, 5])


def test_entries_are_the_tensordicts_own_dict_of_its_entries():
    with relied_on("tensordict.TensorDict._tensordict"):
        x, nested = torch.arange(6).view(3, 2), TensorDict({"y": torch.zeros(3, 5)}, [3, 5])
        td = TensorDict({"x": x, "table": nested}, [3])
        entries = private.entries(td)
        assert set(entries) == {"x", "table"} and entries["x"] is x
        assert entries["table"] is td.get("table")
        td.set("z", torch.ones(3))  # the dict the TensorDict keeps, not a copy
        assert entries["z"] is td.get("z")
        new_x = torch.ones(3, 2, dtype=x.dtype)
        private.write_entries(td, {"x": new_x})
        assert td.get("x") is new_x and td.batch_size == torch.Size([3])


class FlatRewardEnv(TinyEnv):
    """Its step's reward is ``[4]``, not the spec's ``[4, 1]``: TorchRL's step reshapes it."""

    def _step(self, tensordict):
        out = super()._step(tensordict)
        self.stepped = out.set("reward", torch.zeros(4))
        return out


class SkippingEnv(CompleteStepHook, FlatRewardEnv):
    pass


def stepped_reward_shape(env: EnvBase) -> torch.Size:
    td = env.step(env.reset().set("action", torch.zeros(4, dtype=torch.int64)))
    return td.get(("next", "reward")).shape


def test_step_passes_the_step_output_through_the_step_proc_data_hook():
    with relied_on("EnvBase._step_proc_data"):
        assert stepped_reward_shape(FlatRewardEnv()) == (4, 1)  # TorchRL's own reshapes
        env = SkippingEnv()
        assert stepped_reward_shape(env) == (4,)  # the hook took the output as it is...
        td = env.step(env.reset().set("action", torch.zeros(4, dtype=torch.int64)))
        assert td.get("next") is env.stepped
        assert stepped_reward_shape(SkippingEnv(run_type_checks=True)) == (4, 1)  # ...but not with checks


def test_reset_ends_with_the_reset_proc_data_hook_of_the_env_that_is_reset():
    with relied_on("torchrl EnvBase._reset_proc_data (called by EnvBase.reset)"):
        assert parameters(EnvBase._reset_proc_data) == ["self", "tensordict", "tensordict_reset"]
        env = HookedEnv()
        out = env.reset()
        assert out.get("merged_by").tolist() == [1.0] * 4 and env.merged[0] is None
        running = out.clone().set("_reset", torch.tensor([True, False, True, False]).unsqueeze(-1))
        assert env.reset(running).get("merged_by").tolist() == [1.0] * 4
        assert env.merged[0] is running
        # A TransformedEnv runs its own hook, not its base env's (no merge twice).
        base = HookedEnv()
        base.merged = None
        assert HookedTransformedEnv(base).reset().get("merged_by").tolist() == [2.0] * 4
        assert base.merged is None


def test_complete_done_fills_the_missing_done_entries():
    with relied_on("torchrl EnvBase._complete_done"):
        env = TinyEnv()
        reset = TensorDict({"obs": torch.zeros(4, 1), "done": torch.zeros(4, 1, dtype=torch.bool)}, [4])
        private.complete_done(env, reset)
        assert set(env.done_keys) <= set(reset.keys())
        assert not reset.get("terminated").any()


def test_reset_check_done_rejects_a_reset_env_that_is_done():
    with relied_on("torchrl EnvBase._reset_check_done / _allow_done_after_reset"):
        assert parameters(EnvBase._reset_check_done) == ["self", "tensordict", "tensordict_reset"]
        env = TinyEnv()
        mask = torch.tensor([True, False, False, False]).unsqueeze(-1)
        done = torch.zeros(4, 1, dtype=torch.bool)
        running = TensorDict({"_reset": mask, "done": done, "terminated": done}, [4])
        fine = TensorDict({"done": ~mask, "terminated": ~mask}, [4])  # done only where not reset
        private.reset_check_done(env, running, fine)
        bad = TensorDict({"done": mask, "terminated": mask}, [4])
        with pytest.raises(RuntimeError, match="True after reset"):
            private.reset_check_done(env, running, bad)
        assert not private.allows_done_after_reset(env)
        lenient = TinyEnv(allow_done_after_reset=True)
        assert private.allows_done_after_reset(lenient)
        private.reset_check_done(lenient, running, bad)


def test_torchrl_reset_merge_takes_the_marked_rows_and_pops_the_mask():
    with relied_on("torchrl.envs.utils._update_during_reset"):
        from torchrl.envs.utils import _update_during_reset

        assert parameters(_update_during_reset) == ["tensordict_reset", "tensordict", "reset_keys"]
        mask = torch.tensor([True, False, True])
        running = TensorDict({"obs": torch.zeros(3, 2), "_reset": mask.unsqueeze(-1)}, [3])
        fresh = TensorDict({"obs": torch.ones(3, 2)}, [3])
        merged = private.torchrl_reset_merge(fresh, running, ["_reset"])
        assert merged.get("obs")[:, 0].tolist() == [1.0, 0.0, 1.0]
        assert "_reset" not in merged.keys()


def test_the_pinned_versions_named_in_failures_are_the_ones_in_pyproject():
    pyproject = (Path(gvgai_pcg.__file__).parents[1] / "pyproject.toml").read_text()
    for requirement, named in (
        ('"torch==2.13.0"', "torch 2.13.0"),
        ('"torchrl>=0.14,<0.15"', "torchrl 0.14.x"),
        ('"tensordict>=0.14,<0.15"', "tensordict 0.14.x"),
    ):
        assert requirement in pyproject and named in PINNED, (
            f"pyproject.toml's pin changed: update _private_apis.PINNED and re-check every private API "
            f"({requirement}, {named})"
        )
