/* Generated from template c/stm32f103_port.c.j2 with spec spec/paper_motor_improved_r.yaml (sha256 63a0dc42fff05d0f6f8cb3075865de9694b3e07c2854b399c9fb056dc0d7bc10). Do not edit: regenerate with `make`. */
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

#define BLDC_PORT_EGR_COMMUTATE (TIM_EGR_COMG | TIM_EGR_UG) /* enables and compares together */

/* Where the TIM3 handler (Hall edge, commutation end) and its pin table live. At 72 MHz
 * the flash has two wait states (RM0008 3.3.3, FLASH_ACR.LATENCY = 2): every literal or
 * table load from it and every fetch outside its 2 x 64-bit prefetch buffer waits for a
 * 3-cycle read, and the Cortex-M3 fetches the target of each conditional branch at decode
 * whether or not it is taken. From SRAM the code competes with its own data on the
 * System bus instead. `make bench` measures the handler in both places on every run;
 * SRAM is the faster by its model (see emulation/memory.py), so it is the default. The
 * start-up code copies `.RamFunc` with `.data` (STM32Cube linker scripts place
 * `.RamFunc` there too). Define BLDC_PORT_HALL_EDGE_IN_FLASH to 1 to keep it in flash. */
#if defined(__GNUC__) && !(defined(BLDC_PORT_HALL_EDGE_IN_FLASH) && BLDC_PORT_HALL_EDGE_IN_FLASH)
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

/* Branch hints: lay the rare paths out of line, so the Hall edge runs straight through. */
#if defined(__GNUC__)
#define BLDC_PORT_RARE(condition) __builtin_expect((condition) != 0, 0)
#define BLDC_PORT_COLD __attribute__((cold, noinline))
#else
#define BLDC_PORT_RARE(condition) ((condition) != 0)
#define BLDC_PORT_COLD
#endif

volatile uint16_t bldc_adc_phase_current;

/* The packed record of one commutation edge, generated from the switching table
 * (codegen/derivation/switching.py, codegen/port.py): bits 10:0 CCER during the commutation (turn-on and turn-off switch), bits 12:11 and 14:13 the TIM1 channel (0..2 = CCR1..CCR3) of the turn-on and turn-off switch, bits 26:16 the CCER bits of their phase partners; 0 = no valid edge.
 * One 32-bit word, so the Hall edge reads all it needs of an edge with a single load
 * from flash (each costs two wait states at 72 MHz). */
#define PORT_RECORD_CCER_DURING(record) ((record) & 0x7FFu)
#define PORT_RECORD_ON_CHANNEL(record) (((record) >> 11) & 3u)
#define PORT_RECORD_OFF_CHANNEL(record) (((record) >> 13) & 3u)
#define PORT_RECORD_FORBIDDEN(record) ((record) >> 16)
/* The incoming switch alone: the turn-off channel's enables cleared (RM0008 TIMx_CCER
 * has four bits per channel). */
#define PORT_RECORD_CCER_AFTER(record) \
    (PORT_RECORD_CCER_DURING(record) & ~(0xFu << (4u * PORT_RECORD_OFF_CHANNEL(record))))

/* The core's edge of each Hall code pair (bldc_edge_of()) as its packed record, indexed
 * by the pin levels as read, PA6 | PA7 << 1 | PB0 << 2 (previous << 3 | now): the
 * pin decoding, the edge lookup and the register table folded into one table. In SRAM
 * with the handler (256 bytes): from flash the lookup would wait two cycles. */
BLDC_PORT_FAST_DATA static const uint32_t port_edge_of_pins[64] = {
    0x00000000u, /* pins 000 -> 000: Hall 000 -> 000, invalid */
    0x00000000u, /* pins 000 -> 001: Hall 000 -> 100, invalid */
    0x00000000u, /* pins 000 -> 010: Hall 000 -> 010, invalid */
    0x00000000u, /* pins 000 -> 011: Hall 000 -> 110, invalid */
    0x00000000u, /* pins 000 -> 100: Hall 000 -> 001, invalid */
    0x00000000u, /* pins 000 -> 101: Hall 000 -> 101, invalid */
    0x00000000u, /* pins 000 -> 110: Hall 000 -> 011, invalid */
    0x00000000u, /* pins 000 -> 111: Hall 000 -> 111, invalid */
    0x00000000u, /* pins 001 -> 000: Hall 100 -> 000, invalid */
    0x00000000u, /* pins 001 -> 001: Hall 100 -> 100, invalid */
    0x00000000u, /* pins 001 -> 010: Hall 100 -> 010, invalid */
    0x00110844u, /* pins 001 -> 011: Hall 100 -> 110, edge 2, forward into sector 2: T4 on, T2 off */
    0x00000000u, /* pins 001 -> 100: Hall 100 -> 001, invalid */
    0x01104c40u, /* pins 001 -> 101: Hall 100 -> 101, edge 6, reverse into sector 0: T4 on, T6 off */
    0x00000000u, /* pins 001 -> 110: Hall 100 -> 011, invalid */
    0x00000000u, /* pins 001 -> 111: Hall 100 -> 111, invalid */
    0x00000000u, /* pins 010 -> 000: Hall 010 -> 000, invalid */
    0x00000000u, /* pins 010 -> 001: Hall 010 -> 100, invalid */
    0x00000000u, /* pins 010 -> 010: Hall 010 -> 010, invalid */
    0x01011404u, /* pins 010 -> 011: Hall 010 -> 110, edge 8, reverse into sector 2: T6 on, T2 off */
    0x00000000u, /* pins 010 -> 100: Hall 010 -> 001, invalid */
    0x00000000u, /* pins 010 -> 101: Hall 010 -> 101, invalid */
    0x01103440u, /* pins 010 -> 110: Hall 010 -> 011, edge 4, forward into sector 4: T6 on, T4 off */
    0x00000000u, /* pins 010 -> 111: Hall 010 -> 111, invalid */
    0x00000000u, /* pins 011 -> 000: Hall 110 -> 000, invalid */
    0x00442011u, /* pins 011 -> 001: Hall 110 -> 100, edge 7, reverse into sector 1: T1 on, T3 off */
    0x04044101u, /* pins 011 -> 010: Hall 110 -> 010, edge 3, forward into sector 3: T1 on, T5 off */
    0x00000000u, /* pins 011 -> 011: Hall 110 -> 110, invalid */
    0x00000000u, /* pins 011 -> 100: Hall 110 -> 001, invalid */
    0x00000000u, /* pins 011 -> 101: Hall 110 -> 101, invalid */
    0x00000000u, /* pins 011 -> 110: Hall 110 -> 011, invalid */
    0x00000000u, /* pins 011 -> 111: Hall 110 -> 111, invalid */
    0x00000000u, /* pins 100 -> 000: Hall 001 -> 000, invalid */
    0x00000000u, /* pins 100 -> 001: Hall 001 -> 100, invalid */
    0x00000000u, /* pins 100 -> 010: Hall 001 -> 010, invalid */
    0x00000000u, /* pins 100 -> 011: Hall 001 -> 110, invalid */
    0x00000000u, /* pins 100 -> 100: Hall 001 -> 001, invalid */
    0x01014404u, /* pins 100 -> 101: Hall 001 -> 101, edge 0, forward into sector 0: T2 on, T6 off */
    0x00112044u, /* pins 100 -> 110: Hall 001 -> 011, edge 10, reverse into sector 4: T2 on, T4 off */
    0x00000000u, /* pins 100 -> 111: Hall 001 -> 111, invalid */
    0x00000000u, /* pins 101 -> 000: Hall 101 -> 000, invalid */
    0x04403110u, /* pins 101 -> 001: Hall 101 -> 100, edge 1, forward into sector 1: T5 on, T3 off */
    0x00000000u, /* pins 101 -> 010: Hall 101 -> 010, invalid */
    0x00000000u, /* pins 101 -> 011: Hall 101 -> 110, invalid */
    0x04041101u, /* pins 101 -> 100: Hall 101 -> 001, edge 11, reverse into sector 5: T5 on, T1 off */
    0x00000000u, /* pins 101 -> 101: Hall 101 -> 101, invalid */
    0x00000000u, /* pins 101 -> 110: Hall 101 -> 011, invalid */
    0x00000000u, /* pins 101 -> 111: Hall 101 -> 111, invalid */
    0x00000000u, /* pins 110 -> 000: Hall 011 -> 000, invalid */
    0x00000000u, /* pins 110 -> 001: Hall 011 -> 100, invalid */
    0x04404910u, /* pins 110 -> 010: Hall 011 -> 010, edge 9, reverse into sector 3: T3 on, T5 off */
    0x00000000u, /* pins 110 -> 011: Hall 011 -> 110, invalid */
    0x00440811u, /* pins 110 -> 100: Hall 011 -> 001, edge 5, forward into sector 5: T3 on, T1 off */
    0x00000000u, /* pins 110 -> 101: Hall 011 -> 101, invalid */
    0x00000000u, /* pins 110 -> 110: Hall 011 -> 011, invalid */
    0x00000000u, /* pins 110 -> 111: Hall 011 -> 111, invalid */
    0x00000000u, /* pins 111 -> 000: Hall 111 -> 000, invalid */
    0x00000000u, /* pins 111 -> 001: Hall 111 -> 100, invalid */
    0x00000000u, /* pins 111 -> 010: Hall 111 -> 010, invalid */
    0x00000000u, /* pins 111 -> 011: Hall 111 -> 110, invalid */
    0x00000000u, /* pins 111 -> 100: Hall 111 -> 001, invalid */
    0x00000000u, /* pins 111 -> 101: Hall 111 -> 101, invalid */
    0x00000000u, /* pins 111 -> 110: Hall 111 -> 011, invalid */
    0x00000000u, /* pins 111 -> 111: Hall 111 -> 111, invalid */
};

/* State. Written by TIM3_IRQHandler, TIM1_TRG_COM_IRQHandler and the two setters. Every
 * field the handlers share is one aligned word or half-word, so each read and write is
 * atomic; the timing handler never writes the slot the Hall edge may be reading (it
 * fills the other one and then publishes it with one word write), and the duty setter
 * masks interrupts (PRIMASK) for its two lines. */
static struct {
    const bldc_timing_t *timing;    /* what the next Hall edge applies: one of `slots` */
    uint32_t pending;               /* record of the commutation running until its CC2 end, or 0 */
    uint32_t steady;                /* record whose incoming switch runs at main duty, or 0 */
    uint32_t period;                /* last Hall interval in ticks, for the next timing */
    uint32_t previous_pins;         /* Hall pin levels of the sector being left */
    uint16_t main_duty;             /* TIM1 counts, already clamped to the full scale */
    uint16_t bus_code;              /* the bus code of `bus`, or the newer one to compute it for */
    uint32_t bus_changed;           /* set by the bus setter: recompute `bus` before the timing */
    bldc_bus_t bus;                 /* bldc_bus_condition(bus_code), cached */
    bldc_timing_t slots[2];         /* the published timing and the one being computed */
} port;

static uint32_t port_read_pins(void)
{
    return ((GPIOA->IDR >> 6) & 3u) | ((GPIOB->IDR >> 0 & 1u) << 2);
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
#define BLDC_PORT_PERIPHERALS 0x40000000u /* start of the peripheral region holding TIM1, TIM3, GPIOA and GPIOB (RM0008 3.3, bases from the SVD) */
static inline uintptr_t port_peripherals(void)
{
    uintptr_t anchor = BLDC_PORT_PERIPHERALS;
    __asm__("" : "+r"(anchor));
    return anchor;
}
#define PORT_AT(anchor, instance, type) \
    ((type *)((anchor) + ((uintptr_t)(instance) - (uintptr_t)BLDC_PORT_PERIPHERALS)))

/* Every switch off at the next COM event, nothing scheduled. */
BLDC_PORT_COLD BLDC_PORT_FAST_CODE static void port_outputs_off(uintptr_t anchor)
{
    TIM_TypeDef *const tim1 = PORT_AT(anchor, TIM1, TIM_TypeDef);
    tim1->CCER = 0u; /* preloaded (CCPC = 1) */
    tim1->EGR = BLDC_PORT_EGR_COMMUTATE;
    /* No commutation to end; the wrap is read. */
    PORT_AT(anchor, TIM3, TIM_TypeDef)->SR = ~(TIM_SR_CC2IF | TIM_SR_UIF);
    port.pending = 0u;
    port.steady = 0u;
}

/* Hall edge: TIM3 reset its counter and captured the 60 degree interval in CCR1. The
 * duties and the commutation time were computed after the previous edge, from the
 * interval before this one (TIM1_TRG_COM_IRQHandler); this handler only checks, applies
 * and schedules. */
static void port_on_hall_edge(uintptr_t anchor, uint32_t status)
{
    TIM_TypeDef *const tim3 = PORT_AT(anchor, TIM3, TIM_TypeDef);
    const uint32_t pins = ((PORT_AT(anchor, GPIOA, GPIO_TypeDef)->IDR >> 6) & 3u) | ((PORT_AT(anchor, GPIOB, GPIO_TypeDef)->IDR >> 0 & 1u) << 2);
    const uint32_t record = port_edge_of_pins[(port.previous_pins << 3) | pins];
    uint32_t period = tim3->CCR1; /* reading CCR1 clears CC1IF */
    if ((status & TIM_SR_UIF) != 0u) {
        /* The counter wrapped since the last edge: the interval is at least the full
         * counter range, the slowest speed the core can be told. UIF is cleared below,
         * with CC2IF, on every path. */
        period = BLDC_PORT_TIM3_ARR;
    }
    const bldc_timing_t *const timing = port.timing;
    port.previous_pins = pins;
    port.period = period;   /* every path below ends in a COM event, which runs the timing */
    port.pending = record;  /* the safe state below clears it again */
    TIM_TypeDef *const tim1 = PORT_AT(anchor, TIM1, TIM_TypeDef);
    /* Invalid Hall code or sequence; over-speed now, or over-voltage or over-speed when
     * the timing was computed; or a leg swap: CCER reads back the pattern in force
     * (every write is followed by its COM event), and a phase whose other switch is on
     * now would hand over from one switch to the other in one COM event, with no dead
     * time in single-output mode (a direction reversal). */
    if ((record == 0u) || (period < timing->period_min) ||
        ((tim1->CCER & PORT_RECORD_FORBIDDEN(record)) != 0u)) {
        port_outputs_off(anchor);
        return;
    }
    /* During the commutation: turn-off switch at D_off, turn-on switch at D_on. */
    *port_compare(tim1, PORT_RECORD_ON_CHANNEL(record)) = timing->turn_on_compare;
    BLDC_PORT_SEQUENCE();
    *port_compare(tim1, PORT_RECORD_OFF_CHANNEL(record)) = timing->turn_off_compare;
    BLDC_PORT_SEQUENCE();
    tim1->CCER = PORT_RECORD_CCER_DURING(record);
    tim1->EGR = BLDC_PORT_EGR_COMMUTATE;

    /* End of the commutation (Eq. 20) at commutation_ticks after this edge: the counter
     * restarted from 0 at the edge (reset mode), so the compare value is the duration
     * itself. Drop any stale match of the previous value, and if the counter is
     * already past it (latency longer than t_com) raise the match by software. */
    const uint32_t ticks = timing->commutation_ticks;
    tim3->CCR2 = ticks;
    tim3->SR = ~(TIM_SR_CC2IF | TIM_SR_UIF);
    if (tim3->CNT >= ticks) {
        tim3->EGR = TIM_EGR_CC2G;
    }
}

/* Commutation end: outgoing switch off, incoming switch at the main duty. */
static void port_on_commutation_end(uintptr_t anchor)
{
    TIM_TypeDef *const tim3 = PORT_AT(anchor, TIM3, TIM_TypeDef);
    const uint32_t record = port.pending;
    tim3->SR = ~TIM_SR_CC2IF;
    if (record == 0u) {
        return; /* a compare match outside a commutation: nothing scheduled */
    }
    TIM_TypeDef *const tim1 = PORT_AT(anchor, TIM1, TIM_TypeDef);
    *port_compare(tim1, PORT_RECORD_ON_CHANNEL(record)) = port.main_duty;
    tim1->CCER = PORT_RECORD_CCER_AFTER(record); /* a subset of the pattern in force: safe */
    tim1->EGR = BLDC_PORT_EGR_COMMUTATE;
    port.steady = record;
    port.pending = 0u;
}

/* One vector for all TIM3 events on the STM32F103: a pending commutation end first (it
 * belongs to the previous edge). A Hall edge pending at the same time keeps the TIM3
 * interrupt line asserted, so the NVIC enters again at once (tail-chaining) and takes it
 * then. The overflow (UIF) raises no interrupt; the next edge reads it. */
BLDC_PORT_FAST_CODE void TIM3_IRQHandler(void)
{
    const uintptr_t anchor = port_peripherals();
    const uint32_t status = PORT_AT(anchor, TIM3, TIM_TypeDef)->SR;

    if ((status & TIM_SR_CC2IF) != 0u) {
        port_on_commutation_end(anchor);
    } else if (!BLDC_PORT_RARE((status & TIM_SR_CC1IF) == 0u)) {
        port_on_hall_edge(anchor, status);
    }
}

/* The next edge's duties and commutation time, at a lower priority than TIM3. Raised
 * by every COM event (DIER.COMIE), which every Hall edge generates, and pended by
 * software when the bus voltage or, for the methods that use it, the main duty changes.
 * A Hall edge that arrives meanwhile preempts it, raises it again, and the NVIC runs it
 * once more afterwards; the extra run after a commutation end recomputes with the latest
 * current. */
void TIM1_TRG_COM_IRQHandler(void)
{
    TIM1->SR = ~TIM_SR_COMIF;
    if (BLDC_PORT_RARE(port.bus_changed != 0u)) {
        /* The bus voltage changed beyond the hysteresis: its reciprocals, once per
         * change. The flag first: a newer code arriving meanwhile sets it again. */
        port.bus_changed = 0u;
        port.bus = bldc_bus_condition(port.bus_code);
    }
    /* Fill the slot the Hall edge is not reading, then publish it with one word write:
     * an edge sees the previous timing or this one, never half of either. */
    bldc_timing_t *const next = (port.timing == &port.slots[0]) ? &port.slots[1] : &port.slots[0];
    *next = bldc_commutation_timing(&port.bus, port.period, bldc_adc_phase_current, port.main_duty);
    port.timing = next;
}

void bldc_port_set_bus_voltage(uint16_t adc_code)
{
    /* Recompute only for a change beyond the hysteresis, |code - last| > H, written as
     * one unsigned comparison (a negative difference wraps above 2H), and always when
     * the code crosses the over-voltage threshold, so the bridge turns off at once. */
    const uint32_t code = adc_code;
    const uint32_t last = port.bus_code;
    const uint32_t beyond = (code - last + BLDC_PORT_BUS_HYSTERESIS_CODES) >
                            2u * BLDC_PORT_BUS_HYSTERESIS_CODES;
    const uint32_t crossed = (code > BLDC_PORT_BUS_CODE_MAX) != (last > BLDC_PORT_BUS_CODE_MAX);
    if ((beyond | crossed) != 0u) {
        port.bus_code = adc_code;
        port.bus_changed = 1u;
        NVIC_SetPendingIRQ(TIM1_TRG_COM_IRQn);
    }
}

void bldc_port_set_main_duty(uint16_t duty_counts)
{
    const uint16_t duty = (duty_counts > BLDC_PORT_DUTY_FULL_SCALE)
                              ? (uint16_t)BLDC_PORT_DUTY_FULL_SCALE
                              : duty_counts;
    /* A Hall edge between the test and the write would leave this writing the compare
     * register of a phase that is now commutating: mask interrupts for the two lines. */
    if (duty == port.main_duty) {
        return; /* unchanged: nothing to recompute */
    }
    const uint32_t primask = __get_PRIMASK();
    __disable_irq();
    port.main_duty = duty;
    if ((port.pending == 0u) && (port.steady != 0u)) {
        /* CCRx is preloaded: the new duty starts with the next PWM period. */
        *port_compare(TIM1, PORT_RECORD_ON_CHANNEL(port.steady)) = duty;
    }
    __set_PRIMASK(primask);
}

static void port_init_pwm_timer(void)
{
    TIM1->CR1 = BLDC_PORT_TIM1_CMS << TIM_CR1_CMS_Pos; /* stopped; CMS only while stopped */
    TIM1->CR2 = TIM_CR2_CCPC; /* CCxE, CCxNE, OCxM preloaded; COM only from EGR.COMG */
    TIM1->PSC = BLDC_PORT_TIM1_PSC;
    TIM1->ARR = BLDC_PORT_TIM1_ARR;
    TIM1->RCR = 0u;
    TIM1->CCR1 = 0u;
    TIM1->CCR2 = 0u;
    TIM1->CCR3 = 0u;
    TIM1->CCMR1 = (BLDC_PORT_OC_MODE_PWM1 << TIM_CCMR1_OC1M_Pos) | TIM_CCMR1_OC1PE |
                  (BLDC_PORT_OC_MODE_PWM1 << TIM_CCMR1_OC2M_Pos) | TIM_CCMR1_OC2PE;
    TIM1->CCMR2 = (BLDC_PORT_OC_MODE_PWM1 << TIM_CCMR2_OC3M_Pos) | TIM_CCMR2_OC3PE;
    TIM1->CCER = 0u; /* every output disabled: the safe state */
    TIM1->BDTR = (BLDC_PORT_TIM1_DTG << TIM_BDTR_DTG_Pos) | TIM_BDTR_OSSR | TIM_BDTR_OSSI;
    TIM1->EGR = BLDC_PORT_EGR_COMMUTATE; /* load PSC, ARR, CCRx, CCER and OCxM */
    TIM1->SR = ~TIM_SR_COMIF;
    TIM1->DIER = TIM_DIER_COMIE; /* each COM event runs the next edge's timing */
    TIM1->BDTR |= TIM_BDTR_MOE;
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
    TIM3->EGR = TIM_EGR_UG; /* load PSC */
    TIM3->SR = 0u;
    /* The first edge has no valid interval (the counter ran since start-up): start at
     * the top so the first tick overflows and sets UIF, which that edge reads. */
    TIM3->CNT = BLDC_PORT_TIM3_ARR;
    TIM3->DIER = TIM_DIER_CC1IE | TIM_DIER_CC2IE; /* UIF is polled by the Hall edge */
    TIM3->CR1 = TIM_CR1_URS | TIM_CR1_CEN;
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

void bldc_port_init(void)
{
    RCC->APB2ENR |= RCC_APB2ENR_IOPAEN | RCC_APB2ENR_IOPBEN | RCC_APB2ENR_TIM1EN;
    RCC->APB1ENR |= RCC_APB1ENR_TIM3EN;
    (void)RCC->APB1ENR; /* read back: the clocks run before the first register access */

    port.pending = 0u;
    port.steady = 0u;
    port.main_duty = 0u;
    /* Until the application reports a bus voltage, every edge is treated as
     * over-voltage: the bridge stays off. The first timing is the safe state, and the
     * first timing run computes the bus state of this code (over-voltage). */
    port.bus_code = UINT16_MAX;
    port.bus_changed = 1u;
    port.period = BLDC_PORT_TIM3_ARR;
    port.slots[0] = (bldc_timing_t){BLDC_PERIOD_NEVER, 0u, 0u, 0u, 0u};
    port.timing = &port.slots[0];

    port_init_hall_pins();
    port_init_pwm_timer();   /* outputs disabled before the pins become timer outputs */
    port_init_output_pins();

    /* The first edge's previous code is the sector the rotor is in now. */
    port.previous_pins = port_read_pins();
    port_init_hall_timer();

    /* The Hall edge preempts the timing computation, never the other way round. */
    NVIC_SetPriority(TIM3_IRQn, BLDC_PORT_HALL_PRIORITY);
    NVIC_SetPriority(TIM1_TRG_COM_IRQn, BLDC_PORT_TIMING_PRIORITY);
    NVIC_EnableIRQ(TIM1_TRG_COM_IRQn);
    NVIC_EnableIRQ(TIM3_IRQn);
}
