"""Ontology manager: objects, sorts and features in OWL via rdflib (section 8.5).

The ontology has two class hierarchies under ``dk:Object`` (sorts) and ``dk:Feature``
(features); objects are OWL individuals typed by sorts. Symbols from formulas and stream
annotations are resolved by local name, then ignoring case, then by ``rdfs:label``; classes
related by ``owl:equivalentClass`` and individuals related by ``owl:sameAs`` are treated as one.
The packaged vocabulary is ``hdrc3_dyknow/hdrc3.ttl`` (package data).
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import rdflib
from rdflib.namespace import OWL, RDF, RDFS

from hdrc3_base.errors import Hdrc3Error

NAMESPACE = rdflib.Namespace("https://hdrc3.example.org/dyknow#")
OBJECT_ROOT = "Object"
FEATURE_ROOT = "Feature"


class OntologyError(Hdrc3Error):
    """An ontology file is unreadable, or an object is added to an unknown sort."""


class Ontology:
    """The ontology manager: resolves and relates sorts, objects and features."""

    def __init__(self, graph: rdflib.Graph) -> None:
        self._graph = graph
        self._aliases: dict[str, str] = {}
        self._index()

    def merge(self, path: Path) -> None:
        """Add another ontology (e.g. another UAS's, in its own namespace) to this one.

        Its classes and individuals are named ``prefix:Local`` by the file's prefixes and also
        answer to their bare local names unless the hdrc3 vocabulary uses them;
        ``owl:equivalentClass`` and ``owl:sameAs`` statements relate them to ours.

        Raises:
            OntologyError: If the file cannot be read or parsed.

        """
        try:
            self._graph.parse(str(path))
        except (OSError, ValueError, SyntaxError) as exc:
            raise OntologyError(f"cannot load ontology {path}: {exc}") from exc
        self._index()

    def _local(self, node: object) -> str | None:
        """Name of a node: local in the hdrc3 namespace, ``prefix:local`` in others."""
        if not isinstance(node, rdflib.URIRef):
            return None
        text = str(node)
        if text.startswith(str(NAMESPACE)):
            return text[len(str(NAMESPACE)) :]
        try:
            prefix, _, local = self._graph.namespace_manager.compute_qname(node, generate=False)
        except (KeyError, ValueError):
            return None
        return f"{prefix}:{local}" if prefix and local else None

    def _uri(self, name: str) -> rdflib.URIRef:
        if ":" in name:
            prefix, local = name.split(":", 1)
            for bound, namespace in self._graph.namespaces():
                if bound == prefix:
                    return rdflib.URIRef(str(namespace) + local)
        return NAMESPACE[name]

    def canonical_object(self, name: str) -> str:
        """The declared name of object ``name`` (``heli`` -> ``u2:heli``), else ``name``."""
        canonical = self._aliases.get(name)
        if canonical is not None and (self._uri(canonical), RDF.type, OWL.NamedIndividual) in (
            self._graph
        ):
            return canonical
        return name

    @classmethod
    def load(cls, path: Path | None = None) -> Ontology:
        """Load an ontology file (Turtle, RDF/XML, ...) or the packaged hdrc3 ontology.

        Raises:
            OntologyError: If the file cannot be read or parsed.

        """
        graph = rdflib.Graph()
        try:
            if path is None:
                text = resources.files("hdrc3_dyknow").joinpath("hdrc3.ttl").read_text()
                graph.parse(data=text, format="turtle")
            else:
                graph.parse(str(path))
        except (OSError, ValueError, SyntaxError) as exc:
            where = path or "packaged ontology"
            raise OntologyError(f"cannot load ontology {where}: {exc}") from exc
        return cls(graph)

    @property
    def graph(self) -> rdflib.Graph:
        """The underlying RDF graph."""
        return self._graph

    def _index(self) -> None:
        self._aliases.clear()
        labels: dict[str, str] = {}
        nodes = set(self._graph.subjects(RDF.type, OWL.Class)) | set(
            self._graph.subjects(RDF.type, OWL.NamedIndividual)
        )
        named = [(name, node) for node in nodes if (name := self._local(node)) is not None]
        # Our vocabulary first: its names and labels win over a foreign ontology's local names.
        for name, node in sorted(named, key=lambda item: (":" in item[0], item[0])):
            self._aliases[name] = name
            labels.setdefault(name.lower(), name)
            if ":" in name:  # a foreign name also answers to its local part
                labels.setdefault(name.split(":", 1)[1].lower(), name)
            for label in self._graph.objects(node, RDFS.label):
                labels.setdefault(str(label).lower(), name)
        for alias, name in labels.items():
            self._aliases.setdefault(alias, name)

    def _canonical(self, name: str) -> str | None:
        return self._aliases.get(name) or self._aliases.get(name.lower())

    def _equivalents(self, name: str) -> set[str]:
        seen = {name}
        todo = [name]
        while todo:
            node = self._uri(todo.pop())
            neighbours = set(self._graph.objects(node, OWL.equivalentClass)) | set(
                self._graph.subjects(OWL.equivalentClass, node)
            )
            for other in neighbours:
                local = self._local(other)
                if local is not None and local not in seen:
                    seen.add(local)
                    todo.append(local)
        return seen

    def superclasses(self, name: str) -> set[str]:
        """``name``, its equivalents and all their (transitive) superclasses."""
        seen: set[str] = set()
        todo = [name]
        while todo:
            for cls in self._equivalents(todo.pop()):
                if cls in seen:
                    continue
                seen.add(cls)
                for parent in self._graph.objects(self._uri(cls), RDFS.subClassOf):
                    local = self._local(parent)
                    if local is not None:
                        todo.append(local)
        return seen

    def subsumes(self, general: str, specific: str) -> bool:
        """Whether every ``specific`` is a ``general`` (equal, equivalent or subclass)."""
        return general in self.superclasses(specific)

    def _class_under(self, name: str, root: str) -> str | None:
        canonical = self._canonical(name)
        if canonical is None or (self._uri(canonical), RDF.type, OWL.Class) not in self._graph:
            return None
        return canonical if root in self.superclasses(canonical) else None

    def feature(self, name: str) -> str | None:
        """Canonical feature class for ``name`` (e.g. ``"altitude"`` -> ``"Altitude"``)."""
        return self._class_under(name, FEATURE_ROOT)

    def sort(self, name: str) -> str | None:
        """Canonical sort (object class) for ``name`` (e.g. ``"UAV"`` -> ``"UAV"``)."""
        return self._class_under(name, OBJECT_ROOT)

    def arity(self, feature: str) -> int | None:
        """Number of object arguments of a feature (inherited), None if unspecified."""
        for cls in self._ordered_ancestors(feature):
            value = self._graph.value(self._uri(cls), NAMESPACE.arity)
            if value is not None:
                return int(str(value))
        return None

    def _ordered_ancestors(self, name: str) -> list[str]:
        # Breadth-first, so the nearest class that states a property wins.
        order: list[str] = []
        frontier = [name]
        while frontier:
            nxt: list[str] = []
            for cls in frontier:
                for eq in sorted(self._equivalents(cls)):
                    if eq in order:
                        continue
                    order.append(eq)
                    for parent in self._graph.objects(self._uri(eq), RDFS.subClassOf):
                        local = self._local(parent)
                        if local is not None:
                            nxt.append(local)
            frontier = nxt
        return order

    def features(self) -> list[str]:
        """All feature classes, sorted."""
        return sorted(c for c in self._classes() if FEATURE_ROOT in self.superclasses(c))

    def sorts(self) -> list[str]:
        """All sorts (object classes), sorted."""
        return sorted(c for c in self._classes() if OBJECT_ROOT in self.superclasses(c))

    def _classes(self) -> set[str]:
        return {
            n for n in map(self._local, self._graph.subjects(RDF.type, OWL.Class)) if n is not None
        }

    def add_object(self, name: str, sort: str) -> None:
        """Declare object ``name`` to be of ``sort`` (an OWL individual).

        Raises:
            OntologyError: If ``sort`` is not a sort of the ontology or ``name`` is a class.

        """
        canonical = self.sort(sort)
        if canonical is None:
            raise OntologyError(f"unknown sort {sort!r}; known sorts: {', '.join(self.sorts())}")
        if (self._uri(name), RDF.type, OWL.Class) in self._graph:
            raise OntologyError(f"object name {name!r} is already a class of the ontology")
        node = self._uri(name)
        self._graph.add((node, RDF.type, OWL.NamedIndividual))
        self._graph.add((node, RDF.type, self._uri(canonical)))
        self._aliases[name] = name

    def same_as(self, name: str) -> set[str]:
        """``name`` and every individual related to it by ``owl:sameAs``."""
        seen = {name}
        todo = [name]
        while todo:
            node = self._uri(todo.pop())
            for other in set(self._graph.objects(node, OWL.sameAs)) | set(
                self._graph.subjects(OWL.sameAs, node)
            ):
                local = self._local(other)
                if local is not None and local not in seen:
                    seen.add(local)
                    todo.append(local)
        return seen

    def is_object(self, name: str) -> bool:
        """Whether ``name`` is a declared object (individual), by name or alias."""
        for candidate in (name, self._aliases.get(name)):
            if candidate and (self._uri(candidate), RDF.type, OWL.NamedIndividual) in self._graph:
                return True
        return False

    def objects(self) -> list[str]:
        """All declared objects, sorted."""
        nodes = self._graph.subjects(RDF.type, OWL.NamedIndividual)
        return sorted(n for n in map(self._local, nodes) if n is not None)

    def sorts_of(self, name: str) -> set[str]:
        """All sorts the object belongs to (its types and their superclasses)."""
        found: set[str] = set()
        for other in self.same_as(name):
            for cls in self._graph.objects(self._uri(other), RDF.type):
                local = self._local(cls)
                if local is not None:
                    found |= self.superclasses(local)
        return found & set(self.sorts())

    def members(self, sort: str) -> list[str]:
        """All objects of ``sort`` (including its subclasses and equivalents), sorted."""
        canonical = self.sort(sort)
        if canonical is None:
            return []
        return [obj for obj in self.objects() if canonical in self.sorts_of(obj)]
