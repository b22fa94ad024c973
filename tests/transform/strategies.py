"""Hypothesis strategies for world models (YAML text) and off-line programs that move through them."""

from __future__ import annotations

from dataclasses import dataclass, field

from hypothesis import strategies as st

OBJECT_NAMES = ["table", "plate", "fixture", "clamp", "pos0", "home", "jig", "p"]
FRAME_NAMES = ["p", "q", "top", "pos1", "home"]
LENGTHS = st.integers(-600, 600).map(lambda v: "0" if v == 0 else f"{v}mm")
ANGLES = st.sampled_from(["0", "90deg", "-90deg", "180deg", "30deg", "-45deg"])


@dataclass
class Entity:
    """What a generated program may move to."""

    refs: list[str] = field(default_factory=list)     #: `obj`, `obj.frame`, `obj.path[i]`
    tools: list[str] = field(default_factory=list)


def poses() -> st.SearchStrategy[str]:
    return st.tuples(LENGTHS, LENGTHS, LENGTHS, ANGLES, ANGLES, ANGLES).map(lambda t: "[" + ", ".join(t) + "]")


@st.composite
def worlds(draw) -> tuple[str, Entity]:  # type: ignore[no-untyped-def]
    """A world file's text and the entities a program can name."""
    names = draw(st.lists(st.sampled_from(OBJECT_NAMES), min_size=1, max_size=4, unique=True))
    lines = ["# generated", "robot:", "  model: irb2400", "  pose: [0, 0, 0, 0, 0, 0]", "", "world:"]
    entity = Entity()
    for i, name in enumerate(names):
        parent = draw(st.sampled_from(["world"] + names[:i]))
        lines.append(f"  {name}:")
        if parent != "world":
            lines.append(f"    parent: {parent}")
        lines.append(f"    pose: {draw(poses())}")
        if draw(st.booleans()):
            lines.append("    online_frame: true")
        if draw(st.booleans()):
            lines += ["    model:", "      geometry: box", "      size: [100mm, 100mm, 10mm]"]
        frames = draw(st.lists(st.sampled_from(FRAME_NAMES), max_size=3, unique=True))
        if frames:
            lines.append("    frames:")
            lines += [f"      {f}: {draw(poses())}" for f in frames]
            entity.refs += [f"{name}.{f}" for f in frames]
            if draw(st.booleans()):
                points = [draw(st.one_of(st.sampled_from(frames), poses())) for _ in range(draw(st.integers(1, 3)))]
                lines += ["    paths:", f"      seam: [{', '.join(points)}]"]
                entity.refs += [f"{name}.seam[{k}]" for k in range(1, len(points) + 1)]
        entity.refs.append(name)
    if draw(st.booleans()):
        lines += ["  holder:", "    parent: flange", f"    pose: {draw(poses())}",
                  "  gripper:", "    parent: holder", f"    pose: {draw(poses())}", "    tool: true"]
        entity.tools.append("gripper")
    return "\n".join(lines) + "\n", entity


@st.composite
def programs(draw, entity: Entity) -> str:  # type: ignore[no-untyped-def]
    """Off-line program text moving through the world's entities, inside loops and branches."""
    ref = st.sampled_from(entity.refs)
    tools = ["ARM"] + entity.tools

    def motion(depth: int) -> str:
        tool = draw(st.sampled_from(tools))
        target = draw(ref)
        head = f"moveto {target}" if tool == "ARM" and draw(st.booleans()) else f"{draw(st.sampled_from(['move', 'lmove']))} {tool} to {target}"
        if draw(st.booleans()):
            head += f" via {draw(ref)}"
        if draw(st.booleans()):
            head += " speed=0.5 * Vmax"
        return "    " * depth + head

    def block(depth: int, size: int) -> list[str]:
        out: list[str] = []
        for _ in range(size):
            kind = draw(st.sampled_from(["move", "move", "move", "wait", "comment", "blank", "if", "for"] if depth < 2
                                        else ["move", "wait", "comment"]))
            pad = "    " * depth
            if kind == "move":
                out.append(motion(depth))
            elif kind == "wait":
                out.append(pad + "wait 0.1s")
            elif kind == "comment":
                out.append(pad + "# note")
            elif kind == "blank":
                out.append("")
            elif kind == "if":
                out.append(pad + "if n > 1:")
                out += block(depth + 1, draw(st.integers(1, 3)))
                if draw(st.booleans()):
                    out.append(pad + "else:")
                    out += block(depth + 1, draw(st.integers(1, 2)))
            else:
                out.append(pad + "for i in 1..2:")
                out += block(depth + 1, draw(st.integers(1, 3)))
        return out

    header = ["# generated program"] if draw(st.booleans()) else []
    return "\n".join(header + ["const Vmax = 1mps", "n = 2"] + block(0, draw(st.integers(1, 8)))) + "\n"
