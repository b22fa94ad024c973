"""Generated worlds (random trees, poses with units, comments anywhere a person puts them) read back exactly."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from orc_rpl.world import Pose, loads_world, restore_model_attributes, split_model_attributes

LENGTH_UNITS = {"mm": 1e-3, "cm": 1e-2, "m": 1.0, "": 1.0}
ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0, "": 1.0}

comment_text = st.text(st.characters(min_codepoint=32, max_codepoint=126), max_size=20).map(lambda s: "# " + s.strip())
maybe_comment = st.one_of(st.just(""), comment_text.map(lambda c: "   " + c))


@st.composite
def written_value(draw, units: dict[str, float]) -> tuple[str, float]:
    """One pose value as written (`-300mm`, `90deg`, `0`) and its SI value."""
    number = draw(st.integers(-2000, 2000))
    unit = draw(st.sampled_from(sorted(units)))
    if unit == "" and number != 0:
        number = draw(st.integers(-3, 3))
    return f"{number}{unit}", number * units[unit] if unit not in ("mm", "cm") else number / (1000 if unit == "mm" else 100)


@st.composite
def written_pose(draw) -> tuple[str, tuple[float, ...]]:
    values = [draw(written_value(LENGTH_UNITS)) for _ in range(3)] + [draw(written_value(ANGLE_UNITS)) for _ in range(3)]
    return "[" + ", ".join(v[0] for v in values) + "]", tuple(v[1] for v in values)


@dataclass
class Spec:
    """What the generator meant, to compare with what the loader read."""

    parents: dict[str, str] = field(default_factory=dict)
    poses: dict[str, tuple[float, ...]] = field(default_factory=dict)   # object or object.frame -> SI values
    text: str = ""


@st.composite
def worlds(draw) -> Spec:
    spec = Spec()
    count = draw(st.integers(0, 7))
    names = [f"obj{i}" for i in range(count)]
    for i, name in enumerate(names):
        spec.parents[name] = draw(st.sampled_from(["world", "robot", "flange"] + names[:i]))
    order = draw(st.permutations(names))            # parents may come after their children
    lines = [draw(comment_text) for _ in range(draw(st.integers(0, 2)))]
    if draw(st.booleans()):
        lines += ["robot:", "  model: irb2400" + draw(maybe_comment), f"  pose: {draw(written_pose())[0]}"]
    lines.append("world:" + draw(maybe_comment))
    for name in order:
        if draw(st.booleans()):
            lines.append("")
        if draw(st.booleans()):
            lines.append("  " + draw(comment_text))
        lines.append(f"  {name}:" + draw(maybe_comment))
        if spec.parents[name] != "world" or draw(st.booleans()):
            lines.append(f"    parent: {spec.parents[name]}" + draw(maybe_comment))
        text, si = draw(written_pose())
        lines.append(f"    pose: {text}" + draw(maybe_comment))
        spec.poses[name] = si
        if draw(st.booleans()):
            lines.append("    online_frame: true")
        if draw(st.booleans()):
            lines += ["    model:", "      geometry: box" + draw(maybe_comment), "      size: [1m, 2m, 3m]"]
        frames = [f"f{j}" for j in range(draw(st.integers(0, 3)))]
        if frames:
            lines.append("    frames:")
            for frame in frames:
                text, si = draw(written_pose())
                lines.append(f"      {frame}: {text}" + draw(maybe_comment))
                spec.poses[f"{name}.{frame}"] = si
                if draw(st.booleans()):
                    lines.append("      " + draw(comment_text))
            lines += ["    paths:", f"      p: [{', '.join(reversed(frames))}]"]
        if draw(st.booleans()):
            lines += ["    soft:", f"      count: {draw(st.integers(-5, 5))}" + draw(maybe_comment)]
    end = draw(st.sampled_from(["\n", "", "\n\n"]))
    spec.text = "\n".join(lines) + end
    return spec


FAST = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
#: The edit properties reuse the same generator; half as many examples keeps the folder under ~15 s.
QUICK = settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FAST
@given(worlds())
def test_generated_world_dumps_loads_and_dumps_byte_identical(spec: Spec) -> None:
    world = loads_world(spec.text)
    assert world.dump() == spec.text
    assert loads_world(world.dump()).dump() == spec.text
    for obj in world.objects:
        assert obj.parent == spec.parents[obj.name]
    for name, si in spec.poses.items():
        got = world.lookup(name)
        pose = got.pose
        assert np.allclose([pose.x, pose.y, pose.z, pose.a, pose.b, pose.c], si, atol=1e-12), name


@QUICK
@given(worlds())
def test_generated_world_split_restores_exactly(spec: Spec) -> None:
    world = loads_world(spec.text)
    online, store = split_model_attributes(world)
    assert restore_model_attributes(online, store).dump() == spec.text


@QUICK
@given(worlds(), st.data())
def test_teaching_into_a_generated_world_changes_only_that_frame(spec: Spec, data) -> None:
    world = loads_world(spec.text)
    if not world.objects:
        return
    owner = data.draw(st.sampled_from([o.name for o in world.objects]))
    pose = Pose(0.1, -0.2, 0.3, 0.5, -0.25, 1.0, frame=owner)
    after = loads_world(world.with_frame(owner, "taught", pose).dump())
    assert np.allclose(after.relative_pose(f"{owner}.taught", owner).matrix(), pose.matrix(), atol=1e-9)
    kept = [line for line in spec.text.splitlines() if line.strip()]
    new = [line for line in after.dump().splitlines() if line.strip()]
    assert [line for line in new if "taught:" not in line and line.strip() != "frames:"] == [line for line in kept if line.strip() != "frames:"]
    for other in world.objects:
        assert after.object(other.name).frames[: len(other.frames)] == other.frames
