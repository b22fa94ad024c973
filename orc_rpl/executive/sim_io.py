"""Scripted IO of the simulated cell: a program's `<name>.sim.yaml` makes inputs change at times or on conditions."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from orc_rpl.errors import SourceError, UsageError
from orc_rpl.executive import operators as ops
from orc_rpl.executive.machine import CELL_BANKS
from orc_rpl.executive.signals import RunError
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.parser import parse_statement
from orc_rpl.syntax.units import LENGTH, MASS, TIME, Quantity, parse_literal
from orc_rpl.syntax.reading import read_text
from orc_rpl.world.pose import Pose
from orc_rpl.world.source import MAX_YAML_NESTING, too_deep

_KEYS = {"at", "when", "after", "set", "value", "repeat"}


@dataclass(slots=True)
class IOEvent:
    """Set `channel` to `value` at time `at_s`, or `after_s` after `when` became true."""

    bank: str                                   #: the cell's bank name (DigIn, AnaIn...)
    number: int
    value: float
    at_s: float | None = None
    when: Callable[[], bool] | None = None
    after_s: float = 0.0
    repeat: bool = False
    due_s: float | None = None                  #: when the pending set happens
    armed: bool = True


class IOScript:
    """The events of one script, run as a process model of the cell (`CellIO.add_process`), and the
    equipment models the script installs beside it (weld guns, parts to pick)."""

    def __init__(self, events: list[IOEvent]) -> None:
        self.events = events
        self.weld_guns: list[Any] = []       #: plant.processes.WeldGunProcess
        self.parts: list[Any] = []           #: plant.processes.PartSupply
        self.castings: list[Any] = []        #: plant.processes.CastingEdge

    def __call__(self, io: Any, time_s: float) -> None:
        for event in self.events:
            if event.armed:
                if event.at_s is not None:
                    if time_s >= event.at_s - 1e-9:
                        event.due_s, event.armed = time_s, False
                elif event.when is not None and event.when():
                    event.due_s, event.armed = time_s + event.after_s, False
            elif event.repeat and event.due_s is None and event.when is not None and not event.when():
                event.armed = True
            if event.due_s is not None and time_s >= event.due_s - 1e-9:
                bank = io.bank(event.bank)
                bank[event.number] = bool(event.value) if event.bank.startswith("Dig") else float(event.value)
                event.due_s = None


def script_path(program: str | Path, world_dir: str | Path | None = None) -> Path | None:
    """The IO script of a program: `<stem>.sim.yaml` in `world_dir` (or beside a world file) if given, else beside the program."""
    program = Path(program)
    if world_dir is not None and Path(world_dir).is_file():
        world_dir = Path(world_dir).parent
    name = program.with_suffix(".sim.yaml").name
    for folder in ([Path(world_dir)] if world_dir is not None else []) + [program.parent]:
        candidate = folder / name
        if candidate.is_file():
            return candidate
    return None


def load_script(path: str | Path, io: Any, tcp: Callable[[], Pose],
                set_payload: Callable[[float], None] | None = None,
                push: Callable[[Any, Any], None] | None = None) -> IOScript:
    """Read a script and install it on the cell's IO; a mistake is a UsageError naming the file and the event.

    Besides `events:`, a script may list `weld_guns:` (`close`, `weld_ok`, `reaction`, `weld_time`, `fail`)
    and `parts:` (`close`: the gripper's output, `masses`: the part grasped at each closing, 0kg for none;
    `set_payload` puts it on the plant's flange); `push(force, point)` makes a casting's contact force act on the arm."""
    from ruamel.yaml import YAML
    from ruamel.yaml.error import YAMLError

    text = read_text(path, "IO script")
    deep = too_deep(text)
    if deep is not None:
        raise UsageError(f"IO script '{path}', line {deep[0]}: nested too deeply (more than {MAX_YAML_NESTING} levels)")
    try:
        with warnings.catch_warnings():  # ruamel's warnings (a reused anchor) are not for the user's terminal
            warnings.simplefilter("ignore")
            data = YAML(typ="safe", pure=True).load(text) or {}
    except (YAMLError, ValueError, OverflowError) as error:  # also an integer too long for Python
        raise UsageError(f"cannot read the IO script '{path}': {error}") from None
    unknown = set(data) - {"events", "weld_guns", "parts", "castings", "seam"} if isinstance(data, dict) else set()
    if unknown:
        raise UsageError(f"IO script '{path}': unknown section {', '.join(sorted(unknown))}; "
                         "expected events, weld_guns, parts, castings, seam")
    equipment_only = isinstance(data, dict) and ("weld_guns" in data or "parts" in data or "castings" in data or "seam" in data)
    entries = data.get("events", [] if equipment_only else None) \
        if isinstance(data, dict) else None
    if not isinstance(entries, list):
        raise UsageError(f"IO script '{path}': expected a list under 'events:'")
    events = []
    place = _Places(path, text)
    for i, entry in enumerate(entries, 1):
        try:
            events.append(_event(entry, io, tcp))
        except (UsageError, RunError, SourceError, ValueError, KeyError, TypeError, AttributeError, OverflowError) as error:
            raise UsageError(f"{place.of('events', i)}IO script event {i}: {_reason(error)}") from None
    script = IOScript(events)
    io.add_process(script)
    where, section, index = "weld_guns", "weld_guns", 0
    try:
        for i, entry in enumerate(_entries(data, "weld_guns"), 1):
            where, index = f"weld gun {i}", i
            script.weld_guns.append(_weld_gun(entry, io, tcp))
        where, section, index = "parts", "parts", 0
        for i, entry in enumerate(_entries(data, "parts"), 1):
            where, index = f"parts {i}", i
            script.parts.append(_parts(entry, io, set_payload))
        where, section, index = "castings", "castings", 0
        for i, entry in enumerate(_entries(data, "castings"), 1):
            where, index = f"casting {i}", i
            script.castings.append(_casting(entry, tcp, push))
    except (UsageError, RunError, SourceError, ValueError, KeyError, TypeError, AttributeError, OverflowError) as error:
        raise UsageError(f"{place.of(section, index)}IO script {where}: {_reason(error)}") from None
    for process in (*script.weld_guns, *script.parts, *script.castings):
        io.add_process(process)
    if isinstance(data, dict) and "seam" in data:
        try:
            io.add_process(seam_process(data["seam"] or {}))
        except (UsageError, ValueError, TypeError, KeyError, AttributeError, OverflowError) as error:
            raise UsageError(f"{place.of('seam', 0)}IO script seam: {_reason(error)}") from None
    return script


class _Places:
    """Where a script's sections and entries stand, as a `file:line:col: ` prefix for its error messages."""

    def __init__(self, path: str | Path, text: str) -> None:
        from ruamel.yaml import YAML

        self.path = path
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                self.root: Any = YAML(typ="rt").compose(text)
        except Exception:  # the safe load read it; a composer that cannot is no reason to lose the message
            self.root = None

    def of(self, section: str, index: int) -> str:
        """`file:line:col: ` of entry `index` (1-based; 0: the section itself), or of the file when unknown."""
        node = None
        for key, value in getattr(self.root, "value", ()) if isinstance(getattr(self.root, "value", None), list) else ():
            if getattr(key, "value", None) == section:
                node = key if index == 0 else value
                break
        items = getattr(node, "value", None)
        if index > 0 and isinstance(items, list) and index <= len(items) and not isinstance(items[index - 1], tuple):
            node = items[index - 1]
        mark = getattr(node, "start_mark", None)
        if mark is None:
            return f"{self.path}:1:1: "
        return f"{self.path}:{mark.line + 1}:{mark.column + 1}: "


def _reason(error: Exception) -> str:
    """The message of an error about a script entry; a mistyped value (a list where a number belongs) says so."""
    if isinstance(error, OverflowError):
        return f"a number is too large ({error})"
    if isinstance(error, (TypeError, AttributeError)):
        return f"a value has the wrong type ({error})"
    return str(error)


#: `seam:` keys that are lengths, and the other ones
_SEAM_LENGTHS = ("amplitude", "wavelength", "raggedness", "correlation", "edge", "edge_width", "range", "noise")


def seam_process(entry: Any) -> Any:
    """The `seam:` section: a ragged seam (plant.processes.seam) with lengths such as 4mm; start/end are world
    points [x, y, z] (default: the first path the laser is used along), missing: [from, to] along the seam."""
    from orc_rpl.plant.processes.seam import SeamProcess

    if not isinstance(entry, dict) or not set(entry) <= {*_SEAM_LENGTHS, "seed", "start", "end", "missing"}:
        raise UsageError(f"a seam has {', '.join(_SEAM_LENGTHS)}, seed, start, end, missing; got {entry!r}")
    kwargs: dict[str, Any] = {key: _length(entry[key]) for key in _SEAM_LENGTHS if key in entry}
    if "seed" in entry:
        kwargs["seed"] = int(entry["seed"])
    for key in ("start", "end", "missing"):
        if key in entry:
            points = entry[key]
            if not isinstance(points, list) or len(points) != (2 if key == "missing" else 3):
                raise UsageError(f"seam {key} must be a list of {2 if key == 'missing' else 3} lengths, got {points!r}")
            kwargs[key] = tuple(_length(v) for v in points)
    return SeamProcess(**kwargs)


def simulated_sensors(io: Any, tcp: Callable[[], Any]) -> dict[str, Any]:
    """The cell's simulated sampling for the sensor kinds that have a process model: LaserDistance on the seam,
    ForceSensor on the castings' contact force (with a bias and noise).

    `tcp()` gives the TCP position (x, y, z) in m of the tool last moved; the seam is the cell's SeamProcess
    (from the script's `seam:`), or a default one added to the cell when a simulated laser is first read."""
    from orc_rpl.motion.force_sensor import simulated_gauge
    from orc_rpl.motion.sensors import LaserValue
    from orc_rpl.plant.processes.casting import CastingEdge
    from orc_rpl.plant.processes.seam import cell_seam

    def laser(name: str) -> Any:
        def sample(sensor: Any) -> LaserValue:
            found, offset, edge = cell_seam(io).measure(tcp())
            return LaserValue(found, offset, edge)
        return sample

    def contact_force_n() -> float:  # the cell's contact force: what its castings push back with
        return float(sum(getattr(p, "force_n", 0.0) for p in getattr(io, "processes", ()) if isinstance(p, CastingEdge)))

    def force(name: str) -> Any:
        return simulated_gauge(name, contact_force_n)
    return {"LaserDistance": laser, "ForceSensor": force}


def _length(text: Any) -> float:
    text = str(text).replace(" ", "")
    sign = -1.0 if text.startswith("-") else 1.0
    value = parse_literal(text.lstrip("-+"))
    if type(value) is Quantity and value.dim == LENGTH:
        return sign * value.value
    if value == 0:
        return 0.0
    raise UsageError(f"expected a length such as 4mm, got {text!r}")


def _entries(data: dict, key: str) -> list:
    entries = data.get(key) or []
    if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
        raise UsageError(f"'{key}:' must be a list of mappings")
    return entries


def _channel(text: Any, io: Any, bank: str) -> int:
    target = _expression(str(text))
    if not (isinstance(target, n.Index) and isinstance(target.value, n.Name) and target.value.id in CELL_BANKS
            and CELL_BANKS[target.value.id] == bank):
        raise UsageError(f"expected a channel such as {bank}[2], not {text!r}")
    number = int(parse_literal(_number_text(target.index)))
    io.bank(bank)[number]  # the channel must exist
    return number


def _weld_gun(entry: dict, io: Any, tcp: Callable[[], Pose]) -> Any:
    from orc_rpl.plant.processes import WeldGunProcess

    if not set(entry) <= {"close", "weld_ok", "reaction", "weld_time", "fail", "max_speed"} \
            or not {"close", "weld_ok"} <= set(entry):
        raise UsageError(f"a weld gun has close, weld_ok and optionally reaction, weld_time, fail, max_speed; got {entry!r}")

    def position() -> tuple[float, float, float]:
        pose = tcp()
        return (pose.x, pose.y, pose.z)
    return WeldGunProcess(_channel(entry["close"], io, "DigOut"), _channel(entry["weld_ok"], io, "DigIn"),
                          _seconds(entry.get("reaction", "80ms")), _seconds(entry.get("weld_time", "200ms")),
                          tcp=position, fail=bool(entry.get("fail", False)),
                          **({"max_speed_m_s": _speed(entry["max_speed"])} if "max_speed" in entry else {}))


def _parts(entry: dict, io: Any, set_payload: Callable[[float], None] | None) -> Any:
    from orc_rpl.plant.processes import PartSupply

    if not set(entry) <= {"close", "masses"} or not {"close", "masses"} <= set(entry) or not isinstance(entry["masses"], list):
        raise UsageError(f"parts have close (the gripper's DigOut) and masses (a list such as [2kg, 0kg]); got {entry!r}")
    masses = []
    for text in entry["masses"]:
        value = parse_literal(str(text).replace(" ", ""))
        if not (type(value) is Quantity and value.dim == MASS and value.value >= 0) and value != 0:
            raise UsageError(f"a part's mass is a mass such as 0.5kg, got {text!r}")
        masses.append(float(value.value) if type(value) is Quantity else 0.0)
    return PartSupply(_channel(entry["close"], io, "DigOut"), masses, set_payload)


def _casting(entry: dict, tcp: Callable[[], Pose], push: Callable[[Any, Any], None] | None = None) -> Any:
    """A casting's edge with bulges (deburring): `edge` world points [x, y, z], `normal` (outward, default
    [0, 0, 1]), `bulges` [{from, to, height}] as lengths along the edge, `stiffness` (N/m), `removal` (m/N)."""
    from orc_rpl.plant.processes.casting import Bulge, CastingEdge

    keys = {"edge", "normal", "bulges", "stiffness", "removal"}
    if not set(entry) <= keys or "edge" not in entry or not isinstance(entry["edge"], list):
        raise UsageError(f"a casting has edge (a list of [x, y, z]) and optionally normal, bulges, stiffness, removal; got {entry!r}")
    edge = []
    for point in entry["edge"]:
        if not isinstance(point, list) or len(point) != 3:
            raise UsageError(f"an edge point is [x, y, z] with lengths, got {point!r}")
        edge.append(tuple(_length(v) for v in point))
    bulges = []
    for bulge in entry.get("bulges") or []:
        if not isinstance(bulge, dict) or set(bulge) != {"from", "to", "height"}:
            raise UsageError(f"a bulge is {{from: 180mm, to: 220mm, height: 1mm}} along the edge, got {bulge!r}")
        bulges.append(Bulge(_length(bulge["from"]), _length(bulge["to"]), _length(bulge["height"])))
    normal = entry.get("normal", [0, 0, 1])
    if not isinstance(normal, list) or len(normal) != 3:
        raise UsageError(f"a casting's normal is [nx, ny, nz], got {normal!r}")
    extra = {name: float(entry[key]) for key, name in (("stiffness", "stiffness_n_m"), ("removal", "removal_m_n"))
             if key in entry}
    return CastingEdge(edge, bulges, tuple(float(v) for v in normal), tcp=tcp, push=push, **extra)  # type: ignore[arg-type]


def _event(entry: Any, io: Any, tcp: Callable[[], Pose]) -> IOEvent:
    if not isinstance(entry, dict) or not set(entry) <= _KEYS or "set" not in entry:
        raise UsageError(f"an event has 'set' and some of {', '.join(sorted(_KEYS - {'set'}))}; got {entry!r}")
    if ("at" in entry) == ("when" in entry):
        raise UsageError("an event has either 'at' (a time) or 'when' (a condition)")
    target = _expression(str(entry["set"]))
    if not (isinstance(target, n.Index) and isinstance(target.value, n.Name) and target.value.id in CELL_BANKS):
        raise UsageError(f"'set' names a channel such as DigIn[2], not {entry['set']!r}")
    number = int(parse_literal(_number_text(target.index)))
    bank = CELL_BANKS[target.value.id]
    io.bank(bank)[number]  # the channel must exist
    event = IOEvent(bank, number, float(entry.get("value", 1)), repeat=bool(entry.get("repeat", False)))
    if "at" in entry:
        event.at_s = _seconds(entry["at"])
    else:
        event.when = _condition(_expression(str(entry["when"])), io, tcp)
        event.after_s = _seconds(entry.get("after", "0s"))
    return event


def _number_text(expr: n.Expression) -> str:
    if not isinstance(expr, n.Number):
        raise UsageError("a channel number must be a whole number")
    return expr.text


def _seconds(text: Any) -> float:
    value = parse_literal(str(text).replace(" ", ""))
    if type(value) is Quantity and value.dim == TIME:
        return value.value
    raise UsageError(f"expected a time such as 1.5s, got {text!r}")


def _speed(text: Any) -> float:
    value = parse_literal(str(text).replace(" ", ""))
    if type(value) is Quantity and value.dim == LENGTH / TIME and value.value > 0:
        return value.value
    raise UsageError(f"expected a speed such as 20mm/s, got {text!r}")


def _expression(text: str) -> n.Expression:
    stmt = parse_statement(f"WAIT UNTIL {text}", "<io script>")
    assert isinstance(stmt, n.WaitUntil)
    return stmt.condition


def _condition(expr: n.Expression, io: Any, tcp: Callable[[], Pose]) -> Callable[[], bool]:
    f = _compile(expr, io, tcp)
    return lambda: ops.truth(f())


def _compile(expr: n.Expression, io: Any, tcp: Callable[[], Pose]) -> Callable[[], Any]:
    """A small expression language over the cell: IO channels, TCP.x/y/z, numbers with units, comparisons, AND/OR/NOT."""
    if isinstance(expr, n.Number):
        value = parse_literal(expr.text)
        return lambda: value
    if isinstance(expr, n.Boolean):
        return lambda: expr.value
    if isinstance(expr, n.Index) and isinstance(expr.value, n.Name) and expr.value.id in CELL_BANKS:
        bank, number = io.bank(CELL_BANKS[expr.value.id]), int(parse_literal(_number_text(expr.index)))
        digital = expr.value.id.startswith("Dig")
        return lambda: int(bank[number]) if digital else float(bank[number])
    if isinstance(expr, n.Field) and isinstance(expr.value, n.Name) and expr.value.id == "TCP" and expr.name.id in "xyz":
        axis = expr.name.id
        return lambda: Quantity(getattr(tcp(), axis), LENGTH)
    if isinstance(expr, n.Unary):
        operand = _compile(expr.operand, io, tcp)
        return (lambda: not ops.truth(operand())) if expr.op == "NOT" else (lambda: ops.negate(operand()))
    if isinstance(expr, n.Binary):
        left, right = _compile(expr.left, io, tcp), _compile(expr.right, io, tcp)
        if expr.op == "AND":
            return lambda: ops.truth(left()) and ops.truth(right())
        if expr.op == "OR":
            return lambda: ops.truth(left()) or ops.truth(right())
        fn = ops.BINARY[expr.op]
        return lambda: fn(left(), right())
    raise UsageError("a condition may use DigIn/DigOut/AnalogIn/AnalogOut[n], TCP.x/y/z, numbers, comparisons, AND, OR, NOT")
