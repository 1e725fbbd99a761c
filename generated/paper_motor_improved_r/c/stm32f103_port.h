/* Generated from template templates/c/stm32f103_port.h.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`. */
#ifndef STM32F103_PORT_H
#define STM32F103_PORT_H

/*
 * STM32F103 port of the braking drive: the commutation core (bldc_commutation.h), the
 * braking-current PI (bldc_current_loop.h), the PWM-synchronised ADC and the
 * protection. No floating point, no library division helpers, no dynamic memory.
 *
 * Compute ahead. The Hall edge has no time for divides, so it applies duties and a
 * commutation time computed before it: right after each Hall edge, at a lower
 * priority, the timing handler runs bldc_commutation_timing() on the interval just
 * measured, the held braking current and the main duty, for the next edge. The speed
 * the next commutation is computed for is therefore one 60 degree interval old; at a
 * constant speed (the paper's assumption through a commutation) it is the same, and
 * while braking decelerates the drive the relative error is the relative speed change
 * over one sector.
 *
 * Resources (default pin mapping, no AFIO remap)
 *   TIM1  20 kHz edge-aligned PWM, complementary outputs, commutation by COM event
 *         PA8  TIM1_CH1  T1, phase A upper
 *         PA9  TIM1_CH2  T3, phase B upper
 *         PA10  TIM1_CH3  T5, phase C upper
 *         PB13  TIM1_CH1N  T2, phase A lower
 *         PB14  TIM1_CH2N  T4, phase B lower
 *         PB15  TIM1_CH3N  T6, phase C lower
 *         PB12 TIM1_BKIN  over-current comparator (input, pull-up)
 *         CH4 (no pin) triggers the ADC: TRGO = OC4REF
 *   TIM3  Hall-sensor interface: CH1..CH3 XOR (CR2.TI1S), 1 MHz ticks,
 *         counter reset and CC1 capture at each Hall edge (the 60 degree interval),
 *         CC2 compare for the end of the commutation (paper Eq. 20)
 *         PA6  TIM3_CH1  Hall A, code bit 2 (input, pull-up)
 *         PA7  TIM3_CH2  Hall B, code bit 1 (input, pull-up)
 *         PB0  TIM3_CH3  Hall C, code bit 0 (input, pull-up)
 *   ADC1  injected sequence of four conversions per PWM period, triggered by TIM1;
 *         between them the regular group converts the bus channel continuously,
 *         and the analog watchdog watches the bus in both
 *   ADC2  converts the current channel(s) continuously (every 1.67 us), its
 *         analog watchdog on the rails: a current sensor stuck at a rail within
 *         microseconds, not at the next sample
 *   EXTI  both edges of the Hall lines (PA6 EXTI6, PA7 EXTI7, PB0 EXTI0, AFIO_EXTICRx)
 *         PA0 ADC12_IN0: DC-link shunt current (analog input)
 *         PA1 ADC12_IN1: bus voltage divider (analog input)
 *
 * Current sensing (DC-link shunt). Which signal is the braking current I of
 * Eqs. 15-20 once each commutation has ended (codegen/control/sensing.py), sampled in
 * the OFF time of the modulated switch; during a commutation no single signal is I,
 * so the last steady sample is held and the current loop waits:
 *   edge  0 (forward into sector 0): T2 modulated, phase B returns: DC-link shunt, OFF time -> JDR1
 *   edge  1 (forward into sector 1): T5 modulated, phase A returns: DC-link shunt, OFF time -> JDR1
 *   edge  2 (forward into sector 2): T4 modulated, phase C returns: DC-link shunt, OFF time -> JDR1
 *   edge  3 (forward into sector 3): T1 modulated, phase B returns: DC-link shunt, OFF time -> JDR1
 *   edge  4 (forward into sector 4): T6 modulated, phase A returns: DC-link shunt, OFF time -> JDR1
 *   edge  5 (forward into sector 5): T3 modulated, phase C returns: DC-link shunt, OFF time -> JDR1
 *   edge  6 (reverse into sector 0): T4 modulated, phase A returns: DC-link shunt, OFF time -> JDR1
 *   edge  7 (reverse into sector 1): T1 modulated, phase C returns: DC-link shunt, OFF time -> JDR1
 *   edge  8 (reverse into sector 2): T6 modulated, phase B returns: DC-link shunt, OFF time -> JDR1
 *   edge  9 (reverse into sector 3): T3 modulated, phase A returns: DC-link shunt, OFF time -> JDR1
 *   edge 10 (reverse into sector 4): T2 modulated, phase C returns: DC-link shunt, OFF time -> JDR1
 *   edge 11 (reverse into sector 5): T5 modulated, phase B returns: DC-link shunt, OFF time -> JDR1
 * The sample point (7.5-cycle samples at 12 MHz, dead time 36 + settling 72 counts) holds for every steady duty up to
 * D_max = 3428 of 3600 counts (95.2 %), the PI's upper limit; checked at both ends:
 *   D = 0: sample 0 in [3554.0, 3599.0] counts, 3554.0 after the turn-off edge (>= 36 dead + 72 settling), 1.0 before the turn-on edge
 *   D = 3428: sample 0 in [3554.0, 3599.0] counts, 126.0 after the turn-off edge (>= 36 dead + 72 settling), 1.0 before the turn-on edge
 *
 * Interrupts (NVIC priority, 0 the most urgent):
 *   TIM1_BRK_IRQHandler (BLDC_PORT_FAULT_PRIORITY): the break input cleared MOE in
 *         hardware; this completes the safe state and latches OVER_CURRENT.
 *   TIM3_IRQHandler (BLDC_PORT_HALL_PRIORITY): Hall edge (CC1), commutation end (CC2),
 *         the counter's wrap while the bridge switches (UIF: the Hall timeout).
 *         Runs from flash with its pin table (define BLDC_PORT_HALL_EDGE_IN_SRAM to 1
 *         to run it from SRAM: faster, but over the RAM budget).
 *   ADC1_2_IRQHandler (BLDC_PORT_HALL_PRIORITY): end of the injected conversions
 *         (JEOC), once per PWM period: the braking-current PI, the bus voltage for the
 *         timing, the current sensor's plausibility and the Hall timeout; ADC1's analog
 *         watchdog (AWD): over- and under-voltage; ADC2's analog watchdog: a current
 *         conversion at a rail (0 and full scale watched), at any instant. The same priority as the Hall edge,
 *         so neither writes TIM1 while the other is half way through.
 *   EXTI0_IRQHandler, EXTI9_5_IRQHandler (BLDC_PORT_HALL_PRIORITY): both edges of
 *         every Hall line (PA6 EXTI6, PA7 EXTI7, PB0 EXTI0). The lines reading 000 or 111 twice,
 *         1 us apart (a shorter spike trips nothing), is HALL_INVALID at
 *         once, whether or not TIM3 saw an edge: two lines changing within TIM3's input
 *         filter (an unplugged connector pulling two lines up) make no TIM3 edge. At the
 *         Hall edge's level, not below it: a level of its own would stack one more
 *         exception frame (the RAM budget has no room for it), and the trip then writes
 *         TIM1 itself. Each Hall edge runs it once, just before the TIM3 handler, which
 *         it delays by its short common path.
 *   TIM1_TRG_COM_IRQHandler (BLDC_PORT_TIMING_PRIORITY): the next edge's duties and
 *         commutation time, after every COM event and when the bus voltage moved; it
 *         also sets the safe state of the present speed region (TIM1 CR2.OISxN).
 *   TIM1_UP_IRQHandler (BLDC_PORT_TIMING_PRIORITY): TIM1's update vector, which TIM1
 *         never raises (UIE stays 0); the current loop pends it when the bus voltage
 *         moved beyond the hysteresis: the bus state, once per change, then the
 *         timing. The same priority as the timing handler and a lower number: it runs
 *         first when both are pending, never in the middle of a timing run.
 *
 * Faults. Each acts at once, latches its bit and holds the bridge in the safe state
 * until bldc_port_clear_faults() finds its cause gone:
 *   BLDC_FAULT_OVER_CURRENT (0x0001u): the external comparator saw a phase current above protection.over_current; by TIM1 BKIN (the hardware clears MOE), then TIM1_BRK; clears: the break input is inactive
 *   BLDC_FAULT_OVER_VOLTAGE (0x0002u): bus above inverter.bus_voltage_max; by ADC analog watchdog on the bus channel (regular conversions, continuously, every 20 ADC cycles or so, and the injected ones); clears: the last bus sample is within the range
 *   BLDC_FAULT_UNDER_VOLTAGE (0x0004u): bus below inverter.bus_voltage_min, or its ADC reading stuck low (the core would compute with the minimum); by ADC analog watchdog on the bus channel (as OVER_VOLTAGE); clears: the last bus sample is within the range
 *   BLDC_FAULT_CURRENT_SENSOR (0x0008u): a current sample at an ADC rail (0 or full scale): the sensor is open or saturated; by ADC2's analog watchdog on the current channel(s), converted continuously (every conversion, at any instant), and the current-loop interrupt's sample; clears: every current channel's last sample is off the rails
 *   BLDC_FAULT_HALL_INVALID (0x0010u): Hall code 000 or 111 (a sensor unplugged or shorted); by the Hall edge, and the EXTI on both edges of every Hall line (the code 0 or 7 for 1 us: two lines changing within TIM3's input filter make no Hall edge); clears: the Hall code now is valid
 *   BLDC_FAULT_HALL_SEQUENCE (0x0020u): a Hall code pair that is not one sector forward or back (a skipped or repeated code); by the Hall edge; clears: always (the next edge checks again)
 *   BLDC_FAULT_HALL_TIMEOUT (0x0040u): no Hall edge in time: the rotor stopped, a sensor is unplugged, or the Hall lines froze at a valid code; by TIM3's CC3 at 4 T after the last edge (T the interval it ended, where a turning rotor reaches its next edge by then: codegen/control/hall_timeout.py), else its update interrupt at the counter's wrap, while the bridge switches (and the current-loop interrupt, which reads both too); clears: always (the next edge checks again)
 *   BLDC_FAULT_OVER_SPEED (0x0080u): a Hall interval shorter than at controller.speed_max; by the Hall edge; clears: always (the next edge checks again)
 *   BLDC_FAULT_CLOCK (0x0100u): the HSE did not start or failed: the timers do not run at their design clock; by start-up (HSE or PLL timeout) and the clock security system (NMI); clears: never: only a reset
 *   BLDC_FAULT_WATCHDOG (0x0200u): the last reset was the independent watchdog's; by start-up (RCC_CSR.IWDGRSTF); clears: always (it reports the past reset)
 *   BLDC_FAULT_ADC (0x0400u): the ADC's calibration did not finish; by start-up; clears: never: only a reset
 *   BLDC_FAULT_EXTERNAL (0x0800u): raised by the application; by bldc_port_raise_fault(); clears: always
 *   BLDC_FAULT_BUS_TRANSIENT (0x1000u): the bus left its window for less than a conversion and was back before the watchdog's interrupt could read the conversion that tripped it (its entry held by the Hall edge's handler, at the same priority): a spike or a dip, its side not seen, so neither OVER_VOLTAGE nor UNDER_VOLTAGE is claimed; by ADC analog watchdog on the bus channel (as OVER_VOLTAGE), where no bus conversion its interrupt can read is outside the window any more; clears: the last bus sample is within the range
 *
 * The safe state (codegen/control/safe_state.py): MOE = 0 with every output of every
 * phase enabled, so TIM1 holds each at its idle level CR2.OISx / OISxN after a dead
 * time; the upper switches off, the lower ones on (the active short circuit) where
 * all-off would rectify into the bus, off otherwise:
 *   bus_voltage_min 20 V: from 3659 rpm (the speed the last Hall interval says) short circuit (all-off may rectify); below 3659 rpm both are valid: all off
 *   bus_voltage_nominal 24 V: from 4391 rpm (the speed the last Hall interval says) short circuit (all-off may rectify); below 4391 rpm both are valid: all off
 *   bus_voltage_max 30 V: from 5489 rpm (the speed the last Hall interval says) short circuit (all-off may rectify); below 5091 rpm both are valid: all off; 5091..5489 rpm all-off (the short may exceed the rating)
 * The region is decided on the last Hall interval T and bus code B (a bus reading low,
 * or stuck at 0, gives the short, safe at any speed) and written to CR2 after every
 * commutation and, while faulted, every PWM period; the break input finds it in place.
 *
 * The port never drives both switches of one phase in normal operation: each phase
 * has at most one of CCxE / CCxNE set, and a request that would move a phase from its
 * upper to its lower switch (or back) in one COM event (a direction reversal, a Hall
 * code stepping back) is refused, no fault latched and MOE kept: the bridge takes the
 * safe state of the region at the interval just measured (every output off, or each
 * lower switch alone on where all-off would rectify into the bus), entered and left
 * through all-off and TIM1's dead time counted in processor cycles (no dead time is
 * inserted between the two in single-output mode, RM0008 Table 83); the next valid
 * edge commutates from there.
 *
 * Clocks assumed: TIM1 at 72 MHz (APB2 timer clock), TIM3 at
 * 72 MHz (APB1 timer clock, which RM0008 7.2 doubles when APB1 is
 * prescaled), the ADC at PCLK2 / 6 = 12 MHz (the port sets RCC_CFGR.ADCPRE). Set up the
 * RCC clock tree before calling bldc_port_init().
 */

#include <stdint.h>

#include "bldc_commutation.h"
#include "bldc_current_loop.h"

#define BLDC_PORT_TIM1_PSC 0u /* TIM1 counts at the full 72 MHz timer clock */
#define BLDC_PORT_TIM1_ARR 3599u /* 20 kHz edge-aligned at 72 MHz */
#define BLDC_PORT_TIM1_CMS 0u /* CR1.CMS: edge-aligned */
#define BLDC_PORT_DUTY_FULL_SCALE 3600u /* CCRx for 100 % duty = ARR + 1: PWM mode 1 upcounting is active while CNT < CCRx */
#define BLDC_PORT_TIM1_DTG 0x24u /* dead time 500 ns requested, 36 t_DTS = 500 ns programmed (t_DTS = 1 / 72 MHz) */
#define BLDC_PORT_TIM3_PSC 71u /* Hall timer ticks at 1 MHz from 72 MHz */
#define BLDC_PORT_TIM3_ARR 65535u /* 16-bit Hall counter: overflows 65.54 ms after the last edge, and a longer interval reads as this value */
#define BLDC_PORT_HALL_TIMEOUT_SHIFT 2u /* Hall time-out: TIM3 CC3 at T << 2 after the edge ending an interval T (codegen/control/hall_timeout.py): a rotor braking at up to 5000 rad/s^2 (the bridge's rating through the worst k_e, on the rotor's inertia) that reaches its next edge does so by then */
#define BLDC_PORT_HALL_TIMEOUT_PERIOD_MAX 7971u /* T in [1, this]: the time-out is T << BLDC_PORT_HALL_TIMEOUT_SHIFT (a mean speed from 1255 rpm up); above, the counter's wrap (a rotor that slow may stop within the sector) */
#define BLDC_PORT_BUS_CODE_MAX 3385u /* the core's over-voltage threshold, 30 V: the analog watchdog's HTR trips over-voltage above it, whatever the hysteresis */
#define BLDC_PORT_TIM3_IC1F 3u /* Hall input filter: 8 equal samples at 72 MHz, ignores glitches shorter than 111.1 ns and delays each edge as much */
#define BLDC_PORT_TIM1_CCR4 3536u /* the current sample: OC4REF (PWM mode 2) rises at CNT = 3536, 63 counts before the samples end, 1 before the next period */
#define BLDC_PORT_SEQUENCE_COUNTS 504u /* TIM1 counts from an injected trigger to JEOC, one ADC cycle (and for the centre-aligned trigger one count after the peak, two counts) over */
#define BLDC_PORT_SEQUENCE_MIN_COUNTS 464u /* TIM1 counts from an injected trigger to JEOC at the least (the trigger age's terms, no injection latency: the datasheet gives only its largest), less the commutation end's gap between its CNT and SR reads: a younger sequence has not ended, so a JEOC set then is an older one's */
#define BLDC_PORT_IMMINENT_AGE 3588u /* a trigger age from which the next trigger comes within the commutation end's gap between its CNT read and its COM event (END_COM_GAP_CYCLES): that sequence samples the commutating bridge */
#define BLDC_PORT_IMMINENT_READS 12u /* the commutation end's reads of the counter, at the most, while it waits out a trigger within BLDC_PORT_WAIT_COUNTS (it then fires before the COM event, for certain) */
#define BLDC_PORT_WAIT_COUNTS 42u /* counts before the next trigger from which the commutation end's first counter read waits it out: the COM event's gap after the second read and the reads' gap (END_COM_GAP_CYCLES + END_WAIT_GAP_CYCLES) */
#define BLDC_PORT_TRIGGER_WITHIN(cnt, cr1, n) ((uint32_t)((cnt) - (3536u - (n))) < (n)) /* the next injected trigger within n counts of CNT (n up to BLDC_PORT_WAIT_COUNTS): BLDC_PORT_TRIGGER_AGE(cnt, cr1) at least its cycle less n, in one compare */
#define BLDC_PORT_AGE_CR1(tim1) 0u /* what BLDC_PORT_TRIGGER_AGE takes of CR1: its DIR bit (centre-aligned), else no read */
#define BLDC_PORT_TRIGGER_AGE(cnt, cr1) (((cnt) >= BLDC_PORT_TIM1_CCR4) ? (cnt) - BLDC_PORT_TIM1_CCR4 : (cnt) + BLDC_PORT_TIM1_ARR + 1u - BLDC_PORT_TIM1_CCR4) /* TIM1 counts since the last injected trigger, from CNT and CR1 read before a COM event restarts the carrier: CNT = CCR4 */
#define BLDC_PORT_OC4_MODE 7u /* OC4M: PWM mode 2 (rising at CNT = CCR4) */
#define BLDC_PORT_ADC_JSQR ((3u << ADC_JSQR_JL_Pos) | (0u << ADC_JSQR_JSQ1_Pos) | (1u << ADC_JSQR_JSQ2_Pos) | (1u << ADC_JSQR_JSQ3_Pos) | (1u << ADC_JSQR_JSQ4_Pos)) /* JL = 3: JSQ1..JSQ4 land in JDR1..JDR4; JSQ1 IN0, JSQ2 IN1, JSQ3 IN1, JSQ4 IN1 */
#define BLDC_PORT_ADC_SMPR1 (0u) /* 7.5 ADC cycles on channels 10..17 in use */
#define BLDC_PORT_ADC_SMPR2 ((1u << ADC_SMPR2_SMP0_Pos) | (1u << ADC_SMPR2_SMP1_Pos)) /* 7.5 ADC cycles on the channels in use (SMPx = 1) */
#define BLDC_PORT_ADC_BUS_CHANNEL 1u /* analog watchdog channel: the bus divider */
#define BLDC_PORT_ADC_HTR 3385u /* over-voltage: above 30 V (the core's BLDC_BUS_CODE_MAX) */
#define BLDC_PORT_ADC_LTR 2257u /* under-voltage or a stuck bus ADC: below 20 V (the core's BLDC_BUS_CODE_MIN) */
#define BLDC_PORT_ADC_CODE_MAX 4095u /* ADC full scale: a current sample at 0 or here is a rail */
#define BLDC_PORT_ADC_BITS 12u /* ADC resolution: a value with a bit at or above this is no ADC code */
#define BLDC_PORT_CURRENT_LTR 1u /* ADC2's analog watchdog: a current conversion below it is at the low rail */
#define BLDC_PORT_CURRENT_HTR 4094u /* ADC2's analog watchdog: a current conversion above it is at the high rail */
#define BLDC_PORT_ADC2_SQR1 (0u << ADC_SQR1_L_Pos) /* ADC2's regular sequence: 1 conversion(s), continuously */
#define BLDC_PORT_ADC2_SQR3 ((0u << ADC_SQR3_SQ1_Pos)) /* ADC2's regular sequence: the current channel(s) IN0, each converted every 1.67 us */
#define BLDC_PORT_ADC_PRESCALER 2u /* RCC_CFGR.ADCPRE: PCLK2 / 6 = 12 MHz (<= 14 MHz) */
#define BLDC_PORT_ADC_WAIT_LOOPS 1000u /* bound of the start-up waits (ADC power-up, calibration) */
#define BLDC_PORT_BREAK_ACTIVE_HIGH 0u /* TIM1 BKIN (B12) is active low (BDTR.BKP = 0); the comparator trips at 15 A */
#define BLDC_PORT_RECTIFYING_PRODUCT 6166864u /* T B at or below it: lambda k_e n c >= U_d (lambda = 2, k_e at its upper tolerance, c = 1/(1 - hall.sector_shortening): the rotor up to c faster than T says), all-off may rectify: the safe state is the short circuit */
#define BLDC_PORT_SHORT_VALID_PERIOD 1965u /* Hall interval at or above it: the short circuit is within protection.short_circuit_current_max = 120 A (up to 5359 rpm for the worst motor the spec declares, the rotor up to c faster than T says) */
#define BLDC_PORT_SHORT_WHILE_UNKNOWN 1u /* a wrapped Hall interval (the speed unknown before the first edges, or below the counter's range): the short circuit, within the rating up to controller.speed_max */
#define BLDC_PORT_SHORT_WHERE_BOTH 0u /* protection.safe_state = all_off: the safe state where both are valid */
#define BLDC_PORT_OPEN_LOOP 0xffffffffu /* current reference in open loop (bldc_port_set_main_duty) */
#define BLDC_PORT_FAULTS_PERMANENT 0x0500u /* faults only a reset clears */

/* Fault codes: bits of bldc_port_faults(). */
#define BLDC_FAULT_OVER_CURRENT 0x0001u /* the external comparator saw a phase current above protection.over_current */
#define BLDC_FAULT_OVER_VOLTAGE 0x0002u /* bus above inverter.bus_voltage_max */
#define BLDC_FAULT_UNDER_VOLTAGE 0x0004u /* bus below inverter.bus_voltage_min, or its ADC reading stuck low (the core would compute with the minimum) */
#define BLDC_FAULT_CURRENT_SENSOR 0x0008u /* a current sample at an ADC rail (0 or full scale): the sensor is open or saturated */
#define BLDC_FAULT_HALL_INVALID 0x0010u /* Hall code 000 or 111 (a sensor unplugged or shorted) */
#define BLDC_FAULT_HALL_SEQUENCE 0x0020u /* a Hall code pair that is not one sector forward or back (a skipped or repeated code) */
#define BLDC_FAULT_HALL_TIMEOUT 0x0040u /* no Hall edge in time: the rotor stopped, a sensor is unplugged, or the Hall lines froze at a valid code */
#define BLDC_FAULT_OVER_SPEED 0x0080u /* a Hall interval shorter than at controller.speed_max */
#define BLDC_FAULT_CLOCK 0x0100u /* the HSE did not start or failed: the timers do not run at their design clock */
#define BLDC_FAULT_WATCHDOG 0x0200u /* the last reset was the independent watchdog's */
#define BLDC_FAULT_ADC 0x0400u /* the ADC's calibration did not finish */
#define BLDC_FAULT_EXTERNAL 0x0800u /* raised by the application */
#define BLDC_FAULT_BUS_TRANSIENT 0x1000u /* the bus left its window for less than a conversion and was back before the watchdog's interrupt could read the conversion that tripped it (its entry held by the Hall edge's handler, at the same priority): a spike or a dip, its side not seen, so neither OVER_VOLTAGE nor UNDER_VOLTAGE is claimed */

/* What a fault does now (bldc_port_safe_state()). */
#define BLDC_SAFE_ALL_OFF 0u       /* every switch off */
#define BLDC_SAFE_SHORT_CIRCUIT 1u /* every lower switch on, every upper off */

/* NVIC priorities (0 is the most urgent; the STM32F103 implements 4 bits). Define them
 * before including this header to fit another interrupt plan; the Hall edge, the Hall
 * lines' EXTI, the current loop and the break interrupt share one level so none interrupts another
 * half way through a TIM1 update, and the timing runs below them. */
#ifndef BLDC_PORT_HALL_PRIORITY
#define BLDC_PORT_HALL_PRIORITY 1u
#endif
#ifndef BLDC_PORT_FAULT_PRIORITY
#define BLDC_PORT_FAULT_PRIORITY BLDC_PORT_HALL_PRIORITY
#endif
#ifndef BLDC_PORT_TIMING_PRIORITY
#define BLDC_PORT_TIMING_PRIORITY 2u
#endif
#if BLDC_PORT_HALL_PRIORITY >= BLDC_PORT_TIMING_PRIORITY
#error "the Hall edge must preempt the timing computation"
#endif
#if BLDC_PORT_FAULT_PRIORITY != BLDC_PORT_HALL_PRIORITY
#error "the break interrupt must not preempt a Hall edge half way through (nor wait behind the timing)"
#endif
#if (BLDC_PORT_ADC_HTR > 4095u) || (BLDC_PORT_ADC_LTR > 4095u)
#error "ADC1's watchdog thresholds are 12-bit fields (RM0008 11.12.7): a larger one is held as its low bits"
#endif

/* Bus codes a new bus-voltage sample may differ from the code the timing uses before
 * the port recomputes the bus state (bldc_bus_condition(), five divides): the default
 * 1 code = 8.862 mV keeps one code of ADC noise from costing a recomputation.
 * The price: the duties are computed for a bus voltage up to that much off the latest
 * sample, which moves them by up to 3.76 counts at the top speed and
 * the lowest bus voltage (X = 4PE/U_d); define 0 to recompute on every change. The
 * analog watchdog, not this, guards the range. */
#ifndef BLDC_PORT_BUS_HYSTERESIS_CODES
#define BLDC_PORT_BUS_HYSTERESIS_CODES 1u
#endif

/* PWM periods (current-loop runs) from one bus change to the next at the earliest: the
 * whole PWM periods of the shortest sector (the top speed's), 2000 us. A bus
 * ADC with noise of a few codes, or a rippling bus, leaves the band at almost every
 * sample, and each change costs the bus state and a timing run: one every PWM period had
 * doubled the CPU load at 100 kHz. At most one a top-speed sector is the rate the
 * CPU-load budget prices (`make bench`), at every speed. The price: a bus change waits
 * up to this long; the analog watchdog, not this, guards the range, and while faulted
 * the safe state's region follows the bus at each conversion. Define 1 to take every
 * change at the next sample. */
#ifndef BLDC_PORT_BUS_MIN_PERIODS
#define BLDC_PORT_BUS_MIN_PERIODS 40u
#endif

/* While a fault is latched, the bus watchdog's window keeps the safe state's region
 * with the bus: a bus at or below the bound where all-off rectifies at the Hall interval
 * now interrupts at its conversion (the short circuit then, within a few microseconds),
 * and the short circuit is left for all-off only once the bus reads this many codes
 * above that bound, so ADC noise about it raises no interrupt at every conversion. */
#ifndef BLDC_PORT_FAULTED_BUS_HYSTERESIS_CODES
#define BLDC_PORT_FAULTED_BUS_HYSTERESIS_CODES 8u
#endif

/* While a fault is latched, the faulted drive's periodic work (the Hall interval, the
 * safe state's region for it, the bus watchdog's window, a bus its watchdog flagged)
 * runs at one injected sample in this many: every PWM period up to 39.9 kHz, so that
 * at a higher PWM frequency it takes no more of the CPU (50 us apart at the most). The
 * bus watchdog's own interrupt acts at once. */
#ifndef BLDC_PORT_FAULTED_TICK_PERIODS
#define BLDC_PORT_FAULTED_TICK_PERIODS 1u
#endif

/*
 * Start-up. bldc_port_init() enables the clocks of GPIOA, GPIOB, AFIO, TIM1, TIM3, ADC1
 * and ADC2, calibrates both ADCs, routes the Hall lines to the EXTI, configures TIM1 (PWM, dead time, break input, the ADC trigger),
 * TIM3 (Hall interface) and the ADC (injected sequence, the bus in the regular group,
 * analog watchdog), sets up the pins and the NVIC. `start_faults` are latched from the start (e.g.
 * BLDC_FAULT_CLOCK when the HSE did not start); a watchdog reset (RCC_CSR.IWDGRSTF)
 * latches BLDC_FAULT_WATCHDOG by itself. Without a fault the bridge is armed (MOE set,
 * every output off) and switches from the first Hall edge after the first bus sample.
 */
void bldc_port_init(uint32_t start_faults);

/* The braking current to hold, in mA: clamped to the spec's braking range and
 * converted to the nearest ADC code (bldc_current_reference()); closes the current
 * loop (after bldc_port_set_main_duty(), from the duty in force: no bump). Thread
 * mode or any interrupt. */
void bldc_set_braking_current(uint32_t milliamps);

/* Open loop (bring-up, tests): the steady switch runs at this duty in TIM1 counts,
 * clamped to the full scale, until bldc_set_braking_current() closes the loop again. */
void bldc_port_set_main_duty(uint16_t duty_counts);

/* Latched faults, BLDC_FAULT_* bits; 0: none. */
uint32_t bldc_port_faults(void);

/* Clear the latched faults whose cause is gone and, when none is left, re-arm the
 * bridge (every output off until the next Hall edge, the current loop from zero).
 * Returns the faults still latched (0: armed). */
uint32_t bldc_port_clear_faults(void);

/* Latch a fault (BLDC_FAULT_EXTERNAL, or BLDC_FAULT_CLOCK after start-up) and go to
 * the safe state now. */
void bldc_port_raise_fault(uint32_t fault);

/* What a fault does at the present speed and bus (and, while faulted, does):
 * BLDC_SAFE_ALL_OFF or BLDC_SAFE_SHORT_CIRCUIT. */
uint32_t bldc_port_safe_state(void);

/* The core's BLDC_FLAG_* of the timing the next Hall edge applies, computed on demand:
 * the core runs again on the inputs that timing took (interrupts are masked only while
 * they are copied). Call it from thread mode. */
uint32_t bldc_port_status(void);

/* The braking current I in ADC codes as the current loop last sampled it. */
uint32_t bldc_port_current_code(void);

/* Nonzero once per call when the current loop has run since the previous call: the
 * firmware refreshes the independent watchdog only then. */
uint32_t bldc_port_alive(void);

/* Nonzero when the current loop has run since the last bldc_port_alive(), which it
 * does not consume: main() looks with interrupts masked before it sleeps. */
uint32_t bldc_port_alive_pending(void);

/* For the NMI handler when the clock security system reports an HSE failure
 * (RCC_CIR.CSSF): outputs to their idle level at once, BLDC_FAULT_CLOCK, and the safe
 * state completed by the break interrupt. */
void bldc_port_clock_failure(void);

/* For a HardFault (or any handler that cannot go on): MOE cleared, outputs to their
 * idle level. Touches nothing but TIM1 BDTR. */
void bldc_port_emergency_off(void);

/* Interrupt handlers. The port owns
 * these vector table entries (spec firmware.integration: vector_table), under their
 * CMSIS names. */
void TIM3_IRQHandler(void);   /* Hall edge, commutation end, Hall timeout */
void TIM1_TRG_COM_IRQHandler(void); /* the next edge's duties and commutation time */
void TIM1_UP_IRQHandler(void);    /* the bus voltage moved: its state, then the timing */
void ADC1_2_IRQHandler(void);    /* current loop (JEOC), bus watchdog (AWD) */
void TIM1_BRK_IRQHandler(void);    /* break input: over-current */
void EXTI0_IRQHandler(void);    /* a Hall line changed: code 0 or 7 */
void EXTI9_5_IRQHandler(void); /* a Hall line changed: code 0 or 7 */

#endif /* STM32F103_PORT_H */
