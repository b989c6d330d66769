"""TST exceptions: misuse of the API (expected failures are result values with a status)."""

from __future__ import annotations

from hdrc3_base.errors import Hdrc3Error


class TstError(Hdrc3Error):
    """A TST API was misused: an unknown node or parameter, a value of the wrong type."""
