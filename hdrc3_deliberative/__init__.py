"""Deliberative layer (§9): TAL-based TALplanner with control formulas."""
