"""The compiled tick's benchmark splits an env step (its numbers are never asserted)."""

from gvgai_pcg.bench import compiled


def test_an_eager_env_step_has_no_compiled_call_in_its_split():
    split = compiled.step_split("zelda", 3, steps=5)  # the tick is eager here (conftest)
    assert split.step > 0 and split.compiled_call == 0 and split.guards == 0
