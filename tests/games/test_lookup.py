"""Constant lookup tables shared by the games."""

import torch

from gvgai_pcg.games.lookup import constant_table, lookup


def test_lookup_is_values_at_the_codes_in_the_asked_dtype():
    codes = torch.tensor([[2, 0], [1, 1]])
    assert lookup((5, -1, 7), codes).tolist() == [[7, 5], [-1, -1]]
    assert lookup((0.1, 0.4), torch.tensor([1, 0]), torch.float64).dtype == torch.float64
    assert lookup((1, 2), torch.tensor([1], dtype=torch.int32), torch.int32).dtype == torch.int32


def test_a_table_is_made_once_per_values_dtype_and_device():
    cpu = torch.device("cpu")
    assert constant_table((1, 2), torch.int64, cpu) is constant_table((1, 2), torch.int64, cpu)
    assert constant_table((1, 2), torch.int32, cpu) is not constant_table((1, 2), torch.int64, cpu)
