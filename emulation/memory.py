"""What the STM32F103's memory system adds to the Cortex-M3's zero-wait instruction timings.

The TRM's cycle counts (`emulation.cycles`) assume zero-wait memory. At 72 MHz the
STM32F103's flash needs FLASH_ACR.LATENCY = 2 (RM0008 3.3.3 and the FLASH_ACR
description: two wait states for 48 MHz < SYSCLK <= 72 MHz), so a flash read takes
LATENCY + 1 = 3 HCLK cycles. This module prices that on an executed trace. It is a
model, not a measurement: the rules below are what it assumes, and `ASSUMPTIONS` prints
them with every `make bench`.

Flash (RM0008 3.3.3 "Read operations", "Prefetch buffer", "DCode interface"):

* The flash is read 64 bits (one 8-byte block) at a time, one read at a time, each
  LATENCY + 1 cycles. A read once started runs to its end.
* Instruction fetches come over the I-Code bus through the prefetch buffer: two 8-byte
  blocks, direct-mapped (block b lives in slot b mod 2). A fetch from a block in the
  buffer costs nothing extra; from any other block it waits for a read of that block.
  When fetching enters a block b, the controller queues a read of b + 1 into the other
  slot (its block has been consumed), which starts as soon as the flash is free.
* Data reads from flash (literal pools, constant tables, `static const` data) come over
  the D-Code bus, bypass the prefetch buffer, and cost one flash read per bus transfer
  (an LDRD is two). They have priority over a queued prefetch, but wait for a read in
  flight.
* The Cortex-M3's prefetch unit (TRM r2p0 1.4 "Prefetch Unit") fetches 32-bit words in
  order, at most one a cycle, and buffers up to three of them ahead of decode; an
  instruction executes the cycle after its last word is decoded, and never earlier than
  the TRM's timing. A fetch held by wait states holds the next one too.
* Branches: the TRM's refill P stays the floor. The target of B, B<cond>, BL, CBZ and
  CBNZ is presented at decode (TRM 1.4); of BX, POP {pc} and other writes to the PC once
  the instruction has produced it. A conditional branch's target is fetched at decode
  whether or not the branch is taken ("speculatively presented, consuming a fetch
  slot"): from flash that is a read into the buffer, which can evict the block the code
  runs on into (RM0008 does not say the interface treats it otherwise).
* Requests reach the flash in the order the trace walk makes them.

SRAM (code placed in `.ramfunc`): SRAM has no wait states (RM0008 3.3.1), but code there
is fetched over the System bus, which also carries every data access to SRAM and to the
peripherals. Data transfers take the bus first; an instruction word waits for a free
cycle. A fetch after a jump costs `system_bus_fetch_penalty` extra (the Cortex-M3's
System interface registers its fetches: ARM recommends the Code region for code). Reads
of flash data from SRAM code still go through the flash as above.

Exceptions (ARM knowledge article KA16366, "true interrupt latency"): entry is 12 cycles
when the 9-cycle push of the stack frame (System bus) overlaps the 6-cycle vector read
and handler fetch (I-Code). With the vector table and the handler in flash each of those
two reads takes LATENCY more, and a prefetch read in flight when the interrupt arrives
may first have to finish (up to LATENCY more): 3 + max(9, 6 + 3 LATENCY). A handler in
SRAM is fetched over the System bus after the push: 3 + 9 + 3 + the System-bus penalty.
Exit is the TRM's 10 cycles plus LATENCY for fetching the interrupted code (in flash)
again. Tail-chaining (6 cycles) is not credited: every handler run is charged its own
entry and exit, which errs high when one handler follows another.

Not modelled: the AHB-to-APB bridges (a peripheral register access on APB1 at 36 MHz
or APB2 at 72 MHz takes longer than the TRM's figure; RM0008 gives no number), DMA or
debugger traffic on the bus matrix, and the wake-up from WFI sleep.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

#: RM0008 3.3.3: the flash is 64 bits wide; a prefetch block is 8 bytes.
FLASH_BLOCK_BYTES = 8
#: System bus instruction fetches are 32-bit words.
WORD_BYTES = 4
#: The Cortex-M3 code region (I-Code and D-Code buses): on the STM32F103 the flash, its
#: boot alias at 0 and the system memory.
CODE_REGION_END = 0x2000_0000
#: The System bus: SRAM, peripherals, external memory (not the private peripheral bus).
SYSTEM_BUS_END = 0xE000_0000
#: RM0008 3.3: the peripheral registers (APB1, APB2, AHB) start here.
PERIPHERAL_REGION = 0x4000_0000
#: KA16366: the 12-cycle entry overlaps a 9-cycle stack push with a 6-cycle vector read
#: and handler fetch; 3 cycles are neither.
ENTRY_PUSH_CYCLES = 9
ENTRY_FETCH_CYCLES = 6
ENTRY_OTHER_CYCLES = 3
#: TRM: exception return with zero wait states.
EXIT_CYCLES = 10
#: A time before any event of a trace: "long ago, idle".
_IDLE = -(10**9)


@dataclass(frozen=True)
class MemoryTiming:
    """The memory system a trace is priced for. `flash_wait_states` None is the TRM's
    premise (zero-wait memory on separate buses): no memory model at all."""

    name: str
    flash_wait_states: int | None
    system_bus_fetch_penalty: int = 1
    #: TRM 1.4: a conditional branch's target is fetched at decode, taken or not.
    speculative_branch_fetch: bool = True

    @property
    def flash_read_cycles(self) -> int:
        return 1 + (self.flash_wait_states or 0)

    def describe(self) -> str:
        if self.flash_wait_states is None:
            return f"{self.name}: TRM zero-wait timings, no memory model"
        return (
            f"{self.name}: flash LATENCY = {self.flash_wait_states} ({self.flash_read_cycles}"
            f" cycles per 64-bit read), 2 x 64-bit direct-mapped prefetch buffer, D-Code reads"
            f" of flash bypass it; code in SRAM fetched over the System bus"
            f" (+{self.system_bus_fetch_penalty} per jump, data first)"
        )


#: The TRM's premise.
ZERO_WAIT = MemoryTiming("zero wait states", None, 0)
#: STM32F103 at SYSCLK = HCLK = 72 MHz: FLASH_ACR.LATENCY = 2, PRFTBE = 1.
STM32F103_72MHZ = MemoryTiming("STM32F103 at 72 MHz", 2, 1)

ASSUMPTIONS = (
    "flash: LATENCY = 2 at 72 MHz, a 64-bit read takes 3 cycles, one read at a time (RM0008 3.3.3)",
    "prefetch buffer: 2 blocks of 8 bytes, direct-mapped; entering block b queues a read"
    " of b + 1; a fetch outside the buffer waits for its block (taken branches: TRM refill"
    " P = 3 plus that read)",
    "D-Code: literal and constant loads from flash bypass the buffer, one 3-cycle read per"
    " word, priority over a queued prefetch, after a read in flight",
    "the core requests code 2 cycles before it executes; no deeper fetch queue and no"
    " speculative branch-target fetch are modelled (errs high)",
    "SRAM code (.ramfunc): zero wait states, fetched over the System bus shared with data"
    " to SRAM and peripherals (data first), +1 cycle per jump",
    "exception entry 3 + max(9-cycle push, 6-cycle vector + handler fetch + 3 x LATENCY) ="
    " 15 cycles from flash (KA16366); exit 10 + LATENCY = 12; no tail-chaining credit",
    "not modelled: APB bridge wait states on peripheral registers (counted per handler),"
    " DMA or debug bus traffic, wake-up from WFI",
)


def in_code_region(address: int) -> bool:
    return address < CODE_REGION_END


def on_system_bus(address: int) -> bool:
    return CODE_REGION_END <= address < SYSTEM_BUS_END


def exception_entry_cycles(timing: MemoryTiming, handler_address: int) -> int:
    """Cycles from the interrupt request to the handler's first instruction (see the
    module doc): the vector table is in flash, the handler where `handler_address` is."""
    if timing.flash_wait_states is None:
        return ENTRY_OTHER_CYCLES + max(ENTRY_PUSH_CYCLES, ENTRY_FETCH_CYCLES)
    wait = timing.flash_wait_states
    if in_code_region(handler_address):
        fetch = ENTRY_FETCH_CYCLES + 3 * wait  # vector, handler, a prefetch in flight
        return ENTRY_OTHER_CYCLES + max(ENTRY_PUSH_CYCLES, fetch)
    # The handler's fetch needs the System bus, which the push holds; the vector read
    # (flash, I-Code) overlaps the push.
    vector = ENTRY_FETCH_CYCLES // 2 + 2 * wait
    handler_fetch = ENTRY_FETCH_CYCLES // 2 + timing.system_bus_fetch_penalty
    return ENTRY_OTHER_CYCLES + max(ENTRY_PUSH_CYCLES, vector) + handler_fetch


def exception_exit_cycles(timing: MemoryTiming) -> int:
    """Cycles from the handler's return instruction to the interrupted code (in flash)."""
    return EXIT_CYCLES + (timing.flash_wait_states or 0)


class _Flash:
    """The flash read path: one read of LATENCY + 1 cycles at a time, and the prefetch
    buffer. Requests are served in the order the trace walk makes them."""

    def __init__(self, read_cycles: int) -> None:
        self.read_cycles = read_cycles
        self.free_at = _IDLE
        self.slots: list[tuple[int | None, int]] = [(None, _IDLE), (None, _IDLE)]
        self.queued: tuple[int, int] | None = None  # (block, requested at)
        self.current: int | None = None
        self.data_reads = 0

    def _read(self, request: int) -> int:
        start = max(request, self.free_at)
        self.free_at = start + self.read_cycles
        return self.free_at

    def _start_queued(self) -> None:
        assert self.queued is not None
        block, requested = self.queued
        self.slots[block % 2] = (block, self._read(requested))
        self.queued = None

    def _start_queued_before(self, time: int) -> None:
        """A queued prefetch that would have started before `time` is in flight."""
        if self.queued is not None and max(self.queued[1], self.free_at) < time:
            self._start_queued()

    def preload(self, block: int, ready: int) -> None:
        """The state after an exception entry fetched `block` (ready at `ready`)."""
        self.slots[block % 2] = (block, ready)
        self.free_at = ready
        self.current = block
        self.queued = (block + 1, ready - 1)

    def fetch(self, block: int, request: int, *, enters: bool = True) -> int:
        """When an I-Code fetch from `block`, presented at `request`, has its data.
        `enters`: the fetch stream moves on to the block (not a speculative fetch)."""
        if self.queued is not None and self.queued[0] == block:
            self._start_queued()  # the read wanted: it starts when it was due to
        else:
            self._start_queued_before(request + 1)
        cached, ready = self.slots[block % 2]
        if cached != block:
            ready = self._read(request)
            self.slots[block % 2] = (block, ready)
        if enters and block != self.current:
            self.current = block
            self.queued = None
            following = block + 1
            if self.slots[following % 2][0] != following:
                self.queued = (following, request)
        return max(ready, request + 1)

    def read_data(self, request: int) -> int:
        """When a D-Code read of flash issued at `request` has its data."""
        self._start_queued_before(request)  # a tie goes to the D-Code read (priority)
        self.data_reads += 1
        return self._read(request)


class _SystemBus:
    """The System bus seen from SRAM code: one transfer per cycle, data first."""

    def __init__(self) -> None:
        self.busy: set[int] = set()

    def take(self, cycle: int) -> int:
        while cycle in self.busy:
            cycle += 1
        self.busy.add(cycle)
        return cycle


@dataclass(frozen=True)
class Executed:
    """One executed instruction as the memory model needs it."""

    address: int
    size: int
    accesses: Sequence[tuple[int, int, bool]]  # (address, size, write) in program order
    cycles: int  # its TRM cost (refill and condition-failed IT instructions included)
    jumps: bool  # it wrote the PC: the next instruction is reached by a jump
    target: int | None  # B, B<cond>, BL, CBZ, CBNZ: the target, known at decode
    conditional: bool  # B<cond>, CBZ, CBNZ: its target is fetched speculatively
    pc_known_after: int  # any other PC write: cycles after it starts until the PC is known


@dataclass
class MemoryStalls:
    """What the memory system added to a trace, in cycles, and what caused it."""

    fetch: int = 0  # waiting for instructions
    data: int = 0  # waiting for flash data (D-Code) or the System bus
    flash_data_reads: int = 0
    system_bus_data: int = 0  # data transfers on the System bus (SRAM and peripherals)
    peripheral_accesses: int = 0  # of those, to peripheral registers (APB, not priced)
    per_step: list[int] = field(default_factory=list)

    @property
    def total(self) -> int:
        return self.fetch + self.data


class _PrefetchUnit:
    """The Cortex-M3's prefetch unit (TRM r2p0 1.4): it fetches 32-bit words in order,
    one per cycle at most, up to three words ahead of decode (its FIFO); a jump flushes
    it and restarts fetching at the target."""

    FIFO_WORDS = 3

    def __init__(self, timing: MemoryTiming, flash: _Flash, bus: _SystemBus) -> None:
        self.timing = timing
        self.flash = flash
        self.bus = bus
        self.arrival: dict[int, int] = {}  # word -> when its data is in the FIFO
        self.consumed: dict[int, int] = {}  # word -> when decode is done with it
        self.next_word: int | None = None  # the next word the stream fetches
        self.last_issue = _IDLE
        self.first_of_stream = False
        self.last_consumed = _IDLE

    def restart(self, address: int, time: int) -> None:
        """A jump to `address`, its target known at `time`."""
        self.arrival.clear()
        self.next_word = address // WORD_BYTES
        self.last_issue = time - 1
        self.first_of_stream = True

    def preloaded(self, address: int, ready: int) -> None:
        """An exception entry fetched the handler's first word by `ready`."""
        word = address // WORD_BYTES
        self.arrival = {word: ready}
        self.next_word = word + 1
        self.last_issue = ready - 1
        self.first_of_stream = False

    def _memory(self, word: int, issue: int, *, enters: bool = True) -> tuple[int, int]:
        """(issue time, arrival time) of a word fetch presented no earlier than `issue`."""
        address = word * WORD_BYTES
        if in_code_region(address):
            arrival = self.flash.fetch(address // FLASH_BLOCK_BYTES, issue, enters=enters)
            return issue, arrival
        granted = self.bus.take(issue)
        penalty = self.timing.system_bus_fetch_penalty if self.first_of_stream else 0
        return granted, granted + 1 + penalty

    def word(self, word: int) -> int:
        """When `word` (on the current stream) is in the FIFO."""
        assert self.next_word is not None
        while self.next_word <= word:
            w = self.next_word
            slot_free = self.consumed.get(w - self.FIFO_WORDS, self.last_consumed)
            issue, arrival = self._memory(w, max(self.last_issue + 1, slot_free))
            self.first_of_stream = False
            self.arrival[w] = arrival
            # An AHB fetch held by wait states holds the next one's address phase too.
            self.last_issue = max(issue, arrival - 1)
            self.next_word = w + 1
        return self.arrival[word]

    def speculate(self, target: int, time: int) -> None:
        """A conditional branch presents its target at decode (TRM 1.4), taking a fetch
        slot on the bus; when not taken, the stream goes on where it was."""
        issue, arrival = self._memory(
            target // WORD_BYTES, max(self.last_issue + 1, time), enters=False
        )
        self.last_issue = max(issue, arrival - 1)

    def decoded(self, first_word: int, last_word: int, time: int) -> None:
        for w in range(first_word, last_word + 1):
            self.consumed[w] = time
        self.last_consumed = time


def memory_stalls(
    timing: MemoryTiming, trace: Sequence[Executed], *, after_exception: bool
) -> MemoryStalls:
    """Stall cycles of an executed trace on top of its TRM cycles.

    With `after_exception` the first instruction's word was fetched by the exception
    entry (priced there); otherwise the trace starts with a jump into its first
    instruction, its target known at time -1.
    """
    result = MemoryStalls()
    if timing.flash_wait_states is None or not trace:
        result.per_step = [0] * len(trace)
        return result
    flash = _Flash(timing.flash_read_cycles)
    bus = _SystemBus()
    prefetch = _PrefetchUnit(timing, flash, bus)
    first = trace[0].address
    if after_exception:
        if in_code_region(first):
            flash.preload(first // FLASH_BLOCK_BYTES, -1)
        prefetch.preloaded(first, -1)
    else:
        prefetch.restart(first, -1)
    time = 0
    for index, step in enumerate(trace):
        first_word = step.address // WORD_BYTES
        last_word = (step.address + step.size - 1) // WORD_BYTES
        ready = prefetch.word(first_word)  # a 32-bit instruction may span two words
        if last_word != first_word:
            ready = max(ready, *(prefetch.word(w) for w in range(first_word + 1, last_word + 1)))
        start = max(time, ready + 1)  # decoded the cycle its last word arrives
        stall = start - time
        result.fetch += stall
        prefetch.decoded(first_word, last_word, start - 1)
        if step.conditional and step.target is not None and timing.speculative_branch_fetch:
            prefetch.speculate(step.target, start - 1)
        extra = 0
        for offset, (data_address, _, write) in enumerate(step.accesses):
            phase = start + 1 + offset + extra  # TRM: address, then one data cycle each
            if in_code_region(data_address) and not write:
                result.flash_data_reads += 1
                done = flash.read_data(phase)
                extra += done - (phase + 1)
            elif on_system_bus(data_address):
                result.system_bus_data += 1
                if data_address >= PERIPHERAL_REGION:
                    result.peripheral_accesses += 1
                if not in_code_region(step.address):
                    extra += bus.take(phase) - phase
                else:
                    bus.take(phase)
        result.data += extra
        result.per_step.append(stall + extra)
        if step.jumps and index + 1 < len(trace):
            known = start - 1 if step.target is not None else start + step.pc_known_after
            prefetch.restart(trace[index + 1].address, known)
        time = start + step.cycles + extra
    return result
