"""Recovery on the real node chain (chapter 9.3.1): a violation replans a running goal node.

uav0's ``tst_manager`` and ``task_planner`` run in-process on real DDS. The test node is the
aircraft's side: it publishes the helicopter state (airborne, autonomous) and serves
``fcl/traj3d_flyto`` (accepted; the flight never ends). A goal node is planned by TALplanner
into one fly-to; a ``MonitorViolation`` naming the running step is injected (a real fault
scenario needs the payload simulator); the manager must suspend the step, hover, apply the
operator, plan again through the ``task_planner`` service and publish every step as a
``RecoveryEvent``, then run the new plan's fly-to.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from tests.integration.ros_wait import answer, spin_until

pytestmark = pytest.mark.ros

WAIT_S = 60.0
MISSION = (
    "world revinge\nagents uav0\npoint Sq = town_square at 30\n"
    "m(P, TS, TE) = goal at(uav0, Sq) where P = uav0\n"
)


class Chain:
    """tst_manager + task_planner of uav0 and the aircraft's side, in one executor."""

    def __init__(self, context: Any) -> None:
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.node import Node
        from rclpy.parameter import Parameter
        from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

        from hdrc3_deliberative.task_planner_node import TaskPlannerNode
        from hdrc3_interfaces.msg import (
            FclReturn,
            HelicopterState,
            MonitorViolation,
            RecoveryEvent,
            TstNodeStatus,
        )
        from hdrc3_platform_server.codes import FclCommand
        from hdrc3_platform_server.commands import FCL
        from hdrc3_platform_server.geo_frame import frame_from_world
        from hdrc3_tst.node import TstManagerNode

        self.manager = TstManagerNode(context, namespace="/uav0")
        # no simulator: wall time, straight flights (no path_planner node in this chain)
        self.manager.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, False)])
        self.manager.navigation = None
        self.planner = TaskPlannerNode(context, namespace="/uav0")
        self.node = Node("recovery_test", context=context)
        self.executor = SingleThreadedExecutor(context=context)
        for node in (self.manager, self.planner, self.node):
            self.executor.add_node(node)
        self.events: list[Any] = []
        self.statuses: dict[str, str] = {}
        self.flights = 0
        reliable = QoSProfile(
            depth=100,
            reliability=ReliabilityPolicy.RELIABLE,
            durability=DurabilityPolicy.TRANSIENT_LOCAL,
        )
        self.node.create_subscription(
            RecoveryEvent, "/uav0/recovery_events", self.events.append, reliable
        )
        self.node.create_subscription(
            TstNodeStatus,
            "/uav0/tst_status",
            lambda m: self.statuses.__setitem__(m.node_id, m.state),
            reliable,
        )
        self.violations = self.node.create_publisher(
            MonitorViolation, "/uav0/monitor_violations", reliable
        )
        self.state_pub = self.node.create_publisher(HelicopterState, "/uav0/helicopter_state", 10)
        lon, lat, alt = frame_from_world("revinge").to_wgs84(-150.0, 0.0, 30.0)
        self.state = HelicopterState(longitude=lon, latitude=lat, altitude=alt, auto_flag=True)
        self.node.create_timer(0.05, lambda: self.state_pub.publish(self.state))

        def fly(request: Any, response: Any) -> Any:
            self.flights += 1
            response.result = FclReturn(code=FclReturn.FCL_OK, command_id=self.flights)
            return response

        self.node.create_service(
            FCL[FclCommand.TRAJ3D_FLYTO].service_type(), "/uav0/fcl/traj3d_flyto", fly
        )
        self.MonitorViolation = MonitorViolation
        self.RecoveryEvent = RecoveryEvent

    def call(self, name: str, **fields: Any) -> Any:
        import hdrc3_interfaces.srv as srv

        srv_type = getattr(srv, f"Tst{name.capitalize()}")
        client = self.node.create_client(srv_type, f"/uav0/tst_manager/{name}")
        assert client.wait_for_service(timeout_sec=WAIT_S), name
        # keyed commands: sent again until answered, run once
        response = answer(self.executor, client, srv_type.Request(**fields), WAIT_S)
        assert response is not None, f"no answer from {name}"
        self.node.destroy_client(client)
        return response

    def until(self, done: Any, what: str) -> None:
        assert spin_until(self.executor, done, WAIT_S), f"timed out waiting for {what}"


@pytest.fixture
def chain(ros_context: Any) -> Iterator[Chain]:
    made = Chain(ros_context)
    try:
        yield made
    finally:
        made.executor.shutdown()
        for node in (made.node, made.planner, made.manager):
            node.destroy_node()


def test_a_violation_of_the_running_step_replans_the_goal(chain: Chain) -> None:
    from hdrc3_interfaces.msg import TstReturn

    created = chain.call("create", mission="m", text=MISSION, file="m.tst", agents=["uav0"])
    assert created.result.code == TstReturn.TST_OK, created.result.reason
    chain.until(lambda: chain.manager.platform.state() is not None, "the helicopter state")
    executed = chain.call("execute", mission="m", node_id="m", epoch=float("nan"))
    assert executed.result.code == TstReturn.TST_OK, executed.result.reason
    chain.until(lambda: chain.flights == 1, "the planned fly-to")
    assert chain.statuses.get("m/1") == "running"

    v = chain.MonitorViolation
    chain.violations.publish(
        v(
            agent="uav0",
            monitor_id="held@m/1",
            kind=v.KIND_VIOLATION,
            action="fly-to",
            node_id="m/1",
            argument_names=["av"],
            argument_values=["uav0"],
            recovery="retry",
            emergency_brake=False,
        )
    )
    e = chain.RecoveryEvent
    chain.until(lambda: any(ev.step == e.STEP_REPLANNED for ev in chain.events), "the new plan")
    assert [ev.step for ev in chain.events] == [
        e.STEP_SUSPENDED,
        e.STEP_HOVERING,
        e.STEP_OPERATOR_APPLIED,
        e.STEP_REPLANNED,
    ]
    assert {(ev.node_id, ev.monitor_id, ev.recovery, ev.attempt) for ev in chain.events} == {
        ("m", "held@m/1", "retry", 1)
    }
    assert list(chain.events[-1].plan) == ["fly-to uav0 recover_uav0_1 Sq"]
    chain.until(lambda: chain.flights == 2, "the new plan's fly-to")
    assert chain.statuses.get("m/1") == "aborted"
    chain.until(lambda: chain.statuses.get("m/2.1") == "running", "the new step")


def test_a_violation_of_no_held_node_is_recorded_as_ignored(chain: Chain) -> None:
    v = chain.MonitorViolation
    msg = v(agent="uav0", monitor_id="x", kind=v.KIND_VIOLATION, node_id="nowhere/1")
    chain.until(lambda: chain.violations.get_subscription_count() > 0, "the manager")
    chain.violations.publish(msg)
    chain.until(lambda: bool(chain.events), "the ignored event")
    (event,) = chain.events
    assert event.step == chain.RecoveryEvent.STEP_IGNORED
    assert "no mission of uav0 holds node 'nowhere/1'" in event.reason


DELIVERY = (
    "world revinge\nagents uav0\npoint box1 = box1 at 0\n"
    "point OverDepot = supply_depot at 20\npoint OverField = west_field at 20\n"
    "d(P, TS, TE) = goal at(box1, OverField) where P = uav0\n"
)


def test_a_delivery_goal_that_cannot_lift_its_box_gives_up_with_the_planners_reason(
    chain: Chain,
) -> None:
    from hdrc3_interfaces.msg import TstReturn

    created = chain.call("create", mission="d", text=DELIVERY, file="d.tst", agents=["uav0"])
    assert created.result.code == TstReturn.TST_OK, created.result.reason
    chain.until(lambda: chain.manager.platform.state() is not None, "the helicopter state")
    assert chain.call("execute", mission="d", node_id="d", epoch=float("nan")).result.code == 0
    chain.until(lambda: chain.flights == 1, "the flight to the depot")
    tree = chain.manager.engines["d"].tst.tree
    assert [tree.node(c.node_id).action for c in tree.node("d").children] == [
        "fly-to",
        "pick-up-box",
        "fly-to",
        "drop-box",
    ]
    v = chain.MonitorViolation
    chain.violations.publish(
        v(
            agent="uav0",
            monitor_id="lifted@d/1",
            kind=v.KIND_VIOLATION,
            node_id="d/1",
            argument_names=["av", "box"],
            argument_values=["uav0", "box1"],
            recovery="lower-lift-capacity",
        )
    )
    e = chain.RecoveryEvent
    chain.until(lambda: any(ev.step == e.STEP_GAVE_UP for ev in chain.events), "giving up")
    assert [ev.step for ev in chain.events] == [
        e.STEP_SUSPENDED,
        e.STEP_HOVERING,
        e.STEP_OPERATOR_APPLIED,
        e.STEP_GAVE_UP,
    ]
    assert list(chain.events[2].changes) == ["lift-capacity(uav0) = 4", "release(box1)"]
    assert chain.events[3].reason.startswith("planning at: ")
    chain.until(lambda: chain.statuses.get("d") == "failed", "the goal's failure")
