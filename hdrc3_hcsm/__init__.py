"""Hierarchical Concurrent State Machines (chapter 6.1): language, interpreter, tooling."""
