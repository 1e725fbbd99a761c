/* Generated from template templates/c/stm32f103_port.c.j2 with spec spec/example_maxon_ec45_flat_48v.yaml (sha256 4e4bc402b3ee91505838c88f91659557d0005f5a8b56d60c19ecc3e2f665b3c6). Do not edit: regenerate with `bldc-codegen generate spec/example_maxon_ec45_flat_48v.yaml`. */
/*
 * STM32F103 port of the braking commutation core (see stm32f103_port.h).
 *
 * How a switch is driven (RM0008 section 14.4.9, Table 83 "Output control bits for
 * complementary OCx and OCxN channels with break feature", MOE = 1):
 *   CCxE = 1, CCxNE = 0:  OCx  = OCxREF xor CCxP
 *   CCxE = 0, CCxNE = 1:  OCxN = OCxREF xor CCxNP  (not the complement of OCxREF)
 *   CCxE = 1, CCxNE = 1:  OCx = OCxREF, OCxN = not OCxREF, both with dead time
 * OCxN is the complement of OCxREF only when both outputs of the channel are enabled.
 * PWM-OFF-PWM braking modulates one switch of a phase while the other stays off, so
 * each phase enables one output alone, and with CCxP = CCxNP = 0 (active-high gate
 * signals) that output is simply OCxREF. In PWM mode 1 OCxREF is active while
 * CNT < CCRx, so a switch at duty d, upper or lower, gets CCRx = d: the ON time of the
 * switch, as the core returns it. (CCRx = ARR - d would be right only for the
 * complemented output of a pair with both outputs enabled.)
 *   With OSSR = 1 the disabled output of such a phase is driven at its inactive level
 *   (off-state, OCx = CCxP = 0) instead of floating; a phase with both outputs
 *   disabled is not driven by the timer (OCx = OCxN = 0 where the GPIO takes over: ODR
 *   stays 0 on the output pins). OSSI = 1: with MOE = 0 (break) the outputs go to
 *   their idle level OISx = 0 after the dead time.
 *
 * Commutation is atomic: CR2.CCPC = 1 preloads CCxE, CCxNE and OCxM until a COM event,
 * and CCRx are preloaded (OCxPE = 1) until an update event. Each pattern change writes
 * CCR1..3 and CCER, then sets EGR.COMG and EGR.UG together: the new enables and the
 * new compare values start in the same clock cycle, with a PWM period that starts at
 * the commutation instant (the segment duties of Eq. 18 count from there). Without UG
 * the new CCRx would wait for the end of the running period, up to one period late.
 */

#include "stm32f103_port.h"
#include "stm32f103_regs.h"

#if BLDC_PWM_PERIOD_COUNTS != BLDC_PORT_DUTY_FULL_SCALE
#error "core and port disagree on the PWM full scale: generate both from the same spec"
#endif
#if BLDC_PORT_TIM3_ARR != UINT16_MAX
#error "the Hall edge reads a wrapped counter as CCR1 | ARR: ARR must be all ones"
#endif

/* Register codes from RM0008 (sections 14.4, 15.4 and 9.2) */
#define BLDC_PORT_OC_MODE_PWM1 6u          /* OCxM = 110: PWM mode 1, OCxREF active while CNT < CCRx */
#define BLDC_PORT_OC_MODE_FROZEN 0u        /* OCxM = 000: compare match only sets CCxIF */
#define BLDC_PORT_CC1S_TRC 3u              /* CC1S = 11: IC1 mapped on TRC (the Hall XOR edge) */
#define BLDC_PORT_TS_TI1F_ED 4u            /* SMCR.TS = 100: trigger = TI1 edge detector, both edges */
#define BLDC_PORT_SMS_RESET 4u             /* SMCR.SMS = 100: reset mode, counter cleared by the trigger */
#define BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ 3u /* GPIOx_CRy.MODE = 11: output, 50 MHz */
#define BLDC_PORT_GPIO_CNF_AF_PUSH_PULL 2u  /* CNF = 10 with MODE > 0: alternate function push-pull */
#define BLDC_PORT_GPIO_MODE_INPUT 0u       /* MODE = 00: input */
#define BLDC_PORT_GPIO_CNF_INPUT_PULL 2u   /* CNF = 10 with MODE = 00: input with pull-up/down (ODR picks) */

#define BLDC_PORT_GPIO_MODE_ANALOG 0u      /* MODE = 00 with CNF = 00: analog input */
#define BLDC_PORT_GPIO_CNF_ANALOG 0u
#define BLDC_PORT_MMS_OC4REF 7u            /* TIM1 CR2.MMS = 111: TRGO = OC4REF, the ADC's injected trigger */
#define BLDC_PORT_JEXTSEL_TIM1_TRGO 0u     /* ADC_CR2.JEXTSEL = 000: injected trigger TIM1 TRGO */
#define BLDC_PORT_EXTSEL_SWSTART 7u        /* ADC_CR2.EXTSEL = 111: regular group started by SWSTART */
/* ADC1 CR1: scan the injected sequence, its end-of-conversion interrupt, the analog
 * watchdog on the bus channel alone, for the regular and the injected conversions. */
#define BLDC_PORT_ADC_CR1 (ADC_CR1_SCAN | ADC_CR1_JEOCIE | ADC_CR1_AWDIE | ADC_CR1_JAWDEN | \
                           ADC_CR1_AWDEN | ADC_CR1_AWDSGL |                                  \
                           (BLDC_PORT_ADC_BUS_CHANNEL << ADC_CR1_AWDCH_Pos))

/* ADC2 CR1: its regular group (the current channels, scanned) under the analog watchdog,
 * every channel of the group, with its interrupt. */
#define BLDC_PORT_ADC2_CR1 (ADC_CR1_SCAN | ADC_CR1_AWDIE | ADC_CR1_AWDEN)
/* The Hall lines' EXTI lines (pending, mask and trigger registers share the bit layout). */
#define BLDC_PORT_HALL_LINES (EXTI_PR_PR6 | EXTI_PR_PR7 | EXTI_PR_PR0)
/* The Hall lines' confirmation wait: 1 us of the processor clock, counted by
 * the DWT's cycle counter (codegen/port.py HALL_CONFIRM_NS): exact whatever the flash
 * and the code's placement, so the wait delays the handlers of its priority by no more. */
#define BLDC_PORT_HALL_CONFIRM_CYCLES 72u
/* TIM1's dead time (500 ns) in processor cycles, rounded up, by the same
 * counter: where the port hands a phase from one switch to the other outside a fault
 * (out of the refusal's short circuit, or into it), the wait between the one off and
 * the other on. TIM1 inserts none between a channel's outputs enabled one at a time
 * (RM0008 Table 83), and the refusal path is cold, so the wait costs no hot path. */
#define BLDC_PORT_DEAD_TIME_CYCLES 36u
/* The processor clock's cycles (a seam: a host build of the port counts its own). */
#ifndef BLDC_PORT_CYCLES
#define BLDC_PORT_CYCLES() (DWT->CYCCNT)
#endif

#define BLDC_PORT_EGR_COMMUTATE (TIM_EGR_COMG | TIM_EGR_UG) /* enables and compares together */
/* TIM1 CR2: enables preloaded until a COM event, TRGO = OC4REF; the idle levels
 * (OISx, OISxN, used while MOE = 0) are OR-ed in by speed region. */
#define BLDC_PORT_TIM1_CR2 (TIM_CR2_CCPC | (BLDC_PORT_MMS_OC4REF << TIM_CR2_MMS_Pos))
#define BLDC_PORT_OIS_SHORT (TIM_CR2_OIS1N | TIM_CR2_OIS2N | TIM_CR2_OIS3N) /* lower switches on */
/* TIM1 BDTR without MOE: dead time, off-state outputs driven (OSSR, OSSI), the break
 * input enabled with its polarity; MOE is set only when the bridge is armed. */
#define BLDC_PORT_TIM1_BDTR                                                                  \
    ((BLDC_PORT_TIM1_DTG << TIM_BDTR_DTG_Pos) | TIM_BDTR_OSSR | TIM_BDTR_OSSI | TIM_BDTR_BKE | \
     (BLDC_PORT_BREAK_ACTIVE_HIGH << TIM_BDTR_BKP_Pos))
/* CC4E is set in every pattern: channel 4 only triggers the ADC (OC4REF) and its pin
 * PA11 is no alternate-function output, so the bit drives nothing, but CCER is never 0
 * and the Hall edge's partner test refuses an invalid pair too (codegen/port.py). */
#define BLDC_PORT_CCER_OFF TIM_CCER_CC4E
/* The idle state's short circuit with MOE set (port_idle_state: a refused edge, or
 * armed, where all-off rectifies): each lower switch alone enabled, at a compare of the
 * full scale (PWM mode 1, OCxN = OCxREF: on all period). */
#define BLDC_PORT_CCER_SHORT \
    (TIM_CCER_CC1NE | TIM_CCER_CC2NE | TIM_CCER_CC3NE | BLDC_PORT_CCER_OFF)
/* The safe state's CCER: every output of every phase enabled, so with MOE = 0 each is
 * held at its idle level (RM0008 Table 83, MOE = 0, OSSI = 1). */
#define BLDC_PORT_CCER_SAFE                                                            \
    (TIM_CCER_CC1E | TIM_CCER_CC1NE | TIM_CCER_CC2E | TIM_CCER_CC2NE | TIM_CCER_CC3E | \
     TIM_CCER_CC3NE | BLDC_PORT_CCER_OFF)
#define BLDC_PORT_HALL_INTERRUPTS (TIM_DIER_CC1IE | TIM_DIER_CC2IE)

/* Where the TIM3 handler (Hall edge, commutation end) and its pin table live. At 72 MHz
 * the flash has two wait states (RM0008 3.3.3, FLASH_ACR.LATENCY = 2): every literal or
 * table load from it and every fetch outside its 2 x 64-bit prefetch buffer waits for a
 * 3-cycle read, and the Cortex-M3 fetches the target of each conditional branch at decode
 * whether or not it is taken. From SRAM the code competes with its own data on the
 * System bus instead, and costs RAM: the handler and its table take about 450 bytes, and
 * the firmware's RAM budget (firmware.ram_budget, stack included) has no room for them.
 * So the default is flash, with the handler written for it (one conditional branch per
 * decision, constants built by MOVW/MOVT: -mslow-flash-data), and `make bench` measures
 * it in both places on every run. Define BLDC_PORT_HALL_EDGE_IN_SRAM to 1 to place it in
 * SRAM (`.RamFunc`, which the start-up code copies with `.data`; STM32Cube linker
 * scripts place `.RamFunc` there too). */
#if defined(__GNUC__) && defined(BLDC_PORT_HALL_EDGE_IN_SRAM) && BLDC_PORT_HALL_EDGE_IN_SRAM
#define BLDC_PORT_FAST_CODE __attribute__((section(".RamFunc")))
#define BLDC_PORT_FAST_DATA __attribute__((section(".RamFunc.data")))
#else
#define BLDC_PORT_FAST_CODE
#define BLDC_PORT_FAST_DATA
#endif

/* Keep the compiler from issuing the accesses before this point after it or the other
 * way round. Used where loading everything up front would need more registers than the
 * scratch ones, and so a push and pop of callee-saved registers in the Hall edge. */
#if defined(__GNUC__)
#define BLDC_PORT_SEQUENCE() __asm__ volatile("" ::: "memory")
#else
#define BLDC_PORT_SEQUENCE()
#endif

/* Keep the compiler from computing with `value` before the accesses above this point:
 * the value is taken as rewritten here, after them. For two loads that must follow
 * each other with nothing between (the commutation end's CNT and SR). */
#if defined(__GNUC__)
#define BLDC_PORT_AFTER_LOADS(value) __asm__ volatile("" : "+r"(value) : : "memory")
#else
#define BLDC_PORT_AFTER_LOADS(value) ((void)(value))
#endif

/* Branch hints: lay the rare paths out of line, so the Hall edge runs straight through. */
#if defined(__GNUC__)
#define BLDC_PORT_RARE(condition) __builtin_expect((condition) != 0, 0)
/* A rare call kept in line, skipped by a short forward CBZ: stated as likely, so the
 * compiler lays the call out as the fall-through. From flash, a conditional branch
 * that is not taken still fetches its target (TRM r2p0 1.4, speculative fetch), a read
 * of a distant flash line that the next instructions wait behind; the taken short
 * skip lands in the line already fetched. */
#define BLDC_PORT_RARE_IN_LINE(condition) __builtin_expect((condition) != 0, 1)
#define BLDC_PORT_COLD __attribute__((cold, noinline))
#define BLDC_PORT_NOINLINE __attribute__((noinline))
/* Start on a 64-bit flash line: the first fetch brings in four 16-bit instructions. */
#define BLDC_PORT_LINE_ALIGNED __attribute__((aligned(8)))
/* No instruction scheduling before register allocation: it hoists loads and constants
 * to the top, which keeps more values alive than the scratch registers (r0-r3, r12)
 * hold, and so costs a push and a pop of callee-saved registers. */
#define BLDC_PORT_FEW_REGISTERS __attribute__((optimize("no-schedule-insns")))
#else
#define BLDC_PORT_FEW_REGISTERS
#define BLDC_PORT_RARE(condition) ((condition) != 0)
#define BLDC_PORT_RARE_IN_LINE(condition) ((condition) != 0)
#define BLDC_PORT_COLD
#define BLDC_PORT_NOINLINE
#define BLDC_PORT_LINE_ALIGNED
#endif

/* The packed record of one commutation edge, generated from the switching table
 * (codegen/derivation/switching.py, codegen/port.py): bits 12:0 CCER during the commutation (turn-on and turn-off switch, and CC4E), bits 14:13 and 30:29 the TIM1 channel (0..2 = CCR1..CCR3) of the turn-on and turn-off switch, bits 26:16 the CCER bits of their phase partners, bits 31 and 27 the injected data register (0..2 = JDR1..JDR3) that holds the braking current once the commutation has ended (high and low bit), bit 28 set alone: no valid edge (shifted down by 16 it is CC4E, which every pattern has). Shifted down by 16 a valid record's bits above the partners land on CCER bits 11 and 13..15 (CC3NP, CC4P, reserved), which the port keeps 0.
 * One 32-bit word, so the Hall edge reads all it needs of an edge with a single load
 * from flash (each costs two wait states at 72 MHz). */
#define PORT_RECORD_CCER_DURING(record) ((record) & 0x1fffu)
#define PORT_RECORD_ON_CHANNEL(record) (((record) >> 13) & 3u)
#define PORT_RECORD_OFF_CHANNEL(record) (((record) >> 29) & 3u)
#define PORT_RECORD_FORBIDDEN(record) ((record) >> 16)
#define PORT_RECORD_SENSE_SLOT(record) \
    ((((record) >> 27) & 1u) | (((record) >> (31 - 1u)) & 2u))
/* No valid edge for this pin pair (its partner field is CC4E, always set in CCER). */
#define PORT_RECORD_INVALID 0x10000000u
/* The incoming switch alone: the turn-off channel's enables cleared (RM0008 TIMx_CCER
 * has four bits per channel). */
#define PORT_RECORD_CCER_AFTER(record) \
    (PORT_RECORD_CCER_DURING(record) & ~(0xFu << (4u * PORT_RECORD_OFF_CHANNEL(record))))

/* The core's edge of each Hall code pair (bldc_edge_of()) as its packed record, indexed
 * by the pin levels as read, PA6 | PA7 << 1 | PB0 << 2 (previous << 3 | now): the
 * pin decoding, the edge lookup and the register table folded into one table, placed
 * with the handler. */
BLDC_PORT_FAST_DATA static const uint32_t port_edge_of_pins[64] = {
    0x10000000u, /* pins 000 -> 000: Hall 000 -> 000, invalid */
    0x10000000u, /* pins 000 -> 001: Hall 000 -> 100, invalid */
    0x10000000u, /* pins 000 -> 010: Hall 000 -> 010, invalid */
    0x10000000u, /* pins 000 -> 011: Hall 000 -> 110, invalid */
    0x10000000u, /* pins 000 -> 100: Hall 000 -> 001, invalid */
    0x10000000u, /* pins 000 -> 101: Hall 000 -> 101, invalid */
    0x10000000u, /* pins 000 -> 110: Hall 000 -> 011, invalid */
    0x10000000u, /* pins 000 -> 111: Hall 000 -> 111, invalid */
    0x10000000u, /* pins 001 -> 000: Hall 100 -> 000, invalid */
    0x10000000u, /* pins 001 -> 001: Hall 100 -> 100, invalid */
    0x10000000u, /* pins 001 -> 010: Hall 100 -> 010, invalid */
    0x80113044u, /* pins 001 -> 011: Hall 100 -> 110, edge 2, forward into sector 2: T4 on, T2 off */
    0x10000000u, /* pins 001 -> 100: Hall 100 -> 001, invalid */
    0x41103440u, /* pins 001 -> 101: Hall 100 -> 101, edge 6, reverse into sector 0: T4 on, T6 off */
    0x10000000u, /* pins 001 -> 110: Hall 100 -> 011, invalid */
    0x10000000u, /* pins 001 -> 111: Hall 100 -> 111, invalid */
    0x10000000u, /* pins 010 -> 000: Hall 010 -> 000, invalid */
    0x10000000u, /* pins 010 -> 001: Hall 010 -> 100, invalid */
    0x10000000u, /* pins 010 -> 010: Hall 010 -> 010, invalid */
    0x09015404u, /* pins 010 -> 011: Hall 010 -> 110, edge 8, reverse into sector 2: T6 on, T2 off */
    0x10000000u, /* pins 010 -> 100: Hall 010 -> 001, invalid */
    0x10000000u, /* pins 010 -> 101: Hall 010 -> 101, invalid */
    0x21105440u, /* pins 010 -> 110: Hall 010 -> 011, edge 4, forward into sector 4: T6 on, T4 off */
    0x10000000u, /* pins 010 -> 111: Hall 010 -> 111, invalid */
    0x10000000u, /* pins 011 -> 000: Hall 110 -> 000, invalid */
    0x20441011u, /* pins 011 -> 001: Hall 110 -> 100, edge 7, reverse into sector 1: T1 on, T3 off */
    0x44041101u, /* pins 011 -> 010: Hall 110 -> 010, edge 3, forward into sector 3: T1 on, T5 off */
    0x10000000u, /* pins 011 -> 011: Hall 110 -> 110, invalid */
    0x10000000u, /* pins 011 -> 100: Hall 110 -> 001, invalid */
    0x10000000u, /* pins 011 -> 101: Hall 110 -> 101, invalid */
    0x10000000u, /* pins 011 -> 110: Hall 110 -> 011, invalid */
    0x10000000u, /* pins 011 -> 111: Hall 110 -> 111, invalid */
    0x10000000u, /* pins 100 -> 000: Hall 001 -> 000, invalid */
    0x10000000u, /* pins 100 -> 001: Hall 001 -> 100, invalid */
    0x10000000u, /* pins 100 -> 010: Hall 001 -> 010, invalid */
    0x10000000u, /* pins 100 -> 011: Hall 001 -> 110, invalid */
    0x10000000u, /* pins 100 -> 100: Hall 001 -> 001, invalid */
    0x49011404u, /* pins 100 -> 101: Hall 001 -> 101, edge 0, forward into sector 0: T2 on, T6 off */
    0xa0111044u, /* pins 100 -> 110: Hall 001 -> 011, edge 10, reverse into sector 4: T2 on, T4 off */
    0x10000000u, /* pins 100 -> 111: Hall 001 -> 111, invalid */
    0x10000000u, /* pins 101 -> 000: Hall 101 -> 000, invalid */
    0xa4405110u, /* pins 101 -> 001: Hall 101 -> 100, edge 1, forward into sector 1: T5 on, T3 off */
    0x10000000u, /* pins 101 -> 010: Hall 101 -> 010, invalid */
    0x10000000u, /* pins 101 -> 011: Hall 101 -> 110, invalid */
    0x84045101u, /* pins 101 -> 100: Hall 101 -> 001, edge 11, reverse into sector 5: T5 on, T1 off */
    0x10000000u, /* pins 101 -> 101: Hall 101 -> 101, invalid */
    0x10000000u, /* pins 101 -> 110: Hall 101 -> 011, invalid */
    0x10000000u, /* pins 101 -> 111: Hall 101 -> 111, invalid */
    0x10000000u, /* pins 110 -> 000: Hall 011 -> 000, invalid */
    0x10000000u, /* pins 110 -> 001: Hall 011 -> 100, invalid */
    0x4c403110u, /* pins 110 -> 010: Hall 011 -> 010, edge 9, reverse into sector 3: T3 on, T5 off */
    0x10000000u, /* pins 110 -> 011: Hall 011 -> 110, invalid */
    0x08443011u, /* pins 110 -> 100: Hall 011 -> 001, edge 5, forward into sector 5: T3 on, T1 off */
    0x10000000u, /* pins 110 -> 101: Hall 011 -> 101, invalid */
    0x10000000u, /* pins 110 -> 110: Hall 011 -> 011, invalid */
    0x10000000u, /* pins 110 -> 111: Hall 011 -> 111, invalid */
    0x10000000u, /* pins 111 -> 000: Hall 111 -> 000, invalid */
    0x10000000u, /* pins 111 -> 001: Hall 111 -> 100, invalid */
    0x10000000u, /* pins 111 -> 010: Hall 111 -> 010, invalid */
    0x10000000u, /* pins 111 -> 011: Hall 111 -> 110, invalid */
    0x10000000u, /* pins 111 -> 100: Hall 111 -> 001, invalid */
    0x10000000u, /* pins 111 -> 101: Hall 111 -> 101, invalid */
    0x10000000u, /* pins 111 -> 110: Hall 111 -> 011, invalid */
    0x10000000u, /* pins 111 -> 111: Hall 111 -> 111, invalid */
};

/* port.after_refusal after a capture no rotor makes (a line's bounce, microseconds). */
#define PORT_AFTER_BOUNCE 2u

/* Below it a Hall interval is no rotor's after one of `reference`, the last right one:
 * half the top speed's interval (a line's bounce lasts microseconds), or, for a rotor
 * already over speed, half its own (a rotor does not halve its interval in one sector).
 * A fixed half of the top speed's had taken a rotor driven past twice the top speed,
 * faulted, for a bounce at every edge and held its safe state there: all-off,
 * rectifying, up to 3 x (a hunt: an overhauling load on short_sector_5k_16p, 29.5 V).
 * Half the reference alone, a slow one, had taken a rotor stepping to over speed for
 * one, each capture after it too: the clear re-armed it (the clear_over_speed scenario). */
static inline uint32_t port_bounce_below(uint32_t reference)
{
    return ((reference < BLDC_PERIOD_MIN_TICKS) ? reference : BLDC_PERIOD_MIN_TICKS) >> 1;
}

/* The shortest Hall interval a rotor makes after one of `prior` ticks:
 * hall.sector_shortening (5 %) shorter at most, as the core's latest end takes it
 * (1/16). A shorter one ended at an edge no rotor made. */
static inline uint32_t port_plausible_after(uint32_t prior)
{
    return prior - (prior >> 4u);
}

/* A bus code no ADC gives: no sample yet (the timing is then the safe state). */
#define BLDC_PORT_BUS_UNKNOWN UINT16_MAX

/* State. Written by the handlers (the Hall edge, the current loop and the break
 * interrupt share one priority level, the timing handler runs below them) and by the
 * API, which masks interrupts (PRIMASK) where it touches what they use. Every field the
 * handlers share is one aligned word or half-word, so each read and write is atomic;
 * the timing handler never writes the slot the Hall edge may be reading (it fills the
 * other one and then publishes it with one word write). */
static struct {
    bldc_timing_t *timing;          /* what the next Hall edge applies: one of port_slots (it only reads it) */
    uint32_t pending;               /* record of the commutation running until its CC2 end, or 0 */
    uint32_t steady;                /* record whose incoming switch runs at main duty, or 0 */
    uint32_t stale;                 /* injected sequences begun before the commutation end and not yet taken (0..2) */
    volatile uint32_t *steady_compare; /* its compare register (CCRx), set with `steady` */
    const volatile uint32_t *steady_sense; /* the JDRx that holds I then, set with `steady` */
    uint16_t period;                /* last Hall interval in ticks, for the next timing (16 bits: the inlined core's cap to the counter's range folds away) */
    uint16_t after_refusal;         /* 1 from a refused edge to the next commutation end, PORT_AFTER_BOUNCE from a bounce's capture (faulted) to the next: the interval then is part of a sector */
    uint32_t previous_pins;         /* Hall pin levels of the sector being left */
    uint16_t main_duty;             /* TIM1 counts: the current loop's output, or the open-loop duty */
    uint16_t bus_code;              /* the bus code of `bus` (written at the bus change; for a debugger and the PIL, no handler reads it) */
    uint32_t bus_low;               /* the bus code of `bus` - hysteresis (mod 2^32): a sample within the band is no change */
    uint32_t bus_moved;             /* 1: the current loop's last bus sample left the band (the bus-change handler recomputes), else 0 */
    uint32_t all_off_from;          /* all-off is the safe state at Hall intervals from this one (at the bus code of `bus`) */
    uint32_t all_off_span;          /* ... for this many intervals (0: none; port_set_safe_region) */
    uint32_t reference;             /* braking-current reference, ADC code, or BLDC_PORT_OPEN_LOOP */
    int32_t integrator;             /* the PI's x, Q BLDC_LOOP_FRAC_BITS counts */
    uint32_t current;               /* I, ADC code: the last steady sample (held through a commutation); 0 from arming until the first */
    /* The inputs of the published timing beside `bus`, which only the timing handler
     * writes: bldc_port_status() computes its flags from them. */
    uint16_t timed_period;          /* the Hall interval it took */
    uint16_t timed_current;         /* the current code it took */
    uint32_t faults;                /* latched BLDC_FAULT_* */
    uint32_t requested;             /* faults found below the break interrupt's priority, for it to latch */
    uint32_t heartbeat;             /* current-loop runs, for the watchdog */
    uint32_t heartbeat_seen;        /* its value at the last bldc_port_alive() */
    bldc_bus_t bus;                 /* bldc_bus_condition(bus_code), cached */
    /* last: a field added above shifts the others' offsets, and the handlers' loads of
     * them past 124 bytes take 32-bit encodings (a timing handler 2 cycles slower) */
    uint32_t bus_taken;             /* `heartbeat` at the last bus change: the next waits BLDC_PORT_BUS_MIN_PERIODS runs */
    uint16_t faulted_wait;          /* faulted: injected samples until the next faulted tick (BLDC_PORT_FAULTED_TICK_PERIODS) */
    uint16_t faulted_measured;      /* OVER_SPEED latched: the last Hall interval TIM3 measured, a part sector's too (a clear's over-speed test) */
} port;

/* The published timing and the one being computed, each in a 16-byte slot. The pair
 * starts on a 32-byte boundary, so the two addresses differ in bit 4 alone: the slot
 * the timing handler fills is the published one's address XOR 16, one EOR, where a
 * pointer to the spare slot would cost a load and a store on every run. */
typedef union {
    bldc_timing_t timing;
    uint8_t bytes[16];
} port_slot_t;
#define PORT_SLOT_BYTES 16u
typedef char port_slot_is_16_bytes[(sizeof(port_slot_t) == PORT_SLOT_BYTES) ? 1 : -1];
#if !defined(BLDC_PORT_SLOTS_ALIGNED)
#if defined(__GNUC__)
#define BLDC_PORT_SLOTS_ALIGNED __attribute__((aligned(32)))
#else
#error "define BLDC_PORT_SLOTS_ALIGNED to your compiler's 32-byte alignment attribute: port_slots[0] and [1] must differ in address bit 4 alone"
#endif
#endif
static port_slot_t port_slots[2] BLDC_PORT_SLOTS_ALIGNED;

/* The slot that is not `slot`. */
static inline bldc_timing_t *port_other_slot(bldc_timing_t *slot)
{
    return (bldc_timing_t *)((uintptr_t)slot ^ PORT_SLOT_BYTES);
}

/* TIM1 compare register of channel 0..2 (CCR1..CCR3 are consecutive words). */
static volatile uint32_t *port_compare(TIM_TypeDef *tim1, uint32_t channel)
{
    return &tim1->CCR1 + channel;
}

/* Peripheral addresses for the interrupt handlers, built from one register. An address
 * the compiler knows as a constant is loaded from a literal pool in flash, and at 72 MHz
 * each such load waits two cycles for the flash (RM0008 3.3.3). The empty asm hides the
 * value of the peripheral region's start (one MOV), so the handlers reach TIM1, TIM3 and
 * the GPIO ports with an ADD or an offset from it instead. */
#define BLDC_PORT_PERIPHERALS 0x40000000u /* start of the peripheral region holding TIM1, TIM3, ADC1, ADC2, EXTI, GPIOA and GPIOB (RM0008 3.3, bases from the SVD) */
static inline uintptr_t port_peripherals(void)
{
    uintptr_t anchor = BLDC_PORT_PERIPHERALS;
    __asm__("" : "+r"(anchor));
    return anchor;
}
/* The same, made again (one MOV) where keeping the first alive would hold one more
 * register through the Hall edge: every value past the scratch registers (r0-r3,
 * r12) is a callee-saved one pushed and popped. The MOV is in the asm, volatile and
 * ordered by a memory clobber, so the compiler can neither share the first's value
 * nor hoist this one to the top. */
static inline uintptr_t port_peripherals_again(void)
{
#if defined(__arm__)
    uintptr_t anchor;
    __asm__ volatile("mov %0, %1" : "=r"(anchor) : "i"(BLDC_PORT_PERIPHERALS) : "memory");
    return anchor;
#else
    return port_peripherals();
#endif
}
#define PORT_AT(anchor, instance, type) \
    ((type *)((anchor) + ((uintptr_t)(instance) - (uintptr_t)BLDC_PORT_PERIPHERALS)))

/* TIM1 register `name` reached from the address of TIM1 CCR1 by a constant offset
 * (negative: every TIM1 register the Hall edge writes besides CCRx lies below CCR1). */
#define PORT_TIM1_FROM_CCR1(ccr1, name) \
    ((volatile uint32_t *)((uintptr_t)(ccr1) - ((uintptr_t)&TIM1->CCR1 - (uintptr_t)&TIM1->name)))

/* Every output off now (a COM event), then TIM1's dead time: after it any switch may
 * turn on, the partner of one that was on included. The read back after the COM event
 * waits for the bus to carry it to TIM1 (a store may still be on its way), so the
 * count starts with the switches off. `egr` is the COM event's: COMG, with UG to load
 * compares written before (preloaded, OCxPE). Cold: the refusal's paths alone. */
BLDC_PORT_COLD static void port_off_for_dead_time(TIM_TypeDef *tim1, uint32_t egr)
{
    tim1->CCER = BLDC_PORT_CCER_OFF; /* preloaded (CCPC = 1) */
    tim1->EGR = egr;
    (void)tim1->CCER;
    const uint32_t start = BLDC_PORT_CYCLES();
    while ((uint32_t)(BLDC_PORT_CYCLES() - start) < BLDC_PORT_DEAD_TIME_CYCLES) {
        /* unsigned difference: the counter's wrap is harmless */
    }
}


/* 1 where the bridge's state without a fault is the short circuit: where all-off would
 * rectify into the bus at Hall interval T and the latest bus sample B (T B <= K, the
 * product the fault path's region is found from) and the short is rated there; at a
 * wrapped interval (the speed unknown: armed at start-up) or before a bus sample,
 * all-off, as arming always had it (the short there had shorted a rotor at rest). Not
 * the spec's
 * preference alone, as a fault's state is: the short's current is the braking rotor's
 * short-circuit current, which may be over the comparator's threshold, and a refused
 * edge is no fault (the hub motor's 1.3 ms Hall glitch at 115 rpm, the motor in the
 * loop: 30.9 A, the comparator tripped, OVER_CURRENT where all-off rectifies nothing;
 * a hunt). The latest sample, not the bus state the timing uses: that one waits for
 * the bus change's gate (BLDC_PORT_BUS_MIN_PERIODS). */
/* 1 where all-off would rectify into a bus of code `bus` at this Hall interval (T B at
 * or below the product: codegen/control/safe_state.py). */
static inline uint32_t port_rectifies(uint32_t period, uint32_t bus)
{
    return (uint32_t)((uint64_t)period * bus <= BLDC_PORT_RECTIFYING_PRODUCT);
}

static uint32_t port_idle_short(uint32_t period)
{
    const uint32_t bus = (uint16_t)ADC1->JDR4; /* JDATA: bits 15:0 */
    if ((period >= BLDC_PORT_TIM3_ARR) || (bus < BLDC_PORT_ADC_LTR)) {
        /* no measured speed, or no bus sample yet (JDR4 reads 0 until the first; a bus
         * under its range is the watchdog's fault, whose path chooses its state) */
        return 0u;
    }
    const uint32_t rectifies = port_rectifies(period, bus);
#if BLDC_PORT_SHORT_VALID_PERIOD == 0u
    return rectifies; /* rated at every interval */
#else
    return rectifies & (uint32_t)(period >= BLDC_PORT_SHORT_VALID_PERIOD);
#endif
}

/* 1 where no state is safe at this Hall interval: all-off would rectify into the bus
 * (the latest sample, as port_idle_short) and the short is beyond its rating. The
 * loader keeps that outside the speed range, so only an interval over speed, or one no
 * rotor makes, reads so. */
static inline uint32_t port_no_safe_state(uint32_t period)
{
#if BLDC_PORT_SHORT_VALID_PERIOD == 0u
    (void)period;
    return 0u; /* the short is rated at every interval */
#else
    const uint32_t bus = (uint16_t)ADC1->JDR4; /* JDATA: bits 15:0 */
    return port_rectifies(period, bus) & (uint32_t)(period < BLDC_PORT_SHORT_VALID_PERIOD);
#endif
}

/* The bridge's state without a fault and with no switch of a sector on (a refused
 * edge, or armed before the first edge), with MOE set: every switch off, or where all-off
 * would rectify into the bus (port_idle_short) each lower switch alone on, entered
 * through all-off and the dead time. Nothing done where the state is already the one. */
BLDC_PORT_COLD static void port_idle_state(TIM_TypeDef *tim1, uint32_t period)
{
    const uint32_t ccer = tim1->CCER;
    if (port_idle_short(period) == 0u) {
        if (ccer != BLDC_PORT_CCER_OFF) {
            tim1->CCER = BLDC_PORT_CCER_OFF; /* preloaded (CCPC = 1) */
            tim1->EGR = BLDC_PORT_EGR_COMMUTATE;
        }
    } else if (ccer != BLDC_PORT_CCER_SHORT) {
        /* every lower switch's compare at the full scale, loaded by the COM event's UG
         * with every output off; then the lower switches alone, after the dead time */
        tim1->CCR1 = BLDC_PORT_DUTY_FULL_SCALE;
        tim1->CCR2 = BLDC_PORT_DUTY_FULL_SCALE;
        tim1->CCR3 = BLDC_PORT_DUTY_FULL_SCALE;
        port_off_for_dead_time(tim1, BLDC_PORT_EGR_COMMUTATE);
        tim1->CCER = BLDC_PORT_CCER_SHORT;
        tim1->EGR = TIM_EGR_COMG;
    }
}

/* Nothing switches, and no fault: a direction reversal (a phase would hand over from
 * one switch to the other) or no valid timing yet. The idle state at the interval just
 * measured (port_idle_state: all-off had rectified into the bus where a Hall code
 * stepped back one sector late in a sector at 4600 rpm on a 20.5 V bus, the paper
 * motor, until the next edge; a hunt). The current loop's interrupt chooses it again at
 * each sample while it lasts (port_adc_other: a bus falling meanwhile had left all-off
 * rectifying for 2 ms; a hunt). The next valid edge commutates from either
 * (port_refuse leaves the short through all-off and the dead time again where the
 * edge's switches need it). */
BLDC_PORT_COLD static void port_outputs_off(uintptr_t anchor)
{
    port_idle_state(PORT_AT(anchor, TIM1, TIM_TypeDef), port.period);
    /* No commutation to end; the wrap is read. */
    PORT_AT(anchor, TIM3, TIM_TypeDef)->SR = ~(TIM_SR_CC2IF | TIM_SR_UIF);
    port.pending = 0u;
    port.steady = 0u;
}

/* A valid edge in time, out of the refusal's short circuit, whose switches' partners
 * are on in it (a lower switch on where the edge turns the upper one on or off): every
 * switch off and the dead time, then the edge's commutation as the Hall edge applies
 * it (port_on_hall_edge; its record is in `pending`, its timing the one published). */
BLDC_PORT_COLD static void port_commutate_from_short(uintptr_t anchor)
{
    TIM_TypeDef *const tim1 = PORT_AT(anchor, TIM1, TIM_TypeDef);
    TIM_TypeDef *const tim3 = PORT_AT(anchor, TIM3, TIM_TypeDef);
    const uint32_t record = port.pending;
    const bldc_timing_t *const timing = port.timing;
    port_off_for_dead_time(tim1, TIM_EGR_COMG);
    *port_compare(tim1, PORT_RECORD_ON_CHANNEL(record)) = timing->turn_on_compare;
    *port_compare(tim1, PORT_RECORD_OFF_CHANNEL(record)) = timing->turn_off_compare;
    tim1->CCER = PORT_RECORD_CCER_DURING(record);
    tim1->EGR = BLDC_PORT_EGR_COMMUTATE;
    /* the commutation's end, counted from the edge (TIM3 restarted there), raised at
     * once if the counter is already past it */
    const uint32_t ticks = timing->commutation_ticks;
    tim3->CCR2 = ticks;
    tim3->SR = ~(TIM_SR_CC2IF | TIM_SR_UIF);
    tim3->EGR = (tim3->CNT >= ticks) ? TIM_EGR_CC2G : 0u;
}

/* A fault: the safe state now, and latched. MOE = 0 sends every enabled output to its
 * off state at once and to its idle level (CR2.OISx / OISxN: the short circuit or all
 * off, as the region in force says) after a dead time; enabling every output of every
 * phase makes that hold for all three phases. TIM3 stops raising its interrupts (a Hall
 * edge must not apply a pattern), and one it has already pended finds nothing to do.
 * Called at the Hall edge's priority or with interrupts masked. */
BLDC_PORT_COLD static void port_trip(uintptr_t anchor, uint32_t fault)
{
    TIM_TypeDef *const tim1 = PORT_AT(anchor, TIM1, TIM_TypeDef);
    TIM_TypeDef *const tim3 = PORT_AT(anchor, TIM3, TIM_TypeDef);
    tim1->BDTR = BLDC_PORT_TIM1_BDTR; /* MOE = 0 */
    tim1->CCER = BLDC_PORT_CCER_SAFE;
    tim1->EGR = TIM_EGR_COMG; /* load it */
    tim3->DIER = 0u;
    tim3->SR = ~(TIM_SR_CC2IF | TIM_SR_CC1IF);
    NVIC_ClearPendingIRQ(TIM3_IRQn);
    port.pending = 0u;
    port.steady = 0u;
    port.faults |= fault;
    port.faulted_wait = 0u; /* the pended run below is a faulted tick */
    /* The bus watchdog's window for the fault (port_watch_while_faulted) is set by the
     * ADC interrupt's faulted path, pended here to run next, tail-chained at this
     * priority: the trip itself stays short (a handler of this priority ahead of a
     * commutation end delays its switch-off, bench's end-guard figure). */
    NVIC_SetPendingIRQ(ADC1_2_IRQn);
}

/* The Hall edge refused to commutate: find out why. The edge stored its record, pins
 * and interval before calling (so the Hall edge branches here with nothing to pass). */
BLDC_PORT_COLD static void port_refuse(void)
{
    const uintptr_t anchor = port_peripherals();
    const uint32_t pins = port.previous_pins;
    /* The next edge's interval starts at this one: part of a sector, no Hall time-out's
     * measure (port_on_commutation_end). */
    port.after_refusal = 1u;
    if (port.pending == PORT_RECORD_INVALID) {
        /* The interval of an edge to a wrong code is no sector's (a stuck line's next
         * edge comes two sectors on): the safe state keeps the interval the last timing
         * ran with, the last edge that was right (its timing runs after this). */
        port.period = port.timed_period;
        /* 000 and 111 read as the same pin levels in any order */
        port_trip(anchor, ((pins == 0u) || (pins == 7u)) ? BLDC_FAULT_HALL_INVALID
                                                         : BLDC_FAULT_HALL_SEQUENCE);
    } else if (port.period < port.timing->period_min) {
        if (port.timing->period_min == BLDC_PERIOD_NEVER) {
            port_outputs_off(anchor); /* no valid timing: no bus sample yet, or over-voltage */
        } else {
            /* An interval no rotor makes (a line's bounce: microseconds) says nothing of
             * the speed: the safe state keeps the last right edge's. A spec that prefers
             * the short had read a 3 us bounce as a rotor beyond the short's rating and
             * held all-off, rectifying, for the rest of the sector (a hunt). */
            port.faulted_measured = port.period; /* what TIM3 measured: a clear's test */
            port_trip(anchor, BLDC_FAULT_OVER_SPEED);
            const uint32_t measured = port.faulted_measured;
            /* Nor does one shorter than a rotor makes after the last right interval (a
             * line's glitch late in a sector: a part sector), where no state is safe at
             * the speed it reads. That had been read as the rotor's: on a spec
             * preferring the short, beyond its rating, all-off, rectifying, for 1.4
             * sectors (a hunt: 4900 rpm on 20.2 V, a 2 us glitch at 0.6 of a sector, the
             * short rated to 5359 rpm). Where a state is safe at the speed it reads, that
             * one is taken: it is safe at the slower speed too (the short rated there,
             * or all-off rectifying nothing). */
            const uint32_t bounce = (uint32_t)(measured < port_bounce_below(port.timed_period));
            if ((bounce != 0u) || ((measured < port_plausible_after(port.timed_period)) &&
                                   (port_no_safe_state(measured) != 0u))) {
                port.period = port.timed_period; /* the rotor's: the last right edge's */
                /* The next capture starts at the bounce (or at the glitch's return, if
                 * that came before the trip cleared CC1IF): the rest of a sector. */
                port.after_refusal = PORT_AFTER_BOUNCE;
                if (bounce != 0u) {
                    port.faulted_measured = port.timed_period; /* no speed: no over-speed's */
                } /* a part sector: a clear still sees it (port_present_causes) */
            }
        }
    } else if (PORT_AT(anchor, TIM1, TIM_TypeDef)->CCER == BLDC_PORT_CCER_SHORT) {
        port_commutate_from_short(anchor); /* the refusal's short: the switches it holds on */
    } else {
        /* A phase would swap switches: the idle state, then the next edge. Its interval
         * is the time since the last edge, part of a sector (a code stepping back late
         * in one read as a rotor 12 % faster: the short where all-off was safe, and on a
         * rated-short spec all-off where it was required; a hunt): the idle state, and
         * the timing this COM event runs, take the last right edge's, as a wrong code's
         * trip does. */
        port.period = port.timed_period;
        port_outputs_off(anchor);
    }
}

/* Hall edge: TIM3 reset its counter and captured the 60 degree interval in CCR1. The
 * duties and the commutation time were computed after the previous edge, from the
 * interval before this one (TIM1_TRG_COM_IRQHandler); this handler only checks, applies
 * and schedules. */
static void port_on_hall_edge(uintptr_t anchor, uint32_t status)
{
    const uint32_t pins = ((PORT_AT(anchor, GPIOA, GPIO_TypeDef)->IDR >> 6) & 3u) | ((PORT_AT(anchor, GPIOB, GPIO_TypeDef)->IDR >> 0 & 1u) << 2);
    /* Reading CCR1 clears CC1IF. A wrapped counter (UIF, bit 0) reads as its whole
     * range, the slowest speed the core can be told: 0 - UIF is all ones then, and
     * CCR1 | ARR = ARR (CCR1 <= ARR = 2^16 - 1). No branch; UIF is cleared below, with
     * CC2IF, on every path. */
    const uint32_t wrapped = 0u - (status & TIM_SR_UIF);
    const uint32_t period = PORT_AT(anchor, TIM3, TIM_TypeDef)->CCR1 | (wrapped >> 16);
    BLDC_PORT_SEQUENCE(); /* the peripheral reads before the state's: fewer values live at once */
    const uint32_t previous = port.previous_pins;
    port.previous_pins = pins;
    port.period = (uint16_t)period; /* <= ARR; every path below ends in a COM event, which runs the timing */
    const uint32_t record = port_edge_of_pins[(previous << 3) | pins];
    port.pending = record;  /* the safe state below clears it again */
    const bldc_timing_t *const timing = port.timing;
    /* Compared here, so `period` is dead before TIM1 is reached: one register fewer. */
    const uint32_t too_fast = (uint32_t)(period < timing->period_min);
    BLDC_PORT_SEQUENCE();
    TIM_TypeDef *const tim1 = PORT_AT(anchor, TIM1, TIM_TypeDef);
    /* Invalid Hall code or sequence (its record's partner field is CC4E, always set);
     * over-speed now, or over-voltage or over-speed when the timing was computed; or a
     * leg swap: CCER reads back the pattern in force (every write is followed by its COM
     * event), and a phase whose other switch is on now would hand over from one switch
     * to the other in one COM event, with no dead time in single-output mode (a
     * direction reversal). One test, one branch: from flash every conditional branch
     * fetches its target. */
    const uint32_t refused = too_fast | (tim1->CCER & PORT_RECORD_FORBIDDEN(record));
    if (BLDC_PORT_RARE(refused != 0u)) {
        port_refuse();
        return;
    }
    /* During the commutation: turn-off switch at D_off, turn-on switch at D_on. One
     * register, hidden like the anchor, holds CCR1: it reaches CCR1..3 by index and
     * CCER and EGR by an offset, so the compares need no base register of their own
     * (which would be a sixth live value: a push and pop). */
    volatile uint32_t *compare = port_compare(tim1, 0u);
    __asm__("" : "+r"(compare));
    compare[PORT_RECORD_ON_CHANNEL(record)] = timing->turn_on_compare;
    BLDC_PORT_SEQUENCE();
    compare[PORT_RECORD_OFF_CHANNEL(record)] = timing->turn_off_compare;
    BLDC_PORT_SEQUENCE();
    *PORT_TIM1_FROM_CCR1(compare, CCER) = PORT_RECORD_CCER_DURING(record);
    *PORT_TIM1_FROM_CCR1(compare, EGR) = BLDC_PORT_EGR_COMMUTATE;
    const uint32_t ticks = timing->commutation_ticks;
    BLDC_PORT_SEQUENCE();

    /* End of the commutation (Eq. 20) at commutation_ticks after this edge: the counter
     * restarted from 0 at the edge (reset mode), so the compare value is the duration
     * itself. Drop any stale match of the previous value, and if the counter is
     * already past it (latency longer than t_com) raise the match by software: EGR
     * bits are write 1 to act, so writing 0 there does nothing, and the test takes no
     * branch (the path is as long either way). CNT and ticks are at most 16 bits, so
     * ticks + ~CNT = ticks - CNT - 1 is negative (bit 31 set) exactly when
     * CNT >= ticks, and >> 29 brings bit 31 to CC2G's bit 2. */
    TIM_TypeDef *const tim3 = PORT_AT(port_peripherals_again(), TIM3, TIM_TypeDef);
    tim3->CCR2 = ticks;
    tim3->SR = ~(TIM_SR_CC2IF | TIM_SR_UIF);
    tim3->EGR = ((ticks + ~tim3->CNT) >> (31u - TIM_EGR_CC2G_Pos)) & TIM_EGR_CC2G;
}

/* TIM3 wrapped (UIF), or passed the Hall time-out (CC3IF), their interrupts on since the
 * last commutation end: no Hall edge in time. While the bridge switches that is the Hall
 * timeout, acted on now; otherwise the interrupts go off and UIF stays set for the next
 * edge, which reads the interval as the whole range. */
BLDC_PORT_COLD static void port_on_wrap(uintptr_t anchor)
{
    if ((port.steady != 0u) && (port.pending == 0u)) {
        port_trip(anchor, BLDC_FAULT_HALL_TIMEOUT);
    } else {
        PORT_AT(anchor, TIM3, TIM_TypeDef)->DIER = BLDC_PORT_HALL_INTERRUPTS;
    }
}

/* Commutation end: outgoing switch off, incoming switch at the main duty. Not inlined
 * into the TIM3 handler, so the Hall edge's path needs fewer registers. */
BLDC_PORT_NOINLINE BLDC_PORT_FAST_CODE BLDC_PORT_FEW_REGISTERS
static void port_on_commutation_end(uintptr_t anchor)
{
    TIM_TypeDef *const tim3 = PORT_AT(anchor, TIM3, TIM_TypeDef);
    const uint32_t record = port.pending;
    tim3->SR = ~TIM_SR_CC2IF;
    if (record == 0u) {
        return; /* a compare match outside a commutation: nothing scheduled */
    }
    TIM_TypeDef *const tim1 = PORT_AT(anchor, TIM1, TIM_TypeDef);
    volatile uint32_t *const compare = port_compare(tim1, PORT_RECORD_ON_CHANNEL(record));
    *compare = port.main_duty;
    tim1->CCER = PORT_RECORD_CCER_AFTER(record); /* a subset of the pattern in force: safe */
    ADC_TypeDef *const adc1 = PORT_AT(anchor, ADC1, ADC_TypeDef);
    /* A trigger within the COM event's gap of the counter's read below
     * (BLDC_PORT_IMMINENT_AGE) may fire before that event, and its sequence sample the
     * commutating bridge, or not fire at all (the event restarts the carrier): either
     * way the count below is wrong for one of them. Counted stale, the one clean sample
     * a commutation filling its sector leaves before the next edge was dropped, sector
     * after sector (a steady braking's ends keep their phase to the carrier; `make pil`,
     * a 5-pole-pair conventional motor at 5180 rpm, its timing on a current three
     * sectors old). So a first read of the counter waits out a trigger within that gap
     * and this read's (BLDC_PORT_WAIT_COUNTS), a few counts, and the trigger fires
     * before the COM event for certain and its age counts it; at most
     * BLDC_PORT_IMMINENT_READS reads (a counter that stopped: `imminent` below still
     * counts it). Out of line: the usual end pays one read and one compare. */
    uint32_t counter = tim1->CNT;
    if (BLDC_PORT_RARE(BLDC_PORT_TRIGGER_WITHIN(counter, BLDC_PORT_AGE_CR1(tim1),
                                                BLDC_PORT_WAIT_COUNTS))) {
        uint32_t reads = BLDC_PORT_IMMINENT_READS;
        do {
            counter = tim1->CNT;
            --reads;
        } while ((reads != 0u) && BLDC_PORT_TRIGGER_WITHIN(counter, BLDC_PORT_AGE_CR1(tim1),
                                                           BLDC_PORT_WAIT_COUNTS));
    }
    counter = tim1->CNT; /* the carrier before the COM event restarts it */
    uint32_t cr1 = BLDC_PORT_AGE_CR1(tim1);
    tim1->EGR = BLDC_PORT_EGR_COMMUTATE; /* just after the counter: see below */
    const uint32_t status = adc1->SR; /* just after the COM event: see below */
    BLDC_PORT_AFTER_LOADS(counter); /* the age's arithmetic after the SR load, not between */
    BLDC_PORT_AFTER_LOADS(cr1);
    const uint32_t age = BLDC_PORT_TRIGGER_AGE(counter, cr1);
    /* What the current loop needs of this record, found once here, not every period. */
    port.steady_compare = compare;
    port.steady_sense = &PORT_AT(anchor, ADC1, ADC_TypeDef)->JDR1 + PORT_RECORD_SENSE_SLOT(record);
    port.steady = record;
    /* An injected sequence that began before now was sampled while both switches
     * commutated, through the sense slot of the sector before: no single signal was I
     * then, and the new slot's shunt may carry nothing (the turn-on switch at D_on up
     * to the whole period: its lower diode off, the zero code). The loop holds I and
     * the duty through each such sequence: one still converting (JSTRT, or a trigger
     * younger than the sequence: the current loop's SR write clears a JSTRT the next
     * trigger set when it runs after that trigger, which the carrier's restart at the
     * Hall edge brings within the previous sequence's conversions), and one ended but
     * not yet taken (JEOC): that is the last trigger's, unless the last trigger is too
     * young to have ended, when it is an older one's and the last still converts (two;
     * counting two whenever JEOC was set dropped the one sample a commutation filling
     * its sector leaves before the next edge). The counter is read before SR on
     * purpose, and SR straight after it: a sequence that ends between the two reads
     * has its JEOC set and an age up to the reads' gap short of its conversions, and
     * BLDC_PORT_SEQUENCE_MIN_COUNTS leaves that gap out, so it counts one (the last
     * trigger's), not two. Reading SR first, a sequence ending between the reads
     * could read as neither converting (its JSTRT cleared) nor ended, and a sample
     * begun before the end be taken as I. With SR read after the end's other work, an
     * end that kept landing at a JEOC (a steady braking's ends keep their phase to the
     * carrier, sector after sector) counted two each time and dropped the one clean
     * sample of two sectors running (`make pil`, conv_cen_ps at top speed, once the
     * timing ran later in the sector).
     * The COM event comes between the two reads, straight after the counter's: a
     * trigger after the counter's read and before the COM event begins a sequence
     * that samples the commutating bridge. Its JSTRT shows in SR, read after the COM
     * event, unless the injection latency still holds the conversion's start; the
     * counter, BLDC_PORT_IMMINENT_AGE counts or less before the trigger, says it too
     * (`imminent`: one more stale sequence). With SR read before the COM event and the
     * age's arithmetic between, such a trigger went unseen and the loop closed on its
     * sample (`make pil`, conv_80k_centre). The COM event restarts the carrier, whose
     * next trigger is half a period or more away: SR shows no later one. */
    const uint32_t imminent = (uint32_t)(age >= BLDC_PORT_IMMINENT_AGE);
    const uint32_t converting = ((status & ADC_SR_JSTRT) != 0u) ||
                                (age < BLDC_PORT_SEQUENCE_COUNTS) || (imminent != 0u);
    const uint32_t unended = (uint32_t)(age < BLDC_PORT_SEQUENCE_MIN_COUNTS) | imminent;
    port.stale = ((status & ADC_SR_JEOC) != 0u) ? 1u + unended : (uint32_t)converting;
    port.pending = 0u;
    /* The Hall time-out of this sector (codegen/control/hall_timeout.py): a rotor that
     * reaches its next edge at all does so within 4 T of the last one, T the interval
     * that edge ended, wherever T <= BLDC_PORT_HALL_TIMEOUT_PERIOD_MAX; slower, it may
     * stop within the sector, and the counter's wrap is the time-out. CC3 matches there.
     * Hall lines frozen at a valid code had tripped only at the wrap, 65 ms after the
     * last edge on the paper motor (30 sectors at 4600 rpm braking with one sector's
     * pattern; a hunt). Written after the COM event (the switch-off lag is the COM
     * event's), and its flag cleared after it: a match of an older, smaller value (a
     * sector after a refused edge) may have set it, and the counter, near `ticks` now,
     * is below the new one. */
#if BLDC_PORT_HALL_TIMEOUT_PERIOD_MAX == 0u
    tim3->CCR3 = BLDC_PORT_TIM3_ARR;
#else
    BLDC_PORT_SEQUENCE(); /* the interval's load after the COM event, not before it */
    /* After a refused edge (a step back, then forward again) the interval is part of a
     * sector, no bound on the next: all ones, the counter's range (a hunt: the paper
     * motor at 500 rpm, stepping back 2.1 ms into a 20 ms sector and forward again 2.1
     * ms later, timed out 8.4 ms on, 7 ms before its next edge). */
    const uint32_t interval = (uint32_t)port.period | (0u - (uint32_t)port.after_refusal);
    port.after_refusal = 0u;
    tim3->CCR3 = ((interval - 1u) < BLDC_PORT_HALL_TIMEOUT_PERIOD_MAX)
                     ? (interval << BLDC_PORT_HALL_TIMEOUT_SHIFT)
                     : BLDC_PORT_TIM3_ARR;
#endif
    tim3->SR = ~TIM_SR_CC3IF;
    /* The Hall edge cleared UIF: a wrap, or the time-out's match, from now on, with the
     * bridge switching, is the Hall timeout (port_on_wrap). */
    tim3->DIER = BLDC_PORT_HALL_INTERRUPTS | TIM_DIER_UIE | TIM_DIER_CC3IE;
}

/* One vector for all TIM3 events on the STM32F103: a pending commutation end first (it
 * belongs to the previous edge). A Hall edge pending at the same time keeps the TIM3
 * interrupt line asserted, so the NVIC enters again at once (tail-chaining) and takes it
 * then. The overflow (UIF) raises no interrupt; the next edge and the current loop read
 * it. The Hall edge alone is tested with one branch (its path falls through). */
BLDC_PORT_FAST_CODE BLDC_PORT_LINE_ALIGNED void TIM3_IRQHandler(void)
{
    const uintptr_t anchor = port_peripherals();
    const uint32_t status = PORT_AT(anchor, TIM3, TIM_TypeDef)->SR;

    if (!BLDC_PORT_RARE((status & (TIM_SR_CC1IF | TIM_SR_CC2IF)) != TIM_SR_CC1IF)) {
        port_on_hall_edge(anchor, status);
    } else if ((status & TIM_SR_CC2IF) != 0u) {
        port_on_commutation_end(anchor);
    } else if ((status & (TIM_SR_UIF | TIM_SR_CC3IF)) != 0u) {
        port_on_wrap(anchor); /* the wrap, or the Hall time-out's match */
    }
}

#if !BLDC_PORT_SHORT_WHERE_BOTH /* preferring the short, the region needs only the rating */
/* All-off rectifies into the bus where T B is at or below the product
 * (codegen/control/safe_state.py). For whole numbers T >= 0 and B >= 1,
 * T B <= K exactly when T <= floor(K / B): floor(K / B) B <= K, and
 * (floor(K / B) + 1) B > K. So the product test becomes one compare of T with a bound
 * found once per bus code (a UDIV on the bus change, out of line: no divide and no
 * multiply per timing run). B = 0 rectifies at every interval (0 <= K). */
static uint32_t port_rectifying_max(uint32_t bus_code)
{
    return (bus_code == 0u) ? UINT32_MAX : (BLDC_PORT_RECTIFYING_PRODUCT / bus_code);
}
#endif

/* The safe state's speed regions at a bus code. Where the spec prefers all-off: the
 * short circuit where all-off would rectify into the bus (T <= floor(K / B)), all-off
 * elsewhere. Where it prefers the short: the short wherever the bridge is rated for it
 * (T >= BLDC_PORT_SHORT_VALID_PERIOD), all-off where it is not; within the spec's bus
 * range that holds every interval where all-off rectifies (the loader requires the
 * short rated wherever that happens in the speed range), and on a bus reading low
 * (collapsed, or its ADC stuck at 0 with the bus in fact there) the rating still bounds
 * the current, where "rectifying at every interval" had put the short beyond it (a
 * hunt: 79 A on a 60 A bridge at 3000 rpm). The all-off rest is one run of intervals,
 * [from, from + span), kept as its start and length, so the timing run decides with
 * one unsigned compare, T - from < span (mod 2^32: from + span <= 2^32), whatever the
 * policy: two compares joined cost a branch laid out of line, and from flash a taken
 * branch waits for its target. */
typedef struct {
    uint32_t from; /* port.all_off_from */
    uint32_t span; /* port.all_off_span */
} port_region_t;

static inline port_region_t port_region_of(uint32_t bus_code)
{
#if BLDC_PORT_SHORT_WHERE_BOTH && !BLDC_PORT_SHORT_WHILE_UNKNOWN && \
    (BLDC_PORT_SHORT_VALID_PERIOD < BLDC_PORT_TIM3_ARR)
    /* The short preferred, but rated only up to a speed below speed_max: all-off below
     * the rated interval and at a wrapped one (the speed unknown before the first edges,
     * or below the counter's range), where all-off does not rectify at any speed of the
     * range on a bus within the spec's (the loader's condition for such a rating) and
     * the short may exceed its rating. One run round 2^32: from the wrap to the rated
     * interval. */
    (void)bus_code;
    const uint32_t from = BLDC_PORT_TIM3_ARR;
    const uint32_t span = BLDC_PORT_SHORT_VALID_PERIOD - BLDC_PORT_TIM3_ARR; /* mod 2^32 */
#elif BLDC_PORT_SHORT_WHERE_BOTH && !BLDC_PORT_SHORT_WHILE_UNKNOWN
    (void)bus_code; /* rated at no interval below the wrap: all-off at every one */
    const uint32_t from = 0u;
    const uint32_t span = UINT32_MAX;
#elif BLDC_PORT_SHORT_WHERE_BOTH
    (void)bus_code;
    const uint32_t from = 0u;
    const uint32_t span = BLDC_PORT_SHORT_VALID_PERIOD; /* 0: rated at every speed */
#elif BLDC_PORT_SHORT_WHILE_UNKNOWN
    const uint32_t from = port_rectifying_max(bus_code) + 1u; /* 0: rectifies everywhere */
    /* every interval from `from` up (none when from = 0) but the counter's whole range:
     * a wrapped interval is the speed unknown (before the first edges: the start-up
     * value, and the first edge after arming reads TIM3's preset wrap) or below the
     * range; all-off rectifies if the rotor turns fast, the short is rated at every
     * speed of the range */
    const uint32_t span = ((from != 0u) && (from <= BLDC_PORT_TIM3_ARR))
                              ? BLDC_PORT_TIM3_ARR - from
                              : 0u - from;
#else
    /* The short rated only below a speed of the range: it only where all-off rectifies
     * and the short is rated, [BLDC_PORT_SHORT_VALID_PERIOD, rectifying_max]; all-off on
     * the rest, the run from rectifying_max + 1 round to the rated interval (mod 2^32),
     * a wrapped interval included (the speed unknown), or everywhere if none is both.
     * Within the spec's ranges all-off never rectifies then (the loader's condition); on
     * a bus reading low (its ADC stuck at 0 with the bus in fact there) the short had
     * been taken at every speed, beyond its rating (a hunt). */
    const uint32_t rectifying_max = port_rectifying_max(bus_code);
    const int none = BLDC_PORT_SHORT_VALID_PERIOD > rectifying_max;
    const uint32_t from = none ? 0u : rectifying_max + 1u;
    const uint32_t span = none ? UINT32_MAX : BLDC_PORT_SHORT_VALID_PERIOD - from;
#endif
    const port_region_t region = {from, span};
    return region;
}

/* The region at a bus code, set. At the Hall edge's priority (or masked): the bus-change
 * handler, below it, stores the pair masked (port_update_bus). */
static void port_set_safe_region(uint32_t bus_code)
{
    const port_region_t region = port_region_of(bus_code);
    port.all_off_from = region.from;
    port.all_off_span = region.span;
}

/* 1 where the safe state of this Hall interval is the short circuit, else 0. */
static uint32_t port_short_circuit(uint32_t period)
{
    return (uint32_t)((period - port.all_off_from) >= port.all_off_span);
}

/* CR2's idle levels for the region: what MOE = 0 (a fault, the break input) does now. */
static uint32_t port_safe_state_cr2(uint32_t period)
{
    return (port_short_circuit(period) != 0u) ? (BLDC_PORT_TIM1_CR2 | BLDC_PORT_OIS_SHORT)
                                              : BLDC_PORT_TIM1_CR2;
}

/* The bus code the safe state's region is chosen for, while faulted: the reading, or 0
 * for a reading at full scale (the region of a bus that may be anywhere: the short
 * wherever it is rated, since at a bus reading 0 all-off rectifies at every speed). A
 * reading at the rail is a bus ADC stuck high (the divider's lower resistor open: the
 * input clamped at the reference) with the bus anywhere, or a bus far over; chosen from
 * the reading, all-off rectified into a bus that was in fact at its nominal voltage, the
 * rotor above the speed where that begins (a hunt). A reading over the range but below
 * the rail is a bus that is over, measured: its region is its own (all the bus range
 * over, the short had put a braking rotor's short-circuit current over the comparator:
 * OVER_CURRENT as well, where all-off was safe and preferred). */
static inline uint32_t port_region_code(uint32_t code)
{
    return (code >= BLDC_PORT_ADC_CODE_MAX) ? 0u : code;
}

/* While a fault is latched: the bus watchdog's window [LTR, HTR]. A bus fault latched
 * opens its side (an over-voltage, HTR at full scale; an under-voltage, LTR at 0), so a
 * bus that stays outside raises no interrupt at each regular conversion (every few
 * microseconds, at the Hall edge's priority), while the other side still latches its
 * fault. Where the safe state's region at the Hall interval T now depends on the bus
 * (all-off rectifies for T B <= K, i.e. B <= floor(K / T)), the window also keeps the
 * bus on the side of that bound the region in force was chosen for: all-off, LTR above
 * the bound, so a bus falling to it interrupts at that conversion and the short follows
 * within microseconds (it had waited for the next injected sample's bus change, up to
 * 53.5-56.7 us after the cause on a 50 us period; a helper's hunt); the short, HTR
 * BLDC_PORT_FAULTED_BUS_HYSTERESIS_CODES above the bound. A window that does not hold
 * the bus (the region chosen from an older code) interrupts at the next conversion,
 * which chooses the region afresh (port_bus_fault). At the Hall edge's priority or
 * with interrupts masked. */
BLDC_PORT_COLD static void port_watch_while_faulted(uintptr_t anchor, uint32_t interrupt)
{
    const uint32_t faults = port.faults;
    uint32_t low = ((faults & BLDC_FAULT_UNDER_VOLTAGE) != 0u) ? 0u : BLDC_PORT_ADC_LTR;
    uint32_t high = ((faults & BLDC_FAULT_OVER_VOLTAGE) != 0u) ? BLDC_PORT_ADC_CODE_MAX
                                                                 : BLDC_PORT_ADC_HTR;
#if !BLDC_PORT_SHORT_WHERE_BOTH
    const uint32_t period = port.period;
#if BLDC_PORT_SHORT_WHILE_UNKNOWN
    /* a wrapped interval is the short at every bus code */
    const uint32_t follows = (uint32_t)((period - 1u) < (BLDC_PORT_TIM3_ARR - 1u));
#else
    /* the short only where rated: all-off at every bus code below the rated interval */
    const uint32_t follows = (uint32_t)((period != 0u) && (period >= BLDC_PORT_SHORT_VALID_PERIOD));
#endif
    if (follows != 0u) {
        /* a reading at the rail is the bus unknown (port_region_code): outside */
        high = (high >= BLDC_PORT_ADC_CODE_MAX) ? BLDC_PORT_ADC_CODE_MAX - 1u : high;
        const uint32_t bound = BLDC_PORT_RECTIFYING_PRODUCT / period; /* T >= 1: no UDIV by 0 */
        if (port_short_circuit(period) != 0u) {
            high = (bound >= high - BLDC_PORT_FAULTED_BUS_HYSTERESIS_CODES)
                       ? high
                       : bound + BLDC_PORT_FAULTED_BUS_HYSTERESIS_CODES;
        } else if (bound >= BLDC_PORT_ADC_CODE_MAX) {
            /* every code needs the short (all-off was chosen from no reading: the
             * start-up code): an empty window, the next conversion chooses afresh */
            low = BLDC_PORT_ADC_CODE_MAX;
            high = 0u;
        } else {
            low = (bound >= low) ? bound + 1u : low;
        }
    }
#endif
    ADC_TypeDef *const adc = PORT_AT(anchor, ADC1, ADC_TypeDef);
    adc->LTR = low;
    adc->HTR = high;
    /* AWDIE as asked: off after an entry the watchdog raised (port_bus_fault) until
     * the next faulted tick */
    adc->CR1 = (interrupt != 0u) ? BLDC_PORT_ADC_CR1 : (BLDC_PORT_ADC_CR1 & ~ADC_CR1_AWDIE);
}

/* A fault found below the Hall edge's priority (the timing handler, the NMI): a software
 * break (EGR.BG) clears MOE at once, in hardware, and the break interrupt, at the Hall
 * edge's priority, completes the safe state and latches `requested`. */
static void port_request_trip(uint32_t fault)
{
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    port.requested |= fault;
    TIM1->DIER = TIM_DIER_COMIE | TIM_DIER_BIE;
    TIM1->EGR = TIM_EGR_BG;
    __set_PRIMASK(primask);
}

/* The bus voltage changed beyond the hysteresis: its reciprocals, once per change,
 * from the latest injected sample. The request is taken before the sample is read: a
 * sample the current loop finds outside the old band meanwhile requests (and pends the
 * bus-change handler) again, and the rerun takes the newer code. The core flags a bus
 * outside its range: the analog watchdog has tripped already, and this is its
 * backstop. */
static void port_update_bus(void)
{
    port.bus_moved = 0u;
    port.bus_taken = port.heartbeat; /* a word the current loop writes above this: atomic */
    const uint32_t code = (uint16_t)ADC1->JDR4; /* JDATA: bits 15:0 (RM0008 11.12.9) */
    port.bus_code = (uint16_t)code;
    port.bus_low = code - BLDC_PORT_BUS_HYSTERESIS_CODES;
    /* The region's pair stored whole, masked: the bus watchdog's handler, above this
     * one, sets it too. Not while faulted: then the bus watchdog's window keeps the
     * region with the bus (port_watch_while_faulted, its hysteresis included; a
     * sample's code here, with none, had moved the safe state to and fro each period
     * on a bus rippling about the bound). The divide before the mask. */
    const port_region_t region = port_region_of(code);
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    if (port.faults == 0u) {
        port.all_off_from = region.from;
        port.all_off_span = region.span;
    }
    __set_PRIMASK(primask);
    port.bus = bldc_bus_condition(code);
    if (BLDC_PORT_RARE((port.bus.flags & BLDC_FLAG_INPUT_SATURATED) != 0u)) {
        port_request_trip((code > BLDC_BUS_CODE_MAX) ? BLDC_FAULT_OVER_VOLTAGE
                                                     : BLDC_FAULT_UNDER_VOLTAGE);
    }
}

#if !defined(BLDC_PORT_CORE_OUT_OF_LINE)
/* The core compiled into this translation unit as well, its public names prefixed
 * port_core_, so the timing handler has bldc_commutation_timing() inlined (attribute
 * flatten): no call, no second set of saved registers, no result returned through the
 * stack and copied into the slot. The text is bldc_commutation.c itself, the file
 * `make prove` proves; its own object keeps the public names for every other caller,
 * and what this unit does not use the linker drops (-ffunction-sections,
 * --gc-sections). Define BLDC_PORT_CORE_OUT_OF_LINE to call the core instead. */
#define bldc_sector_of_hall port_core_sector_of_hall
#define bldc_edge_of_hall_pair port_core_edge_of_hall_pair
#define bldc_edge_switch port_core_edge_switch
#define bldc_bus_condition port_core_bus_condition
#define bldc_commutation_timing port_core_commutation_timing
#define bldc_commutate port_core_commutate
#include "bldc_commutation.c"
#undef bldc_sector_of_hall
#undef bldc_edge_of_hall_pair
#undef bldc_edge_switch
#undef bldc_bus_condition
#undef bldc_commutation_timing
#undef bldc_commutate
#define PORT_COMMUTATION_TIMING port_core_commutation_timing
#if defined(__GNUC__)
#define PORT_TIMING_FLATTEN __attribute__((flatten))
#endif
#endif
#ifndef PORT_COMMUTATION_TIMING
#define PORT_COMMUTATION_TIMING bldc_commutation_timing
#endif
#ifndef PORT_TIMING_FLATTEN
#define PORT_TIMING_FLATTEN
#endif

/* The next edge's duties and commutation time, at a lower priority than TIM3. Raised
 * by every COM event (DIER.COMIE), which every Hall edge generates, and pended by
 * the bus-change handler once the bus state is new. A Hall edge that
 * arrives meanwhile preempts it, raises it again, and the NVIC runs it once more
 * afterwards; the extra run after a commutation end recomputes with the latest current
 * and main duty. */
PORT_TIMING_FLATTEN void TIM1_TRG_COM_IRQHandler(void)
{
    /* COMIF cleared before the interval is read: a Hall edge after this point raises it
     * again and this handler runs once more; one before it left its interval in
     * `period` already. SR and CR2 next to each other share TIM1's address. */
    TIM_TypeDef *const tim1 = TIM1;
    tim1->SR = ~TIM_SR_COMIF;
    BLDC_PORT_SEQUENCE();
    const uint32_t period = port.period;
    tim1->CR2 = port_safe_state_cr2(period);
    /* The inputs, kept for bldc_port_status(): the flags are not stored, so the
     * compiler drops their arithmetic from this copy of the core (status computes them
     * from the same inputs with the same function). Stored before the core runs, so
     * nothing holds them in a register through it. */
    /* A 12-bit ADC code (the current loop stores JDRx, right-aligned, no offset): the
     * mask says so to the compiler, which then drops the core's clamp to the ADC's full
     * scale (four instructions for one; the core still takes and is proven for every
     * uint32_t). */
    const uint32_t current = port.current & BLDC_PORT_ADC_CODE_MAX;
    port.timed_period = (uint16_t)period;
    port.timed_current = (uint16_t)current;
    const uint32_t duty = port.main_duty; /* not used by the method's duties (a load the compiler drops) */
    /* Fill the slot the Hall edge is not reading, then publish it with one word write:
     * an edge sees the previous timing or this one, never half of either. Only this
     * handler writes `timing` (the Hall edge reads it). */
    const bldc_timing_t timing = PORT_COMMUTATION_TIMING(&port.bus, period, current, duty);
    BLDC_PORT_SEQUENCE(); /* the slot read after the core: one register fewer through it */
    bldc_timing_t *const published = port.timing;
    bldc_timing_t *const next = port_other_slot(published);
    /* Field by field, a half-word store each: a copy of the whole struct, or stores
     * the compiler may merge, packs the half-words into words first (BFI). */
    next->period_min = timing.period_min;
    next->turn_on_compare = timing.turn_on_compare;
    BLDC_PORT_SEQUENCE();
    next->turn_off_compare = timing.turn_off_compare;
    BLDC_PORT_SEQUENCE();
    next->commutation_ticks = timing.commutation_ticks;
    /* Every field stored before the slot is published: without this the compiler may
     * put the publishing store first (GCC did, ahead of commutation_ticks), and a Hall
     * edge between the two applied a torn timing (the PIL's publication check). */
    BLDC_PORT_SEQUENCE();
    port.timing = next;
}

/* 1 if a timing run now may take the held current, else 0. While the Hall interval is
 * unknown (TIM3 wrapped: the first sector after arming) the core takes it for the
 * slowest speed, and with a real current computes a commutation most of a sector long,
 * which the next edge would apply at the rotor's true speed: an over-current (a timing
 * run pended in that sector with a sampled current tripped BKIN at 15 A on the second
 * edge, make pil). The Hall edge's and the commutation end's own runs there read no
 * sample (port_arm clears the held current; the loop samples only after the first
 * end); a bus change (its state too, which bldc_port_status() reads with the published
 * timing's inputs) or a new open-loop duty then waits for the next edge, after which
 * the loop's next sample outside the band pends it again. (improved_r's rule commutates
 * for a carrier period even at zero current: the timing handler drops that while the
 * interval is unknown.) */
static inline uint32_t port_timing_may_run(void)
{
    return (uint32_t)((port.period != BLDC_PORT_TIM3_ARR) || (port.current == 0u));
}

/* The bus voltage moved beyond the hysteresis: its new state, then the timing with it.
 * TIM1's update vector, which TIM1 itself never raises (DIER.UIE stays 0): the current
 * loop pends it. It runs at the timing handler's priority, so neither preempts the
 * other, and has the lower interrupt number, so when both are pending it runs first
 * (PM0056 2.3.6). The timing handler's path so reads no request at all; this handler
 * pends it once the bus state is new. The latest sample decides: a bus back in the
 * band meanwhile changes nothing. */
void TIM1_UP_IRQHandler(void)
{
    if ((port.bus_moved != 0u) && (port_timing_may_run() != 0u)) {
        port_update_bus();
        NVIC_SetPendingIRQ(TIM1_TRG_COM_IRQn);
    }
}

/* Pend the bus-change handler when `moved` is 1, nothing when 0, without a branch: a
 * 0 written to an NVIC set-pending bit has no effect (PM0056 4.3.4). It takes the new
 * code (the latest injected sample) and computes the bus state from it. */
#ifndef BLDC_PORT_PEND_BUS_WHEN
#define BLDC_PORT_PEND_BUS_WHEN(moved)                                         \
    (((volatile uint32_t *)NVIC_ISPR_BASE)[(uint32_t)TIM1_UP_IRQn >> 5u] =  \
         (uint32_t)(moved) << ((uint32_t)TIM1_UP_IRQn & 31u))
#endif
static inline void port_pend_if_bus_moved(uint32_t bus, uint32_t beat)
{
    /* Out of the band, and at least BLDC_PORT_BUS_MIN_PERIODS runs since the last change
     * (mod 2^32: after 2^32 runs without one, a change may wait that long once). */
    const uint32_t moved =
        (uint32_t)((bus - port.bus_low) > 2u * BLDC_PORT_BUS_HYSTERESIS_CODES) &
        (uint32_t)((beat - port.bus_taken) >= BLDC_PORT_BUS_MIN_PERIODS);
    port.bus_moved = moved; /* the latest sample decides: back in the band, no change */
    BLDC_PORT_PEND_BUS_WHEN(moved);
}

/* The analog watchdog: a conversion of the bus (the regular group's, continuously, or
 * the injected sequence's) left [LTR, HTR]. Over if any reading is above HTR: DR and
 * every JDRx of the bus, since the watchdog flags the first injected bus conversion at
 * its end, before the later ones of the sequence are written, and the regular group,
 * interrupted by the injected sequence (RM0008 11.3.9), may not have converted since
 * the bus stepped. Not faulted: the bus left its range, a fault. Faulted: the window is
 * port_watch_while_faulted()'s; a bus out of range latches its fault (the safe state is
 * in force already), and the safe state's region is chosen again from the bus. Either
 * way the window then follows the fault and the region, so a bus that stays where it
 * is raises no interrupt at each conversion; bldc_port_clear_faults() reads the bus
 * itself. */
BLDC_PORT_COLD static void port_bus_fault(uintptr_t anchor)
{
    ADC_TypeDef *const adc = PORT_AT(anchor, ADC1, ADC_TypeDef);
    /* The bus conversions now: the regular group's latest and the injected sequence's
     * bus slots; the one outside the window is the conversion that tripped. */
    const uint32_t latest = (uint16_t)adc->DR; /* DATA: bits 15:0 */
    uint32_t lowest = latest;
    uint32_t highest = latest;
    {
        const uint32_t code = (uint16_t)adc->JDR4;
        lowest = (code < lowest) ? code : lowest;
        highest = (code > highest) ? code : highest;
    }
    uint32_t over = (uint32_t)(highest > BLDC_PORT_ADC_HTR);
    uint32_t under = (uint32_t)(lowest < BLDC_PORT_ADC_LTR);
    if (port.faults == 0u) {
        /* Neither side seen: the conversion that tripped was overwritten before this
         * entry (held by a handler at its priority), a transient shorter than a
         * conversion; not claimed as either side (it had latched UNDER_VOLTAGE for a
         * 1 us over-voltage spike). */
        port_trip(anchor, (over != 0u)    ? BLDC_FAULT_OVER_VOLTAGE
                          : (under != 0u) ? BLDC_FAULT_UNDER_VOLTAGE
                                          : BLDC_FAULT_BUS_TRANSIENT);
    } else {
        /* Faulted: the window is narrower than the range, and the injected slots may
         * hold the sample before the bus moved (up to a PWM period old): each entry had
         * chosen the region from that sample again and re-armed a window the bus was
         * outside, an entry at every conversion and the wrong region until the next
         * sample (a helper's hunt: all-off, rectifying, 53 us after a bus fall that
         * followed an over-voltage). The regular group's latest alone: if the bus is
         * still outside, the next conversion interrupts again. */
        over = (uint32_t)(latest > BLDC_PORT_ADC_HTR);
        under = (uint32_t)(latest < BLDC_PORT_ADC_LTR);
        lowest = latest;
        highest = latest;
        port.faults |= ((over != 0u) ? BLDC_FAULT_OVER_VOLTAGE : 0u) |
                       ((under != 0u) ? BLDC_FAULT_UNDER_VOLTAGE : 0u);
    }
    /* MOE is clear: the idle levels act at once. Chosen from the conversion out of
     * range, where one is (a low bus makes all-off rectify where it did not: at 98 % of
     * the top speed an under-voltage had left the bridge all-off, rectifying, until the
     * next sample's bus change, 57-64 us after the cause on a 50 us period; a helper's
     * hunt), else from the latest conversion, the bus crossing the rectifying bound;
     * a reading at the rail, the bus unknown (port_region_code). */
    port_set_safe_region(
        port_region_code((over != 0u) ? highest : (under != 0u) ? lowest : latest));
    PORT_AT(anchor, TIM1, TIM_TypeDef)->CR2 = port_safe_state_cr2(port.period);
    /* Its interrupt off until the next faulted tick without a watchdog entry (the
     * next injected sample's, or the run a trip pends) turns it on again: a bus
     * rippling across the window's edges faster than the hysteresis had one entry per
     * crossing, up to one per regular conversion (1.7 us) at the Hall edge's priority
     * (a helper's hunt: 138 entries a ms at +-20 codes and 37 kHz). A crossing
     * meanwhile sets AWD all the same, and the next conversion outside the window
     * interrupts once it is on: within BLDC_PORT_FAULTED_TICK_PERIODS PWM periods. */
    port_watch_while_faulted(anchor, 0u);
}

/* ADC2's analog watchdog: a conversion of a current channel, at any instant, read at a
 * rail. Its interrupt goes off until the fault is cleared (ADC2 converts every few
 * microseconds and would set AWD each time). */
BLDC_PORT_COLD static void port_current_rail(uintptr_t anchor)
{
    ADC_TypeDef *const adc2 = PORT_AT(anchor, ADC2, ADC_TypeDef);
    adc2->CR1 = BLDC_PORT_ADC2_CR1 & ~ADC_CR1_AWDIE;
    adc2->SR = ~ADC_SR_AWD;
    port_trip(anchor, BLDC_FAULT_CURRENT_SENSOR);
}

/* While faulted, every PWM period (and at once after each trip, which pends this): the
 * Hall interval from the capture TIM3 still makes (its interrupts are off) and the safe
 * state of the region the rotor is in now, so a decelerating rotor leaves the short
 * circuit for all-off where that becomes valid; the bus watchdog's window for that
 * interval. */
BLDC_PORT_COLD static void port_faulted_tick(uintptr_t anchor, uint32_t watched)
{
    TIM_TypeDef *const tim3 = PORT_AT(anchor, TIM3, TIM_TypeDef);
    const uint32_t status = tim3->SR;
    const uint32_t held = port.period;
    if ((status & (TIM_SR_CC1IF | TIM_SR_UIF)) != 0u) {
        const uint32_t captured = tim3->CCR1; /* clears CC1IF */
        tim3->SR = ~TIM_SR_UIF;
        if ((status & TIM_SR_UIF) != 0u) {
            port.period = BLDC_PORT_TIM3_ARR;
            port.faulted_measured = (uint16_t)BLDC_PORT_TIM3_ARR;
        } else if (captured < port_bounce_below(held)) {
            /* No rotor makes it (a line's bounce): the interval held stays, and the next
             * capture, which starts at the bounce, is part of a sector too. */
            port.after_refusal = PORT_AFTER_BOUNCE;
        } else if (port.after_refusal == PORT_AFTER_BOUNCE) {
            /* The part of a sector after a bounce: read as a rotor faster than it is, a
             * spec whose short is rated to just above the top speed had got all-off,
             * rectifying, for a sector (a hunt: 13 860 rpm, 6 % fast). */
            port.after_refusal = 0u;
        } else {
            port.faulted_measured = (uint16_t)captured;
            port.period = (uint16_t)captured;
        }
    }
    /* A Hall line's fault: the lines' intervals are not the rotor's. A stuck line makes
     * every other interval two sectors long, and a rotor above the speed from which
     * all-off rectifies read as one below it: all-off while it rectified (a hunt: the
     * paper motor at 1.3 x that speed, all-off 17.6 ms after the trip). So the interval
     * only shortens then: the last right one (the trip's), or a shorter capture (a
     * rotor speeding up; a stuck line's one-sector intervals), never a longer one nor a
     * wrap. Taking the speed as unknown instead put the short on a rotor at 40 000 rpm
     * whose Hall connector came off (fast40k: over the comparator's threshold, a second
     * fault, where all-off was safe and preferred). Nor shorter than the top speed's:
     * a spurious edge mid-sector (a line bouncing as the connector came off) had read
     * the rotor at twice its speed, beyond a rated short's speed on a spec that prefers
     * it, and held all-off, rectifying, for as long as the fault lasted (a hunt: 4700 rpm
     * on 20.5 V, the short rated to 5359 rpm). Within the speed range a rotor taken at
     * the top speed gets a state valid there and below: the short where all-off would
     * rectify at the speed it reads, all-off where not or where the short is rated no
     * further. */
    if ((port.faults & (BLDC_FAULT_HALL_INVALID | BLDC_FAULT_HALL_SEQUENCE)) != 0u) {
        const uint32_t shortest = (held < port.period) ? held : port.period;
        port.period = (uint16_t)((shortest < BLDC_PERIOD_MIN_TICKS) ? BLDC_PERIOD_MIN_TICKS
                                                                     : shortest);
    }
    TIM1->CR2 = port_safe_state_cr2(port.period);
    /* the bound moves with the interval; every period, so a window left behind by a
     * region changed meanwhile (a bus change preempted by the trip) lasts one at most */
    port_watch_while_faulted(anchor, (uint32_t)(watched == 0u));
}

/* 1 if a current sample `code` is at a rail that zero current does not read on (0 and full scale):
 * the sensor is open or saturated, or the current is beyond the sensing range. A rail
 * that zero current reads on (a current-sense offset of 0 V or of the reference) is no
 * evidence of a fault: ADC2's watchdog leaves it out too (BLDC_PORT_CURRENT_LTR/HTR). */
static inline uint32_t port_at_a_rail(uint32_t code)
{
    return (uint32_t)((code - 1u) > (BLDC_PORT_ADC_CODE_MAX - 2u)); /* 0 or full scale */
}

/* 1 if `value` is 0, else 0, in two instructions and no branch: CLZ gives 32 for 0 alone
 * (ARMv7-M A7.7.24, defined for every input, unlike __builtin_clz). */
static inline uint32_t port_is_zero(uint32_t value)
{
#if defined(__arm__)
    uint32_t zeros;
    __asm__("clz %0, %1" : "=r"(zeros) : "r"(value));
    return zeros >> 5;
#else
    return (uint32_t)(value == 0u);
#endif
}

/* The current loop proper, in the steady state: the PI's duty for the steady switch
 * from the next PWM period (CCRx is preloaded). */
static inline void port_run_loop(uint32_t measured, uint32_t reference)
{
    const int32_t state = port.integrator;
    const uint32_t duty = bldc_current_loop_duty(state, reference, measured);
    port.integrator = bldc_current_loop_integrate(state, reference, measured);
    port.current = measured;
    port.main_duty = (uint16_t)duty;
    *port.steady_compare = duty; /* the steady switch's CCRx */
}

/* The interrupt's other paths, out of line: either analog watchdog (ADC1's on the bus,
 * ADC2's on the current), a commutation running (I is not sampled: no single signal is
 * I then) or the sequence begun before its end (`stale`), the bridge idle or faulted, the open loop, and the faults this interrupt
 * finds (the Hall counter wrapped while the bridge switches, a current sample at a
 * rail). An entry for ADC2 alone (no JEOC) comes here too and runs no loop step: ADC2's
 * AWD is then set, or the bridge is faulted. */
BLDC_PORT_COLD static void port_adc_other(uintptr_t anchor, uint32_t status, uint32_t bus,
                                          uint32_t measured)
{
    /* ADC1's watchdog: a bus fault, or while faulted the bus crossing the safe state's
     * bound (its window is port_watch_while_faulted()'s, which opens a latched fault's
     * side: a trip each PWM period would raise a COM event, and so a timing run). ADC2's
     * acts while its interrupt is on, i.e. until it has tripped: the conversions set AWD
     * again at every one outside the window (RM0008 11.3.7, whatever AWDIE). */
    /* Faulted, AWD is acted on whatever AWDIE: its interrupt is off after each of its
     * entries (port_bus_fault) until an entry without it (the next injected sample's,
     * or a trip's pended run) turns it on again, and the conversions set AWD
     * meanwhile (one during the entry pends a second entry, which had turned it on
     * again at once: an entry per crossing, 129 a ms, on a rippling bus). So a bus
     * still crossing the window is judged once a PWM period, at the injected sample. */
    ADC_TypeDef *const adc1 = PORT_AT(anchor, ADC1, ADC_TypeDef);
    const uint32_t flagged = (uint32_t)((status & ADC_SR_AWD) != 0u);
    const uint32_t interrupted = flagged & (uint32_t)((adc1->CR1 & ADC_CR1_AWDIE) != 0u);
#if BLDC_PORT_FAULTED_TICK_PERIODS > 1u
    /* Faulted at a high PWM frequency: the faulted drive's periodic work at one sample in
     * BLDC_PORT_FAULTED_TICK_PERIODS (a trip runs it at once: port_trip); the bus
     * watchdog's interrupt at once, and its path to a trip tests nothing more. ADC2's
     * watchdog flagged meanwhile keeps the line asserted: the entries that follow at
     * once count the wait down, and the one that runs the work trips it, a few
     * microseconds on. */
    if ((interrupted == 0u) && (port.faults != 0u)) {
        if (port.faulted_wait != 0u) {
            --port.faulted_wait;
            return;
        }
        port.faulted_wait = BLDC_PORT_FAULTED_TICK_PERIODS - 1u;
    }
#endif
    const uint32_t watched = interrupted | (flagged & (uint32_t)(port.faults != 0u));
    if (watched != 0u) {
        port_bus_fault(anchor); /* tripped: the faulted tick below runs */
    }
    ADC_TypeDef *const adc2 = PORT_AT(anchor, ADC2, ADC_TypeDef);
    if (((adc2->SR & ADC_SR_AWD) != 0u) && ((adc2->CR1 & ADC_CR1_AWDIE) != 0u)) {
        port_current_rail(anchor); /* tripped: the faulted tick below runs */
    }
#if BLDC_PORT_FAULTED_TICK_PERIODS > 1u
    /* Faulted, no bus change: nothing computes with the bus state until a clear, and
     * port_arm opens the gate for the first sample after it. Pended at a faulted tick,
     * one came ticks after the trip and ran the timing handler while the fault's cause
     * held (`make pil`, 80 kHz, bus stuck at full scale); pended at every sample, an
     * HSE failure's CLOCK fault went unpublished at 80 kHz (the CPU on the HSI). */
    if (port.faults == 0u) {
        port_pend_if_bus_moved(bus, port.heartbeat);
    }
#else
    port_pend_if_bus_moved(bus, port.heartbeat);
#endif
    const uint32_t steady = port.steady;
    if ((steady != 0u) && (port.pending == 0u)) {
        if ((PORT_AT(anchor, TIM3, TIM_TypeDef)->SR & (TIM_SR_UIF | TIM_SR_CC3IF)) != 0u) {
            /* The Hall counter wrapped, or passed the Hall time-out, while the bridge
             * switches: no edge in time. */
            port_trip(anchor, BLDC_FAULT_HALL_TIMEOUT);
        } else if (port_at_a_rail(measured) != 0u) {
            port_trip(anchor, BLDC_FAULT_CURRENT_SENSOR); /* at a watched rail */
        } else if (port.stale != 0u) {
            --port.stale; /* begun before the commutation end: not I; hold I and the duty */
        } else if (port.reference <= BLDC_PORT_ADC_CODE_MAX) {
            port_run_loop(measured, port.reference);
        } else {
            port.current = measured; /* open loop: I for the timing, the duty stays */
        }
    } else if (port.faults != 0u) {
        port_faulted_tick(anchor, watched);
    } else if ((port.pending == 0u) &&
               ((PORT_AT(anchor, TIM1, TIM_TypeDef)->BDTR & TIM_BDTR_MOE) != 0u)) {
        /* armed, no sector's switch on (a refused edge, or armed before the first edge):
         * the idle state follows the bus and the interval */
        port_idle_state(PORT_AT(anchor, TIM1, TIM_TypeDef), port.period);
    }
}

/* End of the injected conversions (JEOC), once per PWM period, and the analog watchdog
 * (AWD). In the steady state between commutations, closed loop and nothing amiss, the
 * braking current's sample goes straight to the PI; every condition that leads
 * elsewhere is tested at once, with one branch (from flash each conditional branch
 * fetches its target). */
BLDC_PORT_LINE_ALIGNED void ADC1_2_IRQHandler(void)
{
    const uintptr_t anchor = port_peripherals();
    ADC_TypeDef *const adc = PORT_AT(anchor, ADC1, ADC_TypeDef);
    const uint32_t status = adc->SR;
    adc->SR = ~(ADC_SR_JEOC | ADC_SR_JSTRT | ADC_SR_AWD); /* rc_w0: the others stay */
    const uint32_t beat = port.heartbeat + 1u;
    port.heartbeat = beat;
    const uint32_t bus = adc->JDR4;
    const uint32_t steady = port.steady;
    const uint32_t measured = *port.steady_sense; /* the JDRx of I in this sector */
    const uint32_t reference = port.reference;
    /* Either analog watchdog (AWD is bit 0 of both SRs), the bridge not in the steady
     * state, a sequence begun before the commutation end, the Hall counter wrapped, the open loop (a reference above every ADC code:
     * bits above the code's) (a sample at a rail is ADC2's watchdog's, which sees the
     * rails zero current does not read on (0 and full scale) at every conversion,
     * this sample's instant included), and a Hall code 0 or 7 is the EXTI's
     * (EXTI0_IRQHandler). */
    const uint32_t watchdogs = (status | PORT_AT(anchor, ADC2, ADC_TypeDef)->SR) & ADC_SR_AWD;
    const uint32_t other = watchdogs | port_is_zero(steady) | port.pending | port.stale |
                           (PORT_AT(anchor, TIM3, TIM_TypeDef)->SR & (TIM_SR_UIF | TIM_SR_CC3IF)) |
                           (reference >> BLDC_PORT_ADC_BITS);
    if (BLDC_PORT_RARE(other != 0u)) {
        port_adc_other(anchor, status, bus, measured);
        return;
    }
    port_pend_if_bus_moved(bus, beat);
    port_run_loop(measured, reference);
}

/* A break: the input went active (over-current), or software asked for one
 * (port_request_trip()). TIM1 has already cleared MOE in hardware, so every enabled
 * output is at its idle level; this completes the safe state for all three phases and
 * latches the fault. A break no request explains is the input's, an over-current, even
 * if the input reads inactive by now: a pulse shorter than this entry had stopped the
 * drive with nothing latched, so no clear re-armed it (a helper's hunt: 200 ns mid-
 * sector, up to 1.5 us at a Hall edge). BIF cannot be cleared while the input stays
 * active (RM0008 TIMx_SR), so once OVER_CURRENT is latched the break interrupt stays off
 * until the clear; while it is not (a software request: the bus backstop, the NMI) it
 * stays on, so an over-current during another fault is latched too (it had been lost,
 * and the clear re-armed into it). */
void TIM1_BRK_IRQHandler(void)
{
    const uintptr_t anchor = port_peripherals();
    TIM_TypeDef *const tim1 = PORT_AT(anchor, TIM1, TIM_TypeDef);
    tim1->DIER = TIM_DIER_COMIE;
    tim1->SR = ~TIM_SR_BIF;
    const uint32_t level = (GPIOB->IDR >> 12) & 1u;
    const uint32_t requested = port.requested;
    port.requested = 0u;
    const uint32_t input = ((requested == 0u) || (level == BLDC_PORT_BREAK_ACTIVE_HIGH))
                               ? BLDC_FAULT_OVER_CURRENT
                               : 0u;
    port_trip(anchor, requested | input);
    if ((port.faults & BLDC_FAULT_OVER_CURRENT) == 0u) {
        tim1->DIER = TIM_DIER_COMIE | TIM_DIER_BIE; /* a BIF set since: at once, again */
    }
}

/* The Hall lines read alike at the EXTI's entry: confirm, then trip. Two reads
 * BLDC_PORT_HALL_CONFIRM_CYCLES processor cycles apart (1 us at least) must both
 * read 000 or 111: a spike shorter than that on the lines trips nothing, while a real
 * code 0 or 7 (a connector unplugged) holds. A change during the wait pends the EXTI
 * again, which reads afresh. At the Hall edge's priority: the trip writes TIM1 at once. */
BLDC_PORT_COLD static void port_hall_lines_alike(uintptr_t anchor)
{
    const uint32_t start = BLDC_PORT_CYCLES();
    while ((uint32_t)(BLDC_PORT_CYCLES() - start) < BLDC_PORT_HALL_CONFIRM_CYCLES) {
        /* unsigned difference: the counter's wrap is harmless */
    }
    const uint32_t pins = ((PORT_AT(anchor, GPIOA, GPIO_TypeDef)->IDR >> 6) & 3u) | ((PORT_AT(anchor, GPIOB, GPIO_TypeDef)->IDR >> 0 & 1u) << 2);
    if (((pins - 1u) > 5u) && ((port.faults & BLDC_FAULT_HALL_INVALID) == 0u)) {
        port_trip(anchor, BLDC_FAULT_HALL_INVALID);
    }
}

/* A Hall line changed (EXTI, both edges): every Hall edge comes here too, once, at the
 * TIM3 handler's priority and ahead of it (the EXTI sees the pin before TIM3's input
 * filter does); the code 0 or 7 is the rare path. Only the port's lines'
 * pending bits are cleared (rc_w1), before the read: a change after it pends again. */
static void port_on_hall_lines(void)
{
    const uintptr_t anchor = port_peripherals();
    PORT_AT(anchor, EXTI, EXTI_TypeDef)->PR = BLDC_PORT_HALL_LINES;
    const uint32_t pins = ((PORT_AT(anchor, GPIOA, GPIO_TypeDef)->IDR >> 6) & 3u) | ((PORT_AT(anchor, GPIOB, GPIO_TypeDef)->IDR >> 0 & 1u) << 2);
    if (BLDC_PORT_RARE((pins - 1u) > 5u)) {
        port_hall_lines_alike(anchor);
    }
}

void EXTI0_IRQHandler(void)
{
    port_on_hall_lines();
}

void EXTI9_5_IRQHandler(void)
{
    port_on_hall_lines();
}

/* ------------------------------------------------------------------ the API */

void bldc_set_braking_current(uint32_t milliamps)
{
    const uint32_t code = bldc_current_reference(milliamps);
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    if (port.reference > BLDC_PORT_ADC_CODE_MAX) {
        /* From open loop: the integrator takes the duty in force (no bump). */
        port.integrator = (int32_t)((uint32_t)port.main_duty << BLDC_LOOP_FRAC_BITS);
    }
    port.reference = code;
    __set_PRIMASK(primask);
}

void bldc_port_set_main_duty(uint16_t duty_counts)
{
    const uint16_t duty = (duty_counts > BLDC_PORT_DUTY_FULL_SCALE)
                              ? (uint16_t)BLDC_PORT_DUTY_FULL_SCALE
                              : duty_counts;
    /* A Hall edge between the test and the write would leave this writing the compare
     * register of a phase that is now commutating: mask interrupts for these lines. */
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    const uint32_t changed = (duty != port.main_duty) || (port.reference != BLDC_PORT_OPEN_LOOP);
    port.reference = BLDC_PORT_OPEN_LOOP;
    port.main_duty = duty;
    if ((port.pending == 0u) && (port.steady != 0u)) {
        /* CCRx is preloaded: the new duty starts with the next PWM period. */
        *port_compare(TIM1, PORT_RECORD_ON_CHANNEL(port.steady)) = duty;
    }
    __set_PRIMASK(primask);
    (void)changed; /* the method's commutation duties do not use the main duty */
}

uint32_t bldc_port_faults(void)
{
    return port.faults;
}

uint32_t bldc_port_safe_state(void)
{
    return ((TIM1->CR2 & BLDC_PORT_OIS_SHORT) != 0u) ? BLDC_SAFE_SHORT_CIRCUIT : BLDC_SAFE_ALL_OFF;
}

/* The flags of the published timing: the core once more on the inputs the timing
 * handler took (which it recorded) and the bus state it took (which only it writes),
 * copied with interrupts masked, so no timing run can fall between the reads. The
 * timing handler stores no flags: nothing on its path needs them. */
uint32_t bldc_port_status(void)
{
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    const bldc_bus_t bus = port.bus;
    const uint32_t period = port.timed_period;
    const uint32_t current = port.timed_current;
    const uint32_t duty = 0u; /* the method's duties do not use the main duty */
    __set_PRIMASK(primask);
    return PORT_COMMUTATION_TIMING(&bus, period, current, duty).flags;
}

uint32_t bldc_port_current_code(void)
{
    return port.current;
}

uint32_t bldc_port_alive_pending(void)
{
    return (uint32_t)(port.heartbeat != port.heartbeat_seen);
}

uint32_t bldc_port_alive(void)
{
    const uint32_t beat = port.heartbeat;
    const uint32_t alive = beat != port.heartbeat_seen;
    port.heartbeat_seen = beat;
    return alive;
}

/* The Hall code read now from the pins (0..7, any bit order: only 000 and 111 matter). */
static uint32_t port_read_pins(void)
{
    return ((GPIOA->IDR >> 6) & 3u) | ((GPIOB->IDR >> 0 & 1u) << 2);
}

/* The faults a clear keeps latched: the permanent ones latched, and every fault whose
 * cause is present now, latched or not (only the latched ones' had been looked at: an
 * over-current, a current rail or an over-speed that came while another fault was
 * latched was cleared with it, and the clear re-armed into its cause; a helper's
 * hunt). Over-speed (the clear had re-armed a rotor over speed to all-off,
 * rectifying, until its second edge): the interval the faulted tick keeps from TIM3's
 * captures, or the part sector a refused edge measured where the safe state keeps the
 * last right interval (port_refuse), against the core's top-speed bound. */
static uint32_t port_present_causes(uint32_t latched)
{
    uint32_t present = latched & BLDC_PORT_FAULTS_PERMANENT;
    if ((((GPIOB->IDR >> 12) & 1u) == BLDC_PORT_BREAK_ACTIVE_HIGH)) {
        present |= BLDC_FAULT_OVER_CURRENT;
    }
    /* (not while a Hall line's fault is latched: its intervals are not the rotor's, and
     * the faulted tick keeps the shortest, a bounce's included, for the safe state) */
    if (((latched & (BLDC_FAULT_HALL_INVALID | BLDC_FAULT_HALL_SEQUENCE)) == 0u) &&
        ((port.period < BLDC_PERIOD_MIN_TICKS) ||
         (((latched & BLDC_FAULT_OVER_SPEED) != 0u) &&
          (port.faulted_measured < BLDC_PERIOD_MIN_TICKS)))) {
        present |= BLDC_FAULT_OVER_SPEED;
    }
    /* the bus: the last injected sample and the regular group's latest */
    const uint32_t bus = ADC1->JDR4;
    const uint32_t now = ADC1->DR;
    if ((bus > BLDC_PORT_ADC_HTR) || (now > BLDC_PORT_ADC_HTR)) {
        present |= BLDC_FAULT_OVER_VOLTAGE;
    }
    if ((bus < BLDC_PORT_ADC_LTR) || (now < BLDC_PORT_ADC_LTR)) {
        present |= BLDC_FAULT_UNDER_VOLTAGE;
    }
    const uint32_t currents[3] = {ADC1->JDR1, ADC1->JDR2, ADC1->JDR3};
    for (uint32_t k = 0u; k < 3u; ++k) {
        if (port_at_a_rail(currents[k]) != 0u) {
            present |= BLDC_FAULT_CURRENT_SENSOR;
        }
    }
    /* ADC2's latest conversion (the sequence's last current channel), at a watched rail */
    const uint32_t watched = ADC2->DR & ADC_DR_DATA_Msk;
    if ((watched < BLDC_PORT_CURRENT_LTR) || (watched > BLDC_PORT_CURRENT_HTR)) {
        present |= BLDC_FAULT_CURRENT_SENSOR;
    }
    const uint32_t pins = port_read_pins();
    if ((pins == 0u) || (pins == 7u)) {
        present |= BLDC_FAULT_HALL_INVALID;
    }
    return present;
}

/* Arm the bridge: every output off, then MOE; TIM3 measures afresh (the first interval
 * is unknown) and the current loop starts from zero. Interrupts masked by the caller. */
/* The detectors of the causes `kept` does not hold latched watch again: the break
 * interrupt and ADC2's current watchdog, each of which turns itself off once it has
 * latched its fault (a cause that stays would raise it at every chance). Interrupts
 * masked by the caller: the clear, arming or partly. */
static void port_rewatch(uint32_t kept)
{
    if ((kept & BLDC_FAULT_OVER_CURRENT) == 0u) {
        /* BIF is not cleared here: the clear dropped the latched break's flag before it
         * read the pin, so a flag set now is a break since then, for the interrupt
         * enabled here to latch (port_clear_masked) */
        TIM1->DIER = TIM_DIER_COMIE | TIM_DIER_BIE;
    }
    if ((kept & BLDC_FAULT_CURRENT_SENSOR) == 0u) {
        ADC2->SR = ~ADC_SR_AWD;
        ADC2->CR1 = BLDC_PORT_ADC2_CR1;
    }
}

static void port_arm(void)
{
    if (port_idle_short(port.period) != 0u) {
        /* Where all-off rectifies (a clear at a speed measured before): the short loaded
         * with MOE = 0, so that MOE comes up into it. MOE = 0 holds every enabled output
         * at its idle level meanwhile (OSSI = 1): the fault's short stays as it was, or
         * all-off stays until MOE, with every upper switch off since the trip, far longer
         * than the dead time. Arming all-off first, then the short through the dead time,
         * had every switch off with MOE set for 2.7 us, rectifying (a hunt: the 400 V
         * motor's clear). */
        TIM1->CCR1 = BLDC_PORT_DUTY_FULL_SCALE;
        TIM1->CCR2 = BLDC_PORT_DUTY_FULL_SCALE;
        TIM1->CCR3 = BLDC_PORT_DUTY_FULL_SCALE;
        TIM1->CCER = BLDC_PORT_CCER_SHORT;
        TIM1->EGR = BLDC_PORT_EGR_COMMUTATE; /* the compares (UG) and the pattern (COMG) */
    } else {
        TIM1->CCER = BLDC_PORT_CCER_OFF;
        TIM1->EGR = TIM_EGR_COMG; /* all off before MOE */
    }
    port_rewatch(0u);
    ADC1->HTR = BLDC_PORT_ADC_HTR; /* the bus's range again (the faulted window's) */
    ADC1->LTR = BLDC_PORT_ADC_LTR;
    ADC1->SR = ~ADC_SR_AWD;
    ADC1->CR1 = BLDC_PORT_ADC_CR1;
    port.pending = 0u;
    port.steady = 0u;
    port.integrator = 0;
    port.current = 0u; /* no sample until the first commutation end (port_timing_may_run) */
    /* a bus that moved while faulted (its state may be the fault's, saturated: the
     * bridge held off) is taken at the next sample, not a gate later */
    port.bus_taken = port.heartbeat - BLDC_PORT_BUS_MIN_PERIODS;
    port.previous_pins = port_read_pins();
    /* SR first, then the counter at the top: the next tick wraps and sets UIF, so the
     * first interval reads as unknown. In the other order a tick between the two stores
     * (certain with a Hall clock of a few prescaler counts: TIM3 ticks at 72 MHz / (PSC +
     * 1), and writing CNT does not restart the prescaler) set UIF and the SR store erased
     * it: the first edge after a clear read a part sector, below period_min, refused it
     * and latched OVER_SPEED (`make pil`, a hunt's 72 MHz Hall clock: a clear never
     * re-armed the braking). */
    TIM3->SR = 0u;
    TIM3->CNT = BLDC_PORT_TIM3_ARR;
    TIM3->DIER = BLDC_PORT_HALL_INTERRUPTS;
    TIM1->BDTR = BLDC_PORT_TIM1_BDTR | TIM_BDTR_MOE;
    /* read after the store: a break since the clear began (BIF), or a trip requested */
    if (((TIM1->SR & TIM_SR_BIF) != 0u) ||
        (*(const volatile uint32_t *)&port.requested != 0u)) {
        /* A break since the clear began (the input's pulse ended before the pin's read,
         * or came after it), or a trip requested meanwhile: the NMI (the clock failure),
         * which masking does not hold off, before MOE: off again at once, and the break
         * interrupt, pending, latches it (MOE had stayed set for 13-18 us, every switch
         * off, until then; a helper's hunt). A request after this read clears MOE by its
         * own software break. */
        TIM1->BDTR = BLDC_PORT_TIM1_BDTR;
    } else {
        /* armed at a speed measured before (a clear): where all-off rectifies there, the
         * short until the next edge, not all-off (a hunt: 1.66 ms rectifying after a
         * clear on the paper motor at 4400 rpm and 20.1 V); the current loop's samples
         * keep it with the bus (port_adc_other) */
        port_idle_state(TIM1, port.period);
    }
}

/* The clear proper. Its only caller masks interrupts around it, so no handler stacks
 * on its frame (out of line: the stack report counts it apart, with thread mode alone,
 * codegen/build_firmware.py MASKED). */
BLDC_PORT_NOINLINE static uint32_t port_clear_masked(void)
{
    const uint32_t latched = port.faults;
    if (latched == 0u) {
        return 0u; /* nothing to clear: each cause's own path watches the running drive */
    }
    if ((latched & BLDC_FAULT_OVER_CURRENT) != 0u) {
        /* The latched break's flag, dropped before the pin is read (it stays set while
         * the input is active): from here on a pulse sets it again, and arming looks at
         * it. Cleared after the read, in port_rewatch, it had erased a 100 ns pulse that
         * came between, and the bridge re-armed into the over-current (a hunt). */
        TIM1->SR = ~TIM_SR_BIF;
    }
    const uint32_t remaining = port_present_causes(latched);
    port.faults = remaining;
    if (remaining != 0u) {
        /* Partly cleared: the bridge stays in its safe state, and what watches a cause no
         * longer latched watches again (each path turns its interrupt off once it has
         * latched, until this; only arming had turned them on: an over-current or a
         * current rail after a partial clear was lost), the bus window too (an
         * over-voltage's side stayed open). */
        port_rewatch(remaining);
        port_watch_while_faulted(port_peripherals(),
                                 (uint32_t)((ADC1->CR1 & ADC_CR1_AWDIE) != 0u));
    } else {
        /* The region of the bus now (the last injected sample): while faulted only the
         * bus watchdog moved it, and an over-voltage had set the bus unknown's, which
         * outlived the clear (the short at every interval) until the bus moved beyond
         * the hysteresis (a helper's hunt: a later break took the short for 8 us where
         * the spec prefers all-off). */
        port_set_safe_region((uint16_t)ADC1->JDR4);
        port_arm();
    }
    return remaining;
}

uint32_t bldc_port_clear_faults(void)
{
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    const uint32_t remaining = port_clear_masked();
    __set_PRIMASK(primask);
    return remaining;
}

void bldc_port_raise_fault(uint32_t fault)
{
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    port_trip(port_peripherals(), fault);
    __set_PRIMASK(primask);
}

void bldc_port_emergency_off(void)
{
    TIM1->BDTR = BLDC_PORT_TIM1_BDTR; /* MOE = 0 */
}

void bldc_port_clock_failure(void)
{
    /* The clock failure's break has cleared MOE in hardware (RM0008 7.2.7): the enabled
     * outputs are at their idle levels. Every output enabled here, first, so the idle
     * levels hold for all three phases: the CPU now runs on the 8 MHz HSI, and the break
     * interrupt's completion after this handler had come more than a PWM period after
     * the failure at 60 kHz (one lower switch on alone; a helper's hunt). The NMI may
     * have interrupted a Hall edge half way, whose pattern would then follow this: the
     * software break clears MOE again, and the break interrupt, after that edge,
     * completes the safe state and latches CLOCK. */
    TIM_TypeDef *const tim1 = TIM1;
    tim1->BDTR = BLDC_PORT_TIM1_BDTR; /* MOE = 0 */
    tim1->CCER = BLDC_PORT_CCER_SAFE;
    tim1->EGR = TIM_EGR_COMG; /* load it */
    port_request_trip(BLDC_FAULT_CLOCK);
}

/* ------------------------------------------------------------------ start-up */

static void port_init_pwm_timer(void)
{
    TIM1->CR1 = BLDC_PORT_TIM1_CMS << TIM_CR1_CMS_Pos; /* stopped; CMS only while stopped */
    TIM1->CR2 = BLDC_PORT_TIM1_CR2; /* CCxE, CCxNE, OCxM preloaded; COM only from EGR.COMG; TRGO = OC4REF */
    TIM1->PSC = BLDC_PORT_TIM1_PSC;
    TIM1->ARR = BLDC_PORT_TIM1_ARR;
    TIM1->RCR = 0u;
    TIM1->CCR1 = 0u;
    TIM1->CCR2 = 0u;
    TIM1->CCR3 = 0u;
    TIM1->CCR4 = BLDC_PORT_TIM1_CCR4;
    TIM1->CCMR1 = (BLDC_PORT_OC_MODE_PWM1 << TIM_CCMR1_OC1M_Pos) | TIM_CCMR1_OC1PE |
                  (BLDC_PORT_OC_MODE_PWM1 << TIM_CCMR1_OC2M_Pos) | TIM_CCMR1_OC2PE;
    TIM1->CCMR2 = (BLDC_PORT_OC_MODE_PWM1 << TIM_CCMR2_OC3M_Pos) | TIM_CCMR2_OC3PE |
                  (BLDC_PORT_OC4_MODE << TIM_CCMR2_OC4M_Pos) | TIM_CCMR2_OC4PE;
    TIM1->CCER = BLDC_PORT_CCER_OFF; /* every output disabled (CC4E has no pin here) */
    TIM1->BDTR = BLDC_PORT_TIM1_BDTR; /* MOE stays 0 until the bridge is armed */
    TIM1->EGR = BLDC_PORT_EGR_COMMUTATE; /* load PSC, ARR, CCRx, CCER and OCxM */
    TIM1->SR = ~(TIM_SR_COMIF | TIM_SR_BIF);
    TIM1->DIER = TIM_DIER_COMIE | TIM_DIER_BIE; /* each COM event runs the next edge's timing */
    TIM1->CR1 = (BLDC_PORT_TIM1_CMS << TIM_CR1_CMS_Pos) | TIM_CR1_ARPE | TIM_CR1_CEN;
}

static void port_init_hall_timer(void)
{
    TIM3->CR1 = TIM_CR1_URS; /* only an overflow raises UIF, not the reset by a Hall edge */
    TIM3->CR2 = TIM_CR2_TI1S; /* TI1 = CH1 xor CH2 xor CH3 */
    TIM3->PSC = BLDC_PORT_TIM3_PSC;
    TIM3->ARR = BLDC_PORT_TIM3_ARR;
    TIM3->CCMR1 = (BLDC_PORT_CC1S_TRC << TIM_CCMR1_CC1S_Pos) |
                  (BLDC_PORT_TIM3_IC1F << TIM_CCMR1_IC1F_Pos) |
                  (BLDC_PORT_OC_MODE_FROZEN << TIM_CCMR1_OC2M_Pos); /* CC2: compare, no preload */
    TIM3->SMCR = BLDC_PORT_TS_TI1F_ED << TIM_SMCR_TS_Pos; /* TS first, while SMS = 000 */
    TIM3->SMCR |= BLDC_PORT_SMS_RESET << TIM_SMCR_SMS_Pos;
    TIM3->CCER = TIM_CCER_CC1E; /* capture on; CC2 output stays off (its pin is Hall B) */
    TIM3->CCR2 = BLDC_PORT_TIM3_ARR;
    TIM3->CCR3 = BLDC_PORT_TIM3_ARR; /* the Hall time-out, from the first commutation end */
    TIM3->EGR = TIM_EGR_UG; /* load PSC */
    TIM3->SR = 0u;
    /* The first edge has no valid interval (the counter ran since start-up): start at
     * the top so the first tick overflows and sets UIF, which that edge reads. */
    TIM3->CNT = BLDC_PORT_TIM3_ARR;
    TIM3->DIER = BLDC_PORT_HALL_INTERRUPTS; /* the wrap's interrupt from the first commutation end */
    TIM3->CR1 = TIM_CR1_URS | TIM_CR1_CEN;
}

/* The ADC (RM0008 11): power up, calibrate, then the injected sequence triggered by
 * TIM1 TRGO and its end-of-conversion interrupt, and the analog watchdog on the bus.
 * Between the injected sequences the regular group converts the bus channel over and
 * over (continuous mode, one conversion of the channel's sample time + 12.5 cycles; an
 * injected trigger interrupts it and it resumes, RM0008 11.3.9), so the watchdog sees
 * every bus reading within microseconds, not once per PWM period. Returns
 * BLDC_FAULT_ADC if the calibration does not finish. */
/* Power up and calibrate one ADC; BLDC_FAULT_ADC if the calibration does not finish. */
static uint32_t port_calibrate_adc(ADC_TypeDef *adc)
{
    adc->CR2 = ADC_CR2_ADON; /* power up; t_STAB = 1 us before the calibration */
    for (volatile uint32_t wait = 0u; wait < 100u; ++wait) {
    }
    adc->CR2 = ADC_CR2_ADON | ADC_CR2_CAL;
    uint32_t spins = 0u;
    while (((adc->CR2 & ADC_CR2_CAL) != 0u) && (spins < BLDC_PORT_ADC_WAIT_LOOPS)) {
        ++spins;
    }
    return ((adc->CR2 & ADC_CR2_CAL) != 0u) ? BLDC_FAULT_ADC : 0u;
}

/* ADC2 (independent mode: ADC1's CR1.DUALMOD stays 0) converts the current channel(s)
 * continuously in its regular group, software-started once, with its analog watchdog
 * on every channel of the group at the rails (BLDC_PORT_CURRENT_LTR/HTR): a sensor stuck
 * at a rail is seen at the end of the first conversion that shows it, whatever the
 * rotor and the PWM do. It samples at random instants of the PWM period, switching
 * edges included: a switching transient trips only if it drives the amplifier to a
 * rail, a current the loop could not measure either. Its conversions overlap ADC1's
 * samples of the same channel, each ADC's sample capacitor charging from the amplifier
 * output: the spec's sample time must let the amplifier settle both (RM0008 11.9 forbids
 * the overlap in the dual modes, where the two sample at the same instant by design).
 * Returns BLDC_FAULT_ADC if its calibration does not finish. */
static uint32_t port_init_current_watch(void)
{
    const uint32_t fault = port_calibrate_adc(ADC2);
    ADC2->SMPR1 = BLDC_PORT_ADC_SMPR1;
    ADC2->SMPR2 = BLDC_PORT_ADC_SMPR2;
    ADC2->SQR1 = BLDC_PORT_ADC2_SQR1;
    ADC2->SQR3 = BLDC_PORT_ADC2_SQR3;
    ADC2->HTR = BLDC_PORT_CURRENT_HTR;
    ADC2->LTR = BLDC_PORT_CURRENT_LTR;
    ADC2->SR = 0u;
    ADC2->CR1 = BLDC_PORT_ADC2_CR1;
    ADC2->CR2 = ADC_CR2_ADON | ADC_CR2_CONT | ADC_CR2_EXTTRIG |
                (BLDC_PORT_EXTSEL_SWSTART << ADC_CR2_EXTSEL_Pos);
    ADC2->CR2 |= ADC_CR2_SWSTART;
    return fault;
}

static uint32_t port_init_adc(void)
{
    RCC->CFGR = (RCC->CFGR & ~RCC_CFGR_ADCPRE_Msk) | (BLDC_PORT_ADC_PRESCALER << RCC_CFGR_ADCPRE_Pos);
    const uint32_t fault = port_calibrate_adc(ADC1);
    ADC1->SMPR1 = BLDC_PORT_ADC_SMPR1;
    ADC1->SMPR2 = BLDC_PORT_ADC_SMPR2;
    ADC1->JSQR = BLDC_PORT_ADC_JSQR;
    ADC1->SQR1 = 0u; /* L = 0: one regular conversion */
    ADC1->SQR3 = BLDC_PORT_ADC_BUS_CHANNEL << ADC_SQR3_SQ1_Pos;
    ADC1->HTR = BLDC_PORT_ADC_HTR;
    ADC1->LTR = BLDC_PORT_ADC_LTR;
    ADC1->SR = 0u;
    ADC1->CR1 = BLDC_PORT_ADC_CR1;
    ADC1->CR2 = ADC_CR2_ADON | ADC_CR2_CONT | ADC_CR2_EXTTRIG |
                (BLDC_PORT_EXTSEL_SWSTART << ADC_CR2_EXTSEL_Pos) | ADC_CR2_JEXTTRIG |
                (BLDC_PORT_JEXTSEL_TIM1_TRGO << ADC_CR2_JEXTSEL_Pos);
    ADC1->CR2 |= ADC_CR2_SWSTART; /* the regular group runs from now on */
    return fault;
}

/* Inputs with pull-up (ODR = 1 through BSRR); one read-modify-write per CRL/CRH. */
static void port_init_hall_pins(void)
{
    /* PA6 TIM3_CH1: Hall A, code bit 2; PA7 TIM3_CH2: Hall B, code bit 1 */
    GPIOA->BSRR = GPIO_BSRR_BS6 | GPIO_BSRR_BS7;
    GPIOA->CRL = (GPIOA->CRL & ~(GPIO_CRL_MODE6_Msk | GPIO_CRL_CNF6_Msk | GPIO_CRL_MODE7_Msk | GPIO_CRL_CNF7_Msk)) |
                  (BLDC_PORT_GPIO_MODE_INPUT << GPIO_CRL_MODE6_Pos) | (BLDC_PORT_GPIO_CNF_INPUT_PULL << GPIO_CRL_CNF6_Pos) |
                  (BLDC_PORT_GPIO_MODE_INPUT << GPIO_CRL_MODE7_Pos) | (BLDC_PORT_GPIO_CNF_INPUT_PULL << GPIO_CRL_CNF7_Pos);
    /* PB0 TIM3_CH3: Hall C, code bit 0 */
    GPIOB->BSRR = GPIO_BSRR_BS0;
    GPIOB->CRL = (GPIOB->CRL & ~(GPIO_CRL_MODE0_Msk | GPIO_CRL_CNF0_Msk)) |
                  (BLDC_PORT_GPIO_MODE_INPUT << GPIO_CRL_MODE0_Pos) | (BLDC_PORT_GPIO_CNF_INPUT_PULL << GPIO_CRL_CNF0_Pos);
}

/* The Hall lines to the EXTI (RM0008 9.4.3-9.4.6, 10.2): AFIO_EXTICRx picks each
 * line's port, both edges trigger, the interrupt unmasked; pending bits cleared. */
static void port_init_hall_lines(void)
{
    /* PB0 on EXTI0 */
    AFIO->EXTICR[0] = (AFIO->EXTICR[0] & ~(AFIO_EXTICR1_EXTI0_Msk)) | (1u << AFIO_EXTICR1_EXTI0_Pos);
    /* PA6 on EXTI6, PA7 on EXTI7 */
    AFIO->EXTICR[1] = (AFIO->EXTICR[1] & ~(AFIO_EXTICR2_EXTI6_Msk | AFIO_EXTICR2_EXTI7_Msk)) | (0u << AFIO_EXTICR2_EXTI6_Pos) | (0u << AFIO_EXTICR2_EXTI7_Pos);
    EXTI->RTSR |= BLDC_PORT_HALL_LINES;
    EXTI->FTSR |= BLDC_PORT_HALL_LINES;
    EXTI->PR = BLDC_PORT_HALL_LINES;
    EXTI->IMR |= BLDC_PORT_HALL_LINES;
}

/* Alternate-function push-pull outputs, ODR = 0 (low if the GPIO takes over). */
static void port_init_output_pins(void)
{
    /* PA8 TIM1_CH1: T1, phase A upper; PA9 TIM1_CH2: T3, phase B upper; PA10 TIM1_CH3: T5, phase C upper */
    GPIOA->BSRR = GPIO_BSRR_BR8 | GPIO_BSRR_BR9 | GPIO_BSRR_BR10;
    GPIOA->CRH = (GPIOA->CRH & ~(GPIO_CRH_MODE8_Msk | GPIO_CRH_CNF8_Msk | GPIO_CRH_MODE9_Msk | GPIO_CRH_CNF9_Msk | GPIO_CRH_MODE10_Msk | GPIO_CRH_CNF10_Msk)) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE8_Pos) | (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF8_Pos) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE9_Pos) | (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF9_Pos) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE10_Pos) | (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF10_Pos);
    /* PB13 TIM1_CH1N: T2, phase A lower; PB14 TIM1_CH2N: T4, phase B lower; PB15 TIM1_CH3N: T6, phase C lower */
    GPIOB->BSRR = GPIO_BSRR_BR13 | GPIO_BSRR_BR14 | GPIO_BSRR_BR15;
    GPIOB->CRH = (GPIOB->CRH & ~(GPIO_CRH_MODE13_Msk | GPIO_CRH_CNF13_Msk | GPIO_CRH_MODE14_Msk | GPIO_CRH_CNF14_Msk | GPIO_CRH_MODE15_Msk | GPIO_CRH_CNF15_Msk)) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE13_Pos) | (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF13_Pos) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE14_Pos) | (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF14_Pos) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE15_Pos) | (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF15_Pos);
}

/* The break input: input with pull-up (an open-drain comparator output). */
static void port_init_break_pin(void)
{
    GPIOB->BSRR = GPIO_BSRR_BS12;
    GPIOB->CRH = (GPIOB->CRH & ~(GPIO_CRH_MODE12_Msk | GPIO_CRH_CNF12_Msk)) |
                  (BLDC_PORT_GPIO_MODE_INPUT << GPIO_CRH_MODE12_Pos) | (BLDC_PORT_GPIO_CNF_INPUT_PULL << GPIO_CRH_CNF12_Pos);
}

/* Analog inputs (MODE = 00, CNF = 00). */
static void port_init_analog_pins(void)
{
    /* PA0 ADC12_IN0: phase A low-side shunt current; PA2 ADC12_IN2: phase B low-side shunt current; PA3 ADC12_IN3: phase C low-side shunt current; PA4 ADC12_IN4: bus voltage divider */
    GPIOA->CRL &= ~(GPIO_CRL_MODE0_Msk | GPIO_CRL_CNF0_Msk | GPIO_CRL_MODE2_Msk | GPIO_CRL_CNF2_Msk | GPIO_CRL_MODE3_Msk | GPIO_CRL_CNF3_Msk | GPIO_CRL_MODE4_Msk | GPIO_CRL_CNF4_Msk);
}

void bldc_port_init(uint32_t start_faults)
{
    /* Interrupts masked throughout: nothing preempts the set-up (and its stack does not
     * add to the handlers'; codegen/build_firmware.py counts it apart). */
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    RCC->APB2ENR |= RCC_APB2ENR_IOPAEN | RCC_APB2ENR_IOPBEN | RCC_APB2ENR_AFIOEN |
                    RCC_APB2ENR_TIM1EN | RCC_APB2ENR_ADC1EN | RCC_APB2ENR_ADC2EN;
    RCC->APB1ENR |= RCC_APB1ENR_TIM3EN;
    (void)RCC->APB1ENR; /* read back: the clocks run before the first register access */
    /* The cycle counter the Hall lines' confirmation waits on (DEMCR.TRCENA enables the
     * DWT; a debugger may have set both already). */
    CoreDebug->DEMCR |= CoreDebug_DEMCR_TRCENA_Msk;
    DWT->CTRL |= DWT_CTRL_CYCCNTENA_Msk;

    uint32_t faults = start_faults;
    if ((RCC->CSR & RCC_CSR_IWDGRSTF) != 0u) {
        faults |= BLDC_FAULT_WATCHDOG;
    }
    RCC->CSR |= RCC_CSR_RMVF; /* the reset flags are read: clear them for the next reset */

    port.pending = 0u;
    port.steady = 0u;
    port.steady_compare = &TIM1->CCR1; /* any valid register until the first commutation end */
    port.steady_sense = &ADC1->JDR1;
    port.main_duty = 0u;
    port.integrator = 0;
    port.reference = bldc_current_reference(0u);
    port.current = 0u;
    port.faults = 0u;
    port.requested = 0u;
    port.heartbeat = 0u;
    port.heartbeat_seen = 0u;
    /* Until the first bus sample, every edge is treated as over-voltage: the bridge
     * stays off. The bus state of a code no ADC gives is saturated, so the first timing
     * is the safe state (not a fault). The band starts around 0, what JDR4 reads before
     * any conversion: the first sample above it pends the bus-change handler, which
     * computes the bus state from it and pends the timing; a bus that reads 0 keeps the bridge off (and the analog
     * watchdog trips under-voltage). */
    port.bus_code = BLDC_PORT_BUS_UNKNOWN;
    port.bus_low = 0u - BLDC_PORT_BUS_HYSTERESIS_CODES;
    port.bus_moved = 0u;
    port.bus_taken = 0u - BLDC_PORT_BUS_MIN_PERIODS; /* the first sample may change it */
    port_set_safe_region(BLDC_PORT_BUS_UNKNOWN);
    port.bus = bldc_bus_condition(BLDC_PORT_BUS_UNKNOWN);
    port.period = BLDC_PORT_TIM3_ARR;
    port.timed_period = (uint16_t)BLDC_PORT_TIM3_ARR;
    port.timed_current = 0u;
    port_slots[0].timing = (bldc_timing_t){BLDC_PERIOD_NEVER, 0u, 0u, 0u, 0u};
    port.timing = &port_slots[0].timing;

    port_init_hall_pins();
    port_init_break_pin();
    port_init_analog_pins();
    faults |= port_init_adc();
    faults |= port_init_current_watch();
    port_init_pwm_timer();   /* outputs disabled, MOE = 0, before the pins become timer outputs */
    port_init_output_pins();

    /* The first edge's previous code is the sector the rotor is in now. */
    port.previous_pins = port_read_pins();
    port_init_hall_timer();
    port_init_hall_lines();

    /* The Hall edge, the Hall lines, the current loop and the break share a level and preempt the
     * timing computation, never the other way round. */
    NVIC_SetPriority(TIM3_IRQn, BLDC_PORT_HALL_PRIORITY);
    NVIC_SetPriority(ADC1_2_IRQn, BLDC_PORT_HALL_PRIORITY);
    NVIC_SetPriority(TIM1_BRK_IRQn, BLDC_PORT_FAULT_PRIORITY);
    NVIC_SetPriority(TIM1_TRG_COM_IRQn, BLDC_PORT_TIMING_PRIORITY);
    NVIC_SetPriority(TIM1_UP_IRQn, BLDC_PORT_TIMING_PRIORITY);
    NVIC_SetPriority(EXTI0_IRQn, BLDC_PORT_HALL_PRIORITY);
    NVIC_SetPriority(EXTI9_5_IRQn, BLDC_PORT_HALL_PRIORITY);
    NVIC_EnableIRQ(TIM1_TRG_COM_IRQn);
    NVIC_EnableIRQ(TIM1_UP_IRQn);
    NVIC_EnableIRQ(EXTI0_IRQn);
    NVIC_EnableIRQ(EXTI9_5_IRQn);
    NVIC_EnableIRQ(TIM1_BRK_IRQn);
    NVIC_EnableIRQ(ADC1_2_IRQn);
    NVIC_EnableIRQ(TIM3_IRQn);

    if (faults != 0u) {
        port_trip(port_peripherals(), faults);
    } else {
        TIM1->BDTR = BLDC_PORT_TIM1_BDTR | TIM_BDTR_MOE; /* armed: every output off until an edge */
    }
    __set_PRIMASK(primask);
}
