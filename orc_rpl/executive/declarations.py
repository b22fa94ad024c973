"""Declarations compiled: VAR/CONST/POS/TOOL/PATH/FRAME with their `IN frame`, ENUM, INSTALL; routines."""

from __future__ import annotations

from typing import Any

from orc_rpl.application.runtime import InstallContext
from orc_rpl.executive.blocks import Locals
from orc_rpl.executive.machine import CompiledRoutine, Machine
from orc_rpl.executive.scope import ProgramScopes, Scope
from orc_rpl.executive.signals import RunError
from orc_rpl.executive.values import IO_BANKS, EnumType, EnumValue, Installed, IOChannel, type_name
from orc_rpl.syntax import nodes as n
from orc_rpl.world.pose import Joints, Pose


class DeclarationCompiler:
    """The declaration statements of StatementCompiler, and the routines of a program."""

    def __init__(self, machine: Machine, scopes: ProgramScopes, exprs: Any, statements: Any) -> None:
        self.m, self.scopes, self.exprs, self.statements = machine, scopes, exprs, statements

    def _declaration(self, stmt: n.Declaration, scope: Scope) -> tuple[Any, Any]:
        m, kind, name = self.m, stmt.kind, stmt.name.id
        value = self.exprs.compile(stmt.value, scope)
        frame = stmt.frame.id if stmt.frame is not None else None
        G = m.globals
        local = scope.is_local(name)

        def declare(L: Locals) -> None:
            v = value(L)
            if frame is not None:
                v = in_frame(m, v, frame, name)
            v = checked(kind, name, v)
            if kind == "FRAME":
                m.frames[name] = v
            if local:
                L[name] = v
            else:
                G[name] = v
                if kind == "CONST":
                    m.consts.add(name)
                else:
                    m.consts.discard(name)
        return declare, None

    def _enumdecl(self, stmt: n.EnumDecl, scope: Scope) -> tuple[Any, Any]:
        m, name = self.m, stmt.name.id
        members = tuple(member.id for member in stmt.members)
        values = [EnumValue(name, member, i + 1) for i, member in enumerate(members)]

        def declare(L: Locals) -> None:
            m.globals[name] = EnumType(name, members)
            for member, value in zip(members, values):
                m.globals[member] = value
        return declare, None

    def _install(self, stmt: n.Install, scope: Scope) -> tuple[Any, Any]:
        m, name, kind_name = self.m, stmt.name.id, stmt.kind.id
        attributes = [(w.name.id, self._reference(w.value, scope)) for w in stmt.attributes]
        local = scope.is_local(name)

        def install(L: Locals) -> None:
            kind = m.registry.install_kinds.get(kind_name)
            if kind is None:
                raise RunError(f"unknown INSTALL kind '{kind_name}'")
            values: dict[str, Any] = {a.name: a.default for a in kind.attributes}
            for attr_name, fn in attributes:
                spec = kind.attribute(attr_name)
                if spec is None:
                    raise RunError(f"{kind_name} has no attribute {attr_name}")
                values[spec.name] = fn(L)
            existing = L.get(name) if local else m.globals.get(name)
            tool = existing if type(existing) is Pose else existing.tool if type(existing) is Installed else None
            obj = Installed(name, kind_name, values, tool=tool)
            if kind.factory is None:
                obj.behaviour = None  # methods report "not implemented yet" when called
            else:
                context = InstallContext(name, kind_name, values, lambda ch: read_channel(m, ch),
                                         lambda ch, v: write_channel(m, ch, v), m.robot)
                obj.behaviour = kind.factory(context)
            if local:
                L[name] = obj
            else:
                m.globals[name] = obj
        return install, None

    def _reference(self, expr: n.Expression, scope: Scope) -> Any:
        """An INSTALL attribute: `DigOut[3]` names the channel itself, not its present value."""
        if isinstance(expr, n.Index) and isinstance(expr.value, n.Name) and expr.value.id in IO_BANKS \
                and expr.value.id not in self.scopes.globals:
            bank, index = IO_BANKS[expr.value.id], self.exprs.compile(expr.index, scope)
            return lambda L: IOChannel(bank, _whole(index(L), bank.name))
        return self.exprs.compile(expr, scope)

    # -- routines --------------------------------------------------------------------------

    def routine(self, routine: n.Routine) -> CompiledRoutine:
        """Compile a PROC or FUNC body once; called for every routine before the program starts."""
        scope = self.scopes.scope_of(routine.name.id)
        block = self.statements.block(routine.body, scope)
        compiled = CompiledRoutine(routine.name.id, routine.kind, tuple(p.id for p in routine.params))
        compiled.gen = block.gen
        compiled.fast = block.fast
        compiled.suspends = block.fast is None
        return compiled


def in_frame(m: Machine, value: Any, frame: str, name: str) -> Any:
    """`... IN frame`: a pose's (or a path's) numbers are relative to `frame`."""
    if frame != "world" and frame not in m.frames and frame not in m.moving_frames():
        raise RunError(f"'{frame}' is not a declared FRAME")
    if type(value) is Pose:
        if value.frame not in ("world", frame):
            raise RunError(f"{name} is declared IN {frame} but its value is relative to {value.frame}")
        return value.with_frame(frame)
    if type(value) is tuple:
        return tuple(in_frame(m, item, frame, name) for item in value)
    if type(value) is Joints:
        raise RunError(f"{name}: a joint position is not relative to a frame; drop 'IN {frame}'")
    raise RunError(f"{name}: only poses and paths can be IN a frame, not {type_name(value)}")


def checked(kind: str, name: str, value: Any) -> Any:
    """A declaration's value must suit its kind: TOOL and FRAME poses, POS positions, PATH lists of positions."""
    if kind in ("TOOL", "FRAME") and type(value) is not Pose:
        raise RunError(f"{kind} {name} needs a pose, got {type_name(value)}")
    if kind == "POS" and type(value) not in (Pose, Joints):
        raise RunError(f"POS {name} needs a pose or JOINTS(...), got {type_name(value)}")
    if kind == "PATH":
        if type(value) is not tuple or not all(type(v) in (Pose, Joints) for v in value):
            raise RunError(f"PATH {name} needs a list of positions, got {type_name(value)}")
    return value


def _whole(value: Any, bank: str) -> int:
    if type(value) is float and value == int(value):
        return int(value)
    if type(value) is not int:
        raise RunError(f"{bank}[...] needs a whole channel number, got {type_name(value)}")
    return value


def read_channel(m: Machine, channel: IOChannel) -> Any:
    if not isinstance(channel, IOChannel):
        raise RunError(f"expected an IO channel such as DigIn[2], got {type_name(channel)}")
    return m.read_io(channel.bank, channel.number)


def write_channel(m: Machine, channel: IOChannel, value: Any) -> None:
    if not isinstance(channel, IOChannel):
        raise RunError(f"expected an IO channel such as DigOut[3], got {type_name(channel)}")
    m.write_io(channel.bank, channel.number, value)

