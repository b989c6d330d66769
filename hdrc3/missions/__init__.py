"""Mission files of ``hdrc3 demo`` (TALF, chapter section 9.4)."""
