"""DriverLog (IPC-2002, numeric): domain; the STRIPS control rules apply unchanged."""
