"""Network namespaces a test creates for itself: one per party, joined by a bridge (issue 17).

Each party gets its own namespace with loopback and one veth interface (10.213.<n>.<i>/24)
whose peer sits on a bridge in a namespace of its own, so nothing the parties send can leave
the test's network; :meth:`Network.cut` takes one party's link down (a partition) and
:meth:`Network.heal` brings it back. Everything is deleted on exit.
"""

from __future__ import annotations

import itertools
import os
import shutil
import subprocess
from collections.abc import Sequence
from types import TracebackType

_serial = itertools.count()


def available() -> str:
    """ "" when this process may create namespaces, else why not."""
    if shutil.which("ip") is None:
        return "iproute2's ip command is missing"
    if os.geteuid() != 0:
        return "creating network namespaces needs root"
    return ""


def _ip(*args: str) -> None:
    subprocess.run(["ip", *args], check=True, capture_output=True, timeout=30)


class Network:
    """Namespaces ``<tag><party>`` for each party and ``<tag>br`` for the bridge."""

    def __init__(self, parties: Sequence[str]) -> None:
        serial = next(_serial)
        self.tag = f"hd{os.getpid() % 10000}{serial}"
        self.subnet = 10 + (os.getpid() + serial) % 200
        self.parties = tuple(parties)
        self.created: list[str] = []

    def namespace(self, party: str) -> str:
        """The namespace of a party."""
        return f"{self.tag}{party}"

    def prefix(self, party: str) -> list[str]:
        """Command prefix that runs a program inside the party's namespace."""
        return ["ip", "netns", "exec", self.namespace(party)]

    def address(self, party: str) -> str:
        """The party's address on the test network."""
        return f"10.213.{self.subnet}.{self.parties.index(party) + 1}"

    def _link(self, party: str, side: str) -> str:
        return f"{self.tag[-9:]}{self.parties.index(party)}{side}"

    def __enter__(self) -> Network:
        bridge = f"{self.tag}br"
        try:
            _ip("netns", "add", bridge)
            self.created.append(bridge)
            _ip("-n", bridge, "link", "add", "br0", "type", "bridge")
            _ip("-n", bridge, "link", "set", "br0", "up")
            for party in self.parties:
                ns, inside, outside = (
                    self.namespace(party),
                    self._link(party, "a"),
                    self._link(party, "b"),
                )
                _ip("netns", "add", ns)
                self.created.append(ns)
                _ip("link", "add", inside, "type", "veth", "peer", "name", outside)
                _ip("link", "set", inside, "netns", ns)
                _ip("link", "set", outside, "netns", bridge)
                _ip("-n", bridge, "link", "set", outside, "master", "br0", "up")
                _ip("-n", ns, "addr", "add", f"{self.address(party)}/24", "dev", inside)
                _ip("-n", ns, "link", "set", inside, "up")
                _ip("-n", ns, "link", "set", "lo", "up")
                _ip("-n", ns, "route", "add", "224.0.0.0/4", "dev", inside)  # DDS discovery
        except BaseException:
            self._delete()
            raise
        return self

    def cut(self, party: str) -> None:
        """Partition: the party's link to the bridge goes down."""
        _ip("-n", f"{self.tag}br", "link", "set", self._link(party, "b"), "down")

    def heal(self, party: str) -> None:
        """The party's link comes back."""
        _ip("-n", f"{self.tag}br", "link", "set", self._link(party, "b"), "up")

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        """Delete every namespace (and with them the links)."""
        self._delete()

    def _delete(self) -> None:
        for ns in reversed(self.created):
            subprocess.run(["ip", "netns", "del", ns], capture_output=True, timeout=30)
        self.created.clear()
