"""Motion statements compiled: evaluate and frame-check targets, resolve attributes, hand over to the keyword's behaviour."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from types import GeneratorType
from typing import Any

from orc_rpl.application.runtime import BehaviourError, FunctionParam, MotionCall, MotionView
from orc_rpl.executive.blocks import Locals
from orc_rpl.executive.machine import TICK, Machine, Outstanding
from orc_rpl.executive.scope import ProgramScopes, Scope
from orc_rpl.executive.signals import RunError
from orc_rpl.executive.values import Installed, Routine, type_name
from orc_rpl.syntax import nodes as n
from orc_rpl.syntax.units import TIME, Quantity
from orc_rpl.world.pose import Joints, Pose


#: The parameter name that makes a FUNC target a function of time (docs/language.md section 4).
TIME_PARAMETER = "t"

#: Keywords whose requests can be computed early: the standard motions (an application feature's behaviour may act).
PREDICTABLE = frozenset({"MOVE", "JMOVE", "LMOVE", "CMOVE"})


class MotionCompiler:
    """Turns a motion statement into a generator that submits it and waits as its zone requires."""

    def __init__(self, machine: Machine, scopes: ProgramScopes, exprs: Any) -> None:
        self.m, self.scopes, self.exprs = machine, scopes, exprs
        self.builders: dict[int, Callable[..., Any]] = {}   #: id(statement) -> its request builder (for predictions)

    def planned_ahead(self, requests: Any) -> Iterator[object]:
        """Plan a motion that follows a running one on the robot's worker, the motion cycle going on meanwhile
        (KNOWN "completely" or "almost"); a plan already under way (the FINE motion before predicted this one) is
        waited for the same way. Submitting it then costs the cycle nothing."""
        robot = self.m.robot
        if not hasattr(robot, "plan_ahead"):
            return
        if robot.pending() > 0 and len(requests) == 1:
            robot.plan_ahead(requests[0])
        while not robot.ahead_ready():
            robot.tick()
            yield TICK

    def predictor(self, stmt: n.Motion, scope: Scope) -> Callable[[Locals], Any] | None:
        """The request the motion statement `stmt` will make, computed early without side effects, and whether it
        read sensors (None when it may have side effects or read what the motions before it change: a call of
        anything but a function of its arguments alone (FunctionSpec.of_arguments: not IDENT, which reads the last
        recording), a keyword of an application feature, a motion not known well enough; None too for a motion of
        external axes, which are never planned ahead).

        Sensors are read from their dummies (thesis 5.2: dummy sampling for the precomputation of almost known
        motions): the real sensor is not asked until the statement runs. A motion that needs a sensor's value is
        computed early only when the program declares it KNOWN "almost" (its plan keeps a reserve for the
        correction when the real value comes)."""
        if stmt.keyword not in PREDICTABLE or any(
                isinstance(node, n.Call) and not self._calls_of_arguments(node) for node in stmt.walk()):
            return None
        if any(isinstance(c, n.With) and c.name.id == "KNOWN" and c.value in (n.String("partly"), n.String("not"))
               for c in stmt.clauses):
            return None
        builder = self.builders.get(id(stmt))
        if builder is None:
            try:
                self.compile(stmt, scope)
            except RunError:
                return None
            builder = self.builders[id(stmt)]

        names = {node.id for node in stmt.walk() if isinstance(node, n.Name)}

        def predict(L: Locals) -> tuple[Any, bool] | None:
            if not names.isdisjoint(self.m.routines):  # a FUNC target or parameter: the program's code would run
                return None
            sensors = getattr(self.m.robot, "sensors", None)
            reads = sensors.dummy_reads() if sensors is not None else 0
            try:
                if sensors is None:
                    requests = builder(L, lambda message: None)[-1]
                else:
                    with sensors.dummies():
                        requests = builder(L, lambda message: None)[-1]
            except Exception:  # whatever goes wrong is found again, and reported, when the statement runs
                return None
            if isinstance(requests, (list, tuple, GeneratorType)) or requests.axes or requests.frame_of is not None:
                return None  # external axes move through the cell's stages, never from a plan made ahead
            from_dummy = sensors is not None and sensors.dummy_reads() != reads
            if from_dummy and requests.known != "almost":
                return None  # a completely known motion that reads a sensor: the program's knowledge is wrong
            return requests, from_dummy
        return predict

    def _calls_of_arguments(self, call: n.Call) -> bool:
        """The call is of a registered function whose value depends on its arguments alone (a FUNC of the program
        may read anything)."""
        if not isinstance(call.function, n.Name):
            return False
        spec = self.m.registry.functions.get(call.function.id)
        return spec is not None and spec.of_arguments

    def compile(self, stmt: n.Motion, scope: Scope, following: n.Motion | None = None) -> Callable[[Locals], Iterator[object]]:
        m, keyword, frame = self.m, stmt.keyword, scope.frame
        compile_ = self.exprs.compile
        tool = compile_(stmt.tool, scope)
        target = compile_(stmt.target, scope) if stmt.target is not None else None
        path = compile_(stmt.path, scope) if stmt.path is not None else None
        vias = [compile_(p, scope) for c in stmt.clauses if isinstance(c, n.Via) for p in c.points]
        withs = [(c.name.id, compile_(c.value, scope)) for c in stmt.clauses if isinstance(c, n.With)]
        # UNTIL conditions are compiled now, once: the motion cycle calls a closure, never the tree
        untils = [self.exprs.condition(c.condition, scope.for_motion()) for c in stmt.clauses if isinstance(c, n.Until)]
        span = stmt.span

        def position(value: Any, role: str) -> Pose | Joints:
            if type(value) is Pose:
                if value.frame != frame:
                    where = f"inside FRAME {frame}" if frame != "world" else "outside every FRAME block (relative to world)"
                    raise RunError(f"{keyword}: the {role} is relative to {value.frame}, but this motion is {where}; "
                                   "nothing moved")
                if role != "target" and (value.axes or m.moving_frame_of(value.frame)):
                    raise RunError(f"{keyword}: a {role} cannot carry external-axis values or lie on a moving frame; "
                                   "give them to the target")
                return m.to_world(value)
            if type(value) is Joints:
                return value
            if type(value) is Routine and role == "target":
                return self.path_function(value, position, span)
            raise RunError(f"{keyword}: the {role} must be a position (a pose or JOINTS), got {type_name(value)}")

        def build(L: Locals, warn: Callable[[str], None]) -> tuple[Any, Any, Any, Any, Any]:
            """(spec, tool value, tool pose, UNTIL closure, what the keyword's behaviour asks for)."""
            spec = m.registry.motions.get(keyword)
            if spec is None:
                raise RunError(f"unknown motion keyword '{keyword}'")
            if spec.execute is None:
                raise RunError(f"{keyword} is not implemented yet (feature '{spec.origin}'); nothing moved")
            tool_value = tool(L)
            tool_pose = resolve_tool(tool_value)
            resolve_target = None
            coordination = None
            if spec.output_functions and target is not None:
                goal = None  # the target may use the output bindings (DropPositions[Id]): evaluated later

                def resolve_target(bindings: dict[str, Any]) -> Pose | Joints:
                    m.globals.update(bindings)
                    return position(target(L), "target")
            else:
                raw = target(L) if target is not None else None
                coordination = axes_target(m, raw, keyword)
                goal = coordination[0] if coordination is not None else position(raw, "target") if raw is not None else None
            along = None
            if path is not None:
                points = path(L)
                if type(points) is Routine and goal is None:  # `ALONG f` with FUNC f(s) or f(t): the same path as `TO f`
                    goal = position(points, "target")
                elif type(points) is not tuple or not points:
                    raise RunError(f"{keyword}: ALONG needs a non-empty PATH, got {type_name(points)}")
                else:
                    along = tuple(position(p, "path point") for p in points)
            via = tuple(position(f(L), "via point") for f in vias)
            attributes = self.attributes(spec, withs, L, span)
            until = None
            if untils:
                conditions = untils

                def until(view: MotionView) -> bool:
                    return any(c(L) for c in conditions)
            call = MotionCall(keyword, goal, along, via, tool_pose, attributes, until, m.options.speed_override, warn,
                              equipment=tool_value.behaviour if type(tool_value) is Installed else None,
                              robot=m.robot, resolve_target=resolve_target,
                              call_function=lambda routine, args: m.call_now(m.routines[routine.name], args, span))
            try:
                requests = spec.execute(call)
            except BehaviourError as error:
                raise RunError(f"{keyword}: {error}") from None
            if coordination is not None and resolve_target is None:
                requests = with_axes(requests, coordination, keyword)
            return spec, tool_value, tool_pose, until, requests

        self.builders[id(stmt)] = build
        predict = self.predictor(following, scope) if following is not None else None

        def motion(L: Locals) -> Iterator[object]:
            spec, tool_value, tool_pose, until, requests = build(L, lambda message: m.warn(message, span))
            m.motion_span = span
            if isinstance(requests, GeneratorType):
                m.last_tool = tool_pose
                yield from self.procedure(keyword, requests)
                return
            if not isinstance(requests, (list, tuple)):
                requests = [requests]
            robot = m.robot
            while robot.pending() > 1:  # look ahead by one motion: enough to blend, never more
                robot.tick()
                yield TICK
            m.check_outstanding()
            yield from self.planned_ahead(requests)
            tickets = [robot.submit(r) for r in requests]
            m.motions += 1
            m.last_tool = tool_pose
            if until is None and requests[-1].zone_m > 0:
                m.outstanding.append(Outstanding(tickets[-1], span, m.stack_entries()))
                return  # blended: the next statement runs while this motion goes on
            if predict is not None and until is None:  # FINE: the next motion is planned while this one runs
                upcoming = predict(L)
                if upcoming is not None and hasattr(robot, "plan_ahead"):
                    request, from_dummy = upcoming
                    robot.plan_ahead(request, from_dummy=from_dummy)
            while not all(t.done for t in tickets):
                robot.tick()
                yield TICK
            for t in tickets:
                if t.outcome == "fault":
                    raise t.error if t.error is not None else RunError(f"{keyword} failed")
            if until is not None and not any(t.outcome == "stopped" for t in tickets):
                raise RunError(f"NotFound: {keyword} reached its target before the UNTIL condition became true",
                               name="NotFound")
        return motion

    def procedure(self, keyword: str, steps: GeneratorType) -> Iterator[object]:
        """Drive a behaviour that runs as a procedure: submit what it yields, tick when it yields None."""
        m = self.m
        robot = m.robot
        sent: Any = None
        while True:
            try:
                step = steps.send(sent)
            except StopIteration:
                return
            except BehaviourError as error:
                raise RunError(f"{keyword}: {error}") from None
            if step is None:
                robot.tick()
                sent = None
                yield TICK
                continue
            while robot.pending() > 1:  # look ahead by one motion, as for plain motions
                robot.tick()
                yield TICK
            m.check_outstanding()
            sent = robot.submit(step)
            m.motions += 1

    def path_function(self, routine: Routine, position: Callable[[Any, str], Any], span: n.Span) -> FunctionParam:
        """`MOVE ARM TO f` with `FUNC f(s)` giving poses: a motion in function space, f(0) checked before it starts."""
        m = self.m
        if routine.kind != "FUNC" or len(routine.params) != 1:
            raise RunError(f"a position given as a routine must be a FUNC of one parameter (s, 0..1), not {routine.kind} {routine.name}")

        of_time = routine.params[0] == TIME_PARAMETER  # FUNC f(t): t is the time since the motion started, in s
        riding = belts_ahead(m) if of_time else None

        def world_pose(u: float) -> Pose:
            argument = Quantity(float(u), TIME) if of_time else float(u)
            raw = m.call_now(m.routines[routine.name], [argument], span)
            if riding is not None and type(raw) is Pose and not raw.axes and m.moving_frame_of(raw.frame) in riding[1]:
                position(raw, "target")  # the frame rule
                return riding[0](raw, float(u))
            value = position(raw, f"value of {routine.name}")
            if type(value) is not Pose:
                raise RunError(f"FUNC {routine.name} must give poses, got {type_name(value)}")
            return value
        at = memoised(world_pose)
        at(0.0)  # the frame rule, before anything moves
        return FunctionParam(routine.name, at, "t" if of_time else "s")

    def attributes(self, spec: Any, withs: list[tuple[str, Any]], L: Locals, span: n.Span) -> dict[str, Any]:
        """WITH values by canonical attribute name; a FUNC name becomes a function of the path coordinate."""
        m = self.m
        values: dict[str, Any] = {}
        for name, fn in withs:
            attribute = spec.attribute(name)
            if attribute is None:
                if spec.output_functions:
                    # an output binding, evaluated by the feature during the motion: a thunk in the statement's context
                    values[name] = (lambda f: lambda: f(L))(fn)
                    continue
                raise RunError(f"{spec.keyword} does not accept attribute '{name}'")
            value = fn(L)
            if type(value) is Routine:
                if value.kind != "FUNC" or not attribute.function_ok:
                    raise RunError(f"attribute {attribute.name} cannot be {value.kind} {value.name}")
                if len(value.params) != 1:
                    raise RunError(f"FUNC {value.name} given as {attribute.name} must take one parameter (s, 0..1)")
                value = FunctionParam(value.name, _function_of_s(m, value.name, span))
            values[attribute.name] = value
        return values


def _function_of_s(m: Machine, name: str, span: n.Span) -> Callable[[float], Any]:
    """A FUNC of s, compiled already, as a Python callable for the motion cycle."""
    def at(s: float) -> Any:
        return m.call_now(m.routines[name], [float(s)], span)
    return memoised(at)


def memoised(fn: Callable[[float], Any]) -> Callable[[float], Any]:
    """`fn` called at most once per value of s during one motion: the checker proved it free of side effects,
    and the planner asks for the same grid points several times (path length, time parametrisation, execution)."""
    values: dict[float, Any] = {}

    def at(s: float) -> Any:
        key = float(s)
        if key not in values:
            values[key] = fn(key)
        return values[key]
    return at


def resolve_tool(value: Any) -> Pose:
    """The TCP of a tool name: a TOOL pose, ARM (the flange) or equipment installed on a tool."""
    if type(value) is Pose:
        return value
    if type(value) is Installed:
        if value.tool is None:
            raise RunError(f"{value.name} is installed but not mounted as a TOOL; declare TOOL {value.name} = POSE(...) first")
        return value.tool
    raise RunError(f"the tool must be a TOOL, ARM or installed equipment, got {type_name(value)}")


def belts_ahead(m: Machine) -> tuple[Callable[[Pose, float], Pose], frozenset[str]] | None:
    """For a FUNC of t: a pose relative to a frame a conveyor carries, in the world `u` seconds after now (the belts
    run on at their speeds, the other moving frames stay where they are), and the conveyors' names; None when the
    cell has no conveyor."""
    world = m.options.cell_world
    if world is None:
        return None
    speeds = {name: world.object(name).axis.speed_si for name in world.moving_frames()
              if world.object(name).axis.joint == "conveyor"}
    if not speeds:
        return None
    now = m.axis_values()

    def ahead(pose: Pose, u: float) -> Pose:
        values = {**now, **{name: now.get(name, 0.0) + speed * u for name, speed in speeds.items()}}
        return Pose.from_matrix(m.frame_matrix(pose.frame, values) @ pose.matrix(), "world")
    return ahead, frozenset(speeds)


def axes_target(m: Machine, value: Any, keyword: str) -> tuple[Pose, dict[str, Any]] | None:
    """A target with external-axis values or on a moving frame: its world pose where the axes will be, and what the
    robot needs to move the arm and the axes in one path coordinate; None for any other target."""
    if type(value) is not Pose:
        return None
    moving = m.moving_frame_of(value.frame)
    if not value.axes and moving is None:
        return None
    if m.options.cell_world is None:
        raise RunError(f"{keyword}: the target carries external-axis values, but the cell has no external axes "
                       "(run with --world FILE of a cell with a track or a positioner)")
    world = m.options.cell_world
    known = set(world.moving_frames())
    for name, _ in value.axes:
        if name not in known:
            raise RunError(f"{keyword}: the cell has no external axis '{name}'")
    end = {**m.axis_values(), **dict(value.axes)}
    goal = Pose.from_matrix(m.frame_matrix(value.frame, end) @ value.matrix(), "world")
    extra: dict[str, Any] = {"axes": value.axes}
    if moving is not None:
        frame, local = value.frame, value.with_frame(value.frame)
        extra["frame_of"] = lambda values: Pose.from_matrix(m.frame_matrix(frame, values), "world")
        extra["target_in_frame"] = Pose(local.x, local.y, local.z, local.a, local.b, local.c, frame)
    return goal, extra


def with_axes(requests: Any, coordination: tuple[Pose, dict[str, Any]], keyword: str) -> Any:
    """The motion's last request carrying the axis targets (and the moving frame) of its target."""
    import dataclasses

    if isinstance(requests, GeneratorType) or not requests:
        raise RunError(f"{keyword} does not move external axes; use MOVE or LMOVE for a target with axis values")
    listed = list(requests) if isinstance(requests, (list, tuple)) else [requests]
    listed[-1] = dataclasses.replace(listed[-1], **coordination[1])
    return listed
