"""The executive's robot with external axes: targets in the program's world turned into the base frame the track carries,
and motions that move the arm and the axes in one path coordinate."""

from __future__ import annotations

from typing import Any

import numpy as np

from orc_rpl.application.runtime import MotionRequest
from orc_rpl.errors import PlanningError
from orc_rpl.motion import CartesianMotion, MotionLayer, Params
from orc_rpl.motion.external import coordinated_motion, external_axes_of
from orc_rpl.world.pose import Pose


#: At most this many predictions of a motion's duration for a target on a belt, and how close the target must stay.
BELT_ITERATIONS = 4
BELT_TOLERANCE_M = 1e-5


class CellAxes:
    """A cell's moving frames as the robot sees them: where they are, and where that puts the robot's base.

    The program's world is the cell's world seen from the robot's base with every axis at its home (the scene's
    origin); a track moves the base away from it, a positioner moves the frames on its table.
    """

    def __init__(self, world: Any, layer: MotionLayer) -> None:
        self.world = world
        self.layer = layer
        self.external = external_axes_of(world)
        layer.external = self.external
        self._home_inv = np.linalg.inv(world.world_pose("robot").matrix())
        self._conveyors = {n: world.object(n).axis for n in world.moving_frames() if world.object(n).axis.joint == "conveyor"}

    def values(self) -> dict[str, float]:
        """Every moving frame's value now: the axes measured, the conveyors at their speed times the time."""
        measured = getattr(self.layer.backend, "axis_values", None)
        values = dict(measured()) if measured is not None else dict(self.external.planned if self.external else {})
        now = self.layer.now_s()
        # a simulated cell measures its belts; elsewhere a conveyor is where its speed has taken it
        values.update({name: axis.speed_si * now for name, axis in self._conveyors.items() if name not in values})
        return values

    def base(self, values: dict[str, float]) -> np.ndarray:
        """The robot's base in the program's world when the axes are at `values` (4x4)."""
        return self._home_inv @ self.world.with_axes(values).world_pose("robot").matrix()

    def in_base(self, pose: Pose, values: dict[str, float]) -> Pose:
        """A world pose in the base frame where the axes are at `values`."""
        return Pose.from_matrix(np.linalg.inv(self.base(values)) @ pose.matrix())

    def planned(self) -> dict[str, float]:
        """Where the axes will be when every accepted move is done."""
        return dict(self.external.planned) if self.external is not None else {}

    def submit(self, request: MotionRequest, tool: np.ndarray | None, params: Params, actions: Any) -> Any:
        """A MOVE or LMOVE that moves the arm and the external axes together (the axes linearly in its s)."""
        if not request.axes and self._on_belt(request):
            return self._to_belt(request, tool, params, actions)
        external = self.external
        if external is None:
            raise PlanningError(f"{request.keyword}: the cell has no external axes to move")
        if request.kind not in ("joint", "linear") or request.via:
            raise PlanningError(f"{request.keyword}: only MOVE and LMOVE without VIA points move external axes")
        start = self.planned()
        targets = dict(request.axes)
        end = {**start, **targets}
        layer = self.layer
        if request.frame_of is not None and request.target_in_frame is not None and request.kind == "linear":
            frame_of = request.frame_of

            def frame_in_base(values: dict[str, float]) -> np.ndarray:
                return np.linalg.inv(self.base(values)) @ frame_of(values).matrix()

            here = layer.fk(layer.planned_end_q(), tool)
            start_rel = np.linalg.inv(frame_in_base(start)) @ here
            motion: Any = coordinated_motion(frame_in_base, start_rel, request.target_in_frame.matrix(), start, end, tool)
        else:
            assert isinstance(request.target, Pose)
            motion = CartesianMotion(self.in_base(request.target, end), kind=request.kind, tool=tool)
        return external.request(layer, motion, params, targets, actions)

    # -- conveyors --------------------------------------------------------------------

    def _on_belt(self, request: MotionRequest) -> bool:
        """The request's target is on a frame a conveyor carries: moving the belts moves it."""
        frame_of, local = request.frame_of, request.target_in_frame
        if frame_of is None or local is None or not self._conveyors or request.kind not in ("joint", "linear") or request.via:
            return False
        values = self.values()
        moved = {**values, **{name: values.get(name, 0.0) + 1.0 for name in self._conveyors}}
        return not np.allclose(frame_of(values).matrix(), frame_of(moved).matrix(), atol=1e-9)

    def _to_belt(self, request: MotionRequest, tool: np.ndarray | None, params: Params, actions: Any) -> Any:
        """A MOVE or LMOVE to a target a belt carries: it goes where the target will be when the motion ends.

        The motion's duration is predicted (the motion layer's simulation from where the robot will be), the
        target taken where the belts have carried it by then, and that repeated until the duration holds still
        (a few hundredths of a millimetre at a belt's speed); timed from now, which is when a motion after a
        FINE one starts.
        """
        layer = self.layer
        frame_of, local = request.frame_of, request.target_in_frame
        assert frame_of is not None and local is not None
        now = self.values()
        start_q = layer.planned_end_q()
        axes_end = self.planned()
        duration_s, motion = 0.0, None
        previous: tuple[float, float] | None = None   #: the last guess and how far its prediction was from it
        for _ in range(BELT_ITERATIONS):
            ahead = {**now, **{name: now.get(name, 0.0) + axis.speed_si * duration_s for name, axis in self._conveyors.items()}}
            goal = Pose.from_matrix(frame_of(ahead).matrix() @ local.matrix(), "world")
            motion = CartesianMotion(self.in_base(goal, axes_end), kind=request.kind, tool=tool)
            miss_s = layer.simulate([(motion, params)], start_q).move_times_s[0] - duration_s
            if abs(miss_s) * max(abs(a.speed_si) for a in self._conveyors.values()) < BELT_TOLERANCE_M:
                break
            # the predicted duration itself first, then the secant on the miss: taking the prediction as the next
            # guess alone oscillates where the duration changes nearly as fast as the target is carried away
            # (moves from rest averaged over elastic gears' periods: 0.472, 0.34, 0.384, 0.364 s, 2 mm off)
            step_s = miss_s
            if previous is not None and miss_s != previous[1]:
                step_s = -miss_s * (duration_s - previous[0]) / (miss_s - previous[1])
            previous = (duration_s, miss_s)
            duration_s = max(0.0, duration_s + step_s)
        if self.external is not None:
            return self.external.request(layer, motion, params, {}, actions)
        return layer.move(motion, params, actions)
