"""Shipped world files (``<name>.toml``); see README.md in this directory for the format."""
