"""JSBSim aircraft definitions shipped as package data (``<name>.xml`` beside this file)."""
