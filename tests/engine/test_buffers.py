"""The buffer pool hands a buffer out again only once nothing else refers to it."""

import numpy as np
import torch

from gvgai_pcg.engine.buffers import BufferPool


def address(tensor: torch.Tensor) -> int:
    return tensor.untyped_storage().data_ptr()


def test_a_released_buffer_is_reused():
    pool = BufferPool(min_bytes=0)
    first = pool.empty(1000, torch.uint8, "cpu")
    kept = address(first)
    del first
    assert address(pool.empty(1000, torch.uint8, "cpu")) == kept
    assert len(pool) == 1


def test_a_buffer_still_referred_to_is_not_handed_out():
    pool = BufferPool(min_bytes=0)
    views = pool.empty(1000, torch.uint8, "cpu").view(10, 100)[2:]  # only a view of a view is kept
    array = pool.empty(1000, torch.uint8, "cpu").numpy()
    third = pool.empty(1000, torch.uint8, "cpu")
    addresses = {address(views), array.__array_interface__["data"][0], address(third)}
    assert len(addresses) == 3 and len(pool) == 3
    views.fill_(7)
    assert isinstance(array, np.ndarray)
    del third
    again = pool.empty(1000, torch.uint8, "cpu")
    assert address(again) not in {address(views), array.__array_interface__["data"][0]}
    assert views.eq(7).all()


def test_sizes_and_types_are_not_mixed_and_old_buffers_go():
    pool = BufferPool(keep=2, min_bytes=0)
    small = address(pool.empty(10, torch.uint8, "cpu"))
    assert address(pool.empty(10, torch.int32, "cpu")) != small
    assert pool.empty(20, torch.uint8, "cpu").numel() == 20
    assert len(pool) == 2  # the oldest one was dropped


def test_clone_copies_into_a_pooled_buffer():
    pool = BufferPool(min_bytes=0)
    tensor = torch.arange(24).view(2, 3, 4)
    copy = pool.clone(tensor)
    assert torch.equal(copy, tensor) and copy.is_contiguous() and address(copy) != address(tensor)


def test_small_and_huge_requests_are_not_pooled():
    pool = BufferPool(min_bytes=4096, max_bytes=8192)
    assert pool.empty(1024, torch.uint8, "cpu").numel() == 1024
    assert pool.empty(4096, torch.int32, "cpu").numel() == 4096  # 16 KB
    assert len(pool) == 0
    pool.empty(1024, torch.int32, "cpu")  # 4 KB
    assert len(pool) == 1


def test_a_buffer_whose_storage_object_is_held_is_not_handed_out():
    pool = BufferPool(min_bytes=0)
    storage = pool.empty(1000, torch.uint8, "cpu").untyped_storage()  # only the storage is kept
    storage.fill_(7)
    again = pool.empty(1000, torch.uint8, "cpu")
    assert again.untyped_storage().data_ptr() != storage.data_ptr()
    again.fill_(0)
    assert storage[0] == 7
    del storage, again
    assert len(pool) == 2
    pool.empty(1000, torch.uint8, "cpu")
    assert len(pool) == 2  # released: one of them was reused


def test_a_buffer_moved_to_shared_memory_is_never_handed_out_again():
    """A tensor put on a torch.multiprocessing queue has its storage moved to shared memory,
    where the receiving process reads it whenever it likes."""
    pool = BufferPool(min_bytes=0)
    sent = pool.empty(1000, torch.uint8, "cpu")
    sent.share_memory_()
    shared = sent.untyped_storage().data_ptr()
    del sent
    assert address(pool.empty(1000, torch.uint8, "cpu")) != shared
    assert len(pool) == 1  # the shared buffer left the pool
