"""The registry of motion keywords, functions and INSTALL kinds: one per cell or session, fed by features."""

from __future__ import annotations

import difflib
from importlib import metadata
from typing import Callable, Iterable

from orc_rpl.application.declarations import FunctionSpec, InstallKindSpec, MotionSpec
from orc_rpl.errors import OrcError

#: Entry-point group through which features (built-in and third-party) register themselves.
FEATURE_GROUP = "orc_rpl.features"

#: The built-in features, in registration order: `name -> module:function`. They are also
#: declared as entry points in pyproject.toml; this list is the fallback for a source tree
#: whose package metadata is missing or stale.
BUILTIN_FEATURES: dict[str, str] = {
    "standard": "orc_rpl.application.features.standard:register",
    "equipment": "orc_rpl.application.features.equipment:register",
    "deburring": "orc_rpl.application.features.deburring:register",
    "spot_welding": "orc_rpl.application.features.spot_welding:register",
    "arc_welding": "orc_rpl.application.features.arc_welding:register",
    "assembly": "orc_rpl.application.features.assembly:register",
    "materials_handling": "orc_rpl.application.features.materials_handling:register",
}


class DuplicateDeclaration(OrcError):
    """Two features declared the same word; the message names both."""


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


def _load_reference(reference: str) -> Callable[[Registry], None]:
    module_name, _, attribute = reference.partition(":")
    module = __import__(module_name, fromlist=[attribute])
    return getattr(module, attribute)


def default_registry(extra_features: bool = True) -> Registry:
    """A registry with the built-in features and every installed third-party feature."""
    registry = Registry()
    entry_points = {ep.name: ep for ep in metadata.entry_points(group=FEATURE_GROUP)} if extra_features else {}
    for name, reference in BUILTIN_FEATURES.items():
        registry.load(name, _load_reference(reference))
    for name, entry_point in sorted(entry_points.items()):
        if name in BUILTIN_FEATURES:
            continue  # the built-ins are loaded above, in their documented order
        try:
            register = entry_point.load()
        except Exception as error:  # a broken plugin must not take the system down with a traceback
            raise OrcError(f"feature '{name}' ({entry_point.value}) could not be loaded: {error}") from error
        registry.load(name, register)
    return registry
