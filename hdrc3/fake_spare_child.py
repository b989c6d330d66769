"""A stand-in node entry point for the tests of the warm spare (:mod:`hdrc3.warm_spare`).

``hdrc3.fake_spare_child:main`` with argv ``[exe, CODE|wait, OUT]`` writes what the node
sees (argv, ``HDRC3_PROBE``, whether it leads its own session, its parent) to the file OUT as
JSON, then exits with CODE, or for ``wait`` waits for SIGINT and exits 0.
"""

from __future__ import annotations

import json
import os
import signal
import sys
from pathlib import Path


def main() -> int:
    """Report, then exit or wait (see the module docstring)."""
    _, what, out = sys.argv
    # held until sigwait, whatever the inherited disposition (a shell's background job, a pytest
    # worker, ignore SIGINT): the nodes install their own handlers the same way
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    seen = {
        "argv": sys.argv,
        "probe": os.environ.get("HDRC3_PROBE", ""),
        "leader": os.getsid(0) == os.getpid(),
        "parent": os.getppid(),
    }
    Path(out + ".tmp").write_text(json.dumps(seen))
    Path(out + ".tmp").replace(out)
    if what != "wait":
        return int(what)
    signal.sigwait({signal.SIGINT})
    return 0
