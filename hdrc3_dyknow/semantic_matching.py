"""Stream semantics manager and semantic matching engine (sections 8.5-8.6).

Streams are annotated with the feature term their content is about. The matching engine finds
every stream whose annotation matches a feature term of a formula *by meaning*: the annotated
feature must be the requested feature, an equivalent class or a subclass of it (a stream of
``GroundSpeed(uav0)`` answers ``speed(uav0)``), and each argument must be the requested object
or ``owl:sameAs`` it. Sorts resolve to the objects of that sort. Failures are results naming the
missing symbol and the streams that were searched.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum

from hdrc3_dyknow.ontology import Ontology
from hdrc3_dyknow.sample import FeatureTerm

# Error messages list at most this many searched streams.
MAX_LISTED = 20


class StreamSemantics:
    """The stream semantics manager: semantic annotations of streams by label."""

    def __init__(self) -> None:
        self._annotations: dict[str, FeatureTerm] = {}

    def annotate(self, label: str, term: FeatureTerm) -> None:
        """Declare that stream ``label`` contains samples of ``term``."""
        self._annotations[label] = term

    def remove(self, label: str) -> None:
        """Forget the annotation of ``label`` (no-op if there is none)."""
        self._annotations.pop(label, None)

    def annotation(self, label: str) -> FeatureTerm | None:
        """The annotation of ``label``, if any."""
        return self._annotations.get(label)

    def items(self) -> list[tuple[str, FeatureTerm]]:
        """All (label, annotation) pairs, sorted by label."""
        return sorted(self._annotations.items())


class MatchStatus(StrEnum):
    """Outcome of matching one symbol."""

    MATCHED = "matched"
    UNKNOWN_FEATURE = "unknown_feature"
    UNKNOWN_OBJECT = "unknown_object"
    UNKNOWN_SORT = "unknown_sort"
    NO_STREAM = "no_stream"


@dataclass(frozen=True, slots=True)
class FeatureMatch:
    """Streams found for one feature term."""

    term: FeatureTerm
    status: MatchStatus
    labels: tuple[str, ...] = ()
    reason: str = ""

    @property
    def ok(self) -> bool:
        """Whether at least one stream matched."""
        return self.status is MatchStatus.MATCHED


@dataclass(frozen=True, slots=True)
class SortMatch:
    """Objects found for one sort."""

    sort: str
    status: MatchStatus
    objects: tuple[str, ...] = ()
    reason: str = ""


def _listing(labels: list[str]) -> str:
    if not labels:
        return "none (no annotated streams)"
    shown = ", ".join(labels[:MAX_LISTED])
    more = len(labels) - MAX_LISTED
    return f"{shown}, ... ({more} more)" if more > 0 else shown


class SemanticMatcher:
    """The semantic matching engine over an ontology and the stream semantics manager."""

    def __init__(self, ontology: Ontology, semantics: StreamSemantics) -> None:
        self.ontology = ontology
        self.semantics = semantics

    def match(self, term: FeatureTerm) -> FeatureMatch:
        """Find all streams whose annotated content is ``term``, best first.

        Exact feature names come before equivalent or more specific ones; ties by label.
        """
        searched = [label for label, _ in self.semantics.items()]
        feature = self.ontology.feature(term.feature)
        if feature is None:
            return FeatureMatch(
                term,
                MatchStatus.UNKNOWN_FEATURE,
                reason=f"unknown feature {term.feature!r} in {term}: not in the ontology;"
                f" streams searched: {_listing(searched)}",
            )
        for arg in term.args:
            if not self.ontology.is_object(arg):
                return FeatureMatch(
                    term,
                    MatchStatus.UNKNOWN_OBJECT,
                    reason=f"unknown object {arg!r} in {term}: not declared;"
                    f" streams searched: {_listing(searched)}",
                )
        ranked: list[tuple[int, str]] = []
        for label, annotation in self.semantics.items():
            annotated = self.ontology.feature(annotation.feature)
            if annotated is None or not self.ontology.subsumes(feature, annotated):
                continue
            if len(annotation.args) != len(term.args):
                continue
            if all(
                self.ontology.canonical_object(have)
                in self.ontology.same_as(self.ontology.canonical_object(want))
                for want, have in zip(term.args, annotation.args, strict=True)
            ):
                ranked.append((0 if annotated == feature else 1, label))
        if not ranked:
            return FeatureMatch(
                term,
                MatchStatus.NO_STREAM,
                reason=f"no stream contains {term} (feature {feature});"
                f" streams searched: {_listing(searched)}",
            )
        return FeatureMatch(term, MatchStatus.MATCHED, tuple(label for _, label in sorted(ranked)))

    def match_sort(self, sort: str) -> SortMatch:
        """Find the objects of ``sort`` (the finite domain of a quantifier)."""
        canonical = self.ontology.sort(sort)
        if canonical is None:
            searched = [label for label, _ in self.semantics.items()]
            return SortMatch(
                sort,
                MatchStatus.UNKNOWN_SORT,
                reason=f"unknown sort {sort!r}: not in the ontology;"
                f" known sorts: {', '.join(self.ontology.sorts())};"
                f" streams searched: {_listing(searched)}",
            )
        return SortMatch(sort, MatchStatus.MATCHED, tuple(self.ontology.members(canonical)))
