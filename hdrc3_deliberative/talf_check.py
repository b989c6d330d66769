"""Name and type checks of a TALF file against an elementary action registry (section 9.4).

The registry is passed in (the TST action registry, ``hdrc3_tst.actions.ACTIONS``, is the one
source of truth; this package sits below ``hdrc3_tst`` and only sees it through the
:class:`ElementarySpec` protocol). Checked: every elementary action exists and gets the right
number of arguments of the right kinds, every composite action term names a type declared in
the file with its arity, no composite action type calls itself, every name is bound (interval,
``with``, ``foreach`` or type parameter, ``open`` mission parameter, declared agent or place),
named constraint sets exist, names are not defined twice. :func:`check_capabilities` tells
whether some agent has what each elementary action needs.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from typing import Protocol

from hdrc3_deliberative.mission_syntax import (
    AgentsDecl,
    Cmp,
    Comparison,
    ConsRef,
    Membership,
    Name,
    Number,
    SourcePos,
    WorldDecl,
)
from hdrc3_deliberative.talf_diagnostics import TalfDiagnostic
from hdrc3_deliberative.talf_formulas import (
    And,
    Exists,
    Forall,
    Formula,
    Iff,
    Implies,
    Not,
    Or,
    conjuncts,
    formula_names,
)
from hdrc3_deliberative.talf_syntax import (
    ActionTerm,
    CAct,
    CompositeSpec,
    Foreach,
    If,
    OpenDecl,
    TalfFile,
    While,
)


class Valued(Protocol):
    """An enum member: a parameter type or a capability."""

    @property
    def value(self) -> str:
        """The name (``area``, ``camera``)."""


class ParamKind(Valued, Protocol):
    """A parameter type: numeric, or the kind of name it takes (``agent``, ``area``, ...)."""

    @property
    def numeric(self) -> bool:
        """Whether the parameter takes a number."""


class ParamLike(Protocol):
    """One parameter of an elementary action."""

    @property
    def name(self) -> str:
        """The parameter's name."""

    @property
    def type(self) -> ParamKind:
        """The parameter's type."""


class ElementarySpec(Protocol):
    """What TALF needs of an elementary action type (``hdrc3_tst.actions.ActionSpec``)."""

    @property
    def params(self) -> tuple[ParamLike, ...]:
        """The type-specific parameters, in order."""

    @property
    def required(self) -> int:
        """How many of them must be given."""

    @property
    def needs(self) -> frozenset[Valued]:
        """The platform capabilities the action uses."""


@dataclass
class _Checker:
    tree: TalfFile
    actions: Mapping[str, ElementarySpec]
    diags: list[TalfDiagnostic] = field(default_factory=list)
    unbound: list[str] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.specs = self.tree.specs()
        self.places = self.tree.places()
        self.agents = set(self.tree.agents())
        self.globals = set(self.tree.open_names())
        self.cons = self.tree.constraints()

    def error(self, code: str, message: str, pos: SourcePos) -> None:
        self.diags.append(TalfDiagnostic(code, message, pos))

    def bound(self, name: str, scope: frozenset[str]) -> bool:
        return name in scope or name in self.globals or name in self.agents or name in self.places

    def need(self, name: str, scope: frozenset[str], pos: SourcePos, what: str) -> None:
        if not self.bound(name, scope):
            self.unbound.append(name)
            self.error(
                "T101",
                f"unbound variable {name!r} in {what}: not a parameter, an interval, a with or "
                "foreach variable, an open mission parameter nor a declared agent or place",
                pos,
            )

    # --- formulas -----------------------------------------------------------------------
    def formula(
        self,
        formula: Formula,
        scope: frozenset[str],
        pos: SourcePos,
        what: str,
        seen: tuple[str, ...] = (),
    ) -> None:
        for name in formula_names(formula):
            self.need(name.id, scope, name.pos if name.pos.line else pos, what)
        for part in _refs(formula):
            ref = part.name.id
            definition = self.cons.get(ref)
            if definition is None or ref in seen:
                reason = "unknown" if definition is None else "recursive"
                self.error("T107", f"{reason} constraint set {ref!r}", part.name.pos)
            else:
                self.formula(definition.formula, scope, part.name.pos, ref, (*seen, ref))

    # --- composite actions --------------------------------------------------------------
    def cact(self, cact: CAct, scope: frozenset[str]) -> None:
        for name in (cact.interval.start, cact.interval.end):
            self.need(name, scope, cact.pos, "an interval")
        if cact.agent is not None:
            self.need(cact.agent, scope, cact.pos, "'by'")
            if cact.agent not in scope and cact.agent in self.places:
                kind = self.places[cact.agent]
                self.error("T104", f"'by' takes an agent; {cact.agent} is a {kind}", cact.pos)
        inner = scope | set(cact.with_vars)
        task = cact.task
        if isinstance(task, ActionTerm):
            self.term(task, inner)
        elif isinstance(task, Foreach):
            loop = inner | set(task.vars)
            self.formula(task.cond, loop, cact.pos, "a foreach condition")
            self.cact(task.body, loop)
        else:
            if isinstance(task, If | While):
                self.formula(task.cond, inner, cact.pos, "a condition")
            for child in cact.children():
                self.cact(child, inner)
        if cact.where is not None:
            self.formula(cact.where, inner, cact.pos, "a where clause")

    def term(self, term: ActionTerm, scope: frozenset[str]) -> None:
        if term.interval is not None:
            for name in (term.interval.start, term.interval.end):
                self.need(name, scope, term.pos, "an interval")
        spec = self.actions.get(term.name)
        if spec is not None:
            self.elementary(term, spec, scope)
            return
        comp = self.specs.get(term.name)
        if comp is None:
            self.error(
                "T102",
                f"unknown action {term.name!r}: neither an elementary action of the registry "
                f"({', '.join(sorted(self.actions))}) nor a composite action of this file",
                term.pos,
            )
            return
        if len(term.args) != len(comp.params):
            self.error(
                "T103",
                f"{term.name} takes {len(comp.params)} arguments ({', '.join(comp.params)}), "
                f"got {len(term.args)}",
                term.pos,
            )
        for arg in term.args:
            if isinstance(arg, Name):
                self.need(arg.id, scope, arg.pos, f"an argument of {term.name}")

    def elementary(self, term: ActionTerm, spec: ElementarySpec, scope: frozenset[str]) -> None:
        if not spec.required <= len(term.args) <= len(spec.params):
            sig = ", ".join(p.name for p in spec.params)
            self.error(
                "T103", f"{term.name} takes ({sig}), got {len(term.args)} arguments", term.pos
            )
            return
        for arg, param in zip(term.args, spec.params, strict=False):
            kind = param.type
            what = f"{term.name}'s {param.name}"
            if isinstance(arg, Number):
                if not kind.numeric:
                    self.error("T104", f"{what} is a {kind.value}, not a number", term.pos)
                continue
            if arg.id in scope or arg.id in self.globals:
                continue
            have = "agent" if arg.id in self.agents else self.places.get(arg.id)
            if have is None:
                self.need(arg.id, scope, arg.pos, what)
            elif kind.numeric or have != kind.value:
                self.error("T104", f"{what} is a {kind.value}; {arg.id} is a {have}", arg.pos)

    # --- items --------------------------------------------------------------------------
    def duplicates(self) -> None:
        seen: set[str] = set(self.agents)
        for item in self.tree.items:
            if isinstance(item, WorldDecl | AgentsDecl | OpenDecl):
                continue
            name = item.name
            if name in seen:
                self.error("T105", f"{name!r} defined twice", item.pos)
            elif isinstance(item, CompositeSpec) and name in self.actions:
                self.error("T105", f"{name!r} is an elementary action of the registry", item.pos)
            seen.add(name)

    def recursion(self) -> None:
        for spec in self.specs.values():
            path = _cycle(spec.name, self.specs, ())
            if path:
                chain = " -> ".join(path)
                self.error("T106", f"recursive composite action: {chain}", spec.pos)

    def run(self) -> None:
        self.duplicates()
        self.recursion()
        for spec in self.specs.values():
            head = frozenset((spec.interval.start, spec.interval.end, *spec.params))
            self.cact(spec.body, head)
        for mission in self.tree.missions():
            root = mission.body
            own = (root.interval.start, root.interval.end)
            self.cact(root, frozenset(own if root.agent is None else (*own, root.agent)))
            labels: set[str] = set()
            for cact in root.walk():
                if cact.label is not None and cact.label in labels:
                    self.error("T105", f"label {cact.label!r} used twice", cact.pos)
                if cact.label is not None:
                    labels.add(cact.label)


def _refs(formula: Formula) -> Iterator[ConsRef]:
    """References to named constraint sets inside a formula."""
    if isinstance(formula, ConsRef):
        yield formula
    elif isinstance(formula, Not):
        yield from _refs(formula.arg)
    elif isinstance(formula, And | Or):
        for part in formula.args:
            yield from _refs(part)
    elif isinstance(formula, Implies | Iff):
        yield from _refs(formula.left)
        yield from _refs(formula.right)
    elif isinstance(formula, Exists | Forall):
        yield from _refs(formula.body)


def terms(cact: CAct) -> Iterator[ActionTerm]:
    """Every action term below a C-ACT, depth first."""
    for sub in cact.walk():
        if isinstance(sub.task, ActionTerm):
            yield sub.task


def _cycle(name: str, specs: Mapping[str, CompositeSpec], path: tuple[str, ...]) -> tuple[str, ...]:
    if name in path:
        return (*path, name) if path[0] == name else ()
    spec = specs.get(name)
    if spec is None:
        return ()
    for term in terms(spec.body):
        found = _cycle(term.name, specs, (*path, name))
        if found:
            return found
    return ()


def check(tree: TalfFile, actions: Mapping[str, ElementarySpec]) -> tuple[TalfDiagnostic, ...]:
    """Every name, arity and kind error of a parsed file, in file order."""
    checker = _Checker(tree, actions)
    checker.run()
    return tuple(sorted(checker.diags, key=lambda d: (d.pos.line, d.pos.column)))


def free_names(tree: TalfFile, actions: Mapping[str, ElementarySpec]) -> tuple[str, ...]:
    """The names a file uses without binding them, in order of first use."""
    checker = _Checker(tree, actions)
    checker.run()
    return tuple(dict.fromkeys(checker.unbound))


# --- capabilities ---------------------------------------------------------------------------


def _agent_domains(root: CAct, agents: frozenset[str]) -> dict[str, frozenset[str]]:
    """Agent variables a where clause fixes (``P = uav0``) or restricts (``P in {..}``)."""
    out: dict[str, frozenset[str]] = {}
    for cact in root.walk():
        for part in conjuncts(cact.where):
            var, values = None, frozenset[str]()
            if isinstance(part, Membership):
                var = part.var.id
                values = frozenset(v.id for v in part.values if isinstance(v, Name))
            elif isinstance(part, Comparison) and part.op is Cmp.EQ:
                names = [t.name.id for e in (part.left, part.right) for t in e.terms if t.name]
                if len(names) == 2 and (names[1] in agents) != (names[0] in agents):
                    var, value = (names[0], names[1]) if names[1] in agents else names[::-1]
                    values = frozenset({value})
            if var is not None and values <= agents:
                out[var] = out.get(var, values) & values
    return out


def check_capabilities(
    mission: str,
    root: CAct,
    actions: Mapping[str, ElementarySpec],
    capabilities: Mapping[str, frozenset[str]],
) -> tuple[TalfDiagnostic, ...]:
    """Each elementary action some agent can run, or a T110 naming the node and its needs.

    ``root``, the C-ACT of ``mission``, has no composite action terms left (expanded); the
    node is named by its path of labels from the mission. ``capabilities`` maps every
    agent to the capability names it offers. An action's agent is the nearest ``by`` above it;
    where clauses that fix or restrict that variable restrict the candidates.
    """
    agents = frozenset(capabilities)
    domains = _agent_domains(root, agents)
    diags: list[TalfDiagnostic] = []

    def visit(cact: CAct, agent: str | None, path: str) -> None:
        agent = cact.agent if cact.agent is not None else agent
        task = cact.task
        if cact.label is not None:
            path = f"{path}/{cact.label}"
        if isinstance(task, ActionTerm) and task.name in actions:
            needs = frozenset(c.value for c in actions[task.name].needs)
            fixed = agent in agents
            candidates = frozenset({agent or ""}) if fixed else domains.get(agent or "", agents)
            if not any(needs <= capabilities[a] for a in candidates):
                offered = "; ".join(
                    f"{a}: {'+'.join(sorted(capabilities[a])) or 'nothing'}"
                    for a in sorted(candidates)
                )
                node = path if cact.label else f"{path}/{task.name}"
                diags.append(
                    TalfDiagnostic(
                        "T110",
                        f"unsatisfiable constraints: {node} needs {'+'.join(sorted(needs))}; "
                        f"no agent has it ({offered or 'no candidate agent'})",
                        task.pos,
                    )
                )
        for child in cact.children():
            visit(child, agent, path)

    visit(root, None, mission)
    return tuple(diags)
