"""The base models the metamorphic tests rewrite: the hard-case suite, the Test Set problems, the
library's test components and examples, and the excavator. Each with the span, grid and
tolerance it is compared at (short spans: the sample in `make test` must stay under a minute).
Models that only extend another with new parameter values (Hard.CartesianPendulumLarge,
Hard.SliderCrankCrankStates) have nothing of their own to rewrite; their parents are here."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MODELS = ROOT / "tests" / "models"
OWN_MODELS = ROOT / "tests" / "metamorphic" / "models"
LIBRARY = ROOT / "components"


@dataclass(frozen=True)
class Base:
    name: str                     # the component's name in its file
    path: Path                    # the file that defines it
    lib_dirs: tuple[str, ...]     # where the packages it uses live (besides the shipped library)
    stop: float
    points: int = 21
    rtol: float = 1e-8            # the tolerance of the base and rewritten runs
    prefix: str = ""              # told apart from a base of the same file name in another folder

    @property
    def label(self) -> str:
        return self.prefix + (self.path.stem if self.path.stem == self.name else f"{self.path.stem}.{self.name}")


def _suite(folder: str, name: str, stop: float, **options) -> Base:
    return Base(name, MODELS / folder / f"{name}.dyad", (str(MODELS),), stop, **options)


def _own(folder: str, name: str, stop: float, **options) -> Base:
    return Base(name, OWN_MODELS / folder / f"{name}.dyad", (str(OWN_MODELS),), stop, **options)


EXCAVATOR = Base("Excavator", LIBRARY / "MultibodyComponents/PlanarMechanics/examples/excavator/Excavator.dyad",
                 (), 2.0, points=21, rtol=1e-6)

BASES = (
    # hard cases
    _suite("Hard", "AndrewsSqueezer", 0.01, rtol=1e-8),
    _suite("Hard", "AndrewsSqueezerAccelerations", 0.01, rtol=1e-8),
    _suite("Hard", "CarAxis", 1.0),
    _suite("Hard", "CartesianPendulum", 2.0, prefix="Hard"),     # no state priorities: its state set switches
    _suite("Hard", "PendulumA01", 2.0),
    _suite("Hard", "PendulumA01Sqrt", 2.0),
    _suite("Hard", "SliderCrank", 0.5),
    _suite("Hard", "SliderGuide", 1.0),
    # Test Set problems
    _suite("Benchmarks", "Andrews", 0.01),
    _suite("Benchmarks", "CartesianPendulum", 2.0),
    _suite("Benchmarks", "Robertson", 40.0, rtol=1e-8),
    _own("TestSet", "AndrewsTestSet", 0.01),
    _own("TestSet", "TransistorAmplifier", 0.02, points=41),
    # the library's test components and examples
    _suite("ComponentTests", "CylinderHoldingLoad", 1.0),
    _suite("ComponentTests", "FallingBody", 1.0),
    _suite("ComponentTests", "Lever", 1.0),
    _suite("ComponentTests", "Pendulum", 2.0),
    _suite("ComponentTests", "PrescribedFrameMotion", 1.0),
    _suite("ComponentTests", "SoilCutting", 1.0),
    _suite("ComponentTests", "SoilSinkage", 1.0),
    _suite("ComponentTests", "ValveFlow", 1.0),
    _suite("Stdlib", "BlockSignals", 2.0),
    _suite("Stdlib", "DiodeCircuit", 1.0),
    _suite("Stdlib", "ElectricalSources", 1.0),
    _suite("Stdlib", "LCOscillator", 2.0),
    _suite("Stdlib", "PIDLoop", 2.0),
    _suite("Stdlib", "RCCharging", 1.0),
    _suite("Stdlib", "RLStep", 1.0),
    _suite("Stdlib", "RotationalSystems", 2.0),
    _suite("Stdlib", "ThermalSystems", 2.0),
    _suite("Stdlib", "TranslationalSystems", 2.0),
    EXCAVATOR,
)

BY_LABEL = {base.label: base for base in BASES}
assert len(BY_LABEL) == len(BASES), "two bases share a label: one would never run"
