"""Published components that do not check because the published source itself is inconsistent,
each reviewed by hand against dyadc's diagnosis (issue 17: "where a published component is
genuinely unbalanced, the report must say so with the culprit").

An entry applies only while dyadc still fails on that component with a first error line
containing `expect` (so a different failure, e.g. a dyadc regression, is never hidden by an old
explanation), and a component that checks is simply checked. The explanations are ours, written
from reading the sources; no source text is quoted.
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Explanation:
    expect: str          # a substring of dyadc's first error line
    culprit: str         # what is wrong in the published source, in our words


_SCALAR_MUX = Explanation(
    "array size mismatch in equation",
    "its signal connectors are declared scalar (`RealInput()`/`RealOutput()` without a size; the "
    "size parameters n1, n2, ... are never used), so its one vector equation sets a scalar equal "
    "to a vector of several elements")

_NO_INITIAL_STRETCH = Explanation(
    "has no member `initial_stretch`",
    "it sets `initial coupler1.initial_stretch`, but its couplers extend "
    "TranslationalComponents.SpringDamper, whose documented members (help.juliahub.com, Dyad "
    "standard library: parameters c, d, s_rel0 and the relative states it inherits) include no "
    "`initial_stretch`")

EXPLAINED: dict[str, Explanation] = {
    "DyadExampleComponents/dyad/train.dyad:Train": _NO_INITIAL_STRETCH,
    "DyadExampleComponents/dyad/train_stopper.dyad:TrainStopper": _NO_INITIAL_STRETCH,
    "BlockComponents/dyad/lim_pid.dyad:LimPID": Explanation(
        "is unbalanced",
        "`control_error` is declared but no equation gives it (one unknown too many)"),
    "BlockComponents/dyad/lim_pid_test.dyad:LimPIDTest": Explanation(
        "is unbalanced", "its `pid` is the LimPID above, one equation short"),
    "ElectricalComponents/dyad/rotational_emf.dyad:RotationalEMF": Explanation(
        "is unbalanced",
        "no equation gives the housing's torque `housing.tau` (the reaction torque, "
        "rotor.tau + housing.tau = 0, is missing)"),
    "ElectricalComponents/dyad/rotational_emf_test.dyad:RotationalEMFTest": Explanation(
        "is unbalanced", "its `rot_emf` is the RotationalEMF above, one equation short"),
    "HydraulicComponents/dyad/flow_divider.dyad:FlowDivider": Explanation(
        "is unbalanced",
        "no equation relates the pressures `p` of its three ports (4 equations for the 5 "
        "unknowns its connections leave to it)"),
    "TranslatedComponents/dyad/Analog/CCCTest.dyad:CCCTest": Explanation(
        "structurally singular",
        "the test leaves all four pins of its `ccc` unconnected, so nothing fixes their voltages"),
    "TranslatedComponents/dyad/Analog/ConditionalHeatPort.dyad:ConditionalHeatPort": Explanation(
        "is unbalanced",
        "a base meant to be extended but not declared `partial`: `LossPower` has no equation "
        "(the component extending it gives one)"),
    "TranslatedComponents/dyad/Blocks/DeMultiplex2.dyad:DeMultiplex2": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/DeMultiplex3.dyad:DeMultiplex3": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/DeMultiplex4.dyad:DeMultiplex4": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/DeMultiplex5.dyad:DeMultiplex5": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/DeMultiplex6.dyad:DeMultiplex6": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/Multiplex3.dyad:Multiplex3": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/Multiplex4.dyad:Multiplex4": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/Multiplex5.dyad:Multiplex5": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/Multiplex6.dyad:Multiplex6": _SCALAR_MUX,
    "TranslatedComponents/dyad/Blocks/Sum.dyad:Sum": Explanation(
        "is declared scalar but its value has size",
        "the gains `k` are declared as a scalar `Real` but given a vector (`ones(nin)`)"),
    "TranslatedComponents/dyad/Blocks/MultiSum.dyad:MultiSum": Explanation(
        "is declared scalar but its value has size",
        "the gains `k` are declared as a scalar `Real` but given a vector (`fill(1, nu)`), and "
        "its input `u` is a scalar connector"),
    "TranslatedComponents/dyad/Blocks/StandardDeviation.dyad:StandardDeviation": Explanation(
        "unknown component type",
        "it uses a `Variance` block that the library does not define"),
    "TranslatedComponents/dyad/FluxTubes/Leakage.dyad:Leakage": Explanation(
        "is unbalanced",
        "nothing gives the permeance: `R_m` and `G_m` are related to each other only (one "
        "equation short)"),
    "TranslatedComponents/dyad/HeatTransfer/BodyRadiation.dyad:BodyRadiation": Explanation(
        "unknown name",
        "`units = m2` names an undefined `m2` (a unit is a string, `\"m2\"`)"),
    "TranslatedComponents/dyad/HeatTransfer/TemperatureSensor.dyad:TemperatureSensor": Explanation(
        "is unbalanced",
        "its output `T` has no equation (the sensor never reads its port's temperature)"),
    "TranslatedComponents/dyad/HeatTransfer/TwoMasses.dyad:TwoMasses": Explanation(
        "is unbalanced", "its two sensors are the TemperatureSensor above, each one equation short"),
    "TranslatedComponents/dyad/Rotational/TorqueToAngleAdaptor.dyad:TorqueToAngleAdaptor": Explanation(
        "is unbalanced",
        "`w_internal` and `a_internal` are public inputs (given by whoever connects them) that "
        "also get equations inside (Modelica's protected connectors became public): two "
        "equations too many as a component"),
}


def explanation(file: str, component: str, reason: str) -> str | None:
    """The reviewed culprit for a component that fails with `reason`, or None."""
    entry = EXPLAINED.get(f"{file}:{component}")
    if entry is None or entry.expect not in reason:
        return None
    return entry.culprit
