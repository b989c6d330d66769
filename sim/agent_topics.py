"""Publishers of one agent's namespace in world_sim: sensor samples and ground truth as messages.

Standard messages where they fit (``sensor_msgs/Imu``, ``NavSatFix``, ``TwistStamped``,
``nav_msgs/Odometry``), ``hdrc3_interfaces`` messages elsewhere. Messages are built once and
mutated per sample (rclpy serialises on publish), and a topic nobody subscribes to is skipped.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from geometry_msgs.msg import PoseStamped, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node
from rclpy.qos import QoSProfile
from sensor_msgs.msg import Imu, NavSatFix, NavSatStatus

from hdrc3_base.stamps import set_stamp_ns
from hdrc3_interfaces.msg import (
    Attitude,
    Barometer,
    CameraState,
    GroundContact,
    PowerStatus,
    PtuState,
    RadiationDose,
    RotatingLaserScan,
    RotorRpm,
    TruthState,
    YacsStatus,
)
from sim.odometry import flu_odometry
from sim.render.camera_feed import pose_to_ros
from sim.sensors.camera import CameraFrame
from sim.sensors.gps import GpsParams
from sim.sensors.suite import SensorReadings
from sim.truth_state import TruthState as Truth


def stamp_header(header: Any, ns: int) -> None:
    """Stamp a std_msgs/Header with integer nanoseconds of sim time."""
    set_stamp_ns(header.stamp, ns)


def _ns(seconds: float) -> int:
    return round(seconds * 1e9)


class AgentTopics:
    """Publishers (and reusable messages) of one agent's namespace."""

    def __init__(self, node: Node, agent: str, qos: QoSProfile, imu_qos: QoSProfile) -> None:
        """Create every publisher under ``/<agent>`` (``imu_qos`` for the 200 Hz IMU)."""
        ns = f"/{agent}"
        pub = node.create_publisher
        self.gps_fix = pub(NavSatFix, f"{ns}/sensors/gps/fix", qos)
        self.gps_velocity = pub(TwistStamped, f"{ns}/sensors/gps/velocity", qos)
        self.imu = pub(Imu, f"{ns}/sensors/imu", imu_qos)
        self.barometer = pub(Barometer, f"{ns}/sensors/barometer", qos)
        self.attitude = pub(Attitude, f"{ns}/sensors/attitude", qos)
        self.rpm = pub(RotorRpm, f"{ns}/sensors/rpm", qos)
        self.ground_contact = pub(GroundContact, f"{ns}/sensors/ground_contact", qos)
        self.power = pub(PowerStatus, f"{ns}/sensors/power", qos)
        self.ptu = pub(PtuState, f"{ns}/sensors/ptu", qos)
        self.color_camera = pub(CameraState, f"{ns}/sensors/color_camera", qos)
        self.thermal_camera = pub(CameraState, f"{ns}/sensors/thermal_camera", qos)
        # the pose each frame was exposed at (ground truth, for world_render)
        self.color_pose = pub(PoseStamped, f"{ns}/ground_truth/color_camera_pose", qos)
        self.thermal_pose = pub(PoseStamped, f"{ns}/ground_truth/thermal_camera_pose", qos)
        self.laser = pub(RotatingLaserScan, f"{ns}/sensors/laser", qos)
        self.radiation = pub(RadiationDose, f"{ns}/sensors/radiation", qos)
        self.status = pub(YacsStatus, f"{ns}/yacs/status", qos)
        self.odometry = pub(Odometry, f"{ns}/ground_truth/odometry", qos)
        self.truth = pub(TruthState, f"{ns}/ground_truth/state", qos)
        self.command_topic = f"{ns}/yacs/command"
        # reusable messages: rclpy serialises on publish, so mutating them afterwards is safe
        self.m_fix = NavSatFix()
        self.m_fix.header.frame_id = f"{agent}/gps"
        self.m_fix.status.status = NavSatStatus.STATUS_FIX
        self.m_fix.status.service = NavSatStatus.SERVICE_GPS
        gps = GpsParams()
        h = gps.horizontal_sigma**2 + gps.white_position_sigma**2
        v = gps.vertical_sigma**2 + gps.white_position_sigma**2
        self.m_fix.position_covariance = [h, 0.0, 0.0, 0.0, h, 0.0, 0.0, 0.0, v]
        self.m_fix.position_covariance_type = NavSatFix.COVARIANCE_TYPE_APPROXIMATED
        self.m_vel = TwistStamped()
        self.m_vel.header.frame_id = "world_enu"
        self.m_imu = Imu()
        self.m_imu.header.frame_id = f"{agent}/base_link_frd"
        self.m_imu.orientation_covariance[0] = -1.0  # no orientation estimate
        self.m_baro = Barometer()
        self.m_att = Attitude()
        self.m_rpm = RotorRpm()
        self.m_ground = GroundContact()
        self.m_power = PowerStatus()
        self.m_ptu = PtuState()
        self.m_cam = CameraState()
        self.m_pose = PoseStamped()
        self.m_pose.header.frame_id = "world_enu"
        self.m_laser = RotatingLaserScan()
        self.m_radiation = RadiationDose()
        self.m_status = YacsStatus()
        self.m_odom = Odometry()
        self.m_odom.header.frame_id = "world_enu"
        self.m_odom.child_frame_id = f"{agent}/base_link"
        self.m_truth = TruthState()
        self.m_truth.header.frame_id = "world_enu"
        self.last_exposure_ns: int | None = None
        """Stamp of the newest exposure pose published (None: none yet, or nobody listens)."""

    def publish_readings(self, readings: Sequence[SensorReadings], poses: bool = True) -> None:
        """Publish every sample of ``readings``: :meth:`publish_control`, then the payload's."""
        self.publish_control(readings)
        self.publish_payload(readings, poses)

    def publish_control(self, readings: Sequence[SensorReadings]) -> None:
        """The samples the control kernel reads (time order), those somebody subscribes to.

        IMU, attitude, ground contact, GPS, barometer, rotor rpm, power: world_sim publishes
        them before ``/clock`` and the payload's after it (:meth:`publish_payload`), so that the
        lockstepped controller already computes while the rest goes out.
        Building and publishing a message costs 10-40 us; topics nobody listens to are
        skipped. ``get_subscription_count`` costs < 1 us.
        """
        imu = self.imu.get_subscription_count() > 0
        attitude = self.attitude.get_subscription_count() > 0
        ground = self.ground_contact.get_subscription_count() > 0
        for r in readings:
            if r.imu is not None and imu:
                m = self.m_imu
                stamp_header(m.header, _ns(r.imu.time))
                f, w = r.imu.specific_force, r.imu.angular_rate
                a = m.linear_acceleration
                a.x, a.y, a.z = f
                g = m.angular_velocity
                g.x, g.y, g.z = w
                self.imu.publish(m)
            if r.attitude is not None and attitude:
                m = self.m_att
                stamp_header(m.header, _ns(r.attitude.time))
                m.roll, m.pitch, m.heading = r.attitude.roll, r.attitude.pitch, r.attitude.heading
                self.attitude.publish(m)
            if r.ground_contact is not None and ground:
                m = self.m_ground
                stamp_header(m.header, _ns(r.ground_contact.time))
                m.on_ground = r.ground_contact.on_ground
                self.ground_contact.publish(m)
            if r.gps is not None:
                self._gps(r)
            if r.barometer is not None and self.barometer.get_subscription_count():
                m = self.m_baro
                stamp_header(m.header, _ns(r.barometer.time))
                m.altitude, m.pressure = r.barometer.altitude, r.barometer.pressure
                self.barometer.publish(m)
            if r.rpm is not None and self.rpm.get_subscription_count():
                m = self.m_rpm
                stamp_header(m.header, _ns(r.rpm.time))
                m.rpm = r.rpm.rpm
                self.rpm.publish(m)
            if r.power is not None and self.power.get_subscription_count():
                m = self.m_power
                stamp_header(m.header, _ns(r.power.time))
                m.status, m.voltage, m.current = r.power.status, r.power.voltage, r.power.current
                self.power.publish(m)

    def publish_payload(self, readings: Sequence[SensorReadings], poses: bool = True) -> None:
        """The payload's samples (time order): PTU, cameras and their poses, laser, radiation.

        ``poses`` False skips the exposures' poses (``ground_truth/<camera>_camera_pose``):
        world_sim publishes them only while world_render runs. A recorder subscribing to every
        topic would otherwise make a run without cameras pay for them (a rotation matrix to a
        quaternion and a message per exposure, ~7 % of world_sim's CPU in the basic demo).
        """
        for r in readings:
            if r.ptu is not None and self.ptu.get_subscription_count():
                m = self.m_ptu
                stamp_header(m.header, _ns(r.ptu.time))
                m.pan, m.tilt = r.ptu.pan, r.ptu.tilt
                self.ptu.publish(m)
            for frame, publisher, pose_publisher in (
                (r.color_camera, self.color_camera, self.color_pose),
                (r.thermal_camera, self.thermal_camera, self.thermal_pose),
            ):
                if frame is not None and publisher.get_subscription_count():
                    m = self.m_cam
                    stamp_header(m.header, _ns(frame.time))
                    m.id = frame.camera.value
                    m.pan, m.tilt, m.zoom = frame.pan, frame.tilt, frame.zoom
                    m.ipc_time = m.header.stamp
                    publisher.publish(m)
                if frame is not None and poses and pose_publisher.get_subscription_count():
                    self._camera_pose(frame, pose_publisher)
            if r.laser is not None and self.laser.get_subscription_count():
                self._laser(r)
            if r.radiation is not None and self.radiation.get_subscription_count():
                m = self.m_radiation
                stamp_header(m.header, _ns(r.radiation.time))
                m.dose_rate, m.counts = r.radiation.dose_rate, r.radiation.counts
                m.integration_time = r.radiation.integration_time
                self.radiation.publish(m)

    def _camera_pose(self, frame: CameraFrame, publisher: Any) -> None:
        m = self.m_pose
        self.last_exposure_ns = _ns(frame.time)
        stamp_header(m.header, self.last_exposure_ns)
        position, quat = pose_to_ros(frame.pose)
        p, q = m.pose.position, m.pose.orientation
        p.x, p.y, p.z = position
        q.x, q.y, q.z, q.w = quat
        publisher.publish(m)

    def _gps(self, r: SensorReadings) -> None:
        assert r.gps is not None
        s = r.gps
        ns = _ns(s.time)
        if self.gps_fix.get_subscription_count():
            m = self.m_fix
            stamp_header(m.header, ns)
            m.latitude, m.longitude, m.altitude = s.latitude, s.longitude, s.altitude
            self.gps_fix.publish(m)
        if self.gps_velocity.get_subscription_count():
            v = self.m_vel
            stamp_header(v.header, ns)
            lin = v.twist.linear
            lin.x, lin.y, lin.z = s.velocity_enu
            self.gps_velocity.publish(v)

    def _laser(self, r: SensorReadings) -> None:
        assert r.laser is not None
        s = r.laser
        m = self.m_laser
        stamp_header(m.header, _ns(s.time))
        m.rotation_angle = s.rotation_angle
        beams = s.beam_angles
        m.angle_min = beams[0]
        m.angle_increment = (beams[-1] - beams[0]) / max(1, len(beams) - 1)
        m.range_max = 80.0
        m.ranges = [float(x) for x in s.ranges]
        self.laser.publish(m)

    def publish_truth(self, truth: Truth, ns: int) -> None:
        """Ground truth at tick time ``ns``: TruthState and nav_msgs/Odometry (if subscribed)."""
        m = self.m_truth
        stamp_header(m.header, ns)
        if self.truth.get_subscription_count():
            self._truth_state(truth)
        if self.odometry.get_subscription_count():
            self._odometry(truth)

    def _truth_state(self, truth: Truth) -> None:
        m = self.m_truth
        m.position_enu = truth.position_enu
        m.velocity_enu = truth.velocity_enu
        m.roll, m.pitch, m.heading = truth.roll, truth.pitch, truth.heading
        m.body_rates = truth.body_rates
        m.specific_force_body = truth.specific_force_body
        m.rotor_rpm = truth.rotor_rpm
        m.engine_running = truth.engine_running
        m.on_ground = truth.on_ground
        m.height_above_ground = truth.height_above_ground
        m.mass = truth.mass
        self.truth.publish(m)

    def _odometry(self, truth: Truth) -> None:
        o = self.m_odom
        m = self.m_truth
        o.header.stamp = m.header.stamp
        odo = flu_odometry(truth)
        p = o.pose.pose.position
        p.x, p.y, p.z = truth.position_enu
        q = o.pose.pose.orientation
        q.x, q.y, q.z, q.w = odo.orientation
        lin = o.twist.twist.linear
        lin.x, lin.y, lin.z = odo.linear
        ang = o.twist.twist.angular
        ang.x, ang.y, ang.z = odo.angular
        self.odometry.publish(o)
