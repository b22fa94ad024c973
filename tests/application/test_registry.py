"""The registry: refuses duplicates naming both features; contract tests over every registered word."""

from __future__ import annotations

import pytest

from orc_rpl.application.declarations import TYPE_TAGS, FunctionSpec, MotionSpec
from orc_rpl.application.registry import DuplicateDeclaration, Registry, default_registry
from orc_rpl.syntax.lexicon import is_motion_keyword
from orc_rpl.syntax.units import Dimension

REGISTRY = default_registry()


def test_builtin_words_of_language_md_are_declared() -> None:
    assert {"MOVE", "JMOVE", "LMOVE", "CMOVE", "GRINDMOVE", "WELDMOVE", "TRACKMOVE", "IDENTMOVE"} <= set(REGISTRY.motions)
    assert {"RecordSeam", "OptimalSpeed", "Tracking", "CALIBRATE", "IDENT", "POSE", "OFFS", "RELTOOL"} <= set(REGISTRY.functions)
    assert {"SpotGun", "ArcWelder", "Gripper", "Grinder", "LaserDistance", "ForceSensor", "Switch"} <= set(REGISTRY.install_kinds)


def test_duplicate_motion_names_both_features() -> None:
    registry = Registry()
    registry.add_motion(MotionSpec("XMOVE", "first", (), origin="alpha"))
    with pytest.raises(DuplicateDeclaration, match="declared twice: by feature 'alpha' and by feature 'beta'"):
        registry.add_motion(MotionSpec("XMOVE", "second", (), origin="beta"))


def test_duplicate_function_is_refused() -> None:
    registry = Registry()
    registry.add_function(FunctionSpec("F", "doc", ()))
    with pytest.raises(DuplicateDeclaration):
        registry.add_function(FunctionSpec("F", "doc", ()))


def test_loading_the_same_feature_twice_is_refused() -> None:
    registry = Registry()
    registry.load("x", lambda r: None)
    with pytest.raises(DuplicateDeclaration, match="feature 'x' is registered twice"):
        registry.load("x", lambda r: None)


@pytest.mark.parametrize("spec", REGISTRY.motions.values(), ids=lambda s: s.keyword)
def test_motion_contract(spec: MotionSpec) -> None:
    assert is_motion_keyword(spec.keyword), "a motion keyword must end in MOVE so the grammar accepts it"
    assert spec.doc and spec.origin, "every primitive is documented and names its feature"
    assert set(spec.targets) <= {"TO", "ALONG"} and spec.targets
    names = spec.attribute_names
    assert len(names) == len(set(names)), "attribute names and aliases are unique"
    for attribute in spec.attributes:
        assert attribute.name.isupper() and attribute.doc
        assert attribute.types and all(isinstance(t, Dimension) or t in TYPE_TAGS or t.startswith("installed:")
                                       for t in attribute.types)
    for kind in spec.requires:
        assert kind in REGISTRY.install_kinds


@pytest.mark.parametrize("spec", REGISTRY.functions.values(), ids=lambda s: s.name)
def test_function_contract(spec: FunctionSpec) -> None:
    assert spec.doc and spec.origin
    assert spec.min_args <= (spec.max_args if spec.max_args is not None else 99)


def test_install_kinds_document_attributes_and_methods() -> None:
    for kind in REGISTRY.install_kinds.values():
        assert kind.doc and kind.origin
        assert all(a.doc for a in kind.attributes) and all(m.doc for m in kind.methods)
