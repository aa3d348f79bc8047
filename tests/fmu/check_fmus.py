#!/usr/bin/env python3
"""FMPy checks of mre's FMUs (issue 28). Run by host-tools/tests/integration/fmu_fmpy.rs,
which writes the FMUs and the reference data into DIR:

  every-term/damper.fmu    a model file with every format-2 term
  trace.csv                a bundled drop recording's x, v with a current sweep,
                           and the core's force at each sample (mre_core in Rust)
  sim/damper.fmu, sim/controller.fmu, sim.json
                           the model `mre sim --controlled` flies, and its result

Checks: FMPy's model-description validation passes for both FMUs, every float
has an SI unit; the damper's force equals the core's on every sample (CS and
ME); a falling mass written here, closed through controller.fmu and damper.fmu
in FMPy, reproduces `mre sim --controlled`'s peak force and stroke within 1 %.
Exits non-zero on any failure.
"""
import csv
import json
import math
import shutil
import sys
import tempfile
from pathlib import Path

import fmpy
from fmpy.fmi3 import FMU3Model, FMU3Slave
from fmpy.validation import validate_fmu

F32_EPS = 2.0 ** -23
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


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
    check(md.defaultExperiment is not None and md.defaultExperiment.stepSize is not None,
          f"{path.name}: default experiment with a step size")
    return md


class Fmu:
    """One instance of an FMU by variable name (CS or ME)."""

    def __init__(self, path, me=False):
        self.md = fmpy.read_model_description(str(path))
        self.dir = tempfile.mkdtemp()
        fmpy.extract(str(path), self.dir)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        kind = FMU3Model if me else FMU3Slave
        iface = self.md.modelExchange if me else self.md.coSimulation
        self.fmu = kind(guid=self.md.guid, unzipDirectory=self.dir,
                        modelIdentifier=iface.modelIdentifier, instanceName=path.stem)
        self.fmu.instantiate()
        self.fmu.enterInitializationMode(startTime=0.0)
        self.fmu.exitInitializationMode()
        if me:
            self.fmu.enterContinuousTimeMode()

    def set(self, **values):
        self.fmu.setFloat64([self.vr[k] for k in values], list(values.values()))

    def get(self, name):
        return self.fmu.getFloat64([self.vr[name]])[0]

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


def trace_check(damper_path, trace_path, me):
    rows = list(csv.DictReader(open(trace_path)))
    d = Fmu(damper_path, me=me)
    worst, scale = 0.0, max(abs(float(r["force_core_n"])) for r in rows)
    for r in rows:
        d.set(displacement_m=float(r["displacement_m"]), velocity_m_s=float(r["velocity_m_s"]),
              current_a=float(r["current_a"]))
        worst = max(worst, abs(d.get("force_n") - float(r["force_core_n"])))
    d.close()
    # The FMU takes x in m and converts to the board's mm in f32; the
    # reference fed the recorded mm straight in: a few f32 ulps of the force.
    check(worst <= 8 * F32_EPS * scale,
          f"damper ({'ME' if me else 'CS'}): force equals the core's on {len(rows)} samples "
          f"(worst {worst:.3g} N, f32 rounding allows {8 * F32_EPS * scale:.3g} N)")


def closed_loop(sim_dir, sim):
    damper = Fmu(sim_dir / "damper.fmu")
    ctl = Fmu(sim_dir / "controller.fmu")
    period = ctl.get("control_period_s")
    substeps = int(round(period / sim["step_s"]))
    h = period / substeps
    m, g = sim["mass_kg"], sim["gravity_m_s2"]
    tau = sim["coil_lag_s"]
    lo, hi = sim["drive_range_a"]
    x, v, t = 0.0, sim["impact_velocity_m_s"], 0.0
    current = sim["initial_current_a"]
    peak_force, max_stroke = 0.0, 0.0

    def force(xm, vm, i):
        # The mass touches the damper only at x > 0, and the damper only pushes.
        if xm <= 0.0:
            return 0.0
        damper.set(displacement_m=xm, velocity_m_s=vm, current_a=i)
        return max(damper.get("force_n"), 0.0)

    def accel(xm, vm, i):
        return g - force(xm, vm, i) / m

    while t < sim["max_duration_s"]:
        ctl.set(displacement_m=x, velocity_m_s=v)
        ctl.fmu.doStep(t, period)
        command = ctl.get("coil_command_a")
        done = False
        for _ in range(substeps):
            if tau is None:
                current = command
            else:
                current += (min(max(command, lo), hi) - current) * (1.0 - math.exp(-h / tau))
            k1x, k1v = v, accel(x, v, current)
            k2x, k2v = v + h / 2 * k1v, accel(x + h / 2 * k1x, v + h / 2 * k1v, current)
            k3x, k3v = v + h / 2 * k2v, accel(x + h / 2 * k2x, v + h / 2 * k2v, current)
            k4x, k4v = v + h * k3v, accel(x + h * k3x, v + h * k3v, current)
            x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x)
            v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
            t += h
            peak_force = max(peak_force, force(x, v, current))
            max_stroke = max(max_stroke, x * 1e3)
            if x < 0.0 and v < 0.0:
                done = True
                break
        damper.fmu.doStep(t - period, period)
        if done:
            break
    damper.close()
    ctl.close()
    for what, fmpy_value, mre_value in [
        ("peak force (N)", peak_force, sim["peak_force_n"]),
        ("stroke (mm)", max_stroke, sim["max_stroke_mm"]),
    ]:
        rel = abs(fmpy_value - mre_value) / mre_value
        check(rel <= 0.01, f"closed loop in FMPy: {what} {fmpy_value:.2f} vs mre sim --controlled "
                           f"{mre_value:.2f} ({100 * rel:.2f} %, at most 1 %)")


def main():
    root = Path(sys.argv[1])
    validate(root / "every-term" / "damper.fmu")
    validate(root / "sim" / "damper.fmu")
    validate(root / "sim" / "controller.fmu")
    trace_check(root / "every-term" / "damper.fmu", root / "trace.csv", me=False)
    trace_check(root / "every-term" / "damper.fmu", root / "trace.csv", me=True)
    closed_loop(root / "sim", json.load(open(root / "sim.json")))
    print(f"{len(failures)} failed" if failures else "all FMPy checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
