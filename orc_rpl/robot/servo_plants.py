"""The robot room's plant descriptions of arms on serial-bus servos: the servos' own position loops and gears, documented once."""

from __future__ import annotations

import math
from dataclasses import dataclass

from orc_rpl.robot.tables import check_per_joint


@dataclass(frozen=True, slots=True)
class ServoPlantSpec:
    """The realistic virtual robot of an arm whose joints are bus servos (docs/robots.md, "Arms on bus servos").

    The controller's model of such an arm is the rigid, frictionless MJCF whose joints go where they
    are sent. The plant is each servo as built: a DC motor behind a gearbox with `backlash_rad` of play,
    a magnetic encoder of `encoder_counts_per_rev` on the output shaft, and the servo's own position
    loop (its firmware), which sets the motor's PWM duty from the encoder:

        duty = clip(position_gain_duty_per_count * e - damping_duty_s_rad * speed, -limit, limit)

    with e the goal minus the present position in whole counts, 0 within `deadband_counts` (the
    servo's dead zone), and `limit` the torque limit register as a share of full duty. The motor gives
    tau = stall_torque_nm (duty - motor speed / no_load_speed_rad_s): the loop droops under load by
    tau / (stall torque x gain) counts and lags a moving goal by about speed / (no-load speed x gain).
    Friction is at the gearbox's output; a servo with its torque off is back-driven through its
    gearbox, which holds up to `limp_hold_nm`. The winding heats as dT/dt = (R i^2 Rth - T) / tau_th,
    the current being the share of the stall torque times the stall current; the servo reports the
    temperature in whole degrees and switches itself off above its maximum (the overheating alarm).
    """

    robot: str
    servo: str                                  #: the servo model, e.g. "STS3215"
    stall_torque_nm: float                      #: at full duty, at rest (data sheet)
    stall_current_a: float                      #: at full duty, at rest (data sheet)
    no_load_speed_rad_s: float                  #: at full duty, unloaded (data sheet)
    encoder_counts_per_rev: int                 #: output-shaft encoder (12 bits)
    position_gain_duty_per_count: float         #: the firmware's P: duty per count of error
    damping_duty_s_rad: float                   #: the firmware's D: duty per rad/s of output speed
    deadband_counts: int                        #: no drive while the error is this small
    backlash_rad: float                         #: play of the gearbox (the output turns this much freely)
    coulomb_nm: tuple[float, ...]               #: gearbox friction at the output, per joint
    viscous_nm_s: tuple[float, ...]             #: gearbox viscous friction at the output, per joint
    limp_hold_nm: float                         #: back-driving torque of a servo with its torque off
    winding_resistance_ohm: float
    winding_rth_k_w: float                      #: winding (as the servo's sensor sees it) to ambient
    winding_time_constant_s: float
    link_mass_factors: tuple[float, ...]        #: plant mass / model mass, links 1..n (inertias scale alike)
    unmodelled_flange_mass_kg: float            #: cables the controller's model does not have
    ambient_c: float = 25.0
    max_temperature_c: float = 70.0             #: the servo's factory temperature limit

    def __post_init__(self) -> None:
        check_per_joint(self, ("viscous_nm_s", "link_mass_factors"))

    @property
    def n_joints(self) -> int:
        return len(self.coulomb_nm)

    @property
    def rad_per_count(self) -> float:
        return 2.0 * math.pi / self.encoder_counts_per_rev

    def droop_counts(self, load_nm: float) -> float:
        """The position loop's steady error under a load (counts): what the servo gives to hold it."""
        return load_nm / (self.stall_torque_nm * self.position_gain_duty_per_count)


#: The servo-bus arms' realistic plants, by robot name. The STS3215 figures are its data sheet's (12 V
#: version: 2.94 N m, 2.7 A stall); the loop gains, friction, play and thermal figures are *estimates*
#: of a servo of the class (docs/robots.md), none tuned for an application.
SERVO_PLANTS: dict[str, ServoPlantSpec] = {
    "so101": ServoPlantSpec(
        robot="so101",
        servo="STS3215",
        stall_torque_nm=2.94,
        stall_current_a=2.7,
        no_load_speed_rad_s=4.7,
        encoder_counts_per_rev=4096,
        position_gain_duty_per_count=1.0 / 16.0,
        damping_duty_s_rad=0.6,
        deadband_counts=1,
        backlash_rad=math.radians(0.3),
        coulomb_nm=(0.04, 0.05, 0.04, 0.02, 0.02),
        viscous_nm_s=(0.02, 0.02, 0.02, 0.01, 0.01),
        limp_hold_nm=0.6,
        winding_resistance_ohm=4.4,
        winding_rth_k_w=12.0,
        winding_time_constant_s=240.0,
        link_mass_factors=(1.04, 0.97, 1.05, 0.96, 1.03),
        unmodelled_flange_mass_kg=0.010,
    ),
}


def servo_plant_spec(robot: str) -> ServoPlantSpec | None:
    """The servo-bus plant of a robot, or None for a robot on torque-driven joints."""
    return SERVO_PLANTS.get(robot)
