"""GVGAIEnv refuses bad input at its boundary with one ValueError naming the culprit and the valid
choices: its constructor's arguments, and each step's actions (index or one-hot), before the
compiled tick, where a bad action played as another or aborted the interpreter."""

import math
from pathlib import Path

import numpy as np
import pytest
import torch
from tensordict import TensorDict

from gvgai_pcg.envs import GVGAIEnv, LevelSource
from gvgai_pcg.envs.inputs import ActionCheck
from gvgai_pcg.levels import human_level

ZELDA_ACTIONS = 6


@pytest.fixture(scope="module")
def zelda():
    env = GVGAIEnv("zelda", num_envs=1, seed=0)
    env.reset()
    return env


def step(env, action):
    return env.step(TensorDict({"action": action}, batch_size=[env.num_envs]))


@pytest.mark.parametrize(
    "action, named",
    [
        (torch.tensor([6]), "invalid actions [6] in envs [0]"),
        (torch.tensor([-1]), "invalid actions [-1] in envs [0]"),
        (torch.tensor([2**40]), f"invalid actions [{2**40}]"),
        (torch.tensor([255], dtype=torch.uint8), "invalid actions [255]"),
        (torch.tensor([1.7]), "dtype torch.float32"),
        (torch.tensor([math.nan]), "dtype torch.float32"),
        (torch.tensor([True]), "dtype torch.bool"),
        (torch.tensor([[1, 2]]), "shape [1, 2]"),
        (torch.tensor([[0, 1, 1, 0, 0, 0]]), "do not hold exactly one 1"),
        (torch.tensor([[0, 2, 0, 0, 0, 0]]), "do not hold exactly one 1"),
    ],
)
def test_a_bad_action_is_refused_naming_it_and_the_valid_range(zelda, action, named):
    before = zelda.state.get("tick").clone()
    with pytest.raises(ValueError, match="expected an action index per env in 0..5") as error:
        step(zelda, action)
    assert named in str(error.value) and "\n" not in str(error.value)
    assert torch.equal(zelda.state.get("tick"), before)  # nothing was played


def test_every_bad_env_is_named_and_a_long_list_is_cut():
    check = ActionCheck(20, tuple("abcdef"), torch.device("cpu"))
    action = torch.zeros(20, dtype=torch.int64)
    action[[3, 7]] = torch.tensor([9, -2])
    with pytest.raises(ValueError, match=r"invalid actions \[9, -2\] in envs \[3, 7\] \(of 20\)"):
        check(action)
    with pytest.raises(ValueError, match=r"in envs \[0, 1, 2, 3, 4, 5, 6, 7, \.\.\. 12 more\] \(of 20\)"):
        check(torch.full((20,), 6))


def test_index_and_one_hot_actions_play_alike():
    index_env, hot_env = GVGAIEnv("zelda", seed=3), GVGAIEnv("zelda", seed=3)
    index_env.reset(), hot_env.reset()
    for action in (2, 4, 1, 0, 5, 3, 2, 2):
        index = torch.tensor([[action]], dtype=torch.int32)  # [B, 1], another integer dtype
        one_hot = torch.nn.functional.one_hot(torch.tensor([action]), ZELDA_ACTIONS).bool()
        a, b = step(index_env, index).get("next"), step(hot_env, one_hot).get("next")
        assert torch.equal(a.get("tiles"), b.get("tiles")) and torch.equal(a.get("score"), b.get("score"))
    assert index_env.state.get("tick").item() == 8


def test_the_range_check_can_be_turned_off():
    check = ActionCheck(2, tuple("abcdef"), torch.device("cpu"), strict=False)
    assert check(torch.tensor([7, 1])).tolist() == [7, 1]
    with pytest.raises(ValueError, match="dtype torch.float32"):  # the shape and dtype still are
        check(torch.tensor([1.0, 2.0]))


@pytest.mark.parametrize("num_envs", [1, pytest.param(2, marks=pytest.mark.slow)])  # 2: compiled
def test_boulderdash_out_of_range_raises_where_it_aborted_the_interpreter(num_envs):
    env = GVGAIEnv("boulderdash", num_envs=num_envs, seed=0)
    env.reset()
    with pytest.raises(ValueError, match=r"invalid actions \[99(, 99)?\] in envs \[0(, 1)?\]"):
        step(env, torch.full((num_envs,), 99))
    env.rand_step()  # the env goes on


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"num_envs": 2.5}, "num_envs must be an integer >= 1, got 2.5"),
        ({"num_envs": 0}, "num_envs must be an integer >= 1, got 0"),
        ({"num_envs": True}, "num_envs must be an integer >= 1, got True"),
        ({"max_steps": 0}, "max_steps must be an integer >= 1"),
        ({"shards": "2"}, "shards must be an integer >= 1, got '2'"),
        ({"difficulty": 2.0}, r"difficulty must be a number in \[0, 1\], got 2.0"),
        ({"difficulty": math.nan}, r"difficulty must be a number in \[0, 1\], got nan"),
        ({"device": "tpu"}, "device 'tpu' is not a device; valid devices here are: cpu"),
        ({"levels": "humans"}, "levels: 'humans' is no level file or folder, nor a level name; levels takes"),
        ({"levels": []}, "levels is an empty list; levels takes"),
        ({"levels": 3}, "levels=3 is not a choice of levels; levels takes"),
        ({"seed": 1.5}, "seed must be an int or a list of 1 ints, got 1.5"),
        ({"num_envs": 2, "seed": [1]}, "got 1 seeds for 2 envs"),
    ],
)
def test_a_bad_argument_is_one_value_error_naming_it(kwargs, message):
    with pytest.raises(ValueError, match=message) as error:
        GVGAIEnv("zelda", **kwargs)
    assert "\n" not in str(error.value)


@pytest.mark.skipif(torch.cuda.is_available(), reason="CUDA is present here")
def test_cuda_without_cuda_names_the_devices_there_are():
    with pytest.raises(
        ValueError, match="device 'cuda' is not available on this machine; valid devices here"
    ):
        GVGAIEnv("zelda", device="cuda")


def test_levels_names_what_it_takes_and_takes_a_folder(tmp_path: Path):
    with pytest.raises(ValueError, match='"human" .* a folder of level files, a Level, a list of these'):
        GVGAIEnv("zelda", levels="humans")
    for i in (1, 2):
        (tmp_path / f"room{i}.txt").write_text(str(human_level("zelda", i)))
    env = GVGAIEnv("zelda", levels=tmp_path)
    assert sorted(lv.name for lv in env.level_source.levels) == ["room1", "room2"]
    assert GVGAIEnv("zelda", levels=str(tmp_path / "room1.txt")).level_source.level.name == "room1"


def test_good_arguments_of_other_types_are_taken():
    env = GVGAIEnv("zelda", num_envs=np.int64(1), difficulty=1, device=torch.device("cpu"))
    assert env.num_envs == 1 and env.reset().get("difficulty").tolist() == [[1.0]]


class OneLevel:
    """A level source of the old one-method contract: ``game`` and ``next_levels``, no base class."""

    game = "zelda"

    def next_levels(self, env_indices, episode_seeds, difficulties):
        return [human_level("zelda", 0)] * len(env_indices)


def test_a_source_that_does_not_subclass_level_source_is_refused_in_one_line():
    with pytest.raises(
        ValueError, match="is not a choice of levels; .* a subclass of gvgai_pcg.envs.LevelSource"
    ):
        GVGAIEnv("zelda", levels=OneLevel())


def test_a_source_that_defines_only_next_levels_plays_with_the_declared_defaults():
    class Declared(OneLevel, LevelSource):  # the old source, now subclassing the base
        pass

    source = Declared()
    assert (source.prepare_ahead, source.depends_on_difficulty, source.levels_recur) == (False, False, True)
    assert source.level_difficulties is source.observe is source.trains_on is source.between_updates is None
    env = GVGAIEnv("zelda", num_envs=2, levels=source, difficulty=0.25)
    out = env.reset()
    assert env._prepared_resets is None and [lv.name for lv in env.current_levels] == ["zelda_lvl0"] * 2
    assert out["level_difficulty"].flatten().tolist() == [0.25, 0.25]


def test_a_source_without_next_levels_cannot_be_made():
    class Empty(LevelSource):
        game = "zelda"

    with pytest.raises(TypeError, match="Empty"):
        Empty()
