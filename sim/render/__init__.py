"""Colour and thermal image rendering of the simulated world (moderngl on Mesa/EGL)."""
