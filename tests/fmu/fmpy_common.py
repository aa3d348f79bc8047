"""What check_fmus.py (FMI 3.0) and check_fmi2.py (FMI 2.0) share: the
check record, an FMU instance by variable name for either version and
interface, the drop the controller is driven with, and the falling mass
closed through controller.fmu and damper.fmu that is compared with
`mre sim --controlled`."""
import ctypes
import json
import math
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import fmpy
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Model, FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.fmi3 import FMU3Model, FMU3Slave

F32_EPS = 2.0 ** -23
OK, WARNING, ERROR = 0, 1, 3  # fmi2Status and fmi3Status alike
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def fails(call):
    """The status of an FMI call: the one FMPy raises on, else the one a raw call
    returns, else OK."""
    try:
        result = call()
    except FMICallException as e:
        return getattr(e, "status", ERROR)
    return result if isinstance(result, int) else OK


class Fmu:
    """One instance of an FMU (2.0 or 3.0, CS or ME) by variable name, initialised
    at time 0; with `log` a list, every message the FMU logs as (status, text)."""

    def __init__(self, path, me=False, log=None):
        self.md = fmpy.read_model_description(str(path))
        self.v2 = self.md.fmiVersion == "2.0"
        self.dir = tempfile.mkdtemp()
        fmpy.extract(str(path), self.dir)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        iface = self.md.modelExchange if me else self.md.coSimulation
        if self.v2:
            kind = FMU2Model if me else FMU2Slave
        else:
            kind = FMU3Model if me else FMU3Slave
        self.fmu = kind(guid=self.md.guid, unzipDirectory=self.dir,
                        modelIdentifier=iface.modelIdentifier, instanceName=path.stem)
        if log is None:
            self.fmu.instantiate()
        elif self.v2:
            def logger2(env, name, status, category, message):
                log.append((status, message.decode(errors="replace")))
            self.callbacks = fmi2CallbackFunctions()
            self.callbacks.logger = fmi2CallbackLoggerTYPE(logger2)
            self.callbacks.allocateMemory = fmpy.fmi2.fmi2CallbackAllocateMemoryTYPE(fmpy.fmi2.calloc)
            self.callbacks.freeMemory = fmpy.fmi2.fmi2CallbackFreeMemoryTYPE(fmpy.fmi2.free)
            self.fmu.instantiate(callbacks=self.callbacks, loggingOn=True)
        else:
            def logger3(env, status, category, message):
                log.append((status, message.decode(errors="replace")))
            self.fmu.instantiate(loggingOn=True, logMessage=logger3)
        self.start()
        if me:
            if self.v2:
                self.fmu.newDiscreteStates()
            self.fmu.enterContinuousTimeMode()
            self.z = self.indicator()

    def start(self):
        self.enter_initialization()
        self.fmu.exitInitializationMode()

    def enter_initialization(self):
        if self.v2:
            self.fmu.setupExperiment(startTime=0.0)
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=0.0)

    def set(self, **values):
        vrs, xs = [self.vr[k] for k in values], list(values.values())
        self.fmu.setReal(vrs, xs) if self.v2 else self.fmu.setFloat64(vrs, xs)

    def get(self, name):
        return (self.fmu.getReal if self.v2 else self.fmu.getFloat64)([self.vr[name]])[0]

    def indicator(self):
        """The damper's one event indicator (Model Exchange)."""
        buf = (ctypes.c_double * 1)()
        self.fmu.getEventIndicators(buf, 1)
        return buf[0]

    def handle_events(self):
        """As an ME importer does after new inputs: a sign change of the event
        indicator (the velocity) is an event, where the damper switches branch
        (it holds its branch in continuous time)."""
        z = self.indicator()
        if (z > 0) != (self.z > 0):
            self.fmu.enterEventMode()
            self.fmu.newDiscreteStates() if self.v2 else self.fmu.updateDiscreteStates()
            self.fmu.enterContinuousTimeMode()
        self.z = z

    def raw(self, name, *args):
        """Calls a function of the library directly; returns its status."""
        f = getattr(self.fmu.dll, name)
        f.restype = ctypes.c_uint
        return f(ctypes.c_void_p(self.fmu.component), *args)

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.dir, ignore_errors=True)


def drop_inputs(n):
    """x, v of a mass met at 2.24 m/s and stopped over n ticks: it loads the law."""
    x, out = 0.0, []
    for k in range(n):
        v = 2.24 * (1.0 - k / n)
        out.append((x, v))
        x += v * 1e-4
    return out


def commands(ctl, period, inputs):
    got = []
    for k, (x, v) in enumerate(inputs):
        ctl.set(displacement_m=x, velocity_m_s=v)
        ctl.fmu.doStep(k * period, period)
        got.append((ctl.get("coil_command_a"), ctl.get("target_force_n")))
    return got


def controller_reset_check(path, label, ticks):
    """After fmiXReset and a new initialisation the controller is a fresh instance:
    the command in Initialization Mode is a fresh one's, and on the same drop it
    commands what a fresh instance does. The reset comes `ticks` into the drop
    (state and tick count built up, the command moved)."""
    fresh = Fmu(path)
    reset = "fmi2Reset" if fresh.v2 else "fmi3Reset"
    period = fresh.get("control_period_s")
    at_init = fresh.get("coil_command_a")
    inputs = drop_inputs(60)
    expected = commands(fresh, period, inputs)
    fresh.close()
    check(any(c != at_init for c, _ in expected), f"{label}: the drop moves the command")
    ctl = Fmu(path)
    before = commands(ctl, period, inputs[:ticks])
    check(before[-1][0] != at_init, f"{label}: the reset comes while the command is not the initial one")
    ctl.fmu.reset()
    ctl.enter_initialization()
    check(ctl.get("coil_command_a") == at_init,
          f"{label}: after {reset} the command in Initialization Mode is a fresh instance's")
    ctl.fmu.exitInitializationMode()
    again = commands(ctl, period, inputs)
    ctl.close()
    check(again == expected, f"{label}: after {reset} it commands what a fresh instance does on the same inputs")


def closed_loop(sim_dir, sim, label):
    """A falling mass written here (RK4 at mre sim's step, the coil lag integrated
    here from the controller's drive), closed through sim_dir's controller.fmu and
    damper.fmu, against `mre sim --controlled` (sim: its settings and result)."""
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
    coil_gap, drive_gap = 0.0, 0.0
    ohm = ctl.get("coil_resistance_ohm")

    def force(xm, vm, i):
        # The mass touches the damper only at x > 0, and the damper only pushes.
        if xm <= 0.0:
            return 0.0
        damper.set(displacement_m=xm, velocity_m_s=vm, current_a=i)
        return max(damper.get("force_n"), 0.0)

    def accel(xm, vm, i):
        return g - force(xm, vm, i) / m

    while t < sim["max_duration_s"]:
        t0 = t
        ctl.set(displacement_m=x, velocity_m_s=v)
        ctl.fmu.doStep(t, period)
        command = ctl.get("coil_command_a")
        coil_fmu = ctl.get("coil_current_a")
        drive_gap = max(drive_gap, abs(ctl.get("drive_voltage_v") - command * ohm))
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
        if not done:
            # The FMU's coil current at the tick's end against the lag integrated here.
            coil_gap = max(coil_gap, abs(coil_fmu - current))
        damper.fmu.doStep(t0, period)
        if done:
            break
    damper.close()
    ctl.close()
    check(coil_gap <= 1e-6, f"{label}closed loop: controller's coil_current_a is the coil current the loop "
                            f"integrates (worst {coil_gap:.3g} A)")
    check(drive_gap <= 1e-9, f"{label}closed loop: drive_voltage_v = coil_command_a x {ohm} ohm "
                             f"(worst {drive_gap:.3g} V)")
    for what, fmpy_value, mre_value in [
        ("peak force (N)", peak_force, sim["peak_force_n"]),
        ("stroke (mm)", max_stroke, sim["max_stroke_mm"]),
    ]:
        rel = abs(fmpy_value - mre_value) / mre_value
        check(rel <= 0.01, f"{label}closed loop in FMPy: {what} {fmpy_value:.2f} vs mre sim --controlled "
                           f"{mre_value:.2f} ({100 * rel:.2f} %, at most 1 %)")
    return peak_force, max_stroke


def unsupported_check(script, path, label, error):
    """Runs `script --unsupported path` (the script's child: each unsupported call
    once, a JSON line each) and checks that the process lives and that all 9 calls
    return `error` (fmi2Error / fmi3Error, 3) with a log line naming the call."""
    child = subprocess.run([sys.executable, script, "--unsupported", str(path)], capture_output=True, text=True)
    check(child.returncode == 0, f"{label}: the unsupported calls leave the process alive "
                                 f"(exit {child.returncode}; {child.stderr.strip()[-300:]})")
    results = [json.loads(line) for line in child.stdout.splitlines() if line.startswith("{")]
    check(len(results) == 9, f"{label}: all 9 unsupported calls returned ({len(results)})")
    for r in results:
        check(r["status"] == ERROR and r["logged"],
              f"{label}: {r['call']} returns {error} ({r['status']}) with a log line naming it ({r['logged']})")


def refused_sets_check(f, log, names, label, error):
    """Setting an output or a calculated parameter returns `error` with a log line
    and leaves the value as it was."""
    set_values = f.fmu.setReal if f.v2 else f.fmu.setFloat64
    for name in names:
        before = f.get(name)
        n = len(log)
        status = fails(lambda: set_values([f.vr[name]], [before + 1.0]))
        check(status == ERROR and len(log) > n, f"{label}: setting {name} returns {error} ({status}) with a log line")
        check(f.get(name) == before, f"{label}: {name} keeps its value after the refused set")


def run_script(main, unsupported_calls):
    """A check script's entry point. `SCRIPT --unsupported PATH` is unsupported_check's
    child: each call of unsupported_calls(fmu) (name: call) once, a JSON line each
    with its status and whether the log named it. Otherwise main() runs the checks;
    the last line is the verdict, the exit status non-zero on any failure."""
    if len(sys.argv) == 3 and sys.argv[1] == "--unsupported":
        log = []
        f = Fmu(Path(sys.argv[2]), log=log)
        for name, call in unsupported_calls(f).items():
            n = len(log)
            status = fails(call)
            said = any(name in m for _, m in log[n:])
            print(json.dumps({"call": name, "status": status, "logged": said}), flush=True)
        f.close()
        sys.exit(0)
    main()
    print(f"{len(failures)} failed" if failures else "all FMPy checks passed")
    sys.exit(1 if failures else 0)
