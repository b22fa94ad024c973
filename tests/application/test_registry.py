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


class _EntryPoint:
    """A stand-in for importlib.metadata.EntryPoint."""

    def __init__(self, name: str, value: str, register: object, dist: str) -> None:
        self.name, self.value, self._register = name, value, register
        self.dist = type("Dist", (), {"name": dist})()

    def load(self) -> object:
        return self._register


def _installed(monkeypatch: pytest.MonkeyPatch, extra: list[_EntryPoint]) -> None:
    from importlib import metadata

    from orc_rpl.application import registry as module

    real = list(metadata.entry_points(group=module.FEATURE_GROUP))
    monkeypatch.setattr(module.metadata, "entry_points", lambda group: [*real, *extra] if group == module.FEATURE_GROUP else [])


def test_builtin_features_come_from_the_package_metadata() -> None:
    from importlib import metadata

    from orc_rpl.application.registry import BUILTIN_FEATURES, FEATURE_GROUP

    declared = {ep.name: ep.dist.name for ep in metadata.entry_points(group=FEATURE_GROUP)}
    assert all(declared.get(name) == "orc_rpl" for name in BUILTIN_FEATURES)
    assert REGISTRY.features[0] == "standard" and set(BUILTIN_FEATURES) <= set(REGISTRY.features)


def test_a_third_party_feature_is_loaded_like_a_builtin(monkeypatch: pytest.MonkeyPatch) -> None:
    def register(registry: Registry) -> None:
        registry.add_motion(MotionSpec("PAINTMOVE", "paint along a path", (), origin="painting"))
    _installed(monkeypatch, [_EntryPoint("painting", "paint:register", register, "orc-painting")])
    assert "PAINTMOVE" in default_registry().motions
    assert "PAINTMOVE" not in default_registry(extra_features=False).motions


def test_a_feature_name_claimed_by_two_packages_is_refused(monkeypatch: pytest.MonkeyPatch) -> None:
    _installed(monkeypatch, [_EntryPoint("deburring", "other:register", lambda r: None, "orc-other")])
    with pytest.raises(DuplicateDeclaration, match="feature 'deburring' is registered twice: .*orc-other"):
        default_registry()


def test_missing_metadata_is_a_clear_error(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
                                           tmp_path: object) -> None:
    from orc_rpl.application import registry as module
    from orc_rpl.application.registry import FeaturesMissing
    from orc_rpl.cli import main

    monkeypatch.setattr(module.metadata, "entry_points", lambda group: [])
    with pytest.raises(FeaturesMissing, match="not registered: the package metadata .*pip install -e ."):
        default_registry()
    program = tmp_path / "p.rpl"  # type: ignore[operator]
    program.write_text("PRINT 1\n")
    assert main(["check", str(program)]) == 2
    err = capsys.readouterr().err
    assert "orc: the built-in features standard, equipment" in err and "Traceback" not in err


def test_a_motion_computed_early_may_call_only_functions_of_their_arguments() -> None:
    """Planning ahead evaluates a motion's target before the motions before it have run: IDENT (the last
    recording) or a seam's functions must wait for their statement."""
    registry = default_registry()
    early = {name for name, spec in registry.functions.items() if spec.of_arguments}
    assert early == {"POSE", "AXES", "JOINTS", "TRANSL", "INV", "OFFS", "RELTOOL", "ABS", "ROUND", "SQRT", "SIN",
                     "COS", "ATAN2", "MIN", "MAX", "LEN"}
    assert registry.functions["IDENT"].pure and not registry.functions["IDENT"].of_arguments
