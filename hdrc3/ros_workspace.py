"""A colcon workspace of hdrc3's packages, so ``ros2 run hdrc3_control control_kernel`` works.

A ROS 2 user builds packages with colcon: each needs a ``package.xml``, and an ``ament_python``
package a ``setup.py`` that installs its executables under ``lib/<package>/`` (where ``ros2 run``
looks) and registers it in the ament index. hdrc3 itself is one pip project (the venv stays the
default way in). :func:`write_workspace` writes ``DIR/src/<package>/`` for every Python package
of the project: ``package.xml``, ``setup.py``, ``setup.cfg``, the ament index marker and a
symbolic link to the package's sources. Everything comes from the project's own records, never
a second table: the packages and package data from ``pyproject.toml``'s setuptools sections, the
executables from its ``[project.scripts]`` (``hdrc3-control-kernel = hdrc3_control....:main``
becomes ``control_kernel`` of ``hdrc3_control``), the dependencies between packages from what
their modules import (``ast``). ``hdrc3_interfaces`` is expected in the underlay (``make
setup`` builds it into the venv, a Jazzy install builds it with colcon from its own
``package.xml``); third-party Python packages come from the environment, as the venv has them.
"""

from __future__ import annotations

import ast
import fnmatch
import tomllib
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

from hdrc3_base.errors import ConfigError

SCRIPT_PREFIX = "hdrc3-"
"""Console scripts are ``hdrc3-<executable>``; the ``hdrc3`` CLI keeps its name (no prefix)."""
UNDERLAY = ("hdrc3_interfaces", "rclpy")
"""ROS packages the workspace's packages may depend on that come from the underlay."""
VERSION_DEFAULT = "0.0.0"


@dataclass(frozen=True)
class RosPackage:
    """One ament_python package of the workspace."""

    name: str
    executables: Mapping[str, str]
    """Executable name -> ``module:function``."""
    depends: tuple[str, ...]
    """Packages of the workspace and the underlay its modules import."""


@dataclass(frozen=True)
class Project:
    """What the project's ``pyproject.toml`` says about its packages."""

    root: Path
    version: str
    description: str
    license: str
    maintainer: tuple[str, str]
    """Name and e-mail address (the first of the project's authors)."""
    packages: tuple[str, ...]
    """Top-level Python packages (their directories under ``root``)."""
    package_data: tuple[str, ...]
    """File patterns installed with every package."""
    scripts: Mapping[str, str]


def read_project(root: Path) -> Project:
    """The packages, data patterns and scripts of the project at ``root``.

    Raises:
        ConfigError: ``root`` has no readable ``pyproject.toml`` with the setuptools sections.
    """
    path = root / "pyproject.toml"
    try:
        data = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise ConfigError(f"{path}: not a readable pyproject.toml ({exc})") from exc
    try:
        project = data["project"]
        setuptools = data["tool"]["setuptools"]
        find = setuptools["packages"]["find"]
        includes, excludes = list(find["include"]), list(find.get("exclude", []))
        patterns = tuple(p for ps in setuptools.get("package-data", {}).values() for p in ps)
        scripts = dict(project.get("scripts", {}))
    except (KeyError, TypeError) as exc:
        raise ConfigError(f"{path}: no setuptools packages.find / project section ({exc})") from exc
    tops = sorted(
        d.name
        for d in root.iterdir()
        if d.is_dir()
        and (d / "__init__.py").is_file()
        and any(fnmatch.fnmatchcase(d.name, p) for p in includes)
        and not any(fnmatch.fnmatchcase(d.name, p) for p in excludes)
    )
    license_field = project.get("license", {})
    authors = project.get("authors") or [{}]
    return Project(
        root,
        str(project.get("version", VERSION_DEFAULT)),
        str(project.get("description", "")),
        str(license_field.get("text", "")) if isinstance(license_field, dict) else "",
        (str(authors[0].get("name", "")), str(authors[0].get("email", ""))),
        tuple(tops),
        patterns,
        scripts,
    )


def module_imports(path: Path) -> Iterator[tuple[int, str]]:
    """(line, absolute module) of every import statement in one file, also inside functions."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            yield from ((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.lineno, node.module


def imported_packages(directory: Path, candidates: Iterable[str]) -> tuple[str, ...]:
    """The ``candidates`` the modules under ``directory`` import (itself excluded)."""
    wanted = set(candidates) - {directory.name}
    found = {
        module.split(".", 1)[0]
        for path in directory.rglob("*.py")
        for _, module in module_imports(path)
    }
    return tuple(sorted(found & wanted))


def ros_packages(project: Project) -> tuple[RosPackage, ...]:
    """One package per top-level Python package, with its executables and dependencies."""
    out = []
    for name in project.packages:
        executables = {
            _executable(script): target
            for script, target in project.scripts.items()
            if target.split(".", 1)[0].split(":", 1)[0] == name
        }
        depends = imported_packages(project.root / name, (*project.packages, *UNDERLAY))
        out.append(RosPackage(name, executables, depends))
    return tuple(out)


def _executable(script: str) -> str:
    return script.removeprefix(SCRIPT_PREFIX).replace("-", "_")


def package_xml(package: RosPackage, project: Project) -> str:
    """The package manifest (format 3, build type ament_python)."""
    depends = "".join(f"  <exec_depend>{d}</exec_depend>\n" for d in package.depends)
    return (
        '<?xml version="1.0"?>\n'
        '<package format="3">\n'
        f"  <name>{package.name}</name>\n"
        f"  <version>{project.version}</version>\n"
        f"  <description>{project.description}: {package.name}</description>\n"
        f'  <maintainer email="{project.maintainer[1]}">{project.maintainer[0]}</maintainer>\n'
        f"  <license>{project.license or 'unknown'}</license>\n"
        f"{depends}"
        "  <export>\n    <build_type>ament_python</build_type>\n  </export>\n"
        "</package>\n"
    )


def setup_py(package: RosPackage, project: Project) -> str:
    """A setup.py installing the sources, the data, the ament index marker and the executables."""
    scripts = [f"{exe} = {target}" for exe, target in sorted(package.executables.items())]
    return (
        '"""Generated by `hdrc3 workspace` from the project\'s pyproject.toml."""\n\n'
        "from setuptools import find_packages, setup\n\n"
        "setup(\n"
        f"    name={package.name!r},\n"
        f"    version={project.version!r},\n"
        f"    packages=find_packages(include=[{package.name!r}, {package.name + '.*'!r}]),\n"
        f"    package_data={{'': {list(project.package_data)!r}}},\n"
        "    data_files=[\n"
        "        ('share/ament_index/resource_index/packages',"
        f" ['resource/{package.name}']),\n"
        f"        ('share/{package.name}', ['package.xml']),\n"
        "    ],\n"
        f"    entry_points={{'console_scripts': {scripts!r}}},\n"
        ")\n"
    )


def setup_cfg(package: RosPackage) -> str:
    """Executables under ``lib/<package>/``, where ``ros2 run`` looks."""
    lib = f"$base/lib/{package.name}"
    return f"[develop]\nscript_dir={lib}\n[install]\ninstall_scripts={lib}\n"


def write_workspace(out: Path, project: Project) -> tuple[RosPackage, ...]:
    """Write ``out/src/<package>/`` for every package; returns what it wrote.

    Raises:
        ConfigError: ``out/src/<package>`` exists and was not written by this function.
    """
    packages = ros_packages(project)
    for package in packages:
        directory = out / "src" / package.name
        link = directory / package.name
        if directory.exists() and not (directory / "package.xml").is_file():
            raise ConfigError(f"{directory} exists and is not a generated package: not touched")
        (directory / "resource").mkdir(parents=True, exist_ok=True)
        (directory / "resource" / package.name).write_text("")
        (directory / "package.xml").write_text(package_xml(package, project))
        (directory / "setup.py").write_text(setup_py(package, project))
        (directory / "setup.cfg").write_text(setup_cfg(package))
        if link.is_symlink():
            link.unlink()
        link.symlink_to((project.root / package.name).resolve(), target_is_directory=True)
    return packages
