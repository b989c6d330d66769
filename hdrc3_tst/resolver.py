"""Resolver: syntax tree -> :class:`TaskTree` + :class:`ConstraintNetwork` (section 6.3).

Scoping follows Figure 16 and Example 6.2: a node's head variables bind its interface, either
``(TS, TE)`` or ``(P, TS, TE)``; ``with`` declares variables its children bind; a where clause
may constrain the node's and its ancestors' variables. An action argument named nowhere (the
chapter's ``Speed2``) is an open parameter of that node, visible to the whole tree; a name in
an agent/area/point/path position must be a declared value. A node without a ``P`` runs on its
parent's agent. The control structure adds the temporal semantics of TALF (section 9.4): every
node lies within its parent's interval, a sequence's children do not overlap and keep their
order, ``TS <= TE``; hover and wait fix ``TE - TS``; the RMAX envelope bounds speeds and
altitudes. Every constraint carries a label with its source position, so a conflict names them.
"""

from __future__ import annotations

import enum
import re
from collections.abc import Mapping
from dataclasses import dataclass, field

import shapely

from hdrc3_deliberative.mission_syntax import (
    AgentsDecl,
    AreaDecl,
    Cmp,
    Comparison,
    ConsRef,
    Membership,
    Name,
    Number,
    PathDecl,
    PointDecl,
    SourcePos,
    WorldDecl,
)
from hdrc3_tst.actions import ACTIONS, ActionSpec, ParamSpec, ParamType
from hdrc3_tst.diagnostics import Diagnostic
from hdrc3_tst.finite import LinearConstraint, SolveStatus, SymbolConstraint
from hdrc3_tst.model import UNASSIGNED, NodeKind, NodeRef, TaskTree
from hdrc3_tst.model import Node as TreeNode
from hdrc3_tst.network import ConstraintNetwork, FixResult, FixStatus
from hdrc3_tst.printer import constraint_text
from hdrc3_tst.stn import Inconsistent
from hdrc3_tst.syntax import (
    ActionTask,
    CallTask,
    ConcurrentTask,
    ConsDef,
    Constraint,
    ForeachTask,
    GoalTask,
    IfTask,
    SequenceTask,
    TstDef,
    TstFile,
    WhileTask,
)
from hdrc3_tst.worlds import WorldCache, world_facts


class ResolveStatus(enum.Enum):
    """Outcome of resolving a file."""

    OK = "ok"
    INVALID = "invalid"
    """Unknown names, wrong types, bad declarations."""
    INCONSISTENT = "inconsistent"
    """The constraints admit no solution."""


@dataclass(frozen=True)
class Place:
    """A declared value: an area polygon, a point or a path (local ENU metres)."""

    kind: ParamType
    coords: tuple[tuple[float, ...], ...]


@dataclass
class ResolvedTst:
    """A resolved mission: the tree, its network and the declared values."""

    tree: TaskTree
    network: ConstraintNetwork
    agents: tuple[str, ...]
    places: dict[str, Place]
    world: str | None = None
    resolver: _Resolver | None = field(default=None, repr=False, compare=False)
    """What resolved it: foreach instances are resolved by it at run time."""

    def variable(self, node_id: str, param: str) -> str:
        """The network variable of one node parameter (misuse raises TstError)."""
        from hdrc3_tst.errors import TstError

        node = self.tree.node(node_id)
        if param not in node.params:
            raise TstError(f"{node_id} has no parameter {param!r} (has {', '.join(node.params)})")
        return node.params[param]

    def set(self, node_id: str, param: str, value: float | str) -> FixResult:
        """Fix one node parameter (mixed initiative, ``hdrc3 tst set``); refused on conflict."""
        node = self.tree.nodes.get(node_id)
        if node is None:
            return FixResult(FixStatus.UNKNOWN_VARIABLE, f"no node {node_id!r}")
        if param not in node.params:
            known = ", ".join(node.params)
            return FixResult(
                FixStatus.UNKNOWN_VARIABLE, f"{node_id} has no parameter {param!r} ({known})"
            )
        return self.network.fix(node.params[param], value, f"set {node_id}.{param} = {value}")

    def agent_of(self, node_id: str) -> str:
        """The node's agent if ``P`` is fixed, else :data:`UNASSIGNED`."""
        value = self.network.values.get(self.variable(node_id, "P"), UNASSIGNED)
        return str(value)

    def ref(self, node_id: str) -> NodeRef:
        """The node's reference (agent + id)."""
        return NodeRef(self.agent_of(node_id), node_id)

    def expand_foreach(self, foreach_id: str, answers: tuple[tuple[str, ...], ...]) -> Instance:
        """Instantiate a foreach body once per answer and make them the node's children.

        Returns:
            An OK :class:`Instance` whose ``nodes`` are every node added, or the first refusal
            (the node is then left unexpanded).
        """
        added: list[str] = []
        roots: list[NodeRef] = []
        for values in answers:
            instance = self._instantiate(foreach_id, values)
            added += instance.nodes
            if instance.status is not InstanceStatus.OK:
                return Instance(instance.status, "", tuple(added), instance.reason)
            roots.append(NodeRef(UNASSIGNED, instance.root))
        self.tree.expand(foreach_id, NodeKind.CONCURRENT, roots)
        return Instance(InstanceStatus.OK, foreach_id, tuple(added))

    def materialize(self, node_id: str) -> Instance:
        """Resolve the foreach instances a node id names (``f[uav1]/body/leaf``).

        Another agent's manager expanded the foreach and asks this one to execute an instance's
        node; every replica resolves the same instance from its id, so they agree on it.
        """
        added: list[str] = []
        for match in re.finditer(r"\[([^\[\]]*)\]/", node_id):
            foreach_id = node_id[: match.start()]
            node = self.tree.nodes.get(foreach_id)
            if node is None or node.kind is not NodeKind.FOREACH:
                continue
            instance = self._instantiate(foreach_id, tuple(match.group(1).split(",")))
            added += instance.nodes
            if instance.status is not InstanceStatus.OK:
                return Instance(instance.status, "", tuple(added), instance.reason)
        if node_id not in self.tree.nodes:
            return Instance(InstanceStatus.INVALID, "", tuple(added), f"no node {node_id!r}")
        return Instance(InstanceStatus.OK, node_id, tuple(added))

    def _instantiate(self, foreach_id: str, values: tuple[str, ...]) -> Instance:
        if self.resolver is None or foreach_id not in self.resolver.foreach_bodies:
            return Instance(InstanceStatus.INVALID, "", (), f"{foreach_id} is not a foreach node")
        return self.resolver.instantiate(foreach_id, values)


@dataclass(frozen=True)
class ResolveResult:
    """The resolved mission when valid, and every diagnostic found."""

    status: ResolveStatus
    tst: ResolvedTst | None
    diagnostics: tuple[Diagnostic, ...] = ()


class InstanceStatus(enum.Enum):
    """Outcome of instantiating a foreach body for one answer."""

    OK = "ok"
    INVALID = "invalid"
    """A value of the wrong type, or the body does not resolve with it."""
    INCONSISTENT = "inconsistent"
    """The instance's constraints conflict with the network."""


@dataclass(frozen=True)
class Instance:
    """One foreach instance: its root node and every node it added (also when refused)."""

    status: InstanceStatus
    root: str
    nodes: tuple[str, ...]
    reason: str = ""


@dataclass
class _Scope:
    vars: dict[str, str]
    parent: _Scope | None = None

    def find(self, name: str) -> str | None:
        scope: _Scope | None = self
        while scope is not None:
            if name in scope.vars:
                return scope.vars[name]
            scope = scope.parent
        return None


@dataclass
class _Resolver:
    file: TstFile
    world_extent: shapely.Polygon | None
    world_places: Mapping[str, tuple[float, float]]
    agents: tuple[str, ...]
    diags: list[Diagnostic] = field(default_factory=list)
    net: ConstraintNetwork = field(default_factory=ConstraintNetwork)
    places: dict[str, Place] = field(default_factory=dict)
    cons_defs: dict[str, ConsDef] = field(default_factory=dict)
    library: dict[str, TstDef] = field(default_factory=dict)
    tree: TaskTree | None = None
    mission: str = ""
    root_scope: _Scope = field(default_factory=lambda: _Scope({}))
    pending: list[tuple[Constraint, _Scope, str]] = field(default_factory=list)
    foreach_bodies: dict[str, tuple[TstDef, _Scope]] = field(default_factory=dict)
    """FOREACH node id -> its body as written and the scope its instances resolve in."""
    live: bool = False
    """Resolving at run time (a foreach instance): every temporal edge propagates at once."""

    def error(self, code: str, message: str, pos: SourcePos) -> None:
        self.diags.append(Diagnostic(code, message, pos))

    def edge(self, later: str, earlier: str, bound: float, strict: bool, label: str) -> None:
        """``later - earlier <= bound``: recorded while loading, propagated when ``live``.

        Raises:
            Inconsistent: (live) the edge closes a negative cycle; the network is unchanged.
        """
        if self.live:
            self.net.stn.add(later, earlier, bound, strict, label)
        else:
            self.net.stn.constrain(later, earlier, bound, strict, label)

    # --- declarations -------------------------------------------------------------------
    def declarations(self) -> None:
        for item in self.file.items:
            if isinstance(item, AreaDecl):
                self._area(item)
            elif isinstance(item, PointDecl):
                self._point(item)
            elif isinstance(item, PathDecl):
                missing = [
                    p for p in item.points if self.places.get(p, _NONE).kind is not ParamType.POINT
                ]
                if missing:
                    self.error("E104", f"path {item.name}: unknown point {missing[0]!r}", item.pos)
                coords = tuple(self.places[p].coords[0] for p in item.points if p not in missing)
                self._place(item.name, Place(ParamType.PATH, coords), item.pos)
            elif isinstance(item, ConsDef):
                self.cons_defs[item.name] = item
            elif isinstance(item, TstDef):
                if item.name in self.library:
                    self.error("E105", f"TST {item.name!r} defined twice", item.pos)
                self.library.setdefault(item.name, item)

    def _place(self, name: str, place: Place, pos: SourcePos) -> None:
        if name in self.places or name in self.agents:
            self.error("E105", f"{name!r} declared twice", pos)
        self.places[name] = place

    def _area(self, item: AreaDecl) -> None:
        poly = shapely.Polygon(item.vertices) if len(item.vertices) >= 3 else None
        if poly is None or not poly.is_valid or poly.area <= 0:
            self.error("E103", f"area {item.name}: not a simple polygon of >= 3 vertices", item.pos)
        elif self.world_extent is not None and not self.world_extent.covers(poly):
            self.error("E103", f"area {item.name} leaves the world's extent", item.pos)
        self._place(item.name, Place(ParamType.AREA, item.vertices), item.pos)

    def _point(self, item: PointDecl) -> None:
        if item.place is not None:
            if self.world_extent is None:
                self.error("E102", f"point {item.name}: 'at' needs a world declaration", item.pos)
                return
            if item.place not in self.world_places:
                known = ", ".join(sorted(self.world_places))
                self.error(
                    "E102", f"unknown place {item.place!r} (the world has: {known})", item.pos
                )
                return
            xyz = (*self.world_places[item.place], item.altitude)
        else:
            assert item.xyz is not None
            xyz = item.xyz
            if self.world_extent is not None and not self.world_extent.covers(
                shapely.Point(xyz[:2])
            ):
                self.error("E103", f"point {item.name} lies outside the world", item.pos)
        self._place(item.name, Place(ParamType.POINT, (xyz,)), item.pos)

    # --- variables ----------------------------------------------------------------------
    def var(self, scope: _Scope, name: str, kind: ParamType, pos: SourcePos, node: str) -> str:
        """Bind ``name`` in ``scope`` (declaring it in the root scope when new) with a type."""
        found = scope.find(name)
        if found is None:
            found = name
            self.root_scope.vars[name] = found
        have = self.net.types.get(found)
        if have is None:
            self.net.declare(found, kind, self._domain(kind))
        elif have is not kind:
            self.error(
                "E106", f"{node}: {name} is a {have.value}, used here as a {kind.value}", pos
            )
        return found

    def _domain(self, kind: ParamType) -> tuple[str, ...]:
        if kind is ParamType.AGENT:
            return self.agents
        if kind.numeric:
            return ()
        return tuple(n for n, p in self.places.items() if p.kind is kind)

    def constant(self, value: float | str, kind: ParamType, where: str) -> str:
        var = f"_{where}"
        label = f"{where} = {value:g}" if isinstance(value, float) else f"{where} = {value}"
        self.net.declare(var, kind, self._domain(kind))
        if kind is ParamType.TIME:
            assert isinstance(value, float)
            self.edge(var, "Z", value, False, label)
            self.edge("Z", var, -value, False, label)
        elif kind.numeric:
            assert isinstance(value, float)
            self.net.finite.linear.append(LinearConstraint(((1.0, var),), Cmp.EQ, value, label))
        else:
            self.net.finite.symbolic.append(
                SymbolConstraint(var, Cmp.EQ, (str(value),), None, label)
            )
        self.net.values[var] = value
        return var

    # --- nodes --------------------------------------------------------------------------
    def node(
        self, tst: TstDef, scope: _Scope, parent: TreeNode | None, prefix: str = ""
    ) -> TreeNode | None:
        assert self.tree is not None
        node_id = prefix + tst.name
        if node_id in self.tree.nodes:
            self.error("E105", f"node name {tst.name!r} used twice", tst.pos)
            return None
        if len(tst.params) not in (2, 3):
            self.error("E107", f"{tst.name}: a node interface is (TS, TE) or (P, TS, TE)", tst.pos)
            return None
        own = _Scope({}, scope)
        names = dict(zip(("P", "TS", "TE")[3 - len(tst.params) :], tst.params, strict=True))
        params: dict[str, str] = {}
        for key, kind in (("P", ParamType.AGENT), ("TS", ParamType.TIME), ("TE", ParamType.TIME)):
            if key in names:
                if scope.find(names[key]) is None:
                    own.vars[names[key]] = prefix + names[key]
                params[key] = self.var(own, names[key], kind, tst.pos, tst.name)
            elif parent is not None:
                params[key] = parent.params[key]
            else:
                params[key] = self.var(own, f"{prefix}{key}_{tst.name}", kind, tst.pos, tst.name)
        for name in tst.with_vars:
            own.vars[name] = prefix + name
        node_kind = _KINDS[type(tst.task)]
        node = TreeNode(
            node_id,
            node_kind,
            params,
            None if parent is None else NodeRef(UNASSIGNED, parent.node_id),
            pos=tst.pos,
        )
        self.tree.add(node)
        self._temporal_structure(node, parent)
        task = tst.task
        if isinstance(task, ActionTask):
            self._action(node, task, own)
        elif isinstance(task, GoalTask):
            node.action = task.name
            node.goal_args = tuple(self._goal_arg(a, own) for a in task.args)
        elif isinstance(task, CallTask):
            self._call(node, task, own, prefix)
        else:
            if isinstance(task, IfTask | WhileTask | ForeachTask):
                node.condition = task.cond
                if task.cond.time is not None and own.find(task.cond.time) is None:
                    self.error("E101", f"unknown time variable {task.cond.time!r}", task.cond.pos)
            if isinstance(task, ForeachTask):
                self._foreach(node, task, own)
                for cons in tst.where:
                    self.pending.append((cons, own, node_id))
                return node
            previous: TreeNode | None = None
            in_sequence = f"{tst.pos}: sequence {node_id}: "  # the position formatted once
            for sub in tst.children():
                child = self.node(sub, own, node, prefix)
                if child is None:
                    continue
                node.children.append(NodeRef(UNASSIGNED, child.node_id))
                if node_kind is NodeKind.SEQUENCE and previous is not None:
                    self.edge(
                        previous.params["TE"],
                        child.params["TS"],
                        0.0,
                        False,
                        f"{in_sequence}{previous.node_id} before {child.node_id}",
                    )
                previous = child
        for cons in tst.where:
            self.pending.append((cons, own, node_id))
        return node

    def _goal_arg(self, arg: Name | Number, scope: _Scope) -> str:
        """A goal's argument as the planner sees it: a bound variable (foreach) by its value."""
        if isinstance(arg, Number):
            return f"{arg.value:g}"
        var = scope.find(arg.id)
        value = self.net.values.get(var) if var is not None else None
        if value is None:
            return arg.id
        return f"{value:g}" if isinstance(value, float) else value

    def _foreach(self, node: TreeNode, task: ForeachTask, own: _Scope) -> None:
        """Check the body once as a template; instances are resolved when the query answers.

        The template is not the node's child: it never runs, and it does not keep the foreach
        from ending at once when the query has no answer.
        """
        node.loop_vars = task.vars
        for v in task.vars:
            own.vars[v] = f"{node.node_id}[*].{v}"
        self.foreach_bodies[node.node_id] = (task.body, own)
        template = self.node(task.body, own, None, f"{node.node_id}[*]/")
        if template is not None:
            node.template = template.node_id

    def instantiate(self, foreach_id: str, values: tuple[str, ...]) -> Instance:
        """Resolve one instance of a foreach body with its loop variables bound to ``values``.

        The instance's nodes are added to the tree and its constraints to the network, which
        propagates at once; on a conflict the edge that closes it is not added, and the
        instance is refused (the foreach node then fails).
        """
        assert self.tree is not None
        foreach = self.tree.node(foreach_id)
        body, scope = self.foreach_bodies[foreach_id]
        tag = f"{foreach_id}[{','.join(values)}]"
        if f"{tag}/{body.name}" in self.tree.nodes:
            return Instance(InstanceStatus.OK, f"{tag}/{body.name}", ())
        if len(values) != len(foreach.loop_vars):
            return Instance(
                InstanceStatus.INVALID,
                "",
                (),
                f"{foreach_id} binds {len(foreach.loop_vars)} variables, got {len(values)} values",
            )
        before = set(self.tree.nodes)
        finite = self.net.finite
        linear, symbolic = len(finite.linear), len(finite.symbolic)
        self.diags, self.pending, self.live = [], [], True
        try:
            inner = _Scope({}, scope)
            for name, value in zip(foreach.loop_vars, values, strict=True):
                kind = self.net.types.get(scope.vars[name])
                if kind is None:
                    continue  # the body does not use it
                if self._domain(kind) and value not in self._domain(kind):
                    return Instance(
                        InstanceStatus.INVALID, "", (), f"{value!r} is not a {kind.value}"
                    )
                inner.vars[name] = self.constant(value, kind, f"{tag}.{name}")
            root = self.node(body, inner, foreach, f"{tag}/")
            self.constraints()
        except Inconsistent as exc:
            return Instance(
                InstanceStatus.INCONSISTENT,
                "",
                self._added(before),
                "; ".join(e.label for e in exc.cycle),
            )
        finally:
            self.live = False
        added = self._added(before)
        if self.diags or root is None:
            reason = "; ".join(f"{d.pos}: {d.message}" for d in self.diags)
            return Instance(InstanceStatus.INVALID, "", added, reason)
        solved = self.net.finite.solve()
        if solved.status is SolveStatus.INCONSISTENT:
            del finite.linear[linear:], finite.symbolic[symbolic:]
            return Instance(InstanceStatus.INCONSISTENT, "", added, "; ".join(solved.conflict))
        for var, agent in _fixed_agents(self.net).items():
            self.net.values.setdefault(var, agent)
        return Instance(InstanceStatus.OK, root.node_id, added)

    def _added(self, before: set[str]) -> tuple[str, ...]:
        assert self.tree is not None
        return tuple(n for n in self.tree.nodes if n not in before)

    def _temporal_structure(self, node: TreeNode, parent: TreeNode | None) -> None:
        ts, te = node.params["TS"], node.params["TE"]
        at = f"{node.pos}: {node.node_id}"
        self.edge(ts, te, 0.0, False, f"{at}: TS <= TE")
        if parent is not None and parent.params["TS"] != ts:
            self.edge(parent.params["TS"], ts, 0.0, False, f"{at} starts within {parent.node_id}")
        if parent is not None and parent.params["TE"] != te:
            self.edge(te, parent.params["TE"], 0.0, False, f"{at} ends within {parent.node_id}")

    def _action(self, node: TreeNode, task: ActionTask, scope: _Scope) -> None:
        node.action = task.name
        spec = ACTIONS.get(task.name)
        if spec is None:
            self.error(
                "E110", f"unknown action type {task.name!r} (known: {', '.join(ACTIONS)})", task.pos
            )
            return
        args = list(task.args)
        if not spec.required + 2 <= len(args) <= len(spec.params) + 2:
            sig = ", ".join(["TS", "TE", *(p.name for p in spec.params)])
            self.error("E111", f"{task.name} takes ({sig}), got {len(args)} arguments", task.pos)
            return
        for key, arg in zip(("TS", "TE"), args[:2], strict=True):
            var = self._arg(node, arg, _INTERFACE_TIMES[key], scope)
            if var is not None and var != node.params[key]:
                label = f"{node.node_id}: {key} = {arg.id if isinstance(arg, Name) else arg.value}"
                self.edge(var, node.params[key], 0.0, False, label)
                self.edge(node.params[key], var, 0.0, False, label)
        for i, pspec in enumerate(spec.params):
            arg = (
                args[i + 2] if i + 2 < len(args) else Number(float(pspec.default or 0.0), task.pos)
            )
            var = self._arg(node, arg, pspec, scope)
            if var is None:
                continue
            node.params[pspec.name] = var
            self._envelope(node, spec, pspec, var)

    def _envelope(self, node: TreeNode, spec: ActionSpec, pspec: ParamSpec, var: str) -> None:
        lin = self.net.finite.linear
        for op, bound, text in _ENVELOPE[spec.name, pspec.name]:
            lin.append(LinearConstraint(((1.0, var),), op, bound, node.node_id + text))
        if spec.duration == pspec.name and var in self.net.values:
            d = float(self.net.values[var])
            label = f"{node.pos}: {node.node_id}: TE - TS = {spec.duration} {d:g} s"
            self.edge(node.params["TE"], node.params["TS"], d, False, label)
            self.edge(node.params["TS"], node.params["TE"], -d, False, label)

    def _arg(
        self, node: TreeNode, arg: Name | Number, pspec: ParamSpec, scope: _Scope
    ) -> str | None:
        label = f"{node.node_id}.{pspec.name}"
        if isinstance(arg, Number):
            if not pspec.type.numeric:
                self.error("E106", f"{label} is a {pspec.type.value}, not a number", arg.pos)
                return None
            return self.constant(arg.value, pspec.type, label)
        if scope.find(arg.id) is not None:
            return self.var(scope, arg.id, pspec.type, arg.pos, node.node_id)
        if arg.id in self.places or arg.id in self.agents:
            have = self.places[arg.id].kind if arg.id in self.places else ParamType.AGENT
            if have is not pspec.type:
                self.error(
                    "E106", f"{label} is a {pspec.type.value}; {arg.id} is a {have.value}", arg.pos
                )
                return None
            return self.constant(arg.id, pspec.type, label)
        if not pspec.type.numeric:
            self.error("E102", f"unknown {pspec.type.value} {arg.id!r} for {label}", arg.pos)
            return None
        return self.var(scope, arg.id, pspec.type, arg.pos, node.node_id)

    def _call(self, node: TreeNode, task: CallTask, scope: _Scope, prefix: str) -> None:
        node.action = task.name
        target = self.library.get(task.name)
        if target is None:
            self.error("E112", f"call of unknown TST {task.name!r}", task.pos)
            return
        if target.name == self.mission or f"/{task.name}/" in f"/{prefix}":
            self.error("E113", f"recursive call of {task.name!r}", task.pos)
            return
        if len(task.args) != len(target.params):
            self.error(
                "E111",
                f"{task.name} takes {len(target.params)} arguments, got {len(task.args)}",
                task.pos,
            )
            return
        # The instance's head variables are the call's arguments (its interface).
        inner = _Scope({}, self.root_scope)
        for formal, actual in zip(target.params, task.args, strict=True):
            if isinstance(actual, Name) and scope.find(actual.id) is not None:
                inner.vars[formal] = scope.find(actual.id)  # type: ignore[assignment]
            else:
                self.error(
                    "E114", f"call {task.name}: argument {formal} must be a variable", task.pos
                )
                return
        child = self.node(target, inner, node, f"{node.node_id}/")
        if child is not None:
            node.children.append(NodeRef(UNASSIGNED, child.node_id))

    # --- where clauses ------------------------------------------------------------------
    def constraints(self) -> None:
        for cons, scope, node_id in self.pending:
            self._constraint(cons, scope, node_id, ())

    def _constraint(
        self, cons: Constraint, scope: _Scope, node_id: str, seen: tuple[str, ...]
    ) -> None:
        if isinstance(cons, ConsRef):
            ref = self.cons_defs.get(cons.name.id)
            if ref is None or cons.name.id in seen:
                what = "unknown" if ref is None else "recursive"
                self.error("E120", f"{what} constraint set {cons.name.id!r}", cons.name.pos)
                return
            for sub in ref.constraints:
                self._constraint(sub, scope, node_id, (*seen, cons.name.id))
            return
        if isinstance(cons, Membership):
            var = self._lookup(cons.var, scope)
            if var is None:
                return
            values = tuple(v.id for v in cons.values if isinstance(v, Name))
            if not self._typed(var, list(values), cons.pos):
                return
            text = f"{cons.pos}: {cons.var.id} in {{{', '.join(values)}}}"
            self._symbolic(var, Cmp.EQ, values, None, cons.pos, text)
            return
        self._comparison(cons, scope)

    def _lookup(self, name: Name, scope: _Scope) -> str | None:
        var = scope.find(name.id)
        if var is None:
            self.error(
                "E101",
                f"unknown name {name.id!r}: not a variable of this node or an ancestor, nor a "
                "declared agent, area, point or path",
                name.pos,
            )
        return var

    def _symbolic(
        self,
        var: str,
        op: Cmp,
        values: tuple[str, ...],
        other: str | None,
        pos: SourcePos,
        text: str,
    ) -> None:
        kind = self.net.types[var]
        for value in values:
            if self.places.get(value, _NONE).kind is not kind and not (
                kind is ParamType.AGENT and value in self.agents
            ):
                self.error("E102", f"unknown {kind.value} {value!r}", pos)
                return
        self.net.finite.symbolic.append(SymbolConstraint(var, op, values, other, text))

    def _typed(self, var: str, symbols: list[str], pos: SourcePos) -> bool:
        """Type a variable no action argument typed (a loop variable) by the names it meets.

        False (with an error) when nothing tells its type.
        """
        if var in self.net.types:
            return True
        known = [s for s in symbols if s in self.agents or s in self.places]
        if not known:
            self.error(
                "E106", f"{var.rpartition('.')[2]} has no type: no action argument uses it", pos
            )
            return False
        kind = ParamType.AGENT if known[0] in self.agents else self.places[known[0]].kind
        self.net.declare(var, kind, self._domain(kind))
        return True

    def _comparison(self, cons: Comparison, scope: _Scope) -> None:
        text = f"{cons.pos}: {constraint_text(cons)}"
        terms: dict[str, float] = {}
        const = 0.0
        symbols: list[str] = []
        for side, sign in ((cons.left, 1.0), (cons.right, -1.0)):
            for term in side.terms:
                if term.name is None:
                    const -= sign * term.coef
                    continue
                var = scope.find(term.name.id)
                if var is None and (term.name.id in self.places or term.name.id in self.agents):
                    symbols.append(term.name.id)
                    continue
                var = var or self._lookup(term.name, scope)
                if var is None:
                    return
                terms[var] = terms.get(var, 0.0) + sign * term.coef
        if not all(self._typed(v, symbols, cons.pos) for v in terms):
            return
        kinds = {self.net.types[v] for v in terms}
        if symbols or any(not k.numeric for k in kinds):
            if len(terms) + len(symbols) != 2 or cons.op not in (Cmp.EQ, Cmp.NE) or len(terms) < 1:
                self.error(
                    "E121",
                    "names (agents, areas, points) only take = and != with one other name",
                    cons.pos,
                )
                return
            var, *rest = terms
            self._symbolic(var, cons.op, tuple(symbols), rest[0] if rest else None, cons.pos, text)
            return
        if ParamType.TIME in kinds:
            self._temporal(terms, cons.op, const, cons.pos, text, kinds)
            return
        self.net.finite.linear.append(
            LinearConstraint(tuple((c, v) for v, c in terms.items()), cons.op, const, text)
        )

    def _temporal(
        self,
        terms: dict[str, float],
        op: Cmp,
        const: float,
        pos: SourcePos,
        text: str,
        kinds: set[ParamType],
    ) -> None:
        plus = [v for v, c in terms.items() if c == 1.0]
        minus = [v for v, c in terms.items() if c == -1.0]
        if (
            kinds != {ParamType.TIME}
            or len(plus) > 1
            or len(minus) > 1
            or len(plus) + len(minus) != len(terms)
            or op is Cmp.NE
        ):
            self.error(
                "E122", "a temporal constraint must be a difference X - Y OP c (or X OP c)", pos
            )
            return
        x = plus[0] if plus else "Z"
        y = minus[0] if minus else "Z"
        # x - y OP const
        if op in (Cmp.LE, Cmp.LT, Cmp.EQ):
            self.edge(x, y, const, op is Cmp.LT, text)
        if op in (Cmp.GE, Cmp.GT, Cmp.EQ):
            self.edge(y, x, -const, op is Cmp.GT, text)


class _NoPlace:
    kind = None


_NONE = _NoPlace()


def _envelope_bounds(pspec: ParamSpec) -> tuple[tuple[Cmp, float, str], ...]:
    """The RMAX bounds of a parameter with the end of their labels (after the node id)."""
    if pspec.type is ParamType.DURATION:
        return ()
    return tuple(
        (op, bound, f": {pspec.name} {op.value} {bound:g} {pspec.unit} (RMAX)")
        for op, bound in ((Cmp.GE, pspec.minimum), (Cmp.LE, pspec.maximum))
        if bound is not None
    )


_ENVELOPE = {(a.name, p.name): _envelope_bounds(p) for a in ACTIONS.values() for p in a.params}
"""(action, parameter) -> its envelope bounds, formatted once from the static registry."""

_INTERFACE_TIMES = {key: ParamSpec(key, ParamType.TIME, "s") for key in ("TS", "TE")}
"""The first two arguments of every action, typed as its node's start and end."""

_KINDS: dict[type, NodeKind] = {
    ActionTask: NodeKind.ACTION,
    GoalTask: NodeKind.GOAL,
    CallTask: NodeKind.CALL,
    SequenceTask: NodeKind.SEQUENCE,
    ConcurrentTask: NodeKind.CONCURRENT,
    IfTask: NodeKind.IF,
    WhileTask: NodeKind.WHILE,
    ForeachTask: NodeKind.FOREACH,
}


def resolve(
    tree: TstFile,
    agents: tuple[str, ...] = (),
    file: str = "<string>",
    worlds: WorldCache | None = None,
) -> ResolveResult:
    """Resolve a parsed file against its world and agents, then propagate its network.

    ``agents`` adds to the file's ``agents`` declaration (e.g. ``--agents`` of the command).
    ``worlds`` keeps loaded worlds for the next call; without it the world is loaded anew.
    """
    from sim.world_loader import WorldError, load_world

    diags: list[Diagnostic] = []
    declared = tuple(n for i in tree.items if isinstance(i, AgentsDecl) for n in i.names)
    all_agents = tuple(dict.fromkeys((*declared, *agents)))
    extent: shapely.Polygon | None = None
    places: Mapping[str, tuple[float, float]] = {}
    world_decl = next((i for i in tree.items if isinstance(i, WorldDecl)), None)
    if world_decl is not None:
        try:
            facts = (
                world_facts(load_world(world_decl.name))
                if worlds is None
                else worlds.facts(world_decl.name)
            )
        except WorldError as exc:
            diags.append(Diagnostic("E100", f"world {world_decl.name!r}: {exc}", world_decl.pos))
        else:
            extent, places = facts.extent, facts.places
    resolver = _Resolver(tree, extent, places, all_agents, diags)
    resolver.declarations()
    tsts = mission_candidates(tree)
    if not tsts:
        resolver.error(
            "E130", "the file defines no TST that is not called by another", SourcePos(file, 1, 1)
        )
    else:
        resolver.mission = tsts[0].name
        resolver.tree = TaskTree(tsts[0].name)
        resolver.node(tsts[0], resolver.root_scope, None)
        resolver.constraints()
        if resolver.tree.root in resolver.tree.nodes:
            resolver.net.stn.order(temporal_order(resolver.tree))
        for unused in tsts[1:]:
            resolver.error(
                "E131",
                f"TST {unused.name!r} is neither the mission ({tsts[0].name}) nor called "
                "(a missing ';' before it?)",
                unused.pos,
            )
    if resolver.diags or resolver.tree is None:
        return ResolveResult(ResolveStatus.INVALID, None, tuple(resolver.diags))
    resolved = ResolvedTst(
        resolver.tree,
        resolver.net,
        all_agents,
        resolver.places,
        world_decl.name if world_decl else None,
        resolver,
    )
    conflict = resolver.net.check()
    if conflict:
        message = "inconsistent constraints: " + "; ".join(conflict)
        return ResolveResult(
            ResolveStatus.INCONSISTENT, resolved, (Diagnostic("E200", message, tsts[0].pos),)
        )
    for var, value in _fixed_agents(resolver.net).items():
        resolver.net.values.setdefault(var, value)
    return ResolveResult(ResolveStatus.OK, resolved)


def temporal_order(tree: TaskTree) -> list[str]:
    """Time variables in execution order: a node's TS, its children's, then its TE."""
    out: list[str] = []
    stack: list[tuple[str, bool]] = [(tree.root, False)]
    while stack:
        node_id, done = stack.pop()
        node = tree.nodes[node_id]
        if done:
            out.append(node.params["TE"])
            continue
        out.append(node.params["TS"])
        stack.append((node_id, True))
        stack.extend((c.node_id, False) for c in reversed(node.children) if c.node_id in tree.nodes)
    return out


def mission_candidates(tree: TstFile) -> tuple[TstDef, ...]:
    """TST definitions no ``call`` names, in file order: the first one is the mission."""
    called: set[str] = set()
    stack = list(tree.tsts())
    while stack:
        tst = stack.pop()
        if isinstance(tst.task, CallTask):
            called.add(tst.task.name)
        stack.extend(tst.children())
    return tuple(t for t in tree.tsts() if t.name not in called)


def _fixed_agents(net: ConstraintNetwork) -> dict[str, str]:
    """Agent variables a single ``P = agent`` constraint fixes."""
    out: dict[str, str] = {}
    for sym in net.finite.symbolic:
        if sym.op is Cmp.EQ and sym.other is None and len(sym.values) == 1:
            out[sym.var] = sym.values[0]
    return out
