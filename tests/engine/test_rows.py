"""Row copies through wide views give exactly what ``index_copy_`` and ``td[index]`` give."""

import pytest
import torch
from tensordict import TensorDict

from gvgai_pcg.engine import rows
from gvgai_pcg.engine.rows import copy_rows, copy_tensor_rows_, select_rows, wide_rows

SHAPES = [(), (1,), (3,), (5,), (8,), (195,), (11, 28), (11, 11, 28), (0,), (3, 0)]
DTYPES = [torch.bool, torch.uint8, torch.int16, torch.int32, torch.int64, torch.float32]


def random_rows(rows: int, shape: tuple, dtype: torch.dtype, generator: torch.Generator) -> torch.Tensor:
    values = torch.randint(0, 100, (rows, *shape), generator=generator)
    return (values % 2 == 1) if dtype == torch.bool else values.to(dtype)


@pytest.mark.parametrize("shape", SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("small_copy_bytes", [0, rows.SMALL_COPY_BYTES])  # 0: every copy viewed wide
def test_row_copies_equal_index_copy(shape, dtype, small_copy_bytes, monkeypatch):
    monkeypatch.setattr(rows, "SMALL_COPY_BYTES", small_copy_bytes)
    generator = torch.Generator().manual_seed(len(shape) * 7 + DTYPES.index(dtype))
    target = random_rows(40, shape, dtype, generator)
    source = random_rows(9, shape, dtype, generator)
    index = torch.randperm(40, generator=generator)[:9]
    expected = target.clone().index_copy_(0, index, source)
    assert copy_tensor_rows_(target, index, source) is target
    assert torch.equal(target, expected)


def test_wide_rows_share_memory_with_the_widest_type_that_divides_a_row():
    tiles = torch.zeros(4, 11, 11, 28, dtype=torch.uint8)  # 3,388 bytes a row: int32
    wide = wide_rows(tiles)
    assert wide.dtype == torch.int32 and wide.shape == (4, 847)
    wide[1] = -1
    assert tiles[1].eq(255).all() and tiles[0].eq(0).all()
    assert wide_rows(torch.zeros(4, 5, dtype=torch.bool)).dtype == torch.bool  # odd: stays as it is
    assert wide_rows(torch.zeros(4, 2, dtype=torch.int32)).dtype == torch.int64
    assert wide_rows(torch.zeros(4, 3, dtype=torch.float32)).dtype == torch.float32


def test_a_non_contiguous_target_is_copied_as_it_is():
    target = torch.zeros(6, 8, dtype=torch.uint8)[:, ::2]
    copy_tensor_rows_(target, torch.tensor([4, 1]), torch.full((2, 4), 3, dtype=torch.uint8))
    assert target[:, 0].tolist() == [0, 3, 0, 0, 3, 0]


def nested_state(batch: int) -> TensorDict:
    generator = torch.Generator().manual_seed(batch)
    table = TensorDict(
        {"x": torch.randint(0, 9, (batch, 7), generator=generator), "alive": torch.rand(batch, 7) > 0.5},
        batch_size=[batch, 7],
    )
    return TensorDict(
        {"grid": torch.rand(batch, 3, 5) > 0.5, "score": torch.arange(batch), "logs": table},
        batch_size=[batch],
    )


def test_select_rows_equals_tensordict_indexing():
    state, index = nested_state(12), torch.tensor([11, 0, 5, 5])
    picked = select_rows(state, index)
    assert picked.batch_size == (4,) and picked.get("logs").batch_size == (4, 7)
    assert (picked == state[index]).all()


def test_copy_rows_equals_indexed_assignment():
    target, source, index = nested_state(12), nested_state(3), torch.tensor([2, 9, 4])
    expected = target.clone()
    expected[index] = source
    copy_rows(target, source, index)
    assert (target == expected).all()
