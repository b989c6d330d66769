from pathlib import Path

import pytest

from hdrc3_dyknow.ontology import Ontology, OntologyError


@pytest.fixture
def onto() -> Ontology:
    ontology = Ontology.load()
    ontology.add_object("uav0", "RMAX")
    ontology.add_object("av1", "UAV")
    ontology.add_object("car3", "Car")
    return ontology


@pytest.mark.parametrize(
    ("name", "feature", "sort"),
    [
        ("XYDist", "XYDist", None),
        ("xydist", "XYDist", None),
        ("xy_dist", "XYDist", None),
        ("altitude", "Altitude", None),
        ("HorizontalDistance", "HorizontalDistance", None),
        ("AV", None, "AV"),
        ("uav", None, "UAV"),
        ("Helicopter", None, "Helicopter"),
        ("nonsense", None, None),
    ],
)
def test_resolution(onto: Ontology, name: str, feature: str | None, sort: str | None) -> None:
    assert onto.feature(name) == feature
    assert onto.sort(name) == sort


@pytest.mark.parametrize(
    ("general", "specific", "expected"),
    [
        ("Speed", "GroundSpeed", True),
        ("GroundSpeed", "Speed", False),
        ("XYDist", "HorizontalDistance", True),
        ("HorizontalDistance", "XYDist", True),
        ("AV", "RMAX", True),
        ("UAV", "Helicopter", True),
        ("AV", "Car", False),
    ],
)
def test_subsumption(onto: Ontology, general: str, specific: str, expected: bool) -> None:
    assert onto.subsumes(general, specific) is expected


@pytest.mark.parametrize(
    ("sort", "members"),
    [
        ("AV", ["av1", "uav0"]),
        ("UAV", ["av1", "uav0"]),
        ("RMAX", ["uav0"]),
        ("PhysicalObject", ["av1", "car3", "uav0"]),
        ("Human", []),
        ("bogus", []),
    ],
)
def test_members(onto: Ontology, sort: str, members: list[str]) -> None:
    assert onto.members(sort) == members


def test_arity_objects_and_lists(onto: Ontology) -> None:
    assert (onto.arity("XYDist"), onto.arity("Altitude"), onto.arity("Feature")) == (2, 1, None)
    assert onto.is_object("uav0") and not onto.is_object("AV")
    assert onto.objects() == ["av1", "car3", "uav0"]
    assert "XYDist" in onto.features() and "AV" not in onto.features()
    assert "AV" in onto.sorts() and "XYDist" not in onto.sorts()


def test_same_as(tmp_path: Path) -> None:
    text = """@prefix dk: <https://hdrc3.example.org/dyknow#> .
@prefix owl: <http://www.w3.org/2002/07/owl#> .
@prefix rdfs: <http://www.w3.org/2000/01/rdf-schema#> .
dk:Object a owl:Class . dk:AV a owl:Class ; rdfs:subClassOf dk:Object .
dk:heli1 a owl:NamedIndividual, dk:AV ; owl:sameAs dk:uav7 .
dk:uav7 a owl:NamedIndividual .
"""
    path = tmp_path / "mini.ttl"
    path.write_text(text)
    onto = Ontology.load(path)
    assert onto.same_as("uav7") == {"uav7", "heli1"}
    assert onto.sorts_of("uav7") == {"AV", "Object"}


@pytest.mark.parametrize(
    ("name", "sort", "match"), [("x", "Spaceship", "unknown sort"), ("AV", "AV", "class")]
)
def test_add_object_errors(onto: Ontology, name: str, sort: str, match: str) -> None:
    with pytest.raises(OntologyError, match=match):
        onto.add_object(name, sort)


def test_unreadable_file(tmp_path: Path) -> None:
    bad = tmp_path / "bad.ttl"
    bad.write_text("this is not turtle @@@")
    with pytest.raises(OntologyError, match="cannot load ontology"):
        Ontology.load(bad)
