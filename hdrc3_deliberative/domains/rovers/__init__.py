"""Rovers (IPC-2002, STRIPS): domain and TALplanner control rules."""
