"""`hdrc3 launch` as a child process of a command that flies a mission (demo, ``tst run``).

The launch's output is echoed (indented) until it prints READY; leaving the context stops it
with SIGINT, as a user's Ctrl-C would, and echoes the rest of its output.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from types import TracebackType

from hdrc3_base.errors import ConfigError

READY_TIMEOUT_S = 120.0
STOP_TIMEOUT_S = 60.0


class LaunchedSystem:
    """Starts ``hdrc3 launch`` with the given options; a context manager."""

    def __init__(
        self,
        agents: Sequence[str],
        world: str,
        speed: str,
        domain_id: int,
        record: Path | None = None,
        nodes: Sequence[str] = (),
        log: Callable[[str], None] = print,
        seed: int = 0,
        extra: Sequence[str] = (),
    ) -> None:
        """Prepare the command line (``nodes`` empty: the launcher's default nodes).

        ``extra``: more ``hdrc3 launch`` arguments (e.g. ``--keystore FILE``).
        """
        hdrc3 = str(Path(sys.executable).parent / "hdrc3")
        self.command = [hdrc3, "launch", "--agents", ",".join(agents), "--world", world]
        self.command += ["--speed", speed, "--domain-id", str(domain_id), "--seed", str(seed)]
        if record is not None:
            self.command += ["--record", str(record)]
        if nodes:
            self.command += ["--nodes", ",".join(nodes)]
        self.command += list(extra)
        self.domain_id = domain_id
        self.returncode: int | None = None
        self._log = log
        self._launch: subprocess.Popen[str] | None = None

    def __enter__(self) -> LaunchedSystem:
        """Start the launch and wait for READY (ConfigError if it does not come up)."""
        os.environ["ROS_DOMAIN_ID"] = str(self.domain_id)
        self._log(f"$ {' '.join(self.command)}")
        self._launch = subprocess.Popen(
            self.command,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            env=dict(os.environ, PYTHONUNBUFFERED="1"),
        )
        try:
            self._wait_ready()
        except BaseException:
            self._stop()
            raise
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        """Stop the launch."""
        self._stop()

    def _wait_ready(self) -> None:
        assert self._launch is not None and self._launch.stdout is not None
        deadline = time.monotonic() + READY_TIMEOUT_S
        for line in self._launch.stdout:
            self._log(f"  | {line.rstrip()}")
            if "READY" in line:
                return
            if time.monotonic() > deadline:
                break
        raise ConfigError("the system did not come up; see the launcher output above")

    def _stop(self) -> None:
        launch = self._launch
        if launch is None or self.returncode is not None:
            return
        if launch.poll() is None:
            launch.send_signal(signal.SIGINT)
        try:
            remaining, _ = launch.communicate(timeout=STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            launch.kill()
            remaining, _ = launch.communicate()
        for line in remaining.splitlines():
            self._log(f"  | {line}")
        self.returncode = launch.returncode
