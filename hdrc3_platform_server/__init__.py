"""Platform Server (chapter section 6.2): FCL/PPCL command layer, DRC automaton, Data Interface.

The pure core (everything except :mod:`hdrc3_platform_server.node`) never imports rclpy.
"""
