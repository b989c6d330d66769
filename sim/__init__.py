"""Simulated world for hdrc3: RMAX flight model, YACS emulation, world, sensors (pure cores)."""
