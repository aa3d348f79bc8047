#!/usr/bin/env python3
"""FMPy checks of mre's FMUs (issue 28). Run by host-tools/tests/integration/fmu_fmpy.rs,
which writes the FMUs and the reference data into DIR:

  every-term/damper.fmu, every-term/controller.fmu
                           a model file with every format-2 term (coil tau 2 ms)
  trace.csv                a bundled drop recording's x, v with a current sweep,
                           and the core's force at each sample (mre_algorithm in Rust)
  sim/damper.fmu, sim/controller.fmu, sim.json
                           the model `mre sim --controlled` flies, and its result

Checks: FMPy's model-description validation passes for both FMUs, every float
has an SI unit; the damper's force equals the core's on every sample (CS and
ME); a falling mass written here, closed through controller.fmu and damper.fmu
in FMPy, reproduces `mre sim --controlled`'s peak force and stroke within 1 %.
The FMI error contract (issue 43): after fmi3Reset the controller repeats a
fresh instance's commands; every call the FMUs do not support returns
fmi3Error with a log line and the process lives (run in a child process, so
an abort shows as its exit status); setting an output or a calculated
parameter and a doStep with a bad step or from another time return fmi3Error;
the dependency count of each output equals the model description's.
Units and ranges (issue 43 item 6): every unit has a BaseUnit (the ampere
A="1"); every input a min, max and a nominal on its type; a value set out of
its range or NaN returns fmi3Warning with a warning in the log naming the
variable, and the output stays finite.
Exits non-zero on any failure.
"""
import csv
import ctypes
import json
import math
import sys
from pathlib import Path

import fmpy
from fmpy.validation import validate_fmu

from fmpy_common import (ERROR, F32_EPS, WARNING, Fmu, check, closed_loop, controller_reset_check, drop_inputs,
                         fails, refused_sets_check, run_script, unsupported_check)


def validate(path):
    md = fmpy.read_model_description(
        str(path), validate=True, validate_variable_names=True, validate_model_structure=True
    )
    problems = validate_fmu(str(path))
    check(not problems, f"{path.name}: FMPy validate_fmu finds no problem {problems}")
    units = {u.name for u in md.unitDefinitions}
    types = {t.name: t for t in md.typeDefinitions}
    for v in md.modelVariables:
        if v.type == "Float64":
            t = types.get(v.declaredType.name) if v.declaredType else None
            unit = t.unit if t else None
            check(unit in units, f"{path.name}: {v.name} has an SI unit ({unit})")
            if v.name != "time":
                check(bool(v.description), f"{path.name}: {v.name} has a description")
    for u in md.unitDefinitions:
        check(u.baseUnit is not None, f"{path.name}: unit {u.name} has a BaseUnit")
        if u.name == "A":
            check(u.baseUnit is not None and u.baseUnit.A == 1, f"{path.name}: the ampere's BaseUnit is A=1")
    for v in md.modelVariables:
        if v.causality == "input":
            t = types.get(v.declaredType.name) if v.declaredType else None
            check(v.min is not None and v.max is not None and float(v.min) < float(v.max),
                  f"{path.name}: input {v.name} has a range [{v.min}, {v.max}]")
            check(t is not None and t.nominal is not None and float(t.nominal) > 0,
                  f"{path.name}: input {v.name} has a nominal ({t.nominal if t else None})")
    check(md.defaultExperiment is not None and md.defaultExperiment.stepSize is not None,
          f"{path.name}: default experiment with a step size")
    return md


def trace_check(damper_path, trace_path, me):
    rows = list(csv.DictReader(open(trace_path)))
    d = Fmu(damper_path, me=me)
    worst, scale = 0.0, max(abs(float(r["force_core_n"])) for r in rows)
    for r in rows:
        d.set(displacement_m=float(r["displacement_m"]), velocity_m_s=float(r["velocity_m_s"]),
              current_a=float(r["current_a"]))
        if me:
            d.handle_events()
        worst = max(worst, abs(d.get("force_n") - float(r["force_core_n"])))
    d.close()
    # The FMU takes x in m and converts to the board's mm in f32; the
    # reference fed the recorded mm straight in: a few f32 ulps of the force.
    check(worst <= 8 * F32_EPS * scale,
          f"damper ({'ME' if me else 'CS'}): force equals the core's on {len(rows)} samples "
          f"(worst {worst:.3g} N, f32 rounding allows {8 * F32_EPS * scale:.3g} N)")


def coil_check(every_dir):
    """controller.fmu's coil_current_a is its drive through the coil's lag, integrated here
    exactly (u + (i - u) e^(-T/tau) per tick, tau the damper's coil_tau_s), from the idle
    current it holds before the first tick; drive_voltage_v is the drive times R."""
    damper = Fmu(every_dir / "damper.fmu")
    tau = damper.get("coil_tau_s")
    damper.close()
    ctl = Fmu(every_dir / "controller.fmu")
    period, ohm = ctl.get("control_period_s"), ctl.get("coil_resistance_ohm")
    coil = ctl.get("coil_current_a")
    check(tau > 0 and coil == ctl.get("coil_command_a"), f"coil: tau {tau} s, idle current {coil} A before the first tick")
    worst, lag_seen = 0.0, 0.0
    for k, (x, v) in enumerate(drop_inputs(60)):
        ctl.set(displacement_m=x, velocity_m_s=v)
        ctl.fmu.doStep(k * period, period)
        u = ctl.get("coil_command_a")
        coil = u + (coil - u) * math.exp(-period / tau)
        worst = max(worst, abs(ctl.get("coil_current_a") - coil))
        lag_seen = max(lag_seen, abs(u - coil))
        check(ctl.get("drive_voltage_v") == u * ohm, f"coil: tick {k}: drive_voltage_v = coil_command_a x {ohm} ohm")
    ctl.close()
    check(lag_seen > 0.1, f"coil: the drive leads the current (up to {lag_seen:.3g} A): the check sees the lag")
    check(worst <= 1e-9, f"coil: coil_current_a is the drive through tau = {tau} s (worst {worst:.3g} A)")


def unsupported_calls(f):
    """The calls this FMU does not implement, with arguments of the right shape."""
    u = f.fmu
    vr = (ctypes.c_uint32 * 1)(0)
    x = (ctypes.c_double * 1)(0.0)
    state = ctypes.c_void_p()
    size = ctypes.c_size_t()
    q = (ctypes.c_int * 1)(0)
    return {
        "fmi3GetFMUState": lambda: u.fmi3GetFMUState(u.component, ctypes.byref(state)),
        "fmi3SetFMUState": lambda: u.fmi3SetFMUState(u.component, state),
        "fmi3SerializedFMUStateSize": lambda: u.fmi3SerializedFMUStateSize(u.component, state, ctypes.byref(size)),
        "fmi3GetDirectionalDerivative": lambda: u.fmi3GetDirectionalDerivative(
            u.component, vr, 1, vr, 1, x, 1, x, 1),
        "fmi3GetAdjointDerivative": lambda: u.fmi3GetAdjointDerivative(u.component, vr, 1, vr, 1, x, 1, x, 1),
        "fmi3EvaluateDiscreteStates": lambda: u.fmi3EvaluateDiscreteStates(u.component),
        "fmi3GetIntervalDecimal": lambda: u.fmi3GetIntervalDecimal(u.component, vr, 1, x, q),
        "fmi3GetShiftDecimal": lambda: u.fmi3GetShiftDecimal(u.component, vr, 1, x),
        "fmi3SetIntervalDecimal": lambda: u.fmi3SetIntervalDecimal(u.component, vr, 1, x),
    }


def contract_check(sim_dir):
    for fmu in ["damper.fmu", "controller.fmu"]:
        unsupported_check(__file__, sim_dir / fmu, fmu, "fmi3Error")

    # Setting an output or a calculated parameter is refused; a doStep with a
    # bad step or from another time than the instance's is refused.
    for fmu, names in [("damper.fmu", ["force_n", "coil_tau_s"]),
                       ("controller.fmu", ["coil_command_a", "control_period_s"])]:
        log = []
        f = Fmu(sim_dir / fmu, log=log)
        refused_sets_check(f, log, names, fmu, "fmi3Error")
        h = float(f.md.defaultExperiment.stepSize)
        for what, t, step in [("a negative step", 0.0, -h), ("a NaN step", 0.0, float("nan")),
                              ("a zero step", 0.0, 0.0), ("a step from a later time", 5 * h, h)]:
            n = len(log)
            status = fails(lambda: f.fmu.doStep(t, step))
            check(status == ERROR and len(log) > n, f"{fmu}: doStep with {what} returns fmi3Error ({status})")
        f.fmu.doStep(0.0, h)
        status = fails(lambda: f.fmu.doStep(0.0, h))
        check(status == ERROR, f"{fmu}: doStep going back in time returns fmi3Error ({status})")
        status = fails(lambda: f.fmu.doStep(h, h))
        check(status == 0, f"{fmu}: the next step in time still runs ({status})")

        # Dependencies: the count the FMU gives equals the XML's list.
        for out in f.md.outputs:
            n = ctypes.c_size_t(99)
            f.fmu.fmi3GetNumberOfVariableDependencies(f.fmu.component, out.variable.valueReference,
                                                      ctypes.byref(n))
            declared = out.dependencies
            check(declared is not None and n.value == len(declared),
                  f"{fmu}: fmi3GetNumberOfVariableDependencies({out.variable.name}) = {n.value}, "
                  f"the XML lists {None if declared is None else len(declared)}")
        f.close()
    # By hand: the damper's force is a function of displacement, velocity and current.
    md = fmpy.read_model_description(str(sim_dir / "damper.fmu"))
    force = next(o for o in md.outputs if o.variable.name == "force_n")
    check(sorted(v.name for v in force.dependencies or []) == ["current_a", "displacement_m", "velocity_m_s"],
          "damper.fmu: force_n depends on displacement_m, velocity_m_s and current_a in the XML")


def range_check(path, output):
    """Out-of-range and NaN inputs: fmi3Warning, a warning logged naming the input, a finite output."""
    log = []
    f = Fmu(path, log=log)
    u = f.fmu
    inputs = [v for v in f.md.modelVariables if v.causality == "input"]
    for v in inputs:
        for what, value in [("NaN", float("nan")), ("above max", float(v.max) * 10 + 1.0)]:
            n = len(log)
            vr = (ctypes.c_uint32 * 1)(v.valueReference)
            x = (ctypes.c_double * 1)(value)
            status = u.fmi3SetFloat64(u.component, vr, 1, x, 1)
            warned = [m for s, m in log[n:] if s == WARNING and v.name in m]
            check(status == WARNING and warned,
                  f"{path.name}: {v.name} {what} -> status {status} (fmi3Warning = 1), logged {warned[:1]}")
            if output == "force_n":
                check(math.isfinite(f.get(output)), f"{path.name}: {output} stays finite with {v.name} {what}")
            # Back in range: OK again.
            start = (ctypes.c_double * 1)(float(v.start or 0.0))
            check(u.fmi3SetFloat64(u.component, vr, 1, start, 1) == 0,
                  f"{path.name}: {v.name} back at its start value is OK")
    f.close()


def main():
    root = Path(sys.argv[1])
    validate(root / "every-term" / "damper.fmu")
    validate(root / "sim" / "damper.fmu")
    validate(root / "sim" / "controller.fmu")
    trace_check(root / "every-term" / "damper.fmu", root / "trace.csv", me=False)
    trace_check(root / "every-term" / "damper.fmu", root / "trace.csv", me=True)
    closed_loop(root / "sim", json.load(open(root / "sim.json")), "")
    controller_reset_check(root / "sim" / "controller.fmu", "controller", 8)
    coil_check(root / "every-term")
    contract_check(root / "sim")
    range_check(root / "sim" / "damper.fmu", "force_n")
    range_check(root / "sim" / "controller.fmu", "coil_command_a")


if __name__ == "__main__":
    run_script(main, unsupported_calls)
