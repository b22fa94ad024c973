"""The registry of motion keywords, functions and INSTALL kinds: one per cell or session, fed by features."""

from __future__ import annotations

import difflib
from importlib import metadata
from typing import Callable, Iterable

from orc_rpl.application.declarations import FunctionSpec, InstallKindSpec, MotionSpec
from orc_rpl.errors import OrcError

#: Entry-point group through which features (built-in and third-party) register themselves.
FEATURE_GROUP = "orc_rpl.features"

#: The built-in features. They register through the same entry points as third-party ones (declared in
#: pyproject.toml, read from the installed package's metadata); this list only names what must be there,
#: so a checkout that was never installed fails with a clear message instead of a half-empty language.
BUILTIN_FEATURES: tuple[str, ...] = (
    "standard", "equipment", "deburring", "spot_welding", "arc_welding", "assembly", "materials_handling",
)
#: The distribution that provides the built-in features.
DISTRIBUTION = "orc_rpl"
#: Loaded first: other features build on its words (motion attributes, POSE...).
FIRST_FEATURE = "standard"


class DuplicateDeclaration(OrcError):
    """Two features declared the same word; the message names both."""


class FeaturesMissing(OrcError):
    """The package metadata that registers the built-in features is missing (a checkout never installed)."""


def suggest(word: str, candidates: Iterable[str]) -> str | None:
    """The closest known word, for `did you mean ...?` (case-insensitive first)."""
    pool = list(candidates)
    lowered = {c.lower(): c for c in pool}
    if word.lower() in lowered and lowered[word.lower()] != word:
        return lowered[word.lower()]
    matches = difflib.get_close_matches(word, pool, n=1, cutoff=0.7)
    return matches[0] if matches else None


class Registry:
    """Known motion keywords, functions and INSTALL kinds; refuses duplicates."""

    def __init__(self) -> None:
        self.motions: dict[str, MotionSpec] = {}
        self.functions: dict[str, FunctionSpec] = {}
        self.install_kinds: dict[str, InstallKindSpec] = {}
        self.features: list[str] = []

    def _refuse_duplicate(self, kind: str, name: str, existing_origin: str, origin: str) -> None:
        raise DuplicateDeclaration(
            f"{kind} '{name}' is declared twice: by feature '{existing_origin}' and by feature '{origin}'"
        )

    def add_motion(self, spec: MotionSpec) -> MotionSpec:
        """Register a motion keyword."""
        if spec.keyword in self.motions:
            self._refuse_duplicate("motion keyword", spec.keyword, self.motions[spec.keyword].origin, spec.origin)
        self.motions[spec.keyword] = spec
        return spec

    def add_function(self, spec: FunctionSpec) -> FunctionSpec:
        """Register a function."""
        if spec.name in self.functions:
            self._refuse_duplicate("function", spec.name, self.functions[spec.name].origin, spec.origin)
        self.functions[spec.name] = spec
        return spec

    def add_install_kind(self, spec: InstallKindSpec) -> InstallKindSpec:
        """Register an INSTALL kind."""
        if spec.name in self.install_kinds:
            self._refuse_duplicate("INSTALL kind", spec.name, self.install_kinds[spec.name].origin, spec.origin)
        self.install_kinds[spec.name] = spec
        return spec

    def load(self, name: str, register: Callable[[Registry], None]) -> None:
        """Run one feature's registration function."""
        if name in self.features:
            raise DuplicateDeclaration(f"feature '{name}' is registered twice")
        register(self)
        self.features.append(name)

    def words(self) -> list[str]:
        """Every registered word, for completion."""
        return sorted({*self.motions, *self.functions, *self.install_kinds})


def _feature_entry_points(group: str = FEATURE_GROUP) -> dict[str, metadata.EntryPoint]:
    """The installed features by name; one name offered by two distributions is refused, naming both."""
    found: dict[str, metadata.EntryPoint] = {}
    for entry_point in metadata.entry_points(group=group):
        other = found.get(entry_point.name)
        if other is not None and other.value != entry_point.value:
            raise DuplicateDeclaration(
                f"feature '{entry_point.name}' is registered twice: by {_origin(other)} and by {_origin(entry_point)}")
        found[entry_point.name] = entry_point
    return found


def _origin(entry_point: metadata.EntryPoint) -> str:
    dist = entry_point.dist
    return f"'{entry_point.value}' ({dist.name if dist is not None else 'unknown package'})"


def default_registry(extra_features: bool = True, group: str = FEATURE_GROUP) -> Registry:
    """A registry with every feature registered in the `orc_rpl.features` entry points: the built-in ones
    (of this package) and, unless `extra_features` is false, third-party ones; `standard` first, the rest
    by name. Missing built-in entry points raise FeaturesMissing (the package is not installed)."""
    entry_points = _feature_entry_points(group)
    missing = [name for name in BUILTIN_FEATURES if name not in entry_points]
    if missing:
        raise FeaturesMissing(
            f"the built-in features {', '.join(missing)} are not registered: the package metadata of "
            f"{DISTRIBUTION} (its '{group}' entry points) is missing or stale; install the package, e.g. "
            f"`pip install -e .` in the checkout")
    if not extra_features:
        entry_points = {name: ep for name, ep in entry_points.items() if name in BUILTIN_FEATURES}
    order = sorted(entry_points, key=lambda name: (name != FIRST_FEATURE, name))
    registry = Registry()
    for name in order:
        entry_point = entry_points[name]
        try:
            register = entry_point.load()
        except Exception as error:  # a broken plugin must not take the system down with a traceback
            raise OrcError(f"feature '{name}' ({entry_point.value}) could not be loaded: {error}") from error
        registry.load(name, register)
    return registry
