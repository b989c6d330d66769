"""Memory bank with labelled slots, the ``cache`` slot, and the action flags (chapter 6.1).

Received event data lands in ``cache``; GET copies a slot into ``cache`` and PUT copies ``cache``
into a slot. Slots have fixed size limits like the chapter's predefined packets. The bank is
locked while the interpreter runs a macro step; other code takes the same lock to read or write.
"""

from __future__ import annotations

import threading
from collections.abc import Iterable, Mapping

from hdrc3_hcsm.errors import BindingError
from hdrc3_hcsm.model import CACHE

# The cache must hold the largest event payload the transport carries.
DEFAULT_CACHE_SIZE = 4096


class MemoryBank:
    """Labelled byte slots with size limits; all start empty."""

    def __init__(self, sizes: Mapping[str, int], cache_size: int = DEFAULT_CACHE_SIZE) -> None:
        self._sizes = dict(sizes)
        # GET copies any slot into the cache, so the cache must hold the largest slot.
        self._sizes[CACHE] = max(cache_size, *self._sizes.values(), 0)
        self._values: dict[str, bytes] = dict.fromkeys(self._sizes, b"")
        self.lock = threading.RLock()

    def slots(self) -> tuple[str, ...]:
        """Names of all slots, ``cache`` included."""
        return tuple(self._sizes)

    def size(self, slot: str) -> int:
        """Size limit of ``slot`` in bytes."""
        return self._sizes[self._known(slot)]

    def read(self, slot: str) -> bytes:
        """Return the current content of ``slot``."""
        return self._values[self._known(slot)]

    def fits(self, slot: str, data: bytes) -> bool:
        """Tell whether ``data`` fits into ``slot``."""
        return len(data) <= self._sizes[self._known(slot)]

    def write(self, slot: str, data: bytes) -> None:
        """Store ``data`` in ``slot``; raises ValueError if it does not fit (a misuse)."""
        if not self.fits(slot, data):
            raise ValueError(f"{len(data)} bytes do not fit slot {slot!r} of {self.size(slot)}")
        self._values[slot] = bytes(data)

    def commit(self, cache: bytes, writes: Mapping[str, bytes] | None) -> None:
        """Set the cache and store already size-checked slot values (the interpreter's commit)."""
        self._values[CACHE] = cache
        if writes:
            self._values.update(writes)

    @property
    def cache(self) -> bytes:
        """Content of the cache slot."""
        return self._values[CACHE]

    def _known(self, slot: str) -> str:
        if slot not in self._sizes:
            raise BindingError(f"unknown memory slot {slot!r}")
        return slot


class ActionFlags:
    """Binary action flags: set by SET actions, read by control functions, unset each iteration."""

    def __init__(self, names: Iterable[str]) -> None:
        self._names = frozenset(names)
        self._set: set[str] = set()

    def names(self) -> frozenset[str]:
        """All declared flag names."""
        return self._names

    def raise_flag(self, name: str) -> None:
        """Set flag ``name`` (what a ``SET`` action does)."""
        if name not in self._names:
            raise BindingError(f"unknown action flag {name!r}")
        self._set.add(name)

    def is_set(self, name: str) -> bool:
        """Tell whether flag ``name`` was set in this iteration."""
        return name in self._set

    def active(self) -> frozenset[str]:
        """Return the flags set in this iteration."""
        return frozenset(self._set)

    def clear(self) -> None:
        """Unset all flags (end of a main-loop iteration)."""
        self._set.clear()
