"""The DyKnow side of an execution monitor: streams of an agent's Data Interface (chapter 8).

:func:`data_interface_spec` writes the stream specification (``hdrc3_dyknow`` SSL_T-like
language) that annotates the fields of the agent's ``helicopter_state`` topic (§6.2.4) with
ontology features, so formulas about ``altitude(uav0)`` or ``speed(uav0)`` find them by
semantic matching; :func:`hook_spec` annotates the payload hook's ``carrying`` sensor
(``sensors/carrying``, ``HookState``) as one ``Carrying(<agent>, <load>)`` stream per box or
carrier of the world (true while the magnet holds that load's tag), for Examples 9.2 and 9.4.
:class:`MonitorStreams` bundles the host, ontology, semantics manager,
catalogue and matcher built from that and any further specifications.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

from hdrc3_dyknow.knowledge_process import KnowledgeProcessHost
from hdrc3_dyknow.ontology import Ontology
from hdrc3_dyknow.sample import Sample
from hdrc3_dyknow.semantic_matching import SemanticMatcher, StreamSemantics
from hdrc3_dyknow.semantic_spec import parse_spec
from hdrc3_dyknow.sources import StreamCatalog
from hdrc3_platform_server.hook_api import Winch

DATA_INTERFACE_TOPIC = "helicopter_state"
DATA_INTERFACE_STREAMS: tuple[tuple[str, str, str], ...] = (
    ("altitude", "Altitude", "extrapolate"),
    ("speed", "Speed", "extrapolate"),
    ("ground_speed", "GroundSpeed", "extrapolate"),
    ("velocity_up", "VerticalSpeed", "extrapolate"),
    ("heading", "Heading", "last_value"),
    ("pitch", "Pitch", "last_value"),
    ("roll", "Roll", "last_value"),
    ("rpm", "RotorSpeed", "extrapolate"),
    ("on_ground_flag", "OnGround", "last_value"),
    ("auto_flag", "AutoMode", "last_value"),
    ("power_status", "PowerStatus", "last_value"),
)
"""(HelicopterState field, ontology feature, missing-value handling) of the default streams."""


def power_label(agent: str) -> str:
    """Label of the stream of ``agent``'s electrical power (W)."""
    return f"{agent}/power"


HOOK_TOPIC = "sensors/carrying"
"""The agent's carrying sensor (``HookState``), relative to its namespace."""


def hook_spec(agent: str, loads: Sequence[tuple[str, str]], topic: str = HOOK_TOPIC) -> str:
    """Stream specification of the carrying sensor.

    ``Carrying(agent, load)`` for each (tag, sort) of ``loads``, and ``WinchStalled(agent)``.
    Labels are ``<agent>/hook/<tag>`` (whether the magnet holds that tag) and
    ``<agent>/hook/stalled`` (whether the winch is stalled under its load). A missing value is
    the last one (the sensor reports at 10 Hz; late samples are dropped).
    """
    lines = [f"object {tag} : {sort};" for tag, sort in loads]
    lines.append(
        f'stream {agent}/hook/stalled contains WinchStalled({agent}) from topic "{topic}"'
        f' type HookState field winch == "{Winch.STALLED.value}" with max_delay 1000 ms,'
        " missing last_value;"
    )
    for tag, _ in loads:
        lines.append(
            f'stream {agent}/hook/{tag} contains Carrying({agent}, {tag}) from topic "{topic}"'
            f' type HookState field object_id == "{tag}" with max_delay 1000 ms,'
            " missing last_value;"
        )
    return "\n".join(lines) + "\n"


def data_interface_spec(agent: str, sort: str = "RMAX", topic: str = DATA_INTERFACE_TOPIC) -> str:
    """Stream specification of ``agent``'s Data Interface fields (labels ``<agent>/di/<field>``).

    Late samples (more than 1 s old) are dropped; a missing value is extrapolated from the two
    latest samples or held, per field (§9.3.2).
    """
    lines = [f"object {agent} : {sort};"]
    # fed by the power unit's PowerStatus (MonitorStreams.publish_power), not a topic field
    lines.append(f"stream {power_label(agent)} contains Power({agent}) with missing extrapolate;")
    for name, feature, missing in DATA_INTERFACE_STREAMS:
        lines.append(
            f'stream {agent}/di/{name} contains {feature}({agent}) from topic "{topic}"'
            f" field {name} with max_delay 1000 ms, missing {missing};"
        )
    return "\n".join(lines) + "\n"


@dataclass
class MonitorStreams:
    """Host, ontology, stream semantics, catalogue and matcher of one execution monitor."""

    ontology: Ontology = field(default_factory=Ontology.load)
    host: KnowledgeProcessHost = field(default_factory=KnowledgeProcessHost)
    semantics: StreamSemantics = field(default_factory=StreamSemantics)
    catalog: StreamCatalog = field(init=False)
    matcher: SemanticMatcher = field(init=False)

    def __post_init__(self) -> None:
        self.catalog = StreamCatalog(self.host, self.ontology, self.semantics)
        self.matcher = SemanticMatcher(self.ontology, self.semantics)

    @classmethod
    def for_agent(
        cls,
        agent: str,
        ontology_file: Path | None = None,
        loads: Sequence[tuple[str, str]] = (),
    ) -> MonitorStreams:
        """Streams of ``agent``'s Data Interface in the packaged (or given) ontology.

        ``loads``: (tag, ontology sort) of the boxes and carriers the hook may carry; each gets
        a ``Carrying(agent, tag)`` stream from the carrying sensor.
        """
        streams = cls(Ontology.load(ontology_file))
        streams.load(data_interface_spec(agent), f"<data interface of {agent}>")
        if loads:
            streams.load(hook_spec(agent, loads), f"<carrying sensor of {agent}>")
        return streams

    def publish_power(
        self, agent: str, valid_ms: int, available_ms: int, voltage: float, current: float
    ) -> bool:
        """Publish ``voltage * current`` (W) on the agent's power stream; False if not finite."""
        power = float(voltage) * float(current)
        if not math.isfinite(power):
            return False
        self.host.publish(power_label(agent), Sample(valid_ms or available_ms, available_ms, power))
        return True

    def load(self, text: str, source: str) -> list[str]:
        """Load a stream specification; returns the labels declared.

        Raises:
            SpecError: The specification is malformed or inconsistent (``source:line:column``).

        """
        return self.catalog.load(parse_spec(text, source))
