"""Scenarios on the rehosted board image (stm32l4.py), run by
host-tools/tests/integration/rehost.rs (`cargo test`) or by hand:

    python3 firmware/rehost/scenarios.py --elf ELF --board b-l475e-iot01a SCENARIO [--page F] [--upload F]

Prints `ok SCENARIO ...` and exits 0, or fails with the reason (exit 1).
Expected values come from the hardware, not from the image: the coil driver
is 12 V into 4 ohm (3 A at 100 % duty), TIM3 runs at 20 kHz from 80 MHz
(ARR + 1 = 4000, RM0351's TIM2-5 "PWM mode"), so the boot fail-safe (1 A, the weakest
coil the board admits) is duty 1333/4000 and the default coil's 2 A is
2666/4000; the current sense is 1 V/A into a 12-bit ADC at 3.3 V.
"""
import argparse
import struct
import sys
import os

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from stm32l4 import Chip, SYSCLK  # noqa: E402
from unicorn.arm_const import UC_ARM_REG_R0, UC_ARM_REG_PRIMASK, UC_ARM_REG_SP  # noqa: E402

PERIOD = SYSCLK // 10_000          # one control period (10 kHz)
MS = SYSCLK // 1000
UART4_EXC = 16 + 52                # the control executor's vector
DUTY_1A = 1333 / 4000
DUTY_2A = 2666 / 4000
LSB = 1 / 4000
OVER_CURRENT = 1 << 16
CURRENT_SENSE = 1 << 17
CSR = {
    # RM0351 "Control/status register (RCC_CSR)" reset flags: LPWR 31, WWDG 30, IWDG 29, SFT 28,
    # BOR 27, PIN 26. NRST pulses on every reset, so PINRSTF accompanies all;
    # a power-on sets BORRSTF too (and reads like a brown-out).
    "power-on": (1 << 27) | (1 << 26),
    "brown-out": (1 << 27) | (1 << 26),
    "pin": 1 << 26,
    "iwdg": (1 << 29) | (1 << 26),
    "software": (1 << 28) | (1 << 26),
}


def check(cond, what):
    if not cond:
        raise AssertionError(what)


def periods(chip):
    return sum(1 for e in chip.log if e[1] == "enter" and e[2] == UART4_EXC)


def run_periods(chip, n, limit_ms=200):
    target = periods(chip) + n
    reached = chip.run(limit_ms * MS, until=lambda: periods(chip) >= target)
    check(reached, f"the control loop did not run {n} periods within {limit_ms} ms "
                   f"(resets {chip.resets}, coil {chip.coil_history[-4:]})")


def latched(chip):
    return chip.sym_word("LATCHED_FAULTS")


def duty_now(chip):
    s = chip.coil_state()
    return s if isinstance(s, float) else 0.0


def near(a, b):
    return isinstance(a, float) and abs(a - b) <= LSB


def after_pre_init(history):
    """The coil's history from `__pre_init`'s pin-low on (before it, PB4 is
    the reset state's NJTRST pull-up: not a command)."""
    for k, (_t, s) in enumerate(history):
        if s == 0.0:
            return history[k:]
    raise AssertionError(f"the coil pin never went low: {history}")


def boot(args, cause="power-on", page=None):
    chip = Chip(args.elf, board=args.board, csr_flags=CSR[cause], flash_page=page)
    return chip


# ---------------------------------------------------------------- scenarios --
def scenario_boot(args, cause):
    chip = boot(args, cause)
    run_periods(chip, 40)
    hist = after_pre_init(chip.coil_history)
    commands = [(t, s) for t, s in hist if isinstance(s, float) and s > 0]
    check(commands, f"{cause}: no coil command: {hist}")
    first_t, first = commands[0]
    # Boot is supervised: the watchdog runs before the first ADC busy-wait
    # (ADC1's calibration) and before the first coil command.
    started = chip.iwdg.started_at
    check(started is not None and started < chip.adc1.cal_done_at and started < first_t,
          f"{cause}: watchdog started at {started}, ADC1 calibrated at {chip.adc1.cal_done_at}")
    cal3 = chip.adc3.regular_conversion_times
    if cause == "pin":
        # Calibration first with the coil off: 64 current-sense zero samples
        # (ADC3 regular conversions) all before the first drive.
        check(len(cal3) >= 64, f"pin: current-sense calibration did not run at boot ({len(cal3)} conversions)")
        check(max(cal3) < first_t, f"pin: the coil was driven at {first_t} before calibration ended at {max(cal3)}")
    else:
        # The fail-safe at once: before the ADCs' own calibration, and the
        # current-sense calibration deferred (no ADC3 regular conversion at boot).
        check(near(first, DUTY_1A), f"{cause}: first command {first}, expected the boot fail-safe {DUTY_1A}")
        check(chip.adc1.cal_done_at is not None and first_t < chip.adc1.cal_done_at,
              f"{cause}: fail-safe at {first_t}, after ADC1's calibration at {chip.adc1.cal_done_at}")
        check(not cal3, f"{cause}: current-sense calibration ran at boot ({len(cal3)} conversions)")
    # Before the first period: the installed configuration's fail-safe (the
    # built-in table's 2 A coil).
    first_period = next(e[0] for e in chip.log if e[1] == "enter" and e[2] == UART4_EXC)
    before = [s for t, s in hist if t <= first_period]
    check(near(before[-1], DUTY_2A), f"{cause}: coil before the first period {before[-1]}, expected {DUTY_2A}")
    # Fresh current-sense conversions on every path: they continue over the
    # last periods, and CURRENT_SENSE is not latched.
    n0 = chip.adc3.injected_conversions
    run_periods(chip, 20)
    fresh = chip.adc3.injected_conversions - n0
    check(fresh >= 20, f"{cause}: {fresh} current-sense conversions in 20 periods")
    check(not latched(chip) & CURRENT_SENSE, f"{cause}: CURRENT_SENSE latched ({latched(chip):#x})")
    check(not chip.resets, f"{cause}: reset during boot: {chip.resets}")
    return f"first command {first:.4f} at cycle {first_t}, {fresh} fresh conversions in 20 periods"


def scenario_over_current(args):
    chip = boot(args)
    run_periods(chip, 20)
    chip.shunt_a = 3.0                      # a shorted coil: 3 V on the sense, above 2.4 A
    run_periods(chip, 10)
    check(latched(chip) & OVER_CURRENT, f"OVER_CURRENT not latched ({latched(chip):#x})")
    check(duty_now(chip) == 0.0, f"coil at {chip.coil_state()} after an over-current, expected 0 A")
    # B1 (PC13, active low) pressed for 150 ms at rest, then released:
    # OVER_CURRENT stays latched and the drive stays off.
    gpioc = chip.periph[0x48000800]
    gpioc.inputs[13] = 0
    chip.run(150 * MS)
    gpioc.inputs[13] = 1
    chip.run(60 * MS)
    check(latched(chip) & OVER_CURRENT, f"B1 cleared OVER_CURRENT ({latched(chip):#x})")
    check(duty_now(chip) == 0.0, f"coil at {chip.coil_state()} after B1, expected 0 A")
    return "0 A within 10 periods, kept through B1"


def at_rest_then_upload(chip, frames):
    # REST_BEFORE_UPLOAD_S = 0.5 s of still periods first.
    chip.run(560 * MS)
    chip.vcp.rx.extend(frames)
    chip.run(1500 * MS, until=lambda: len(chip.vcp.tx) >= 24 and not chip.vcp.rx)
    chip.run(5 * MS)


def scenario_upload(args, fail):
    frames = open(args.upload, "rb").read()
    chip = boot(args, "pin")
    before = bytes(chip.flash_mem[0xFF800:0x100000])
    if fail == "erase":
        chip.flash.fail_erase = True
    if fail == "program":
        chip.flash.fail_program = True
    at_rest_then_upload(chip, frames)
    after = bytes(chip.flash_mem[0xFF800:0x100000])
    print("tx", chip.vcp.tx.hex())
    print("page", after.hex())
    check(not chip.resets, f"reset during the upload: {chip.resets}")
    return f"page {'changed' if after != before else 'unchanged'}"


def scenario_page(args, torn):
    page = open(args.page, "rb").read()
    chip = boot(args, "power-on", page=page)
    if torn:
        # A double-ECC error in the page's blob (a torn write): reading it raises NMI.
        chip.ecc_bad.add(0xFF800 + 0x40)
    run_periods(chip, 30)
    first_period = next(e[0] for e in chip.log if e[1] == "enter" and e[2] == UART4_EXC)
    hist = after_pre_init(chip.coil_history)
    before = [s for t, s in hist if t <= first_period]
    nmis = sum(1 for e in chip.log if e[1] == "enter" and e[2] == 2)
    check(not chip.resets, f"resets: {chip.resets}")
    if torn:
        check(nmis >= 1, "the torn page raised no NMI")
        check(near(before[-1], DUTY_2A), f"torn page: fail-safe {before[-1]}, expected the built-in table's {DUTY_2A}")
    else:
        check(near(before[-1], DUTY_1A), f"uploaded 1 A coil: fail-safe {before[-1]}, expected {DUTY_1A}")
    return f"fail-safe before the first period {before[-1]:.4f}, {nmis} NMI"


def inject_panic(chip):
    """A panic at the current instruction: the image's own panic handler
    (`rust_begin_unwind`) entered with a PanicInfo whose location is valid."""
    info, loc, text = 0x20010000, 0x20010010, 0x20010020
    uc = chip.uc
    uc.mem_write(text, b"injected.rs")
    uc.mem_write(loc, struct.pack("<IIII", text, 11, 1, 1))
    uc.mem_write(info, struct.pack("<IIII", loc, loc, 0, 0))
    uc.reg_write(UC_ARM_REG_R0, info)
    chip.pc = chip.elf.symbol("rust_begin_unwind") | 1


def scenario_fault(args, kind, over_current_first=False):
    chip = boot(args)
    run_periods(chip, 20)
    if over_current_first:
        # The coil driven first: a displacement at the ADC rail (27.8 mm, out
        # of range) holds the 2 A fail-safe every period.
        chip.vin["x"] = 3.3
        run_periods(chip, 15)
        check(near(duty_now(chip), DUTY_2A), f"out of range: coil at {chip.coil_state()}")
        chip.shunt_a = 3.0
        # The fault strikes in the period that latches OVER_CURRENT, right
        # after that period's step removed the drive (within one slice of
        # the CCR1 write), before the period ends: LATCHED_FAULTS must
        # already say so, or the handler drives the fail-safe into the short.
        hit = chip.run(10 * PERIOD, until=lambda: duty_now(chip) == 0.0)
        check(hit, "the over-current did not remove the drive within 10 periods")
    if kind == "hardfault":
        chip.take(3)                        # a precise fault escalated to HardFault
    else:
        inject_panic(chip)
    start = chip.cycles
    chip.run(MS // 2)
    check(chip.uc.reg_read(UC_ARM_REG_PRIMASK) & 1, f"{kind}: interrupts not masked")
    expected = 0.0 if over_current_first else DUTY_2A
    check(near(duty_now(chip), expected) or duty_now(chip) == expected,
          f"{kind}: coil at {chip.coil_state()}, expected {expected}")
    n = periods(chip)
    chip.run(3 * MS, until=lambda: bool(chip.resets))
    check(periods(chip) == n, f"{kind}: the control interrupt ran after the fault")
    chip.run(10 * MS, until=lambda: bool(chip.resets))
    check(chip.resets and chip.resets[0][1] == "IWDG", f"{kind}: no watchdog reset: {chip.resets}")
    check(chip.resets[0][0] - start <= 6 * MS, f"{kind}: the watchdog reset {chip.resets[0][0] - start} cycles later")
    # Into the fail-safe: the IWDG reset takes the fail-safe at once.
    t_reset = chip.resets[0][0]
    chip.run(5 * MS)
    after = after_pre_init([(t, s) for t, s in chip.coil_history if t >= t_reset])
    drives = [s for _t, s in after if isinstance(s, float) and s > 0]
    check(drives and near(drives[0], DUTY_1A), f"{kind}: after the watchdog reset the coil went {after}")
    return f"coil {expected:.4f} with PRIMASK set, watchdog reset after {chip.resets[0][0] - start} cycles"


def scenario_panic_in_panic(args):
    """A panic inside the panic handler's own log line (issue 39: "a panic
    inside a defmt frame re-panics without limit"): every time the handler
    starts its defmt frame (`_defmt_acquire`), the harness makes that call
    panic again. The handler must skip the log when entered a second time
    (`PANICKING`): two entries, no more; the coil stays at the fail-safe with
    interrupts masked and the watchdog resets. Without the flag each entry
    logs and re-panics until the stack runs out (a HardFault)."""
    from unicorn import UC_HOOK_CODE
    from unicorn.arm_const import UC_ARM_REG_PC
    chip = boot(args)
    run_periods(chip, 20)
    entries = [0]
    unwind = chip.elf.symbol("rust_begin_unwind") & ~1
    acquire = chip.elf.symbol("_defmt_acquire") & ~1

    def count(uc, address, size, user):
        entries[0] += 1

    def repanic(uc, address, size, user):
        # Only inside the handler, and bounded (the planted failure recurses).
        if 0 < entries[0] < 200:
            inject_panic(chip)
            uc.reg_write(UC_ARM_REG_PC, chip.pc)
    chip.uc.hook_add(UC_HOOK_CODE, count, begin=unwind, end=unwind + 1)
    chip.uc.hook_add(UC_HOOK_CODE, repanic, begin=acquire, end=acquire + 1)
    inject_panic(chip)
    start = chip.cycles
    chip.run(MS // 2)
    hardfaults = sum(1 for e in chip.log if e[1] == "enter" and e[2] == 3)
    check(entries[0] == 2, f"the panic handler was entered {entries[0]} times (a panic in its log must end at the second)")
    check(hardfaults == 0, f"{hardfaults} HardFaults (the recursion ran out of stack)")
    check(chip.uc.reg_read(UC_ARM_REG_PRIMASK) & 1, "panic in panic: interrupts not masked")
    check(near(duty_now(chip), DUTY_2A), f"panic in panic: coil at {chip.coil_state()}, expected {DUTY_2A}")
    chip.run(10 * MS, until=lambda: bool(chip.resets))
    check(chip.resets and chip.resets[0][1] == "IWDG", f"panic in panic: no watchdog reset: {chip.resets}")
    return f"2 handler entries, coil {DUTY_2A:.4f} with PRIMASK set, watchdog reset after {chip.resets[0][0] - start} cycles"


def stack_bottom(chip):
    """The stack's lowest address: `_stack_end` (memory.x), else, in an
    image without the guard, the end of the statics (cortex-m-rt's default
    stack ends there)."""
    for name in ("_stack_end", "__euninit"):
        if name in chip.elf.symbols:
            return chip.elf.symbols[name][0]
    raise KeyError("no _stack_end or __euninit symbol")


def scenario_stack_overflow(args):
    """A deliberate overflow: the control interrupt entered with 32 bytes of
    stack left (SP moved to the stack's bottom + 32 at its first
    instruction), so its own calls run past the bottom. With the guard
    (memory.x: the stack alone in SRAM2, reserved space below) the first push
    past the bottom is a bus error -> HardFault -> the coil at the fail-safe,
    interrupts masked, a watchdog reset; without it the pushes land in
    .bss/.data and nothing notices."""
    chip = boot(args)
    run_periods(chip, 20)
    used = chip.stack_high_water()
    run_periods(chip, 1)                    # now at the control interrupt's first instruction
    bottom = stack_bottom(chip)
    chip.uc.reg_write(UC_ARM_REG_SP, bottom + 32)
    start = chip.cycles
    chip.run(MS // 2, until=lambda: bool(chip.bus_errors))
    check(chip.bus_errors, f"stack overflow: no fault within 0.5 ms: the stack ran below {bottom:#010x} "
                           f"into {'.bss/.data' if bottom >= 0x20000000 else 'memory'} unnoticed")
    _t, addr, _pc = chip.bus_errors[0]
    check(bottom - 64 <= addr < bottom, f"stack overflow: bus error at {addr:#010x}, not at the stack's "
                                        f"bottom {bottom:#010x}")
    chip.run(MS // 2)
    check([e for e in chip.log if e[0] >= start and e[1] == "enter" and e[2] == 3], "stack overflow: no HardFault")
    check(chip.uc.reg_read(UC_ARM_REG_PRIMASK) & 1, "stack overflow: interrupts not masked")
    check(near(duty_now(chip), DUTY_2A), f"stack overflow: coil at {chip.coil_state()}, expected {DUTY_2A}")
    n = periods(chip)
    chip.run(10 * MS, until=lambda: bool(chip.resets))
    check(periods(chip) == n, "stack overflow: the control interrupt ran after the fault")
    check(chip.resets and chip.resets[0][1] == "IWDG", f"stack overflow: no watchdog reset: {chip.resets}")
    t_reset = chip.resets[0][0]
    check(t_reset - start <= 6 * MS, f"stack overflow: the watchdog reset {t_reset - start} cycles later")
    chip.run(5 * MS)
    after = after_pre_init([(t, s) for t, s in chip.coil_history if t >= t_reset])
    drives = [s for _t, s in after if isinstance(s, float) and s > 0]
    check(drives and near(drives[0], DUTY_1A), f"stack overflow: after the watchdog reset the coil went {after}")
    return (f"bus error at {addr:#010x} (stack bottom {bottom:#010x}), HardFault, coil {DUTY_2A:.4f} with "
            f"PRIMASK set, watchdog reset after {t_reset - start} cycles; stack high-water mark before it "
            f"{used} bytes")


def scenario_hung_task(args):
    chip = boot(args)
    run_periods(chip, 20)
    # A thread-mode task hangs: the next time the core is in thread mode it
    # is sent into a branch-to-self (the control interrupt keeps running).
    chip.run(50 * MS, until=lambda: not chip.active)
    spin = 0x20010100                       # `b .` in free SRAM1
    chip.uc.mem_write(spin, b"\xfe\xe7")
    chip.pc = spin | 1
    start = chip.cycles
    chip.run(400 * MS, until=lambda: bool(chip.resets))
    check(chip.resets and chip.resets[0][1] == "IWDG", f"hung task: no watchdog reset: {chip.resets}")
    t_reset = chip.resets[0][0]
    chip.run(5 * MS)
    after = after_pre_init([(t, s) for t, s in chip.coil_history if t >= t_reset])
    drives = [s for _t, s in after if isinstance(s, float) and s > 0]
    check(drives and near(drives[0], DUTY_1A), f"hung task: after the reset the coil went {after}")
    return f"watchdog reset {(t_reset - start) / MS:.1f} ms after the hang, then the fail-safe"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--elf", required=True)
    ap.add_argument("--board", default="b-l475e-iot01a")
    ap.add_argument("--page")
    ap.add_argument("--upload")
    ap.add_argument("scenario")
    args = ap.parse_args()
    s = args.scenario
    if s.startswith("boot:"):
        detail = scenario_boot(args, s.split(":", 1)[1])
    elif s == "over-current":
        detail = scenario_over_current(args)
    elif s in ("upload", "upload-erase-error", "upload-program-error"):
        detail = scenario_upload(args, {"upload": None, "upload-erase-error": "erase",
                                        "upload-program-error": "program"}[s])
    elif s in ("page", "torn-page"):
        detail = scenario_page(args, s == "torn-page")
    elif s == "hardfault":
        detail = scenario_fault(args, "hardfault")
    elif s == "panic":
        detail = scenario_fault(args, "panic")
    elif s == "panic-in-panic":
        detail = scenario_panic_in_panic(args)
    elif s == "hardfault-after-over-current":
        detail = scenario_fault(args, "hardfault", over_current_first=True)
    elif s == "stack-overflow":
        detail = scenario_stack_overflow(args)
    elif s == "hung-task":
        detail = scenario_hung_task(args)
    else:
        raise SystemExit(f"unknown scenario {s}")
    print(f"ok {s} ({args.board}): {detail}")


if __name__ == "__main__":
    main()
