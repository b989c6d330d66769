"""Misuse of the delegation layer (expected failures are results, e.g. a refusal)."""

from hdrc3_base.errors import Hdrc3Error


class DelegationError(Hdrc3Error):
    """The delegation layer was misused (e.g. signing another agent's message)."""
