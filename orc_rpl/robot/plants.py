"""The robot room's plant descriptions: how each simulated robot differs from the controller's model, documented once."""

from __future__ import annotations

from dataclasses import dataclass

from orc_rpl.errors import UsageError
from orc_rpl.robot.servo_plants import SERVO_PLANTS
from orc_rpl.robot.tables import check_per_joint

#: Temperature coefficient of copper's resistance: +0.393 % per kelvin.
COPPER_TEMPCO_1_K = 0.00393


@dataclass(frozen=True, slots=True)
class PlantSpec:
    """The realistic virtual robot of one arm: friction, motors, encoders and what its masses really are.

    Per-joint tuples are j1..jn. Friction is at the joint (after the gear). The controller's model
    knows the *nominal* warm friction (`coulomb_nm`, `viscous_nm_s`) for its feed-forward; the plant's
    warm friction is that times `plant_coulomb_factor` / `plant_viscous_factor`, and a cold plant has
    `cold_friction_factor` times the warm friction. The excess decays as exp(-rise / warm_rise_k) with
    the gearbox temperature rise, which follows dT/dt = (P - T / Rth) / (Rth Cth) with P the friction
    power plus `gear_motor_heat_share` of the motor's copper loss.

    Motors: a torque tau at the joint needs a current i = tau / torque_per_amp; the winding loses
    R (1 + 0.00393 (T - 20 C)) i^2 and heats by the same first-order law with its own Rth and time
    constant. The winding figures are the data sheet's (what the controller's estimate uses); the
    plant's own are those times the `plant_*_factor`s. The encoder sees the motor-side angle quantised to `encoder_counts_per_rev` per joint
    revolution (motor encoder counts times the gear ratio); the velocity the servo reads carries
    seeded Gaussian noise of `velocity_noise_rad_s` (1 sigma).
    """

    robot: str
    coulomb_nm: tuple[float, ...]              #: nominal warm Coulomb friction (the controller's model)
    viscous_nm_s: tuple[float, ...]            #: nominal warm viscous friction (the controller's model)
    torque_per_amp_nm_a: tuple[float, ...]     #: motor torque constant times gear ratio (joint side)
    winding_resistance_ohm: tuple[float, ...]  #: at 20 C (data sheet: the controller's estimate uses it)
    winding_rth_k_w: tuple[float, ...]         #: winding to ambient thermal resistance (data sheet)
    winding_time_constant_s: tuple[float, ...] #: (data sheet)
    gear_rth_k_w: tuple[float, ...]            #: gearbox to ambient thermal resistance
    encoder_counts_per_rev: float              #: per joint revolution
    velocity_noise_rad_s: float                #: 1 sigma on the measured joint speed
    link_mass_factors: tuple[float, ...]       #: plant mass / model mass, links 1..n (inertias scale alike)
    unmodelled_flange_mass_kg: float           #: dress pack and cables the controller's model does not have
    plant_coulomb_factor: float = 1.10         #: plant warm Coulomb friction / nominal
    plant_viscous_factor: float = 0.92         #: plant warm viscous friction / nominal
    plant_resistance_factor: float = 1.02      #: plant winding resistance / data sheet
    plant_winding_rth_factor: float = 1.02     #: plant winding thermal resistance / data sheet
    plant_winding_time_factor: float = 0.97    #: plant winding time constant / data sheet
    cold_friction_factor: float = 2.0          #: friction at ambient / warm friction
    warm_rise_k: float = 6.0                   #: gearbox rise over which the cold excess falls to 1/e
    gear_time_constant_s: float = 1200.0       #: gearbox warm-up time constant (20 min)
    gear_motor_heat_share: float = 0.3         #: share of the motor's copper loss that warms the gearbox
    ambient_c: float = 20.0
    gear_stiffness_nm_rad: tuple[float, ...] | None = None  #: elastic gears (motor and link sides), None: rigid
    gear_damping_nm_s: tuple[float, ...] = ()              #: the gears' own damping, with the stiffness

    def __post_init__(self) -> None:
        check_per_joint(self, ("viscous_nm_s", "torque_per_amp_nm_a", "winding_resistance_ohm", "winding_rth_k_w",
                               "winding_time_constant_s", "gear_rth_k_w", "link_mass_factors"))

    @property
    def n_joints(self) -> int:
        return len(self.coulomb_nm)


#: Plant mass and inertia over the model's, links 1..6: a few percent either way (the same for both arms).
LINK_MASS_FACTORS = (1.03, 0.97, 1.04, 0.96, 1.05, 0.98)

#: The realistic plants, by robot name. Every figure is an *estimate* of a robot of the class
#: (docs/robots.md, "The realistic plant"); none is tuned for an application.
PLANTS: dict[str, PlantSpec] = {
    "irb2400": PlantSpec(
        robot="irb2400",
        coulomb_nm=(40.0, 50.0, 25.0, 4.0, 4.0, 2.0),
        viscous_nm_s=(60.0, 60.0, 30.0, 3.0, 3.0, 1.5),
        torque_per_amp_nm_a=(40.0, 60.0, 35.0, 8.0, 8.0, 5.0),
        winding_resistance_ohm=(1.2, 0.8, 1.5, 4.0, 4.0, 6.0),
        winding_rth_k_w=(0.45, 0.45, 0.6, 1.2, 1.2, 1.8),
        winding_time_constant_s=(40.0, 40.0, 30.0, 20.0, 20.0, 15.0),
        gear_rth_k_w=(0.5, 0.4, 0.8, 4.0, 4.0, 8.0),
        encoder_counts_per_rev=2.0**20 * 120.0,
        velocity_noise_rad_s=2e-4,
        link_mass_factors=LINK_MASS_FACTORS,
        unmodelled_flange_mass_kg=1.5,
        gear_stiffness_nm_rad=(1.5e5, 2.0e5, 1.0e5, 1.5e4, 1.5e4, 5.0e3),
        gear_damping_nm_s=(250.0, 280.0, 100.0, 9.0, 7.0, 1.0),
    ),
    "ur5e": PlantSpec(
        robot="ur5e",
        coulomb_nm=(4.0, 4.0, 3.0, 0.8, 0.8, 0.8),
        viscous_nm_s=(5.0, 5.0, 3.0, 0.6, 0.6, 0.6),
        torque_per_amp_nm_a=(12.0, 12.0, 12.0, 3.0, 3.0, 3.0),
        winding_resistance_ohm=(0.6, 0.6, 0.6, 1.5, 1.5, 1.5),
        winding_rth_k_w=(1.5, 1.5, 1.5, 3.0, 3.0, 3.0),
        winding_time_constant_s=(30.0, 30.0, 30.0, 15.0, 15.0, 15.0),
        gear_rth_k_w=(3.0, 3.0, 3.0, 8.0, 8.0, 8.0),
        encoder_counts_per_rev=2.0**18 * 100.0,
        velocity_noise_rad_s=2e-4,
        link_mass_factors=LINK_MASS_FACTORS,
        unmodelled_flange_mass_kg=0.2,
    ),
}


def plant_spec(robot: str) -> PlantSpec:
    """The realistic plant of a robot; a UsageError naming the robots that have one."""
    try:
        return PLANTS[robot]
    except KeyError:
        raise UsageError(f"robot {robot!r} has no realistic plant description (robots with one: "
                         f"{', '.join(sorted(PLANTS))}); use --plant ideal") from None


#: The simulated plants a run can ask for (`--plant`, `plant=`; docs/robots.md, "Which plant"): "realistic" (rigid
#: gears), "elastic-gears" (the realistic plant with elastic gears, their feed-forward and the state feedback: robots
#: whose description has a gear stiffness), "ideal" (the controller's own model, exactly).
SIMULATED_PLANTS = ("realistic", "elastic-gears", "ideal")


def has_elastic_gears(robot: str) -> bool:
    """True when the robot's realistic plant has elastic gears (its description gives a gear stiffness)."""
    spec = PLANTS.get(robot)
    return spec is not None and spec.gear_stiffness_nm_rad is not None


def check_elastic_gears(robot: str, argument: str) -> None:
    """A UsageError naming `argument` and the robots with elastic gears when `robot` has none."""
    if not has_elastic_gears(robot):
        robots = ", ".join(sorted(name for name in PLANTS if has_elastic_gears(name)))
        raise UsageError(f"{argument}: robot {robot!r} has no elastic gears (robots with elastic gears: {robots})")


def default_plant(robot: str) -> str:
    """The plant a simulated run gets when none is asked for: realistic where the robot has a description."""
    return "realistic" if robot in PLANTS or robot in SERVO_PLANTS else "ideal"
