"""The robot room's catalogue: the figures we keep per robot beside its MJCF (limits, flange, home)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from orc_rpl.errors import UsageError


def worlds_dir() -> Path:
    """The folder of robot models and cells: inside the package when installed, else the repository's `worlds/`."""
    here = Path(__file__).resolve().parent.parent
    for candidate in (here / "worlds", here.parent / "worlds"):
        if candidate.is_dir():
            return candidate
    raise UsageError(f"cannot find the worlds/ folder next to {here} (robot models live there)")


def _deg(*values: float) -> tuple[float, ...]:
    return tuple(math.radians(v) for v in values)


@dataclass(frozen=True, slots=True)
class RobotSpec:
    """What we know about one robot beyond its MJCF: ranges, speeds, torques and where its flange is."""

    name: str                           #: registry key, e.g. "irb2400"
    mjcf_file: str                      #: file name inside worlds/
    q_min_rad: tuple[float, ...]        #: lower joint limits
    q_max_rad: tuple[float, ...]        #: upper joint limits
    qd_max_rad_s: tuple[float, ...]     #: joint speed limits (data sheet)
    qdd_max_rad_s2: tuple[float, ...]   #: joint acceleration limits (our estimates, see docs/robots.md)
    tau_max_nm: tuple[float, ...]       #: motor torque limits at the joint (= MJCF actuator forcerange)
    home_q_rad: tuple[float, ...]       #: home configuration
    flange_frame: str = "flange"        #: MJCF site of the tool flange (z out of the flange)
    description: str = ""               #: one line for listings and docs

    @property
    def mjcf_path(self) -> Path:
        """Absolute path of the robot's MJCF file."""
        return worlds_dir() / self.mjcf_file

    def __post_init__(self) -> None:
        n = len(self.q_min_rad)
        for field_name in ("q_max_rad", "qd_max_rad_s", "qdd_max_rad_s2", "tau_max_nm", "home_q_rad"):
            if len(getattr(self, field_name)) != n:
                raise UsageError(f"robot {self.name!r}: {field_name} has {len(getattr(self, field_name))} values, expected {n}")
        if any(lo >= hi for lo, hi in zip(self.q_min_rad, self.q_max_rad)):
            raise UsageError(f"robot {self.name!r}: every q_min must be below q_max")


class RobotRegistry:
    """Robots known by name; refuses a second robot under a name already taken."""

    def __init__(self) -> None:
        self._specs: dict[str, RobotSpec] = {}

    def register(self, spec: RobotSpec) -> RobotSpec:
        """Add a robot; a duplicate name is an error naming both definitions."""
        old = self._specs.get(spec.name)
        if old is not None:
            raise UsageError(
                f"robot {spec.name!r} is already registered (from {old.mjcf_file}); "
                f"refusing the second definition (from {spec.mjcf_file})"
            )
        self._specs[spec.name] = spec
        return spec

    def names(self) -> list[str]:
        """The known robot names, sorted."""
        return sorted(self._specs)

    def get(self, name: str) -> RobotSpec:
        """The spec of a robot; an unknown name lists the known ones."""
        try:
            return self._specs[name]
        except KeyError:
            raise UsageError(f"unknown robot {name!r}; known robots: {', '.join(self.names())}") from None

    def __contains__(self, name: object) -> bool:
        return name in self._specs


ROBOTS = RobotRegistry()

ROBOTS.register(
    RobotSpec(
        name="irb2400",
        mjcf_file="irb2400.xml",
        q_min_rad=_deg(-180, -100, -60, -200, -120, -400),
        q_max_rad=_deg(180, 110, 65, 200, 120, 400),
        qd_max_rad_s=_deg(150, 150, 150, 360, 360, 450),
        qdd_max_rad_s2=(6.0, 6.0, 8.0, 20.0, 20.0, 30.0),
        tau_max_nm=(1200.0, 1800.0, 700.0, 120.0, 120.0, 60.0),
        home_q_rad=_deg(0, 0, 30, 0, 60, 0),
        description="IRB-2400-class 6-axis arm, reach 1.55 m, ABB kinematics, estimated masses",
    )
)

ROBOTS.register(
    RobotSpec(
        name="ur5e",
        mjcf_file="ur5e.xml",
        q_min_rad=_deg(-360, -360, -360, -360, -360, -360),
        q_max_rad=_deg(360, 360, 360, 360, 360, 360),
        qd_max_rad_s=_deg(180, 180, 180, 180, 180, 180),
        qdd_max_rad_s2=(8.0, 8.0, 8.0, 15.0, 15.0, 15.0),
        tau_max_nm=(150.0, 150.0, 150.0, 28.0, 28.0, 28.0),
        home_q_rad=_deg(180, -90, 90, -90, -90, 0),
        description="Universal Robots UR5e, reach 0.85 m, published DH and masses",
    )
)

ROBOTS.register(
    RobotSpec(
        name="so101",
        mjcf_file="so101.xml",
        # the published model's joint ranges (joint zero in the middle of each range)
        q_min_rad=(-1.9198621771937616, -1.7453292519943224, -1.69, -1.6580628494556928, -2.7438472969992493),
        q_max_rad=(1.9198621771937634, 1.7453292519943366, 1.69, 1.6580627293335335, 2.841206309382605),
        qd_max_rad_s=_deg(180, 180, 180, 180, 180),
        qdd_max_rad_s2=(15.0, 15.0, 15.0, 20.0, 20.0),
        tau_max_nm=(2.94, 2.94, 2.94, 2.94, 2.94),
        home_q_rad=(0.0, -0.6, 0.6, 1.5707963267948966, 0.0),
        description="SO-101-class desktop arm, 5 axes and a gripper on STS3215 bus servos, reach 0.4 m",
    )
)
