"""`hdrc3 keys generate FILE --agents gcs,uav0,...`: a keystore for authenticated speech acts.

The file gets one fresh random HMAC key per agent and mode 0600; every gateway and the
ground operator read it (``hdrc3 launch --keystore``, ``hdrc3 delegate --keystore``). The keys
are never printed. Exit codes: 0 written, 2 bad input (an agent name, an existing file).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from hdrc3_base.agents import parse_agents
from hdrc3_base.errors import ConfigError
from hdrc3_delegation.keystore import write_keystore


def register(subparsers: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    """Add the ``keys`` subcommand."""
    parser = subparsers.add_parser("keys", help="agent keys for authenticated delegation")
    actions = parser.add_subparsers(dest="keys_action", metavar="ACTION", required=True)
    generate = actions.add_parser("generate", help="write a new keystore (mode 0600)")
    generate.add_argument("file", help="the keystore to create, e.g. keys.toml")
    generate.add_argument(
        "--agents",
        default="gcs,uav0,uav1,uav2",
        help="agents to make keys for (default %(default)s)",
    )
    generate.add_argument("--force", action="store_true", help="overwrite an existing file")
    generate.set_defaults(handler=_generate)


def _generate(args: argparse.Namespace) -> int:
    path = Path(args.file)
    if path.exists() and not args.force:
        raise ConfigError(f"{path} exists; give --force to replace its keys")
    keystore = write_keystore(path, parse_agents(args.agents))
    print(f"{path}: keys for {', '.join(keystore.agents)} (mode 0600)", flush=True)
    return 0
