import pytest

from hdrc3_dyknow.ontology import Ontology
from hdrc3_dyknow.sample import FeatureTerm
from hdrc3_dyknow.semantic_matching import MatchStatus, SemanticMatcher, StreamSemantics


@pytest.fixture
def matcher() -> SemanticMatcher:
    onto = Ontology.load()
    for name, sort in [("av1", "RMAX"), ("uav2", "UAV"), ("uav3", "Quadrotor"), ("car1", "Car")]:
        onto.add_object(name, sort)
    semantics = StreamSemantics()
    semantics.annotate("s/d21", FeatureTerm("XYDist", ("uav2", "av1")))
    semantics.annotate("s/h31", FeatureTerm("HorizontalDistance", ("uav3", "av1")))
    semantics.annotate("s/d12", FeatureTerm("xydist", ("av1", "uav2")))
    semantics.annotate("s/gs2", FeatureTerm("GroundSpeed", ("uav2",)))
    semantics.annotate("s/sp2", FeatureTerm("speed", ("uav2",)))
    semantics.annotate("s/alt", FeatureTerm("Altitude", ("av1",)))
    return SemanticMatcher(onto, semantics)


@pytest.mark.parametrize(
    ("term", "labels"),
    [
        (FeatureTerm("XYDist", ("uav2", "av1")), ("s/d21",)),
        (FeatureTerm("XYDist", ("uav3", "av1")), ("s/h31",)),  # equivalent class
        (FeatureTerm("xy_dist", ("av1", "uav2")), ("s/d12",)),  # label spelling, argument order
        (FeatureTerm("Speed", ("uav2",)), ("s/sp2", "s/gs2")),  # exact first, then subclass
        (FeatureTerm("GroundSpeed", ("uav2",)), ("s/gs2",)),  # a plain speed is not ground speed
        (FeatureTerm("altitude", ("av1",)), ("s/alt",)),
    ],
)
def test_matches(matcher: SemanticMatcher, term: FeatureTerm, labels: tuple[str, ...]) -> None:
    result = matcher.match(term)
    assert result.ok and result.labels == labels


@pytest.mark.parametrize(
    ("term", "status", "fragments"),
    [
        (
            FeatureTerm("Temperature", ("av1",)),
            MatchStatus.UNKNOWN_FEATURE,
            ["'Temperature'", "s/alt"],
        ),
        (FeatureTerm("XYDist", ("uav9", "av1")), MatchStatus.UNKNOWN_OBJECT, ["'uav9'", "s/d21"]),
        (
            FeatureTerm("XYDist", ("car1", "av1")),
            MatchStatus.NO_STREAM,
            ["XYDist[car1, av1]", "s/h31"],
        ),
        (FeatureTerm("Altitude", ("uav2",)), MatchStatus.NO_STREAM, ["Altitude[uav2]"]),
    ],
)
def test_failures_name_symbol_and_searched_streams(
    matcher: SemanticMatcher, term: FeatureTerm, status: MatchStatus, fragments: list[str]
) -> None:
    result = matcher.match(term)
    assert result.status is status and not result.ok and result.labels == ()
    for fragment in fragments:
        assert fragment in result.reason


@pytest.mark.parametrize(
    ("sort", "status", "objects"),
    [
        ("AV", MatchStatus.MATCHED, ("av1", "uav2", "uav3")),
        ("Helicopter", MatchStatus.MATCHED, ("av1",)),
        ("Car", MatchStatus.MATCHED, ("car1",)),
        ("Dragon", MatchStatus.UNKNOWN_SORT, ()),
    ],
)
def test_sorts(
    matcher: SemanticMatcher, sort: str, status: MatchStatus, objects: tuple[str, ...]
) -> None:
    result = matcher.match_sort(sort)
    assert (result.status, result.objects) == (status, objects)


def test_semantics_manager_remove() -> None:
    semantics = StreamSemantics()
    semantics.annotate("a", FeatureTerm("Altitude", ("x",)))
    semantics.remove("a")
    semantics.remove("a")
    assert semantics.items() == [] and semantics.annotation("a") is None


FOREIGN = """
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix dk: <https://hdrc3.example.org/dyknow#> .
@prefix u2: <https://uas2.example.org/ontology#> .
u2:Aircraft a owl:Class ; owl:equivalentClass dk:AV .
u2:Velocity a owl:Class ; owl:equivalentClass dk:Speed .
u2:Speed a owl:Class ; owl:equivalentClass dk:Speed .
u2:heli a owl:NamedIndividual, u2:Aircraft ; owl:sameAs dk:uav1 .
"""


def test_another_uas_ontology_is_matched_through_equivalence_and_same_as(tmp_path) -> None:
    """Another UAS annotates its streams in its own namespace (section 8.5, last paragraph)."""
    path = tmp_path / "uas2.ttl"
    path.write_text(FOREIGN)
    ontology = Ontology.load()
    ontology.add_object("uav1", "UAV")
    ontology.merge(path)
    semantics = StreamSemantics()
    semantics.annotate("uas2/vel", FeatureTerm("Velocity", ("heli",)))
    semantics.annotate("uas2/vel_qualified", FeatureTerm("u2:Velocity", ("u2:heli",)))
    semantics.annotate("own/speed", FeatureTerm("speed", ("uav1",)))
    matcher = SemanticMatcher(ontology, semantics)
    found = matcher.match(FeatureTerm("speed", ("uav1",)))
    assert found.labels == ("own/speed", "uas2/vel", "uas2/vel_qualified")
    # our vocabulary keeps its names: "Speed" is dk:Speed, the foreign one is u2:Speed
    assert ontology.feature("Speed") == "Speed"
    assert ontology.feature("velocity") == "u2:Velocity"
    assert ontology.is_object("heli") and ontology.canonical_object("heli") == "u2:heli"
    assert "u2:heli" in ontology.same_as("uav1")
    assert "u2:heli" in ontology.members("AV")
