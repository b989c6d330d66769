"""hdrc3/ros_workspace.py: the colcon packages come from pyproject.toml and the imports."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from catkin_pkg.package import parse_package

from hdrc3.ros_workspace import (
    imported_packages,
    read_project,
    ros_packages,
    write_workspace,
)
from hdrc3_base.errors import ConfigError

ROOT = Path(__file__).resolve().parents[3]
PROJECT = read_project(ROOT)
PACKAGES = {p.name: p for p in ros_packages(PROJECT)}
SCRIPTS = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]


def test_every_python_package_of_the_project_is_a_ros_package() -> None:
    assert "hdrc3_interfaces" not in PACKAGES  # an ament_cmake package of its own
    assert {"hdrc3", "hdrc3_base", "hdrc3_control", "hdrc3_tst", "sim"} <= set(PACKAGES)
    assert all((ROOT / name / "__init__.py").is_file() for name in PACKAGES)


@pytest.mark.parametrize("script", sorted(SCRIPTS))
def test_every_console_script_is_an_executable_of_its_package(script: str) -> None:
    target = SCRIPTS[script]
    owners = [p for p in PACKAGES.values() if target in p.executables.values()]
    assert len(owners) == 1
    (package,) = owners
    assert target.startswith(f"{package.name}.")
    (executable,) = [e for e, t in package.executables.items() if t == target]
    assert executable == script.removeprefix("hdrc3-").replace("-", "_")


@pytest.mark.parametrize(
    ("package", "depends"),
    [
        ("hdrc3_base", set()),
        ("hdrc3_hcsm", {"hdrc3_base"}),
        ("hdrc3_control", {"hdrc3_base", "hdrc3_hcsm", "hdrc3_interfaces", "rclpy"}),
    ],
)
def test_dependencies_are_what_the_modules_import(package: str, depends: set[str]) -> None:
    assert depends <= set(PACKAGES[package].depends)
    assert package not in PACKAGES[package].depends
    assert set(PACKAGES[package].depends) == set(
        imported_packages(ROOT / package, (*PACKAGES, "hdrc3_interfaces", "rclpy"))
    )


def test_the_written_packages_are_valid_ament_python_packages(tmp_path: Path) -> None:
    written = write_workspace(tmp_path, PROJECT)
    assert [p.name for p in written] == sorted(PACKAGES)
    for package in written:
        directory = tmp_path / "src" / package.name
        manifest = parse_package(str(directory / "package.xml"))  # colcon-ros's parser
        assert manifest.name == package.name
        assert manifest.get_build_type() == "ament_python"
        assert {d.name for d in manifest.exec_depends} == set(package.depends)
        assert (directory / package.name).resolve() == (ROOT / package.name).resolve()
        assert (directory / "resource" / package.name).is_file()
        cfg = (directory / "setup.cfg").read_text()
        assert f"install_scripts=$base/lib/{package.name}" in cfg
        compile((directory / "setup.py").read_text(), "setup.py", "exec")
    write_workspace(tmp_path, PROJECT)  # again over its own output: fine


def test_a_directory_it_did_not_write_is_left_alone(tmp_path: Path) -> None:
    (tmp_path / "src" / "hdrc3_base").mkdir(parents=True)
    with pytest.raises(ConfigError, match="not a generated package"):
        write_workspace(tmp_path, PROJECT)


@pytest.mark.parametrize(
    ("pyproject", "reason"),
    [
        (None, "not a readable pyproject.toml"),
        ("[project\nname = 'x'", "not a readable pyproject.toml"),
        ("[project]\nname = 'x'\n", "no setuptools packages.find"),
    ],
)
def test_a_source_without_the_project_sections_is_refused(
    tmp_path: Path, pyproject: str | None, reason: str
) -> None:
    if pyproject is not None:
        (tmp_path / "pyproject.toml").write_text(pyproject)
    with pytest.raises(ConfigError, match=reason):
        read_project(tmp_path)
