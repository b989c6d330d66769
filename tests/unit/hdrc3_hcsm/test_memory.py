from __future__ import annotations

import pytest

from hdrc3_hcsm.errors import BindingError
from hdrc3_hcsm.memory import ActionFlags, MemoryBank


def test_slots_start_empty_and_respect_sizes() -> None:
    bank = MemoryBank({"A-DO": 4}, cache_size=8)
    assert bank.slots() == ("A-DO", "cache")
    assert bank.read("A-DO") == b"" and bank.cache == b""
    bank.write("A-DO", b"1234")
    assert bank.read("A-DO") == b"1234"
    assert not bank.fits("A-DO", b"12345")
    with pytest.raises(ValueError, match="do not fit"):
        bank.write("A-DO", b"12345")
    bank.commit(b"xy", {"A-DO": b"z"})
    assert (bank.cache, bank.read("A-DO")) == (b"xy", b"z")


@pytest.mark.parametrize("call", ["read", "size"])
def test_unknown_slot_is_misuse(call: str) -> None:
    with pytest.raises(BindingError):
        getattr(MemoryBank({}), call)("Nope-DO")


def test_flags_are_triggers_cleared_each_iteration() -> None:
    flags = ActionFlags(["A-AC", "B-AC"])
    flags.raise_flag("A-AC")
    assert flags.is_set("A-AC") and not flags.is_set("B-AC")
    assert flags.active() == {"A-AC"}
    flags.clear()
    assert flags.active() == frozenset()
    with pytest.raises(BindingError):
        flags.raise_flag("C-AC")


def test_cache_holds_the_largest_slot() -> None:
    assert MemoryBank({"Big-DO": 9000}, cache_size=4096).size("cache") == 9000
    assert MemoryBank({}, cache_size=16).size("cache") == 16
