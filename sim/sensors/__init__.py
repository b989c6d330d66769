"""Simulated on-board sensors (HDRC3 chapter sections 4.2-4.3, 11.2) with fault switches.

Every sensor is a small object with a rate, ``reset(seed)`` and ``update(truth) -> sample | None``;
faults (drop, freeze, bias, noise-up) are injected through one shared :class:`FaultSwitch`.
"""
