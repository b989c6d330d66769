"""ZenoTravel (IPC-2002, numeric): domain and control rules."""
