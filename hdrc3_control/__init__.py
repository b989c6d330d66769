"""Control layer of the HDRC3 chapter (section 5): flight control functions and state estimation.

Pure core, no rclpy. The ``control_kernel`` node maps ``commands.AttitudeCommand`` to the YACS
interface and feeds ``state_estimator.StateEstimator`` from sensor messages; every control
function takes a ``commands.EstimatedState`` and the sim time per 50 Hz tick and returns a command
plus an enum status. ``template.py`` adapts them to the HCSM control-function template.
"""
