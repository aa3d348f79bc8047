"""The real board image (`cargo fw`, `cargo fw-nucleo`) on a Cortex-M4 in the
Unicorn engine, with STM32L4 peripheral models written from the reference
manual RM0351 (Rev 9). Each model cites the section it encodes; offsets and bits
are as stm32-metapac 21 and embassy-stm32 0.6.0 use them. Every read or
write the firmware makes to an address no model claims stops the run and fails
the test (`Unmodelled`). What is a model and what is real: the CPU (Unicorn's
QEMU-derived Thumb-2/FPU core) runs the real image, bit for bit what `cargo fw`
links; everything outside the core (RCC, PWR, FLASH, GPIO, TIM2/3, ADC1-3,
IWDG, USART, NVIC/SCB/SysTick/DWT, the exception entry and return) is this
file's model, not the silicon.

Why the `unicorn` Python package: a pip wheel with the engine prebuilt (no
cmake or C toolchain step on CI), and the peripheral models are plain Python
callbacks on MMIO regions; the `unicorn-engine` crate builds the C engine with
cmake at `cargo build` time.

Citations: RM0351 itself could not be opened here. A section is cited by
number only where an independent public citation (found by search in public
code, not in the manual) confirms it: §2.2.2 memory map, §3.3.7 flash
programming (and §3.3.3 read access latency), §3.7 FLASH registers,
§6.4.16/§6.4.17 RCC_AHB1ENR/AHB2ENR, §13 NVIC, §15 CRC, §18 ADC, §18.4.6 the
ADC's power-up (DEEPPWD, ADVREGEN: cited as "RM0351 18.4.6" by a public
STM32L4 ADC driver, and RM0394's ADC chapter has the same subsection as
§16.4.6 "ADC Deep-power-down mode (DEEPPWD) & ADC Voltage Regulator
(ADVREGEN)"), §18.4.32 temperature sensor, §31 TIM2-5 (§31.4.6 EGR, §31.4.8
CCMR1 output mode, §31.4.11 CCER), §36 IWDG (§36.4 registers), §40 USART
(§40.5.4, §40.8 registers), §48 debug support. Everything else is cited by
the register's name as ST titles it ("ADC control register (ADC_CR)") or by
the functional section's topic, not by a number: the first version cited
numbers from memory and several were wrong (IWDG §32 for §36, RCC_CSR
§6.4.29, FLASH_ECCR §3.7.4, the USART registers §40.8.10-13), and numbers
counted from a register's place in its chapter are not confirmation. The
register text the models rely on most (JADSTART is set only when ADEN = 1
and ADDIS = 0; ADRDY set after ADEN, cleared by writing 1; the injected
context queue, JQDIS) matches ST's register descriptions as RM0394 (the
STM32L43x manual, the same ADC) words them, quoted in
github.com/bobmittmann/thinkos sdk/include/stm32f/stm32l4-adc.h, where the
queue is §16.4.21 "Queue of context for injected conversions".

Timing model: one instruction is one cycle of the 80 MHz core clock. The run
advances in slices of at most `SLICE` instructions; timers, ADC conversions
and the watchdog advance between slices, and pending interrupts are taken
between slices (never inside an IT block).
"""
import struct

from unicorn import Uc, UcError, UC_ARCH_ARM, UC_MODE_THUMB, UC_MODE_MCLASS
from unicorn import UC_HOOK_CODE, UC_HOOK_INTR, UC_HOOK_MEM_UNMAPPED, UC_HOOK_MEM_WRITE_PROT
from unicorn import UC_PROT_READ, UC_PROT_EXEC, UC_PROT_ALL
from unicorn.arm_const import *

SYSCLK = 80_000_000
SLICE = 200
# SRAM1 (.data, .bss, .uninit) and SRAM2 (the stack alone, memory.x).
SRAM1, SRAM1_SIZE = 0x20000000, 96 * 1024
SRAM2, SRAM2_SIZE = 0x10000000, 32 * 1024
# Reserved address space between the 1 MiB flash and SRAM2 (RM0351 memory
# map): an access is a bus error (a BusFault, escalated to HardFault: no
# configurable fault handler is enabled), not a test failure. A stack that
# overflows SRAM2 runs into it.
RESERVED_BELOW_SRAM2 = (0x08100000, SRAM2)
# SRAM2 is painted with this byte at power-on: the stack's high-water mark.
STACK_PAINT = 0xA5


class Unmodelled(Exception):
    pass


# ---------------------------------------------------------------- ELF -----
class Elf:
    def __init__(self, path):
        self.data = open(path, "rb").read()
        d = self.data
        assert d[:4] == b"\x7fELF" and d[4] == 1 and d[5] == 1, "32-bit little-endian ELF"
        (self.entry, phoff, shoff, _f, _eh, phentsize, phnum, shentsize, shnum, shstrndx) = struct.unpack_from(
            "<IIIIHHHHHH", d, 24)
        self.segments = []
        for k in range(phnum):
            p_type, p_offset, p_vaddr, p_paddr, p_filesz, p_memsz, _fl, _al = struct.unpack_from(
                "<IIIIIIII", d, phoff + k * phentsize)
            if p_type == 1 and p_filesz:
                self.segments.append((p_paddr, d[p_offset:p_offset + p_filesz]))
        secs = [struct.unpack_from("<IIIIIIIIII", d, shoff + k * shentsize) for k in range(shnum)]
        self.symbols = {}
        for s in secs:
            if s[1] == 2:  # SHT_SYMTAB
                strtab = secs[s[6]]
                for j in range(s[5] // 16):
                    name, value, size, info, _o, _shndx = struct.unpack_from("<IIIBBH", d, s[4] + j * 16)
                    start = strtab[4] + name
                    end = d.index(b"\0", start)
                    self.symbols[d[start:end].decode("ascii", "replace")] = (value, size)

    def symbol(self, part):
        """The address of the one symbol whose (mangled) name contains `part`."""
        hits = [(n, v) for n, v in self.symbols.items() if part in n]
        if len(hits) != 1:
            raise KeyError(f"{part}: {len(hits)} symbols match")
        return hits[0][1][0]


# ------------------------------------------------------- register files -----
class Regs:
    """A peripheral's register file: 32-bit words at offsets, reset values."""
    name = "?"
    regs = {}  # offset -> (name, reset)

    def __init__(self, chip, base):
        self.chip, self.base = chip, base
        self.v = {off: reset for off, (_n, reset) in self.regs.items()}

    def read(self, off):
        if off not in self.v:
            raise Unmodelled(f"read {self.name}+{off:#x}")
        return self.v[off]

    def write(self, off, val):
        if off not in self.v:
            raise Unmodelled(f"write {self.name}+{off:#x} = {val:#x}")
        self.v[off] = val

    def tick(self, cycles):
        pass


class Rcc(Regs):
    """RM0351 RCC registers. Ready flags follow their enables at once:
    RCC_CR HSIRDY = HSION, MSIRDY = MSION, PLLRDY = PLLON; RCC_CFGR
    SWS = SW; RCC_CSR ("Control/status register") LSIRDY = LSION, RMVF clears the reset flags
    (bits 24..31), which persist across every reset but power-on."""
    name = "RCC"
    regs = {0x00: ("CR", 0x63), 0x04: ("ICSCR", 0x10000000), 0x08: ("CFGR", 0), 0x0C: ("PLLCFGR", 0x1000),
            0x10: ("PLLSAI1CFGR", 0x1000), 0x14: ("PLLSAI2CFGR", 0x1000), 0x18: ("CIER", 0), 0x1C: ("CIFR", 0),
            0x20: ("CICR", 0), 0x28: ("AHB1RSTR", 0), 0x2C: ("AHB2RSTR", 0), 0x30: ("AHB3RSTR", 0),
            0x38: ("APB1RSTR1", 0), 0x3C: ("APB1RSTR2", 0), 0x40: ("APB2RSTR", 0), 0x48: ("AHB1ENR", 0x100),
            0x4C: ("AHB2ENR", 0), 0x50: ("AHB3ENR", 0), 0x58: ("APB1ENR1", 0), 0x5C: ("APB1ENR2", 0),
            0x60: ("APB2ENR", 0), 0x68: ("AHB1SMENR", 0x11303), 0x6C: ("AHB2SMENR", 0x5327F),
            0x70: ("AHB3SMENR", 0x101), 0x78: ("APB1SMENR1", 0xF2FECA3F), 0x7C: ("APB1SMENR2", 0x25),
            0x80: ("APB2SMENR", 0x1677C01), 0x88: ("CCIPR", 0), 0x90: ("BDCR", 0), 0x94: ("CSR", 0x0C000600)}

    def read(self, off):
        v = super().read(off)
        if off == 0x00:
            v &= ~((1 << 1) | (1 << 10) | (1 << 25))
            v |= (1 << 1) if v & 1 else 0            # MSIRDY
            v |= (1 << 10) if v & (1 << 8) else 0    # HSIRDY
            v |= (1 << 25) if v & (1 << 24) else 0   # PLLRDY
        if off == 0x08:
            v = (v & ~0xC) | ((v & 3) << 2)          # SWS = SW
        if off == 0x94:
            v = (v & ~2) | ((v & 1) << 1)            # LSIRDY = LSION
        if off == 0x90:
            v = (v & ~2) | ((v & 1) << 1)            # LSERDY = LSEON
        return v

    def write(self, off, val):
        if off == 0x94:
            if val & (1 << 23):                      # RMVF
                self.v[0x94] &= 0x00FFFFFF
            self.v[0x94] = (self.v[0x94] & 0xFF000000) | (val & 0x00FFFFFF & ~(1 << 23))
            return
        super().write(off, val)


class Pwr(Regs):
    """RM0351 PWR registers: PWR_CR1 VOS; PWR_SR2 VOSF and REGLPF read 0
    (the regulator is always settled in this model)."""
    name = "PWR"
    regs = {0x00: ("CR1", 0x200), 0x04: ("CR2", 0), 0x08: ("CR3", 0x8000), 0x0C: ("CR4", 0), 0x10: ("SR1", 0),
            0x14: ("SR2", 0), 0x18: ("SCR", 0)}


class Flash(Regs):
    """RM0351 §3.7 FLASH registers; the flash chapter's unlock, page erase
    and (§3.3.7) programming sequences. FLASH_KEYR: 0x45670123 then
    0xCDEF89AB clears LOCK (CR bit 31); a wrong
    key locks until reset. FLASH_CR: PER, PNB[10:3], BKER (bit 11), STRT
    (bit 16) erases a page; PG (bit 0) with a 64-bit double word written to
    flash programs it (bits can only be cleared). FLASH_SR: EOP (bit 0),
    errors OPERR 1, PROGERR 3, WRPERR 4, PGAERR 5, SIZERR 6, PGSERR 7, MISERR 8,
    FASTERR 9, RDERR 14, OPTVERR 15, write 1 to clear; BSY 16. EOPIE (CR bit
    24) and ERRIE (bit 25) raise the FLASH interrupt (IRQ 4). FLASH_ECCR:
    ECCD bit 31 (write 1 to clear), BK_ECC bit 19, ADDR_ECC 18:0; a double ECC
    error on a read raises NMI ("Error code correction (ECC)")."""
    name = "FLASH"
    regs = {0x00: ("ACR", 0x600), 0x04: ("PDKEYR", 0), 0x08: ("KEYR", 0), 0x0C: ("OPTKEYR", 0),
            0x10: ("SR", 0), 0x14: ("CR", 0xC0000000), 0x18: ("ECCR", 0), 0x20: ("OPTR", 0xFFEFF8AA)}
    IRQ = 4

    def __init__(self, chip, base):
        super().__init__(chip, base)
        self.key_step = 0
        self.pending = None
        self.fail_erase = False
        self.fail_program = False
        self.busy_until = 0

    def write(self, off, val):
        if off == 0x08:
            if self.key_step == 0 and val == 0x45670123:
                self.key_step = 1
            elif self.key_step == 1 and val == 0xCDEF89AB:
                self.v[0x14] &= ~(1 << 31)
                self.key_step = 0
            else:
                self.key_step = 2                    # locked until reset
            return
        if off == 0x10:
            self.v[0x10] &= ~(val & 0xC3FB)          # write 1 to clear
            self.chip.nvic_update_flash()
            return
        if off == 0x18:
            keep = self.v[0x18]
            if val & (1 << 31):
                keep &= ~(1 << 31)
            if val & (1 << 30):
                keep &= ~(1 << 30)
            self.v[0x18] = (keep & ~(1 << 24)) | (val & (1 << 24))
            return
        if off == 0x14:
            if self.v[0x14] & (1 << 31):
                # Locked: FLASH_CR cannot be written (flash unlock).
                self.chip.violation("FLASH_CR written while locked")
                return
            self.v[0x14] = val & ~(1 << 16)
            if val & (1 << 16) and val & (1 << 1):   # STRT with PER
                bank = 2 if val & (1 << 11) else 1
                page = (val >> 3) & 0xFF
                self.chip.flash_erase(bank, page)
            self.chip.nvic_update_flash()
            return
        super().write(off, val)

    # Datasheet DS10969 §6.3.10 "Flash memory characteristics": page erase
    # t_ERASE 22 ms typ, double-word program t_prog 81.7 µs typ. BSY (SR bit
    # 16) is set meanwhile.
    ERASE_CYCLES = SYSCLK * 22 // 1000
    PROGRAM_CYCLES = SYSCLK * 817 // 10_000_000

    def start(self, cycles, error_bits, effect):
        self.v[0x10] |= 1 << 16
        self.pending = (self.chip.cycles + cycles, error_bits, effect)

    def tick(self, cycles):
        if self.pending and self.chip.cycles >= self.pending[0]:
            _t, bits, effect = self.pending
            self.pending = None
            if effect:
                effect()
            self.v[0x10] &= ~(1 << 16)
            self.finish(bits)

    def finish(self, error_bits):
        self.v[0x10] |= error_bits | 1              # EOP (FLASH_SR: set also on error when EOPIE)
        self.chip.nvic_update_flash()

    def irq_level(self):
        cr, sr = self.v[0x14], self.v[0x10]
        return bool((cr & (1 << 24) and sr & 1) or (cr & (1 << 25) and sr & 0xC3FA))


class Gpio(Regs):
    """RM0351 GPIO registers: MODER, OTYPER, OSPEEDR, PUPDR, IDR, ODR,
    BSRR (BRy in 31:16 reset, BSy in 15:0 set, set wins), LCKR, AFRL,
    AFRH, BRR, ASCR (STM32L47x/L48x). IDR mirrors ODR for outputs and
    reads the pull (or the bench's level in `inputs`) otherwise."""
    regs = {0x00: ("MODER", 0xFFFFFFFF), 0x04: ("OTYPER", 0), 0x08: ("OSPEEDR", 0), 0x0C: ("PUPDR", 0),
            0x10: ("IDR", 0), 0x14: ("ODR", 0), 0x18: ("BSRR", 0), 0x1C: ("LCKR", 0), 0x20: ("AFRL", 0),
            0x24: ("AFRH", 0), 0x28: ("BRR", 0), 0x2C: ("ASCR", 0)}
    RESET = {"A": (0xABFFFFFF, 0x0C000000, 0x64000000), "B": (0xFFFFFEBF, 0, 0x100)}

    def __init__(self, chip, base, port):
        super().__init__(chip, base)
        self.name = "GPIO" + port
        self.port = port
        if port in self.RESET:
            self.v[0x00], self.v[0x08], self.v[0x0C] = self.RESET[port]
        self.inputs = {}

    def mode(self, pin):
        return (self.v[0x00] >> (2 * pin)) & 3

    def read(self, off):
        if off == 0x10:
            idr = 0
            for pin in range(16):
                if self.mode(pin) == 1:
                    bit = (self.v[0x14] >> pin) & 1
                else:
                    pull = (self.v[0x0C] >> (2 * pin)) & 3
                    bit = self.inputs.get(pin, 1 if pull == 1 else 0)
                idr |= bit << pin
            return idr
        if off in (0x18, 0x28):
            return 0
        return super().read(off)

    def write(self, off, val):
        old_moder = self.v[0x00]
        if off == 0x18:
            self.v[0x14] = (self.v[0x14] & ~(val >> 16)) | (val & 0xFFFF)
            self.v[0x14] &= 0xFFFF
        elif off == 0x28:
            self.v[0x14] &= ~(val & 0xFFFF)
        else:
            super().write(off, val)
        if self.port == "B":
            self.chip.coil_pin_event(old_moder)


class Timer(Regs):
    """RM0351 §31.4 general-purpose timer registers (TIM2..TIM5): CR1 CEN
    (bit 0), DIER UIE 0, CCxIE 1..4; SR UIF 0, CCxIF 1..4,
    write 0 to clear; EGR UG (§31.4.6) reloads PSC and zeroes CNT; CNT counts
    up at f_CK / (PSC + 1) to ARR, then wraps with an update; CCxIF is set when
    CNT reaches CCRx ("Output compare mode"). CCMR/CCER/CCR are stored; TIM3 CH1 in PWM mode
    1 ("PWM mode") drives its pin high while CNT < CCR1, CH4 in PWM mode 2 rises
    at CCR4: the injected trigger TIM3_CH4 for the ADC (the ADC's external
    triggers for injected conversions)."""
    regs = {0x00: ("CR1", 0), 0x04: ("CR2", 0), 0x08: ("SMCR", 0), 0x0C: ("DIER", 0), 0x10: ("SR", 0),
            0x14: ("EGR", 0), 0x18: ("CCMR1", 0), 0x1C: ("CCMR2", 0), 0x20: ("CCER", 0), 0x24: ("CNT", 0),
            0x28: ("PSC", 0), 0x2C: ("ARR", 0xFFFFFFFF), 0x30: ("RCR", 0), 0x34: ("CCR1", 0), 0x38: ("CCR2", 0),
            0x3C: ("CCR3", 0), 0x40: ("CCR4", 0), 0x48: ("DCR", 0), 0x4C: ("DMAR", 0), 0x50: ("OR1", 0),
            0x60: ("OR2", 0)}

    def __init__(self, chip, base, name, irq, bits):
        super().__init__(chip, base)
        self.name, self.irq, self.mask = name, irq, (1 << bits) - 1
        self.v[0x2C] = self.mask
        self.psc_active = 0
        self.frac = 0
        self.on_ch4 = None

    def read(self, off):
        return super().read(off)

    def write(self, off, val):
        if off == 0x10:
            self.v[0x10] &= val
            self.chip.nvic_level(self.irq, self.irq_level())
            return
        if off == 0x14:
            if val & 1:
                self.psc_active = self.v[0x28]
                self.v[0x24] = 0
                self.frac = 0
                if not (self.v[0x04] & 0) and not (self.v[0x00] & (1 << 2)):  # URS=0: UG sets UIF
                    self.v[0x10] |= 1
            self.chip.nvic_level(self.irq, self.irq_level())
            return
        super().write(off, val & 0xFFFFFFFF)
        if off == 0x0C:
            self.chip.nvic_level(self.irq, self.irq_level())
        if self.name == "TIM3":
            self.chip.note_coil()

    def irq_level(self):
        return bool(self.v[0x10] & self.v[0x0C] & 0x1F)

    def tick(self, cycles):
        if not self.v[0x00] & 1:
            return
        div = self.psc_active + 1
        self.frac += cycles
        steps, self.frac = divmod(self.frac, div)
        arr = self.v[0x2C] & self.mask
        cnt = self.v[0x24]
        while steps > 0:
            to_wrap = arr - cnt + 1
            seg = min(steps, to_wrap)
            lo, hi = cnt, cnt + seg          # counts lo+1 .. hi
            for ch in range(4):
                ccr = self.v[0x34 + 4 * ch] & self.mask
                if lo < ccr <= hi or (ccr == 0 and lo == 0 and seg > 0 and cnt == 0):
                    self.v[0x10] |= 1 << (ch + 1)
                    if ch == 3 and self.on_ch4 and self.v[0x20] & (1 << 12):
                        self.on_ch4()
            cnt += seg
            steps -= seg
            if cnt > arr:
                cnt = 0
                self.v[0x10] |= 1
                self.psc_active = self.v[0x28]
        self.v[0x24] = cnt
        self.chip.nvic_level(self.irq, self.irq_level())


class Adc(Regs):
    """RM0351 ADC registers (one ADC of ADC1..3).
    ADC_CR: DEEPPWD bit 29 (reset 1), ADVREGEN 28, ADCAL 31, JADSTP 5,
    ADSTP 4, JADSTART 3, ADSTART 2, ADDIS 1, ADEN 0.
    - §18.4.6: the regulator needs t_ADCVREG_STUP (20 µs, datasheet) after
      ADVREGEN before calibration or enable; DEEPPWD must be 0 first.
    - calibration: ADCAL with ADEN = 0 runs 116 ADC cycles, then
      clears; CALFACT is loaded.
    - "ADC on-off control (ADEN, ADDIS, ADRDY)": ADEN sets ADRDY (ISR bit 0) after t_STAB; ADDIS clears ADEN.
    - ADC_CR JADSTART: "software is allowed to set JADSTART only when ADEN =
      1 and ADDIS = 0": with ADEN = 0 the write is ignored. With JADSTART set
      and JEXTEN != 0, each trigger JEXTSEL (ADC_JSQR; 4 = TIM3_CH4,
      the table of injected triggers) converts JSQ1: ADC_JDR1 and
      JEOC (ISR bit 5) and JEOS (bit 6).
    - ADSTART converts SQ1 (ADC_SQR1) into DR; EOC (bit 2), EOS (bit 3).
    ADC_ISR flags clear by writing 1."""
    regs = {0x00: ("ISR", 0), 0x04: ("IER", 0), 0x08: ("CR", 0x20000000), 0x0C: ("CFGR", 0x80000000),
            0x10: ("CFGR2", 0), 0x14: ("SMPR1", 0), 0x18: ("SMPR2", 0), 0x20: ("TR1", 0x0FFF0000),
            0x24: ("TR2", 0x00FF0000), 0x28: ("TR3", 0x00FF0000), 0x30: ("SQR1", 0), 0x34: ("SQR2", 0),
            0x38: ("SQR3", 0), 0x3C: ("SQR4", 0), 0x40: ("DR", 0), 0x4C: ("JSQR", 0), 0x60: ("OFR1", 0),
            0x64: ("OFR2", 0), 0x68: ("OFR3", 0), 0x6C: ("OFR4", 0), 0x80: ("JDR1", 0), 0x84: ("JDR2", 0),
            0x88: ("JDR3", 0), 0x8C: ("JDR4", 0), 0xA0: ("AWD2CR", 0), 0xA4: ("AWD3CR", 0),
            0xB0: ("DIFSEL", 0), 0xB4: ("CALFACT", 0)}
    VREG_STUP = SYSCLK * 20 // 1_000_000
    CAL_CYCLES = 116
    STAB_CYCLES = 50
    CONV_CYCLES = 40

    def __init__(self, chip, base, name):
        super().__init__(chip, base)
        self.name = name
        self.vreg_on_at = None
        self.events = []          # (due_cycle, fn)
        self.channels = {}        # channel -> volts (callable or float)
        self.calibrated = False
        self.cal_done_at = None
        self.injected_conversions = 0
        self.regular_conversion_times = []

    def cr(self):
        return self.v[0x08]

    def at(self, delay, fn):
        self.events.append((self.chip.cycles + delay, fn))

    def code(self, ch):
        src = self.channels.get(ch)
        if src is None:
            raise Unmodelled(f"{self.name}: channel {ch} converted, nothing wired in the model")
        volts = src() if callable(src) else src
        return max(0, min(4095, int(round(volts / 3.3 * 4095))))

    def write(self, off, val):
        if off == 0x00:
            self.v[0x00] &= ~val
            return
        if off != 0x08:
            return super().write(off, val)
        cr = self.v[0x08]
        # DEEPPWD / ADVREGEN (§18.4.6)
        deeppwd = val & (1 << 29)
        vreg = val & (1 << 28)
        if vreg and not cr & (1 << 28):
            if deeppwd:
                self.chip.violation(f"{self.name}: ADVREGEN with DEEPPWD = 1")
            self.vreg_on_at = self.chip.cycles
        if not vreg:
            self.vreg_on_at = None
        new = (cr & 0x3D) | (val & (3 << 28)) | (val & (1 << 30))
        if val & (1 << 31) and not cr & (1 << 31):  # ADCAL
            if cr & 1:
                self.chip.violation(f"{self.name}: ADCAL with ADEN = 1")
            elif not self.regulator_ready():
                self.chip.violation(f"{self.name}: ADCAL before the regulator start-up time")
            else:
                new |= 1 << 31
                def cal_done(self=self):
                    self.v[0x08] &= ~(1 << 31)
                    self.v[0xB4] = 0x40
                    self.calibrated = True
                    self.cal_done_at = self.chip.cycles
                self.at(self.CAL_CYCLES, cal_done)
        else:
            new |= cr & (1 << 31)
        if val & 1 and not cr & 1:                    # ADEN
            if not self.regulator_ready():
                self.chip.violation(f"{self.name}: ADEN before the regulator start-up time")
            else:
                new |= 1
                def ready(self=self):
                    if self.v[0x08] & 1:
                        self.v[0x00] |= 1
                self.at(self.STAB_CYCLES, ready)
        if val & 2 and cr & 1:                        # ADDIS
            new &= ~1 & ~(1 << 3) & ~(1 << 2)
            self.v[0x00] &= ~1
        if val & 4 and new & 1:                       # ADSTART
            new |= 4
            ch = (self.v[0x30] >> 6) & 0x1F
            def conv(self=self, ch=ch):
                self.v[0x40] = self.code(ch)
                self.regular_conversion_times.append(self.chip.cycles)
                self.v[0x00] |= (1 << 2) | (1 << 3)
                self.v[0x08] &= ~4
            self.at(self.CONV_CYCLES, conv)
        if val & 8:                                   # JADSTART: ignored with ADEN = 0
            if new & 1 and not val & 2:
                new |= 8
        if val & 0x10 and cr & 4:                     # ADSTP
            new &= ~4
        if val & 0x20:                                # JADSTP
            new &= ~8
        self.v[0x08] = new

    def regulator_ready(self):
        return self.vreg_on_at is not None and self.chip.cycles - self.vreg_on_at >= self.VREG_STUP

    def injected_trigger(self, source):
        jsqr = self.v[0x4C]
        if not self.v[0x08] & 8 or ((jsqr >> 2) & 0xF) != source or not (jsqr >> 6) & 3:
            return
        ch = (jsqr >> 8) & 0x1F
        def conv(self=self, ch=ch):
            self.v[0x80] = self.code(ch)
            self.v[0x00] |= (1 << 5) | (1 << 6)
            self.injected_conversions += 1
        self.at(self.CONV_CYCLES, conv)

    def tick(self, cycles):
        now = self.chip.cycles
        due = [e for e in self.events if e[0] <= now]
        self.events = [e for e in self.events if e[0] > now]
        for _t, fn in sorted(due, key=lambda e: e[0]):
            fn()


class AdcCommon(Regs):
    """RM0351 ADC common registers: CSR (read-only flags), CCR (CKMODE,
    PRESC, VREFEN bit 22, TSEN 23, VBATEN 24), CDR."""
    name = "ADC_COMMON"
    regs = {0x00: ("CSR", 0), 0x08: ("CCR", 0), 0x0C: ("CDR", 0)}


class Iwdg(Regs):
    """RM0351 §36.4 IWDG registers: KR 0xCCCC starts (forces the LSI on),
    0xAAAA reloads RLR into the counter, 0x5555 unlocks PR/RLR/WINR; PR
    divider 4 << PR; RLR (reset 0xFFF); SR PVU,
    RVU, WVU read 0 (updates take effect at once). The counter runs from the
    32 kHz LSI; reaching 0 resets the chip with IWDGRSTF (RCC_CSR bit 29)."""
    name = "IWDG"
    regs = {0x00: ("KR", 0), 0x04: ("PR", 0), 0x08: ("RLR", 0xFFF), 0x0C: ("SR", 0), 0x10: ("WINR", 0xFFF)}
    LSI = 32_000

    def __init__(self, chip, base):
        super().__init__(chip, base)
        self.running = False
        self.started_at = None
        self.unlocked = False
        self.counter_cycles = 0
        self.reloads = 0

    def timeout_cycles(self):
        return (self.v[0x08] + 1) * (4 << self.v[0x04]) * SYSCLK // self.LSI

    def read(self, off):
        if off == 0x00:
            return 0
        return super().read(off)

    def write(self, off, val):
        if off == 0x00:
            key = val & 0xFFFF
            if key == 0xCCCC:
                if not self.running:
                    self.running = True
                    self.started_at = self.chip.cycles
                    self.counter_cycles = self.timeout_cycles()
                self.unlocked = False
            elif key == 0xAAAA:
                self.counter_cycles = self.timeout_cycles()
                self.reloads += 1
                self.unlocked = False
            elif key == 0x5555:
                self.unlocked = True
            else:
                self.unlocked = False
            return
        if off in (0x04, 0x08, 0x10):
            if self.unlocked:
                self.v[off] = val & (0x7 if off == 0x04 else 0xFFF)
            return
        super().write(off, val)

    def tick(self, cycles):
        if self.running:
            self.counter_cycles -= cycles
            if self.counter_cycles <= 0:
                self.chip.reset("IWDG")


class Usart(Regs):
    """RM0351 §40.8 USART registers (CR1 UE 0, RE 2, TE 3, RXNEIE 5,
    TCIE 6, TXEIE 7; ISR RXNE 5, TC 6, TXE 7, ORE 3; RDR, TDR, ICR). Transmission is instant: TDR's byte lands in
    `tx`, TXE and TC stay set. `rx_push` delivers bytes one at a time (RXNE)."""
    regs = {0x00: ("CR1", 0), 0x04: ("CR2", 0), 0x08: ("CR3", 0), 0x0C: ("BRR", 0), 0x10: ("GTPR", 0),
            0x14: ("RTOR", 0), 0x18: ("RQR", 0), 0x1C: ("ISR", 0xC0), 0x20: ("ICR", 0), 0x24: ("RDR", 0),
            0x28: ("TDR", 0)}

    def __init__(self, chip, base, name, irq):
        super().__init__(chip, base)
        self.name, self.irq = name, irq
        self.tx = bytearray()
        self.rx = bytearray()
        self.last_rx = 0
        self.idle_due = False

    BYTE_CYCLES = SYSCLK * 10 // 115_200     # 8N1 at 115200 baud: 10 bit times a byte

    def read(self, off):
        if off == 0x24:
            self.v[0x1C] &= ~(1 << 5)
            return self.v[0x24]
        return super().read(off)

    def feed(self):
        """One byte per frame time into RDR (RXNE; a byte not read before the
        next arrives sets ORE: overrun error), then IDLE (ISR bit 4)
        one frame after the last byte."""
        isr = self.v[0x1C]
        if self.v[0x00] & 5 != 5:
            return
        if self.chip.cycles - self.last_rx >= self.BYTE_CYCLES:
            if self.rx:
                if isr & (1 << 5):
                    self.v[0x1C] |= 1 << 3          # ORE: the byte is lost
                    self.rx.pop(0)
                else:
                    self.v[0x24] = self.rx.pop(0)
                    self.v[0x1C] |= 1 << 5
                self.last_rx = self.chip.cycles
                self.idle_due = True
            elif self.idle_due:
                self.v[0x1C] |= 1 << 4
                self.idle_due = False
        self.chip.nvic_level(self.irq, self.irq_level())

    def irq_level(self):
        cr1, isr = self.v[0x00], self.v[0x1C]
        return bool((cr1 & (1 << 5) and isr & (1 << 5)) or (cr1 & (1 << 7) and isr & (1 << 7))
                    or (cr1 & (1 << 4) and isr & (1 << 4)) or (cr1 & (1 << 5) and isr & (1 << 3))
                    or (cr1 & (1 << 6) and isr & (1 << 6)))

    def write(self, off, val):
        if off == 0x28:
            self.tx.append(val & 0xFF)
            self.v[0x1C] |= (1 << 7) | (1 << 6)
        elif off == 0x20:
            self.v[0x1C] &= ~(val & 0x1FFF & ~0xE0)
        elif off == 0x18:
            pass
        else:
            super().write(off, val)
        self.chip.nvic_level(self.irq, self.irq_level())

    def tick(self, cycles):
        self.feed()


class Simple(Regs):
    """A register file with reset values and no behaviour."""

    def __init__(self, chip, base, name, regs):
        self.regs = regs
        super().__init__(chip, base)
        self.name = name


# ------------------------------------------------------------- the chip -----
class Chip:
    """STM32L475VG / STM32L476RG: 1 MiB flash (two 512 KiB banks, 2 KiB pages),
    SRAM1 96 KiB, the peripherals above at their RM0351 §2.2.2 (memory map)
    addresses, and a Cortex-M4 core with NVIC/SCB/SysTick/DWT modelled from
    the ARMv7-M Architecture Reference Manual (B3)."""

    def __init__(self, elf_path, board="b-l475e-iot01a", csr_flags=0x0C000000, flash_page=None):
        self.elf = Elf(elf_path)
        self.board = board
        self.cycles = 0
        self.violations = []
        self.log = []
        self.resets = []
        self.flash_mem = bytearray(b"\xff" * 0x100000)
        for addr, data in self.elf.segments:
            if 0x08000000 <= addr < 0x08100000:
                o = addr - 0x08000000
                self.flash_mem[o:o + len(data)] = data
        if flash_page is not None:
            o = 0xFF800
            self.flash_mem[o:o + len(flash_page)] = flash_page
        self.pending_reset = None
        self.masked_run = 0
        self.dw_words = {}
        self.sleeps = 0
        self.fault_log = []
        self.bus_errors = []        # (cycle, address, pc): accesses to reserved space
        self.stacking_faults = []   # (cycle, exception, sp): an exception frame that could not be pushed
        self.ecc_bad = set()        # flash offsets (8-byte aligned) with a double-ECC error
        self.csr_flags = csr_flags | 0x600
        self.coil_history = []      # (cycle, duty or None for pin low / 'pin-low')
        self.shunt_a = None         # a bench override of the coil current (a short)
        self.vin = {"x": 0.3, "v": 1.65, "vrefint": 1.212}
        self.build()

    # -- construction and reset -------------------------------------------------
    def build(self):
        uc = Uc(UC_ARCH_ARM, UC_MODE_THUMB | UC_MODE_MCLASS)
        uc.ctl_set_cpu_model(UC_CPU_ARM_CORTEX_M4)
        self.uc = uc
        # Flash bank 1 and 2 as memory (read/exec), except the table page's
        # 4 KiB, which is MMIO so reads can raise ECC errors.
        uc.mem_map(0x08000000, 0xFF000, UC_PROT_READ | UC_PROT_EXEC)
        uc.mem_write(0x08000000, bytes(self.flash_mem[:0xFF000]))
        uc.mmio_map(0x080FF000, 0x1000, self.table_read, None, self.table_write, None)
        uc.mem_map(SRAM1, SRAM1_SIZE, UC_PROT_ALL)
        uc.mem_map(SRAM2, SRAM2_SIZE, UC_PROT_ALL)
        uc.mem_write(SRAM2, bytes([STACK_PAINT]) * SRAM2_SIZE)
        # System memory: VREFINT_CAL at 0x1FFF75AA (datasheet DS10969 §3.15.1)
        uc.mmio_map(0x1FFF7000, 0x1000, self.sysmem_read, None, self.bad_write, "system memory")
        # EXC_RETURN landing page (see `exception_return`).
        uc.mem_map(0xFFFFF000, 0x1000, UC_PROT_EXEC | UC_PROT_READ)
        self.periph = {}
        P = self.periph
        P[0x40021000] = self.rcc = Rcc(self, 0x40021000)
        P[0x40007000] = self.pwr = Pwr(self, 0x40007000)
        P[0x40022000] = self.flash = Flash(self, 0x40022000)
        for k, port in enumerate("ABCDEFGH"):
            P[0x48000000 + 0x400 * k] = Gpio(self, 0x48000000 + 0x400 * k, port)
        self.gpiob = P[0x48000400]
        # B1 (PC13) has an external pull-up on both boards: released reads 1.
        P[0x48000800].inputs[13] = 1
        P[0x40000000] = self.tim2 = Timer(self, 0x40000000, "TIM2", 28, 32)
        P[0x40000400] = self.tim3 = Timer(self, 0x40000400, "TIM3", 29, 16)
        P[0x50040000] = self.adc1 = Adc(self, 0x50040000, "ADC1")
        P[0x50040100] = self.adc2 = Adc(self, 0x50040100, "ADC2")
        P[0x50040200] = self.adc3 = Adc(self, 0x50040200, "ADC3")
        P[0x50040300] = self.adc_common = AdcCommon(self, 0x50040300)
        P[0x40003000] = self.iwdg = Iwdg(self, 0x40003000)
        P[0x40013800] = Usart(self, 0x40013800, "USART1", 37)
        P[0x40004400] = Usart(self, 0x40004400, "USART2", 38)
        self.vcp = P[0x40013800] if self.board == "b-l475e-iot01a" else P[0x40004400]
        P[0x40010000] = Simple(self, 0x40010000, "SYSCFG", {0x00: ("MEMRMP", 0), 0x04: ("CFGR1", 0x7C000001),
                                                             0x08: ("EXTICR1", 0), 0x0C: ("EXTICR2", 0),
                                                             0x10: ("EXTICR3", 0), 0x14: ("EXTICR4", 0),
                                                             0x18: ("SCSR", 0), 0x1C: ("CFGR2", 0),
                                                             0x20: ("SWPR", 0), 0x24: ("SKR", 0)})
        P[0x40010400] = Simple(self, 0x40010400, "EXTI", {o: (f"EXTI+{o:#x}", 0) for o in range(0, 0x40, 4)})
        self.tim3.on_ch4 = lambda: [a.injected_trigger(4) for a in (self.adc1, self.adc2, self.adc3)]
        # ADC channels wired on the bench (firmware/README.md "Wiring").
        x_ch, v_ch = (14, 13) if self.board == "b-l475e-iot01a" else (5, 6)
        self.adc1.channels = {x_ch: lambda: self.vin["x"], 0: lambda: self.vin["vrefint"]}
        self.adc2.channels = {v_ch: lambda: self.vin["v"]}
        self.adc3.channels = {2: self.shunt_volts}
        # Peripheral space as MMIO pages, dispatched to the models.
        for base, size in ((0x40000000, 0x10000), (0x40010000, 0x10000), (0x40020000, 0x10000),
                           (0x48000000, 0x2000), (0x50040000, 0x1000)):
            uc.mmio_map(base, size, self.mmio_read, base, self.mmio_write, base)
        # Private peripheral bus: SCS (NVIC, SCB, SysTick), DWT, DCB, DBGMCU.
        uc.mmio_map(0xE0000000, 0x100000, self.ppb_read, None, self.ppb_write, None)
        self.nvic_init()
        uc.hook_add(UC_HOOK_CODE, self.exc_return_hook, begin=0xFFFFF000, end=0xFFFFFFFF)
        uc.hook_add(UC_HOOK_MEM_UNMAPPED, self.unmapped)
        uc.hook_add(UC_HOOK_MEM_WRITE_PROT, self.flash_write_hook)
        uc.hook_add(UC_HOOK_INTR, self.cpu_exception)
        self.stop_reason = None
        self.pending_return = None
        self.cpu_fault = None
        self.lockup = None          # the cycle the core locked up (a fault in HardFault or NMI)
        self.power_on()

    def power_on(self):
        self.rcc.v[0x94] = (self.rcc.v[0x94] & 0x00FFFFFF) | self.csr_flags
        self.boot()

    def boot(self):
        uc = self.uc
        sp, pc = struct.unpack("<II", bytes(self.flash_mem[0:8]))
        for r in range(13):
            uc.reg_write(UC_ARM_REG_R0 + r, 0)
        uc.reg_write(UC_ARM_REG_MSP, sp)
        uc.reg_write(UC_ARM_REG_SP, sp)
        uc.reg_write(UC_ARM_REG_LR, 0xFFFFFFFF)
        uc.reg_write(UC_ARM_REG_PRIMASK, 0)
        uc.reg_write(UC_ARM_REG_BASEPRI, 0)
        uc.reg_write(UC_ARM_REG_CONTROL, 0)
        self.pc = pc | 1
        self.active = []
        self.boot_cycle = self.cycles

    def reset(self, cause):
        """A system reset (RM0351 RCC "System reset"): every peripheral to its reset
        state, SRAM1 kept (the runtime rewrites .data/.bss), the flash kept,
        RCC_CSR's reset flags ORed (RCC_CSR: an internal reset also pulses
        NRST, so PINRSTF accompanies it)."""
        flag = {"IWDG": 1 << 29, "SFT": 1 << 28, "PIN": 0}[cause]
        self.resets.append((self.cycles, cause))
        self.pending_reset = (self.rcc.v[0x94] | flag | (1 << 26)) & 0xFF000000
        self.uc.emu_stop()
        self.stop_reason = "reset"

    # -- memory -------------------------------------------------------------------
    def unmapped(self, uc, access, address, size, value, user):
        if RESERVED_BELOW_SRAM2[0] <= address < RESERVED_BELOW_SRAM2[1]:
            # A bus error (precise here): HardFault at this instruction.
            self.bus_errors.append((self.cycles, address, uc.reg_read(UC_ARM_REG_PC)))
            self.stop_reason = "fault"
            return False
        self.violation(f"unmapped access {access} at {address:#010x} (size {size}) pc {uc.reg_read(UC_ARM_REG_PC):#x}")
        return False

    def bad_write(self, uc, off, size, value, what):
        self.violation(f"write to {what}+{off:#x}")

    def sysmem_read(self, uc, off, size, user):
        # VREFINT_CAL (0x1FFF75AA, 16 bits): the raw code at 3.0 V, 30 °C.
        cal = 1655
        if off == 0x5AA and size == 2:
            return cal
        if off == 0x5A8 and size == 4:
            return cal << 16
        self.violation(f"read system memory +{off:#x} size {size}")
        return 0

    def table_read(self, uc, off, size, user):
        o = 0xFF000 + off
        if (o & ~7) in self.ecc_bad:
            # ECC: double error on read: ECCD, BK_ECC, ADDR_ECC, NMI.
            eccr = self.flash.v[0x18]
            if not eccr & (1 << 31):
                bank_off = o - 0x80000
                self.flash.v[0x18] = (eccr & (1 << 24)) | (1 << 31) | (1 << 19) | (bank_off & 0x7FFFF)
                self.pend(2)
                self.stop_soon()
        return int.from_bytes(self.flash_mem[o:o + size], "little")

    def table_write(self, uc, off, size, value, user):
        self.program(0x080FF000 + off, size, value)

    def flash_write_hook(self, uc, access, address, size, value, user):
        if 0x08000000 <= address < 0x08100000:
            self.program(address, size, value)
            return True
        return False

    def program(self, address, size, value):
        """§3.3.7 programming: PG set, 32-bit writes of a double word, the
        second completes it (BSY then EOP). Without PG: PGSERR."""
        cr = self.flash.v[0x14]
        if not cr & 1 or cr & (1 << 31):
            self.flash.v[0x10] |= 1 << 7     # PGSERR
            return
        o = address - 0x08000000
        if self.flash.v[0x10] & (1 << 16):
            self.flash.v[0x10] |= 1 << 7     # PGSERR: written while busy
            return
        dw = o & ~7
        if o % 8 == 0:
            self.dw_words = {}
        self.dw_words[o % 8] = (value, size)
        if (o + size) % 8:
            return                           # the double word completes with its second word
        words = self.dw_words
        self.dw_words = {}
        erased = all(b == 0xFF for b in self.flash_mem[dw:dw + 8])
        data = bytearray(8)
        for at, (v, n) in words.items():
            for k in range(n):
                data[at + k] = (v >> (8 * k)) & 0xFF
        if self.flash.fail_program:
            self.flash.start(Flash.PROGRAM_CYCLES, 1 << 3, None)   # PROGERR: nothing written
            return
        if not erased and any(data):
            # FLASH_SR PROGERR: the double word was not erased (and the data is not all 0).
            self.flash.start(Flash.PROGRAM_CYCLES, 1 << 3, None)
            return

        def write(dw=dw, data=bytes(data)):
            for k in range(8):
                self.flash_mem[dw + k] &= data[k]
            if dw < 0xFF000:
                self.uc.mem_write(0x08000000 + dw, bytes(self.flash_mem[dw:dw + 8]))
        self.flash.start(Flash.PROGRAM_CYCLES, 0, write)

    def flash_erase(self, bank, page):
        if self.flash.fail_erase:
            self.flash.start(Flash.ERASE_CYCLES, 1 << 1, None)   # OPERR: the page keeps its content
            return
        o = (bank - 1) * 0x80000 + page * 0x800

        def erase(o=o):
            self.flash_mem[o:o + 0x800] = b"\xff" * 0x800
            self.ecc_bad = {a for a in self.ecc_bad if not o <= a < o + 0x800}
            if o < 0xFF000:
                self.uc.mem_write(0x08000000 + o, b"\xff" * 0x800)
        self.flash.start(Flash.ERASE_CYCLES, 0, erase)

    def periph_at(self, addr):
        if 0x50040000 <= addr < 0x50040400:
            base = addr & ~0xFF
        else:
            base = addr & ~0x3FF
        if base in self.periph:
            return self.periph[base], addr - base
        return None, None

    def mmio_read(self, uc, off, size, region):
        addr = region + off
        p, o = self.periph_at(addr)
        try:
            if p is None:
                raise Unmodelled(f"read {addr:#010x}")
            word = p.read(o & ~3)
        except Unmodelled as e:
            self.violation(str(e) + f" (pc {uc.reg_read(UC_ARM_REG_PC):#x})")
            return 0
        return (word >> (8 * (o & 3))) & ((1 << (8 * size)) - 1)

    def mmio_write(self, uc, off, size, value, region):
        addr = region + off
        p, o = self.periph_at(addr)
        try:
            if p is None:
                raise Unmodelled(f"write {addr:#010x} = {value:#x}")
            if size < 4:
                if isinstance(p, Gpio) and o & ~3 == 0x18 and size == 2:
                    value = value << (8 * (o & 3))
                else:
                    word = p.v.get(o & ~3, 0)
                    shift = 8 * (o & 3)
                    m = ((1 << (8 * size)) - 1) << shift
                    value = (word & ~m) | ((value << shift) & m)
            p.write(o & ~3, value)
        except Unmodelled as e:
            self.violation(str(e) + f" (pc {uc.reg_read(UC_ARM_REG_PC):#x})")

    def stop_soon(self):
        """Stops at the next translation block (an MMIO callback that stops
        the CPU itself would restart its instruction): a pended NMI is then
        taken within a few instructions of its cause."""
        def once(uc, address, size, user):
            uc.hook_del(self.once_hook)
            self.stop_reason = "nmi"
            uc.emu_stop()
        self.once_hook = self.uc.hook_add(UC_HOOK_CODE, once)

    def violation(self, what):
        self.violations.append(what)
        self.uc.emu_stop()
        self.stop_reason = "violation"

    # -- the coil -------------------------------------------------------------------
    def coil_state(self):
        """What drives the coil: 'low' (PB4 an output at 0), 'high', or the
        PWM duty (TIM3 CH1 on PB4 in AF2 while TIM3 counts)."""
        g = self.gpiob
        mode = g.mode(4)
        if mode == 1:
            return 1.0 if (g.v[0x14] >> 4) & 1 else 0.0
        if mode == 2:
            af = (g.v[0x20] >> 16) & 0xF
            t = self.tim3
            if af != 2 or not t.v[0x00] & 1 or not t.v[0x20] & 1:
                # OC1 disabled: the pin at its pull (GPIO pull-up/pull-down, §31.4.11 CC1E).
                pull = (g.v[0x0C] >> 8) & 3
                return {1: 1.0, 2: 0.0}.get(pull, "floating")
            arr = t.v[0x2C] & 0xFFFF
            return min(1.0, (t.v[0x34] & 0xFFFF) / (arr + 1))
        return "floating"

    def coil_pin_event(self, old_moder):
        self.note_coil()

    def note_coil(self):
        s = self.coil_state()
        if not self.coil_history or self.coil_history[-1][1] != s:
            self.coil_history.append((self.cycles, s))

    def coil_current_a(self):
        s = self.coil_state()
        duty = s if isinstance(s, float) else 0.0
        return duty * 3.0

    def shunt_volts(self):
        a = self.shunt_a if self.shunt_a is not None else self.coil_current_a()
        return a * 1.0

    # -- NVIC / SCB / SysTick / DWT (ARMv7-M ARM B3.2, B3.3, B3.4) ---------------
    def nvic_init(self):
        self.iser = [0] * 8
        self.ispr = [0] * 8
        self.ipr = bytearray(240)
        self.shpr = bytearray(12)
        self.sys_pending = set()
        self.levels = {}
        self.ppb = {0xE000ED08: 0, 0xE000ED0C: 0xFA050000, 0xE000ED10: 0, 0xE000ED14: 0x200,
                    0xE000ED24: 0, 0xE000ED88: 0, 0xE000EF34: 0xC0000000, 0xE000EF38: 0,
                    0xE000EDFC: 0, 0xE0001000: 0x40000000, 0xE0001004: 0, 0xE0042008: 0,
                    0xE0042000: 0x10076415, 0xE000E010: 0, 0xE000E014: 0, 0xE000E018: 0,
                    0xE000ED04: 0, 0xE000ED28: 0, 0xE000ED2C: 0, 0xE000ED34: 0, 0xE000ED38: 0,
                    0xE0042004: 0, 0xE004200C: 0, 0xE0042010: 0}

    def ppb_read(self, uc, off, size, user):
        a = 0xE0000000 + off
        w = a & ~3
        if 0xE000E100 <= w < 0xE000E120:
            v = self.iser[(w - 0xE000E100) // 4]
        elif 0xE000E180 <= w < 0xE000E1A0:
            v = self.iser[(w - 0xE000E180) // 4]
        elif 0xE000E200 <= w < 0xE000E220:
            v = self.ispr[(w - 0xE000E200) // 4]
        elif 0xE000E280 <= w < 0xE000E2A0:
            v = self.ispr[(w - 0xE000E280) // 4]
        elif 0xE000E400 <= w < 0xE000E4F0:
            v = int.from_bytes(self.ipr[w - 0xE000E400:w - 0xE000E400 + 4], "little")
        elif 0xE000ED18 <= w < 0xE000ED24:
            v = int.from_bytes(self.shpr[w - 0xE000ED18:w - 0xE000ED18 + 4], "little")
        elif w == 0xE0001004:
            v = (self.cycles - self.boot_cycle) & 0xFFFFFFFF if self.ppb[0xE0001000] & 1 else self.ppb[w]
        elif w == 0xE000ED04:
            v = 0
        elif w in self.ppb:
            v = self.ppb[w]
        else:
            self.violation(f"read PPB {a:#010x}")
            return 0
        return (v >> (8 * (a & 3))) & ((1 << (8 * size)) - 1)

    def ppb_write(self, uc, off, size, value, user):
        a = 0xE0000000 + off
        w = a & ~3
        if size < 4 and not (0xE000E400 <= a < 0xE000E4F0 or 0xE000ED18 <= a < 0xE000ED24):
            shift = 8 * (a & 3)
            value <<= shift
        if 0xE000E100 <= w < 0xE000E120:
            self.iser[(w - 0xE000E100) // 4] |= value
        elif 0xE000E180 <= w < 0xE000E1A0:
            self.iser[(w - 0xE000E180) // 4] &= ~value
        elif 0xE000E200 <= w < 0xE000E220:
            self.ispr[(w - 0xE000E200) // 4] |= value
        elif 0xE000E280 <= w < 0xE000E2A0:
            self.ispr[(w - 0xE000E280) // 4] &= ~value
        elif 0xE000E400 <= a < 0xE000E4F0:
            for k in range(size):
                self.ipr[a - 0xE000E400 + k] = (value >> (8 * k)) & 0xFF
        elif 0xE000ED18 <= a < 0xE000ED24:
            for k in range(size):
                self.shpr[a - 0xE000ED18 + k] = (value >> (8 * k)) & 0xFF
        elif w == 0xE000EF00:                       # STIR
            n = value & 0x1FF
            self.ispr[n // 32] |= 1 << (n % 32)
        elif w == 0xE000ED04:                       # ICSR: PENDSVSET 28, PENDSTSET 26, NMIPENDSET 31
            if value & (1 << 28):
                self.sys_pending.add(14)
            if value & (1 << 27):
                self.sys_pending.discard(14)
            if value & (1 << 26):
                self.sys_pending.add(15)
        elif w == 0xE000ED0C:                       # AIRCR: SYSRESETREQ with VECTKEY 0x05FA
            if value >> 16 == 0x05FA and value & 4:
                self.reset("SFT")
        elif w in self.ppb:
            self.ppb[w] = value if size == 4 else (self.ppb[w] & ~(((1 << (8 * size)) - 1) << (8 * (a & 3)))) | value
        else:
            self.violation(f"write PPB {a:#010x} = {value:#x}")

    def nvic_level(self, irq, level):
        """A peripheral's interrupt line: a level sets the pending bit."""
        if level:
            self.ispr[irq // 32] |= 1 << (irq % 32)

    def nvic_update_flash(self):
        self.nvic_level(Flash.IRQ, self.flash.irq_level())

    def pend(self, exc):
        if exc < 16:
            self.sys_pending.add(exc)
        else:
            self.nvic_level(exc - 16, True)

    def priority(self, exc):
        if exc == 2:
            return -2
        if exc == 3:
            return -1
        if exc < 16:
            return self.shpr[exc - 4] >> 4
        return self.ipr[exc - 16] >> 4

    def execution_priority(self):
        p = 256
        for e, _ in self.active:
            p = min(p, self.priority(e))
        if self.uc.reg_read(UC_ARM_REG_PRIMASK) & 1:
            p = min(p, 0)
        bp = self.uc.reg_read(UC_ARM_REG_BASEPRI) & 0xFF
        if bp:
            p = min(p, bp >> 4)
        return p

    def any_pending(self):
        return bool(self.sys_pending) or any(self.ispr[k] & self.iser[k] for k in range(8))

    def next_exception(self):
        cands = list(self.sys_pending)
        for k in range(8):
            bits = self.ispr[k] & self.iser[k]
            for b in range(32):
                if bits >> b & 1:
                    cands.append(16 + 32 * k + b)
        if not cands:
            return None
        best = min(cands, key=lambda e: (self.priority(e), e))
        if self.priority(best) < self.execution_priority():
            return best
        return None

    def take(self, exc):
        """Exception entry (ARMv7-M ARM B1.5.6, B1.5.7): push the basic frame
        (or the extended one with S0-S15 and FPSCR when CONTROL.FPCA), 8-byte
        aligned (xPSR bit 9), LR = EXC_RETURN, PC = the vector."""
        uc = self.uc
        if exc < 16:
            self.sys_pending.discard(exc)
        else:
            n = exc - 16
            self.ispr[n // 32] &= ~(1 << (n % 32))
        regs = [uc.reg_read(r) for r in (UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3,
                                         UC_ARM_REG_R12, UC_ARM_REG_LR)]
        xpsr = uc.reg_read(UC_ARM_REG_XPSR)
        control = uc.reg_read(UC_ARM_REG_CONTROL)
        fp = bool(control & 4)
        sp = uc.reg_read(UC_ARM_REG_SP)
        frame = 0x68 if fp else 0x20
        aligned = (sp - frame) & ~7
        pad = (sp - frame) != aligned
        words = regs + [self.pc & ~1, (xpsr & ~(1 << 9)) | (pad << 9) | (1 << 24)]
        data = struct.pack("<8I", *words)
        if fp:
            s = [uc.reg_read(UC_ARM_REG_S0 + k) for k in range(16)]
            data += struct.pack("<16I", *s) + struct.pack("<II", uc.reg_read(UC_ARM_REG_FPSCR), 0)
        if self.in_ram(aligned, len(data)):
            uc.mem_write(aligned, data)
        else:
            # The frame's push is a bus error (STKERR). Entering HardFault,
            # the handler still runs with the pushes lost (Cortex-M3/M4 TRM
            # "Hard Fault": "if a corrupted stack causes a fault, the fault
            # handler still executes even though the stack pushes for the
            # handler failed"); any other exception escalates to HardFault,
            # whose frame fails the same way.
            self.stacking_faults.append((self.cycles, exc, aligned))
            exc = 3
        uc.reg_write(UC_ARM_REG_SP, aligned)
        exc_return = 0xFFFFFFF1 if self.active else 0xFFFFFFF9
        if fp:
            exc_return &= ~0x10
        uc.reg_write(UC_ARM_REG_LR, exc_return)
        uc.reg_write(UC_ARM_REG_CONTROL, control & ~4)
        vector = struct.unpack_from("<I", self.flash_mem, 4 * exc)[0]
        self.active.append((exc, None))
        self.pc = vector | 1
        self.log.append((self.cycles, "enter", exc))

    @staticmethod
    def in_ram(addr, n):
        return any(base <= addr and addr + n <= base + size
                   for base, size in ((SRAM1, SRAM1_SIZE), (SRAM2, SRAM2_SIZE)))

    def stack_high_water(self):
        """Bytes of SRAM2 (the stack) ever written since power-on: from the
        lowest byte that lost its paint up to the top."""
        ram = bytes(self.uc.mem_read(SRAM2, SRAM2_SIZE))
        for k, b in enumerate(ram):
            if b != STACK_PAINT:
                return SRAM2_SIZE - k
        return 0

    def exc_return_hook(self, uc, address, size, user):
        self.pending_return = address | 1
        uc.emu_stop()
        self.stop_reason = "exc_return"

    def exception_return(self, exc_return):
        uc = self.uc
        if not self.active:
            self.violation(f"exception return {exc_return:#x} in thread mode")
            return
        self.active.pop()
        sp = uc.reg_read(UC_ARM_REG_SP)
        r0, r1, r2, r3, r12, lr, pc, xpsr = struct.unpack("<8I", uc.mem_read(sp, 32))
        fp = not exc_return & 0x10
        frame = 0x68 if fp else 0x20
        if fp:
            s = struct.unpack("<16I", uc.mem_read(sp + 32, 64))
            for k in range(16):
                uc.reg_write(UC_ARM_REG_S0 + k, s[k])
            uc.reg_write(UC_ARM_REG_FPSCR, struct.unpack("<I", uc.mem_read(sp + 96, 4))[0])
        for r, v in zip((UC_ARM_REG_R0, UC_ARM_REG_R1, UC_ARM_REG_R2, UC_ARM_REG_R3, UC_ARM_REG_R12,
                         UC_ARM_REG_LR), (r0, r1, r2, r3, r12, lr)):
            uc.reg_write(r, v)
        uc.reg_write(UC_ARM_REG_SP, sp + frame + (4 if xpsr & (1 << 9) else 0))
        uc.reg_write(UC_ARM_REG_XPSR, (xpsr & 0xF80F0000) | (1 << 24))
        control = uc.reg_read(UC_ARM_REG_CONTROL)
        uc.reg_write(UC_ARM_REG_CONTROL, (control & ~4) | (4 if fp else 0))
        self.pc = pc | 1

    def cpu_exception(self, uc, intno, user):
        if intno == 8:
            # QEMU's EXCP_EXCEPTION_EXIT: a branch to an EXC_RETURN value;
            # the return itself is this model's (`exception_return`).
            self.pending_return = uc.reg_read(UC_ARM_REG_PC) | 1
            self.stop_reason = "exc_return"
            uc.emu_stop()
            return
        # A synchronous fault (UDF, an undefined or NOCP instruction, a bus
        # error): escalated to HardFault (no configurable fault handler is
        # enabled, ARMv7-M ARM B1.5.1).
        self.cpu_fault = intno
        self.fault_log.append((self.cycles, intno, uc.reg_read(UC_ARM_REG_PC)))
        self.stop_reason = "fault"
        uc.emu_stop()

    # -- running ----------------------------------------------------------------
    def primask(self):
        return self.uc.reg_read(UC_ARM_REG_PRIMASK) & 1

    def step(self, budget):
        uc = self.uc
        self.stop_reason = None
        start = self.cycles
        if self.lockup is not None:
            # Lockup (ARMv7-M ARM B1.5.15): the core executes nothing until
            # a reset; the peripherals (PWM, watchdog) run on.
            self.cycles += budget
            for p in self.periph.values():
                p.tick(budget)
            if self.pending_reset is not None:
                csr = self.pending_reset
                self.pending_reset = None
                self.csr_flags = csr & 0xFF000000
                self.build_reset()
            return
        try:
            uc.emu_start(self.pc, 0xFFFFFFFF, count=budget)
        except UcError as e:
            pc = uc.reg_read(UC_ARM_REG_PC)
            before = struct.unpack("<H", uc.mem_read(pc - 2, 2))[0] if pc >= 0x08000002 else 0
            if self.stop_reason == "fault":
                pass                            # a bus error: `unmapped` noted it
            elif before in (0xBF20, 0xBF30):
                # Unicorn halts on WFE/WFI (and reports the next instruction
                # invalid): the core sleeps for the rest of the slice.
                self.sleeps += 1
            else:
                self.violation(f"CPU: {e} at pc {pc:#x}")
        self.pc = uc.reg_read(UC_ARM_REG_PC) | 1
        ran = budget if self.stop_reason is None else max(1, budget // 2)
        self.cycles += ran
        for p in self.periph.values():
            p.tick(ran)
        if getattr(self, "pending_reset", None) is not None:
            csr = self.pending_reset
            self.pending_reset = None
            self.csr_flags = csr & 0xFF000000
            self.build_reset()
            return
        if self.stop_reason == "exc_return":
            self.exception_return(self.pending_return)
        if self.stop_reason == "fault":
            self.cpu_fault = None
            if any(e in (2, 3) for e, _ in self.active):
                # A fault at HardFault's or NMI's priority cannot escalate:
                # lockup (ARMv7-M ARM B1.5.15).
                self.lockup = self.cycles
                self.fault_log.append((self.cycles, "lockup", self.pc))
            else:
                self.take(3)
        if not (uc.reg_read(UC_ARM_REG_XPSR) & 0x0600FC00):
            exc = self.next_exception()
            if exc is not None:
                self.take(exc)

    def build_reset(self):
        flash, ecc, csr = self.flash_mem, self.ecc_bad, self.csr_flags
        resets, violations, log, cycles = self.resets, self.violations, self.log, self.cycles
        history, shunt, vin = self.coil_history, self.shunt_a, self.vin
        ram = bytes(self.uc.mem_read(SRAM1, SRAM1_SIZE))
        ram2 = bytes(self.uc.mem_read(SRAM2, SRAM2_SIZE))
        bus_errors, stacking_faults = self.bus_errors, self.stacking_faults
        self.build()
        self.uc.mem_write(SRAM1, ram)
        self.uc.mem_write(SRAM2, ram2)
        self.bus_errors, self.stacking_faults = bus_errors, stacking_faults
        self.rcc.v[0x94] = (self.rcc.v[0x94] & 0x00FFFFFF) | csr
        self.flash_mem, self.ecc_bad = flash, ecc
        self.resets, self.violations, self.log, self.cycles = resets, violations, log, cycles
        self.coil_history, self.shunt_a, self.vin = history, shunt, vin
        self.boot_cycle = cycles
        self.note_coil()

    def run(self, cycles, until=None):
        end = self.cycles + cycles
        while self.cycles < end:
            if self.violations:
                raise AssertionError("rehost: " + "; ".join(self.violations[:5]))
            # A pending interrupt held off by PRIMASK (a critical section)
            # is taken within 2 instructions of `cpsie` (the NVIC takes it at
            # once): short steps while masked, for at most 4000 cycles in a
            # row (a fault handler that masks for good runs in slices).
            budget = SLICE
            if self.any_pending() and self.primask():
                self.masked_run += 1
                if self.masked_run <= 2000:
                    budget = 2
            else:
                self.masked_run = 0
            self.step(min(budget, end - self.cycles))
            if until is not None and until():
                return True
        if self.violations:
            raise AssertionError("rehost: " + "; ".join(self.violations[:5]))
        return False

    # -- reading the image's state ------------------------------------------------
    def word(self, addr):
        return struct.unpack("<I", self.uc.mem_read(addr, 4))[0]

    def sym_word(self, part):
        return self.word(self.elf.symbol(part))
