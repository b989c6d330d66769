"""hdrc3: the HDRC3 autonomy architecture for unmanned helicopters on ROS 2 Jazzy."""

__version__ = "0.1.0"
