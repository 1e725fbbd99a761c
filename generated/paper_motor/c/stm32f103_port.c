/* Generated from template c/stm32f103_port.c.j2 with spec spec/paper_motor.yaml (sha256 07b8685d3a2684e5f837564446d9717554545097976668f5f4050212bf8dcce5). Do not edit: regenerate with `make`. */
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

#define BLDC_PORT_SWITCH_COUNT 6u /* T1..T6; switch s is on phase s >> 1, upper when s is even */
#define BLDC_PORT_PHASE_COUNT 3u  /* A, B, C on TIM1 channels 1, 2, 3 */

volatile uint16_t bldc_adc_bus_voltage;
volatile uint16_t bldc_adc_phase_current;
volatile uint16_t bldc_main_duty;

/* CCER enable bit of each switch T1..T6 (core contract: CHx upper, CHxN lower). */
static const uint32_t port_switch_ccer[BLDC_PORT_SWITCH_COUNT] = {
    TIM_CCER_CC1E, TIM_CCER_CC1NE, /* T1, T2: phase A */
    TIM_CCER_CC2E, TIM_CCER_CC2NE, /* T3, T4: phase B */
    TIM_CCER_CC3E, TIM_CCER_CC3NE, /* T5, T6: phase C */
};

/* State, touched only by TIM3_IRQHandler and (at the same priority) the functions
 * it shares it with. */
static uint8_t port_previous_hall_code;  /* code of the sector being left */
static uint8_t port_hall_timed_out;      /* TIM3 overflowed since the last edge */
static uint8_t port_commutating;         /* between a Hall edge and its CC2 end */
static uint8_t port_incoming_switch;     /* runs at main duty once the commutation ends */
static uint8_t port_steady_switch;       /* switch at main duty between commutations */
static uint32_t port_ccer;               /* CCER of the pattern in force */

static uint8_t port_read_hall(void)
{
    uint8_t code = 0u;
    if ((GPIOA->IDR & GPIO_IDR_IDR6) != 0u) { /* PA6: Hall A, code bit 2 */
        code |= 0x4u;
    }
    if ((GPIOA->IDR & GPIO_IDR_IDR7) != 0u) { /* PA7: Hall B, code bit 1 */
        code |= 0x2u;
    }
    if ((GPIOB->IDR & GPIO_IDR_IDR0) != 0u) { /* PB0: Hall C, code bit 0 */
        code |= 0x1u;
    }
    return code;
}

static uint16_t port_main_duty(void)
{
    const uint16_t duty = bldc_main_duty;
    return (duty > BLDC_PORT_DUTY_FULL_SCALE) ? (uint16_t)BLDC_PORT_DUTY_FULL_SCALE : duty;
}

/* Would going from `from` to `to` hand a phase from one of its switches to the other?
 * Single-output mode has no dead time, so that must never happen in one COM event. */
static uint8_t port_swaps_a_leg(uint32_t from, uint32_t to)
{
    uint8_t phase;
    for (phase = 0u; phase < BLDC_PORT_PHASE_COUNT; phase++) {
        const uint32_t upper = port_switch_ccer[2u * phase];
        const uint32_t lower = port_switch_ccer[2u * phase + 1u];
        if ((((from & upper) != 0u) && ((to & lower) != 0u)) ||
            (((from & lower) != 0u) && ((to & upper) != 0u))) {
            return 1u;
        }
    }
    return 0u;
}

/* Apply a pattern of at most two modulated switches (BLDC_NO_SWITCH for none) at one
 * COM event; every other output off. Returns 0 and applies all-off instead when the
 * pattern is unsafe: two switches on one phase, or a phase swapping switches. */
static uint8_t port_apply(uint8_t first_switch, uint16_t first_counts,
                          uint8_t second_switch, uint16_t second_counts)
{
    uint16_t ccr[BLDC_PORT_PHASE_COUNT] = {0u, 0u, 0u};
    uint32_t ccer = 0u;
    uint8_t safe = 1u;

    if (first_switch < BLDC_PORT_SWITCH_COUNT) {
        ccer |= port_switch_ccer[first_switch];
        ccr[first_switch >> 1u] = first_counts;
    }
    if (second_switch < BLDC_PORT_SWITCH_COUNT) {
        if ((first_switch < BLDC_PORT_SWITCH_COUNT) &&
            ((first_switch >> 1u) == (second_switch >> 1u))) {
            safe = 0u;
        }
        ccer |= port_switch_ccer[second_switch];
        ccr[second_switch >> 1u] = second_counts;
    }
    if ((safe == 0u) || (port_swaps_a_leg(port_ccer, ccer) != 0u)) {
        safe = 0u;
        ccer = 0u;
        ccr[0] = 0u;
        ccr[1] = 0u;
        ccr[2] = 0u;
    }
    TIM1->CCR1 = ccr[0];
    TIM1->CCR2 = ccr[1];
    TIM1->CCR3 = ccr[2];
    TIM1->CCER = ccer;                    /* preloaded (CCPC = 1) */
    TIM1->EGR = TIM_EGR_COMG | TIM_EGR_UG; /* enables and compares take effect together */
    port_ccer = ccer;
    return safe;
}

static void port_outputs_off(void)
{
    port_commutating = 0u;
    port_steady_switch = BLDC_NO_SWITCH;
    (void)port_apply(BLDC_NO_SWITCH, 0u, BLDC_NO_SWITCH, 0u);
}

static void port_write_phase_ccr(uint8_t phase, uint16_t counts)
{
    if (phase == 0u) {
        TIM1->CCR1 = counts;
    } else if (phase == 1u) {
        TIM1->CCR2 = counts;
    } else {
        TIM1->CCR3 = counts;
    }
}

/* Hall edge: TIM3 reset its counter and captured the 60 degree interval in CCR1. */
static void port_on_hall_edge(void)
{
    bldc_inputs_t in;
    bldc_outputs_t out;
    const uint16_t captured = (uint16_t)TIM3->CCR1; /* reading CCR1 clears CC1IF */

    TIM3->SR = ~(TIM_SR_CC1IF | TIM_SR_CC1OF);
    in.hall_code = port_read_hall();
    in.previous_hall_code = port_previous_hall_code;
    /* After an overflow the capture has wrapped: the interval is at least the full
     * counter range, the slowest speed the core can be told. */
    in.hall_period_ticks = (port_hall_timed_out != 0u) ? (uint16_t)BLDC_PORT_TIM3_ARR : captured;
    in.bus_voltage_adc = bldc_adc_bus_voltage;
    in.phase_current_adc = bldc_adc_phase_current;
    in.main_duty_counts = bldc_main_duty;
    port_hall_timed_out = 0u;
    port_previous_hall_code = in.hall_code;

    bldc_commutate(&in, &out);

    if ((out.flags & BLDC_FLAG_INVALID_HALL) != 0u) {
        port_outputs_off();
        return;
    }
    /* During the commutation: turn-off switch at D_off, turn-on switch at D_on. */
    if (port_apply(out.turn_off_switch, out.turn_off_compare,
                   out.turn_on_switch, out.turn_on_compare) == 0u) {
        port_commutating = 0u;
        port_steady_switch = BLDC_NO_SWITCH;
        return;
    }
    port_incoming_switch = out.turn_on_switch;
    port_steady_switch = BLDC_NO_SWITCH;
    port_commutating = 1u;

    /* End of the commutation (Eq. 20) at commutation_ticks after this edge: the counter
     * restarted from 0 at the edge (reset mode), so the compare value is the duration
     * itself. Write it, drop any stale match of the previous value, and if the counter
     * is already past it (interrupt latency longer than t_com) raise the match by
     * software so the end is never missed until the counter wraps. */
    TIM3->CCR2 = out.commutation_ticks;
    TIM3->SR = ~TIM_SR_CC2IF;
    if (TIM3->CNT >= (uint32_t)out.commutation_ticks) {
        TIM3->EGR = TIM_EGR_CC2G;
    }
}

/* Commutation end: outgoing switch off, incoming switch at the main duty. */
static void port_on_commutation_end(void)
{
    if (port_commutating == 0u) {
        return; /* a compare match outside a commutation: nothing scheduled */
    }
    port_commutating = 0u;
    if (port_apply(port_incoming_switch, port_main_duty(), BLDC_NO_SWITCH, 0u) != 0u) {
        port_steady_switch = port_incoming_switch;
    } else {
        port_steady_switch = BLDC_NO_SWITCH;
    }
}

/* One vector for all TIM3 events on the STM32F103. The update (overflow) is handled
 * first, then a pending commutation end (it belongs to the previous edge), then the
 * new Hall edge. */
void TIM3_IRQHandler(void)
{
    const uint32_t status = TIM3->SR;

    if ((status & TIM_SR_UIF) != 0u) {
        TIM3->SR = ~TIM_SR_UIF;
        port_hall_timed_out = 1u;
    }
    if ((status & TIM_SR_CC2IF) != 0u) {
        TIM3->SR = ~TIM_SR_CC2IF;
        port_on_commutation_end();
    }
    if ((status & TIM_SR_CC1IF) != 0u) {
        port_on_hall_edge();
    }
}

void bldc_port_apply_main_duty(void)
{
    if ((port_commutating == 0u) && (port_steady_switch < BLDC_PORT_SWITCH_COUNT)) {
        /* CCRx is preloaded: the new duty starts with the next PWM period. */
        port_write_phase_ccr((uint8_t)(port_steady_switch >> 1u), port_main_duty());
    }
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
    TIM1->EGR = TIM_EGR_COMG | TIM_EGR_UG; /* load PSC, ARR, CCRx, CCER and OCxM */
    port_ccer = 0u;
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
    TIM3->DIER = TIM_DIER_CC1IE | TIM_DIER_CC2IE | TIM_DIER_UIE;
    TIM3->CR1 = TIM_CR1_URS | TIM_CR1_CEN;
}

static void port_init_hall_pins(void)
{
    GPIOA->BSRR = GPIO_BSRR_BS6; /* pull-up */
    GPIOA->CRL = (GPIOA->CRL & ~(GPIO_CRL_MODE6_Msk | GPIO_CRL_CNF6_Msk)) |
                  (BLDC_PORT_GPIO_MODE_INPUT << GPIO_CRL_MODE6_Pos) |
                  (BLDC_PORT_GPIO_CNF_INPUT_PULL << GPIO_CRL_CNF6_Pos); /* PA6 TIM3_CH1: Hall A, code bit 2 */
    GPIOA->BSRR = GPIO_BSRR_BS7; /* pull-up */
    GPIOA->CRL = (GPIOA->CRL & ~(GPIO_CRL_MODE7_Msk | GPIO_CRL_CNF7_Msk)) |
                  (BLDC_PORT_GPIO_MODE_INPUT << GPIO_CRL_MODE7_Pos) |
                  (BLDC_PORT_GPIO_CNF_INPUT_PULL << GPIO_CRL_CNF7_Pos); /* PA7 TIM3_CH2: Hall B, code bit 1 */
    GPIOB->BSRR = GPIO_BSRR_BS0; /* pull-up */
    GPIOB->CRL = (GPIOB->CRL & ~(GPIO_CRL_MODE0_Msk | GPIO_CRL_CNF0_Msk)) |
                  (BLDC_PORT_GPIO_MODE_INPUT << GPIO_CRL_MODE0_Pos) |
                  (BLDC_PORT_GPIO_CNF_INPUT_PULL << GPIO_CRL_CNF0_Pos); /* PB0 TIM3_CH3: Hall C, code bit 0 */
}

static void port_init_output_pins(void)
{
    GPIOA->BSRR = GPIO_BSRR_BR8; /* ODR = 0: low if the GPIO takes over */
    GPIOA->CRH = (GPIOA->CRH & ~(GPIO_CRH_MODE8_Msk | GPIO_CRH_CNF8_Msk)) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE8_Pos) |
                  (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF8_Pos); /* PA8 TIM1_CH1: T1, phase A upper */
    GPIOA->BSRR = GPIO_BSRR_BR9; /* ODR = 0: low if the GPIO takes over */
    GPIOA->CRH = (GPIOA->CRH & ~(GPIO_CRH_MODE9_Msk | GPIO_CRH_CNF9_Msk)) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE9_Pos) |
                  (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF9_Pos); /* PA9 TIM1_CH2: T3, phase B upper */
    GPIOA->BSRR = GPIO_BSRR_BR10; /* ODR = 0: low if the GPIO takes over */
    GPIOA->CRH = (GPIOA->CRH & ~(GPIO_CRH_MODE10_Msk | GPIO_CRH_CNF10_Msk)) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE10_Pos) |
                  (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF10_Pos); /* PA10 TIM1_CH3: T5, phase C upper */
    GPIOB->BSRR = GPIO_BSRR_BR13; /* ODR = 0: low if the GPIO takes over */
    GPIOB->CRH = (GPIOB->CRH & ~(GPIO_CRH_MODE13_Msk | GPIO_CRH_CNF13_Msk)) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE13_Pos) |
                  (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF13_Pos); /* PB13 TIM1_CH1N: T2, phase A lower */
    GPIOB->BSRR = GPIO_BSRR_BR14; /* ODR = 0: low if the GPIO takes over */
    GPIOB->CRH = (GPIOB->CRH & ~(GPIO_CRH_MODE14_Msk | GPIO_CRH_CNF14_Msk)) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE14_Pos) |
                  (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF14_Pos); /* PB14 TIM1_CH2N: T4, phase B lower */
    GPIOB->BSRR = GPIO_BSRR_BR15; /* ODR = 0: low if the GPIO takes over */
    GPIOB->CRH = (GPIOB->CRH & ~(GPIO_CRH_MODE15_Msk | GPIO_CRH_CNF15_Msk)) |
                  (BLDC_PORT_GPIO_MODE_OUTPUT_50MHZ << GPIO_CRH_MODE15_Pos) |
                  (BLDC_PORT_GPIO_CNF_AF_PUSH_PULL << GPIO_CRH_CNF15_Pos); /* PB15 TIM1_CH3N: T6, phase C lower */
}

void bldc_port_init(void)
{
    RCC->APB2ENR |= RCC_APB2ENR_IOPAEN | RCC_APB2ENR_IOPBEN | RCC_APB2ENR_TIM1EN;
    RCC->APB1ENR |= RCC_APB1ENR_TIM3EN;
    (void)RCC->APB1ENR; /* read back: the clocks run before the first register access */

    port_commutating = 0u;
    port_incoming_switch = BLDC_NO_SWITCH;
    port_steady_switch = BLDC_NO_SWITCH;

    port_init_hall_pins();
    port_init_pwm_timer();   /* outputs disabled before the pins become timer outputs */
    port_init_output_pins();

    /* The first edge has no valid interval (the counter ran since start-up): mark it
     * as timed out. Its previous code is the sector the rotor is in now. */
    port_previous_hall_code = port_read_hall();
    port_hall_timed_out = 1u;
    port_init_hall_timer();

    NVIC_EnableIRQ(TIM3_IRQn);
}
