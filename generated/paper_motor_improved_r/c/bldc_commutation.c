/* Generated from template templates/c/bldc_commutation.c.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `make`. */
#include "bldc_commutation.h"

#define N_X_HIGH 2396667768u /* N_X >> 11, round(K_X 2^7), K_X = 3.834668e+10 */
#define N_X_LOW 1219u /* N_X mod 2^11 */
#define N_X_SHIFT 11u
#define N_Y_HIGH 1080986531u /* N_Y >> 0, round(K_Y 2^18 / 1), K_Y = 4.123636e+03 */
#define N_Y_LOW 0u /* N_Y mod 2^0 */
#define N_Y_SHIFT 0u
#define UNIT_Q 1073741824u /* 1 in Q30 (e, u1, v2) */
#define PERIOD_Q 460800 /* P in Q7 counts */
#define CURRENT_OFFSET_Q 2048 /* zero current: 2048 codes x 1 */
#define KAPPA_Q 615816u /* kappa = 2.867618e-04 in Q31 / 1: A = kappa i X */
#define THETA_HALF_Q 217167u /* theta/2 in Q20, theta = sqrt(2) - 1 = 0.414213562 */
#define K_RHO_Q 50332u /* K_rho = R/(L f_hall) = 3.750000e-04 in Q27: rho = K_rho T */

/* Per-edge quantities of the rule (Q(fc) duty counts unless noted) */
typedef struct {
    int32_t x;    /* X = 4 P E / U_d, Q(fc) counts */
    int32_t a2;   /* 2 A, A = 3 P L I / (U_d T_s): the turn-off current at the edge */
    uint32_t rho; /* rho = R T_s / L, Q(frho) */
    int32_t s0;   /* 2P + Y - X: the held duty sum at the edge's EMFs */
    int32_t s1;   /* theta X / 2: its growth per sector of commutation */
} bldc_rule_edge_t;

/* Hall code -> sector (Table 1 order), 0xFF for 000 and 111 */
const uint8_t bldc_sector_of_hall[8] = {
    255u, /* 000: invalid */
    5u, /* 001: sector 5 */
    3u, /* 010: sector 3 */
    4u, /* 011: sector 4 */
    1u, /* 100: sector 1 */
    0u, /* 101: sector 0 */
    2u, /* 110: sector 2 */
    255u, /* 111: invalid */
};

/* (previous Hall code << 3 | Hall code) -> edge, BLDC_EDGE_NONE when invalid */
const uint8_t bldc_edge_of_hall_pair[64] = {
    255u, /* 000 -> 000: invalid: every switch off */
    255u, /* 000 -> 001: invalid: every switch off */
    255u, /* 000 -> 010: invalid: every switch off */
    255u, /* 000 -> 011: invalid: every switch off */
    255u, /* 000 -> 100: invalid: every switch off */
    255u, /* 000 -> 101: invalid: every switch off */
    255u, /* 000 -> 110: invalid: every switch off */
    255u, /* 000 -> 111: invalid: every switch off */
    255u, /* 001 -> 000: invalid: every switch off */
    255u, /* 001 -> 001: invalid: every switch off */
    255u, /* 001 -> 010: invalid: every switch off */
    10u, /* 001 -> 011: reverse into sector 4 */
    255u, /* 001 -> 100: invalid: every switch off */
    0u, /* 001 -> 101: forward into sector 0 */
    255u, /* 001 -> 110: invalid: every switch off */
    255u, /* 001 -> 111: invalid: every switch off */
    255u, /* 010 -> 000: invalid: every switch off */
    255u, /* 010 -> 001: invalid: every switch off */
    255u, /* 010 -> 010: invalid: every switch off */
    4u, /* 010 -> 011: forward into sector 4 */
    255u, /* 010 -> 100: invalid: every switch off */
    255u, /* 010 -> 101: invalid: every switch off */
    8u, /* 010 -> 110: reverse into sector 2 */
    255u, /* 010 -> 111: invalid: every switch off */
    255u, /* 011 -> 000: invalid: every switch off */
    5u, /* 011 -> 001: forward into sector 5 */
    9u, /* 011 -> 010: reverse into sector 3 */
    255u, /* 011 -> 011: invalid: every switch off */
    255u, /* 011 -> 100: invalid: every switch off */
    255u, /* 011 -> 101: invalid: every switch off */
    255u, /* 011 -> 110: invalid: every switch off */
    255u, /* 011 -> 111: invalid: every switch off */
    255u, /* 100 -> 000: invalid: every switch off */
    255u, /* 100 -> 001: invalid: every switch off */
    255u, /* 100 -> 010: invalid: every switch off */
    255u, /* 100 -> 011: invalid: every switch off */
    255u, /* 100 -> 100: invalid: every switch off */
    6u, /* 100 -> 101: reverse into sector 0 */
    2u, /* 100 -> 110: forward into sector 2 */
    255u, /* 100 -> 111: invalid: every switch off */
    255u, /* 101 -> 000: invalid: every switch off */
    11u, /* 101 -> 001: reverse into sector 5 */
    255u, /* 101 -> 010: invalid: every switch off */
    255u, /* 101 -> 011: invalid: every switch off */
    1u, /* 101 -> 100: forward into sector 1 */
    255u, /* 101 -> 101: invalid: every switch off */
    255u, /* 101 -> 110: invalid: every switch off */
    255u, /* 101 -> 111: invalid: every switch off */
    255u, /* 110 -> 000: invalid: every switch off */
    255u, /* 110 -> 001: invalid: every switch off */
    3u, /* 110 -> 010: forward into sector 3 */
    255u, /* 110 -> 011: invalid: every switch off */
    7u, /* 110 -> 100: reverse into sector 1 */
    255u, /* 110 -> 101: invalid: every switch off */
    255u, /* 110 -> 110: invalid: every switch off */
    255u, /* 110 -> 111: invalid: every switch off */
    255u, /* 111 -> 000: invalid: every switch off */
    255u, /* 111 -> 001: invalid: every switch off */
    255u, /* 111 -> 010: invalid: every switch off */
    255u, /* 111 -> 011: invalid: every switch off */
    255u, /* 111 -> 100: invalid: every switch off */
    255u, /* 111 -> 101: invalid: every switch off */
    255u, /* 111 -> 110: invalid: every switch off */
    255u, /* 111 -> 111: invalid: every switch off */
};

/* edge -> {switch at D_on, switch at D_off} (codegen/derivation/switching.py) */
const uint8_t bldc_edge_switch[12][2] = {
    {1u, 5u}, /* edge 0: into sector 0 (0-60 deg), forward 0 deg: non-commutating B via D4, off C (T6), on A (T2) */
    {4u, 2u}, /* edge 1: into sector 1 (60-120 deg), forward 60 deg: non-commutating A via D1, off B (T3), on C (T5) */
    {3u, 1u}, /* edge 2: into sector 2 (120-180 deg), forward 120 deg: non-commutating C via D6, off A (T2), on B (T4) */
    {0u, 4u}, /* edge 3: into sector 3 (180-240 deg), forward 180 deg: non-commutating B via D3, off C (T5), on A (T1) */
    {5u, 3u}, /* edge 4: into sector 4 (240-300 deg), forward 240 deg: non-commutating A via D2, off B (T4), on C (T6) */
    {2u, 0u}, /* edge 5: into sector 5 (300-360 deg), forward 300 deg: non-commutating C via D5, off A (T1), on B (T3) */
    {3u, 5u}, /* edge 6: into sector 0 (0-60 deg), reverse 60 deg: non-commutating A via D2, off C (T6), on B (T4) */
    {0u, 2u}, /* edge 7: into sector 1 (60-120 deg), reverse 120 deg: non-commutating C via D5, off B (T3), on A (T1) */
    {5u, 1u}, /* edge 8: into sector 2 (120-180 deg), reverse 180 deg: non-commutating B via D4, off A (T2), on C (T6) */
    {2u, 4u}, /* edge 9: into sector 3 (180-240 deg), reverse 240 deg: non-commutating A via D1, off C (T5), on B (T3) */
    {1u, 3u}, /* edge 10: into sector 4 (240-300 deg), reverse 300 deg: non-commutating C via D6, off B (T4), on A (T2) */
    {4u, 0u}, /* edge 11: into sector 5 (300-360 deg), reverse 0 deg: non-commutating B via D3, off A (T1), on C (T5) */
};

/* Complements round((1 - psi) 2^16) of psi1(y) = (1 - e^-y)/y and psi2(y) = 2(y - 1 + e^-y)/y^2 on octave segments: rows 0..63 cover [0, 1) in steps of 2^-6, octave j >= 1 covers [2^(j-1), 2^j) in steps of 2^(j-1-6); one closing row. Linear interpolation error <= 2.69e-05 (psi1), 2.55e-05 (psi2). 1540 bytes. */
static const uint16_t bldc_psi_complement[385][2] = {
    {0u, 0u}, /* y = 0, octave 0 */
    {509u, 340u}, /* y = 0.015625 */
    {1013u, 677u}, /* y = 0.03125 */
    {1512u, 1012u}, /* y = 0.046875 */
    {2006u, 1344u}, /* y = 0.0625 */
    {2495u, 1674u}, /* y = 0.078125 */
    {2978u, 2001u}, /* y = 0.09375 */
    {3457u, 2325u}, /* y = 0.109375 */
    {3931u, 2647u}, /* y = 0.125 */
    {4399u, 2967u}, /* y = 0.140625 */
    {4863u, 3284u}, /* y = 0.15625 */
    {5323u, 3599u}, /* y = 0.171875 */
    {5777u, 3911u}, /* y = 0.1875 */
    {6227u, 4221u}, /* y = 0.203125 */
    {6673u, 4528u}, /* y = 0.21875 */
    {7114u, 4834u}, /* y = 0.234375 */
    {7550u, 5136u}, /* y = 0.25 */
    {7982u, 5437u}, /* y = 0.265625 */
    {8409u, 5735u}, /* y = 0.28125 */
    {8833u, 6031u}, /* y = 0.296875 */
    {9252u, 6325u}, /* y = 0.3125 */
    {9666u, 6617u}, /* y = 0.328125 */
    {10077u, 6906u}, /* y = 0.34375 */
    {10483u, 7193u}, /* y = 0.359375 */
    {10886u, 7478u}, /* y = 0.375 */
    {11284u, 7761u}, /* y = 0.390625 */
    {11678u, 8042u}, /* y = 0.40625 */
    {12069u, 8321u}, /* y = 0.421875 */
    {12455u, 8597u}, /* y = 0.4375 */
    {12838u, 8872u}, /* y = 0.453125 */
    {13217u, 9144u}, /* y = 0.46875 */
    {13592u, 9415u}, /* y = 0.484375 */
    {13963u, 9683u}, /* y = 0.5 */
    {14331u, 9950u}, /* y = 0.515625 */
    {14695u, 10214u}, /* y = 0.53125 */
    {15055u, 10477u}, /* y = 0.546875 */
    {15412u, 10738u}, /* y = 0.5625 */
    {15765u, 10996u}, /* y = 0.578125 */
    {16115u, 11253u}, /* y = 0.59375 */
    {16462u, 11508u}, /* y = 0.609375 */
    {16805u, 11761u}, /* y = 0.625 */
    {17144u, 12012u}, /* y = 0.640625 */
    {17481u, 12262u}, /* y = 0.65625 */
    {17814u, 12509u}, /* y = 0.671875 */
    {18143u, 12755u}, /* y = 0.6875 */
    {18470u, 12999u}, /* y = 0.703125 */
    {18793u, 13242u}, /* y = 0.71875 */
    {19114u, 13482u}, /* y = 0.734375 */
    {19431u, 13721u}, /* y = 0.75 */
    {19745u, 13958u}, /* y = 0.765625 */
    {20056u, 14193u}, /* y = 0.78125 */
    {20364u, 14427u}, /* y = 0.796875 */
    {20669u, 14659u}, /* y = 0.8125 */
    {20971u, 14889u}, /* y = 0.828125 */
    {21270u, 15118u}, /* y = 0.84375 */
    {21566u, 15345u}, /* y = 0.859375 */
    {21860u, 15570u}, /* y = 0.875 */
    {22151u, 15794u}, /* y = 0.890625 */
    {22439u, 16016u}, /* y = 0.90625 */
    {22724u, 16237u}, /* y = 0.921875 */
    {23006u, 16456u}, /* y = 0.9375 */
    {23286u, 16674u}, /* y = 0.953125 */
    {23563u, 16890u}, /* y = 0.96875 */
    {23837u, 17104u}, /* y = 0.984375 */
    {24109u, 17317u}, /* y = 1, octave 1 */
    {24379u, 17529u}, /* y = 1.01562 */
    {24645u, 17739u}, /* y = 1.03125 */
    {24910u, 17947u}, /* y = 1.04688 */
    {25171u, 18155u}, /* y = 1.0625 */
    {25431u, 18360u}, /* y = 1.07812 */
    {25688u, 18564u}, /* y = 1.09375 */
    {25942u, 18767u}, /* y = 1.10938 */
    {26194u, 18969u}, /* y = 1.125 */
    {26444u, 19169u}, /* y = 1.14062 */
    {26691u, 19367u}, /* y = 1.15625 */
    {26936u, 19565u}, /* y = 1.17188 */
    {27179u, 19760u}, /* y = 1.1875 */
    {27420u, 19955u}, /* y = 1.20312 */
    {27658u, 20148u}, /* y = 1.21875 */
    {27894u, 20340u}, /* y = 1.23438 */
    {28128u, 20531u}, /* y = 1.25 */
    {28360u, 20720u}, /* y = 1.26562 */
    {28590u, 20908u}, /* y = 1.28125 */
    {28817u, 21095u}, /* y = 1.29688 */
    {29043u, 21280u}, /* y = 1.3125 */
    {29266u, 21464u}, /* y = 1.32812 */
    {29488u, 21647u}, /* y = 1.34375 */
    {29707u, 21829u}, /* y = 1.35938 */
    {29924u, 22010u}, /* y = 1.375 */
    {30140u, 22189u}, /* y = 1.39062 */
    {30353u, 22367u}, /* y = 1.40625 */
    {30565u, 22544u}, /* y = 1.42188 */
    {30774u, 22719u}, /* y = 1.4375 */
    {30982u, 22894u}, /* y = 1.45312 */
    {31188u, 23067u}, /* y = 1.46875 */
    {31392u, 23240u}, /* y = 1.48438 */
    {31594u, 23411u}, /* y = 1.5 */
    {31794u, 23581u}, /* y = 1.51562 */
    {31993u, 23749u}, /* y = 1.53125 */
    {32190u, 23917u}, /* y = 1.54688 */
    {32385u, 24084u}, /* y = 1.5625 */
    {32578u, 24249u}, /* y = 1.57812 */
    {32770u, 24413u}, /* y = 1.59375 */
    {32959u, 24577u}, /* y = 1.60938 */
    {33148u, 24739u}, /* y = 1.625 */
    {33334u, 24900u}, /* y = 1.64062 */
    {33519u, 25060u}, /* y = 1.65625 */
    {33702u, 25219u}, /* y = 1.67188 */
    {33884u, 25377u}, /* y = 1.6875 */
    {34064u, 25534u}, /* y = 1.70312 */
    {34242u, 25690u}, /* y = 1.71875 */
    {34419u, 25845u}, /* y = 1.73438 */
    {34595u, 25999u}, /* y = 1.75 */
    {34768u, 26152u}, /* y = 1.76562 */
    {34941u, 26304u}, /* y = 1.78125 */
    {35111u, 26455u}, /* y = 1.79688 */
    {35281u, 26605u}, /* y = 1.8125 */
    {35449u, 26755u}, /* y = 1.82812 */
    {35615u, 26903u}, /* y = 1.84375 */
    {35780u, 27050u}, /* y = 1.85938 */
    {35944u, 27196u}, /* y = 1.875 */
    {36106u, 27341u}, /* y = 1.89062 */
    {36267u, 27486u}, /* y = 1.90625 */
    {36426u, 27629u}, /* y = 1.92188 */
    {36584u, 27772u}, /* y = 1.9375 */
    {36741u, 27914u}, /* y = 1.95312 */
    {36896u, 28054u}, /* y = 1.96875 */
    {37050u, 28194u}, /* y = 1.98438 */
    {37203u, 28333u}, /* y = 2, octave 2 */
    {37504u, 28609u}, /* y = 2.03125 */
    {37801u, 28881u}, /* y = 2.0625 */
    {38092u, 29149u}, /* y = 2.09375 */
    {38379u, 29415u}, /* y = 2.125 */
    {38661u, 29677u}, /* y = 2.15625 */
    {38938u, 29936u}, /* y = 2.1875 */
    {39211u, 30191u}, /* y = 2.21875 */
    {39479u, 30444u}, /* y = 2.25 */
    {39743u, 30693u}, /* y = 2.28125 */
    {40002u, 30940u}, /* y = 2.3125 */
    {40257u, 31183u}, /* y = 2.34375 */
    {40509u, 31424u}, /* y = 2.375 */
    {40756u, 31661u}, /* y = 2.40625 */
    {40999u, 31896u}, /* y = 2.4375 */
    {41238u, 32128u}, /* y = 2.46875 */
    {41473u, 32357u}, /* y = 2.5 */
    {41705u, 32584u}, /* y = 2.53125 */
    {41933u, 32808u}, /* y = 2.5625 */
    {42158u, 33029u}, /* y = 2.59375 */
    {42378u, 33248u}, /* y = 2.625 */
    {42596u, 33464u}, /* y = 2.65625 */
    {42810u, 33677u}, /* y = 2.6875 */
    {43021u, 33889u}, /* y = 2.71875 */
    {43228u, 34097u}, /* y = 2.75 */
    {43433u, 34304u}, /* y = 2.78125 */
    {43634u, 34508u}, /* y = 2.8125 */
    {43832u, 34709u}, /* y = 2.84375 */
    {44027u, 34909u}, /* y = 2.875 */
    {44219u, 35106u}, /* y = 2.90625 */
    {44408u, 35301u}, /* y = 2.9375 */
    {44595u, 35493u}, /* y = 2.96875 */
    {44778u, 35684u}, /* y = 3 */
    {44959u, 35872u}, /* y = 3.03125 */
    {45137u, 36059u}, /* y = 3.0625 */
    {45313u, 36243u}, /* y = 3.09375 */
    {45486u, 36425u}, /* y = 3.125 */
    {45656u, 36605u}, /* y = 3.15625 */
    {45824u, 36783u}, /* y = 3.1875 */
    {45990u, 36960u}, /* y = 3.21875 */
    {46153u, 37134u}, /* y = 3.25 */
    {46314u, 37307u}, /* y = 3.28125 */
    {46472u, 37477u}, /* y = 3.3125 */
    {46628u, 37646u}, /* y = 3.34375 */
    {46782u, 37813u}, /* y = 3.375 */
    {46934u, 37978u}, /* y = 3.40625 */
    {47084u, 38142u}, /* y = 3.4375 */
    {47231u, 38303u}, /* y = 3.46875 */
    {47377u, 38464u}, /* y = 3.5 */
    {47520u, 38622u}, /* y = 3.53125 */
    {47662u, 38779u}, /* y = 3.5625 */
    {47801u, 38934u}, /* y = 3.59375 */
    {47939u, 39087u}, /* y = 3.625 */
    {48075u, 39239u}, /* y = 3.65625 */
    {48208u, 39389u}, /* y = 3.6875 */
    {48340u, 39538u}, /* y = 3.71875 */
    {48471u, 39685u}, /* y = 3.75 */
    {48599u, 39831u}, /* y = 3.78125 */
    {48726u, 39975u}, /* y = 3.8125 */
    {48851u, 40118u}, /* y = 3.84375 */
    {48974u, 40259u}, /* y = 3.875 */
    {49096u, 40399u}, /* y = 3.90625 */
    {49216u, 40537u}, /* y = 3.9375 */
    {49335u, 40674u}, /* y = 3.96875 */
    {49452u, 40810u}, /* y = 4, octave 3 */
    {49682u, 41077u}, /* y = 4.0625 */
    {49905u, 41339u}, /* y = 4.125 */
    {50123u, 41597u}, /* y = 4.1875 */
    {50336u, 41849u}, /* y = 4.25 */
    {50543u, 42096u}, /* y = 4.3125 */
    {50745u, 42338u}, /* y = 4.375 */
    {50942u, 42576u}, /* y = 4.4375 */
    {51134u, 42810u}, /* y = 4.5 */
    {51322u, 43039u}, /* y = 4.5625 */
    {51505u, 43264u}, /* y = 4.625 */
    {51684u, 43484u}, /* y = 4.6875 */
    {51858u, 43701u}, /* y = 4.75 */
    {52029u, 43914u}, /* y = 4.8125 */
    {52195u, 44123u}, /* y = 4.875 */
    {52358u, 44328u}, /* y = 4.9375 */
    {52517u, 44529u}, /* y = 5 */
    {52673u, 44727u}, /* y = 5.0625 */
    {52825u, 44922u}, /* y = 5.125 */
    {52973u, 45113u}, /* y = 5.1875 */
    {53118u, 45300u}, /* y = 5.25 */
    {53261u, 45485u}, /* y = 5.3125 */
    {53400u, 45666u}, /* y = 5.375 */
    {53536u, 45845u}, /* y = 5.4375 */
    {53669u, 46020u}, /* y = 5.5 */
    {53799u, 46192u}, /* y = 5.5625 */
    {53927u, 46362u}, /* y = 5.625 */
    {54052u, 46529u}, /* y = 5.6875 */
    {54175u, 46693u}, /* y = 5.75 */
    {54295u, 46854u}, /* y = 5.8125 */
    {54412u, 47013u}, /* y = 5.875 */
    {54527u, 47169u}, /* y = 5.9375 */
    {54640u, 47323u}, /* y = 6 */
    {54751u, 47474u}, /* y = 6.0625 */
    {54860u, 47623u}, /* y = 6.125 */
    {54966u, 47769u}, /* y = 6.1875 */
    {55070u, 47913u}, /* y = 6.25 */
    {55173u, 48055u}, /* y = 6.3125 */
    {55273u, 48195u}, /* y = 6.375 */
    {55372u, 48333u}, /* y = 6.4375 */
    {55469u, 48469u}, /* y = 6.5 */
    {55564u, 48602u}, /* y = 6.5625 */
    {55657u, 48734u}, /* y = 6.625 */
    {55748u, 48864u}, /* y = 6.6875 */
    {55838u, 48991u}, /* y = 6.75 */
    {55927u, 49117u}, /* y = 6.8125 */
    {56013u, 49241u}, /* y = 6.875 */
    {56099u, 49363u}, /* y = 6.9375 */
    {56182u, 49484u}, /* y = 7 */
    {56265u, 49603u}, /* y = 7.0625 */
    {56345u, 49720u}, /* y = 7.125 */
    {56425u, 49835u}, /* y = 7.1875 */
    {56503u, 49949u}, /* y = 7.25 */
    {56580u, 50061u}, /* y = 7.3125 */
    {56655u, 50172u}, /* y = 7.375 */
    {56730u, 50281u}, /* y = 7.4375 */
    {56803u, 50389u}, /* y = 7.5 */
    {56875u, 50495u}, /* y = 7.5625 */
    {56945u, 50600u}, /* y = 7.625 */
    {57015u, 50703u}, /* y = 7.6875 */
    {57083u, 50805u}, /* y = 7.75 */
    {57151u, 50905u}, /* y = 7.8125 */
    {57217u, 51005u}, /* y = 7.875 */
    {57282u, 51103u}, /* y = 7.9375 */
    {57347u, 51199u}, /* y = 8, octave 4 */
    {57472u, 51389u}, /* y = 8.125 */
    {57594u, 51574u}, /* y = 8.25 */
    {57713u, 51754u}, /* y = 8.375 */
    {57827u, 51930u}, /* y = 8.5 */
    {57939u, 52101u}, /* y = 8.625 */
    {58047u, 52268u}, /* y = 8.75 */
    {58153u, 52431u}, /* y = 8.875 */
    {58255u, 52590u}, /* y = 9 */
    {58355u, 52746u}, /* y = 9.125 */
    {58452u, 52898u}, /* y = 9.25 */
    {58546u, 53046u}, /* y = 9.375 */
    {58638u, 53191u}, /* y = 9.5 */
    {58728u, 53333u}, /* y = 9.625 */
    {58815u, 53471u}, /* y = 9.75 */
    {58900u, 53607u}, /* y = 9.875 */
    {58983u, 53739u}, /* y = 10 */
    {59064u, 53869u}, /* y = 10.125 */
    {59142u, 53996u}, /* y = 10.25 */
    {59219u, 54120u}, /* y = 10.375 */
    {59295u, 54242u}, /* y = 10.5 */
    {59368u, 54361u}, /* y = 10.625 */
    {59440u, 54477u}, /* y = 10.75 */
    {59510u, 54592u}, /* y = 10.875 */
    {59578u, 54704u}, /* y = 11 */
    {59645u, 54813u}, /* y = 11.125 */
    {59711u, 54921u}, /* y = 11.25 */
    {59775u, 55026u}, /* y = 11.375 */
    {59837u, 55130u}, /* y = 11.5 */
    {59899u, 55231u}, /* y = 11.625 */
    {59959u, 55330u}, /* y = 11.75 */
    {60017u, 55428u}, /* y = 11.875 */
    {60075u, 55524u}, /* y = 12 */
    {60131u, 55617u}, /* y = 12.125 */
    {60186u, 55710u}, /* y = 12.25 */
    {60240u, 55800u}, /* y = 12.375 */
    {60293u, 55889u}, /* y = 12.5 */
    {60345u, 55976u}, /* y = 12.625 */
    {60396u, 56062u}, /* y = 12.75 */
    {60446u, 56146u}, /* y = 12.875 */
    {60495u, 56229u}, /* y = 13 */
    {60543u, 56310u}, /* y = 13.125 */
    {60590u, 56390u}, /* y = 13.25 */
    {60636u, 56469u}, /* y = 13.375 */
    {60681u, 56546u}, /* y = 13.5 */
    {60726u, 56622u}, /* y = 13.625 */
    {60770u, 56697u}, /* y = 13.75 */
    {60813u, 56770u}, /* y = 13.875 */
    {60855u, 56842u}, /* y = 14 */
    {60896u, 56914u}, /* y = 14.125 */
    {60937u, 56983u}, /* y = 14.25 */
    {60977u, 57052u}, /* y = 14.375 */
    {61016u, 57120u}, /* y = 14.5 */
    {61055u, 57187u}, /* y = 14.625 */
    {61093u, 57252u}, /* y = 14.75 */
    {61130u, 57317u}, /* y = 14.875 */
    {61167u, 57380u}, /* y = 15 */
    {61203u, 57443u}, /* y = 15.125 */
    {61239u, 57505u}, /* y = 15.25 */
    {61273u, 57565u}, /* y = 15.375 */
    {61308u, 57625u}, /* y = 15.5 */
    {61342u, 57684u}, /* y = 15.625 */
    {61375u, 57742u}, /* y = 15.75 */
    {61408u, 57800u}, /* y = 15.875 */
    {61440u, 57856u}, /* y = 16, octave 5 */
    {61503u, 57966u}, /* y = 16.25 */
    {61564u, 58074u}, /* y = 16.5 */
    {61623u, 58178u}, /* y = 16.75 */
    {61681u, 58279u}, /* y = 17 */
    {61737u, 58378u}, /* y = 17.25 */
    {61791u, 58474u}, /* y = 17.5 */
    {61844u, 58568u}, /* y = 17.75 */
    {61895u, 58659u}, /* y = 18 */
    {61945u, 58748u}, /* y = 18.25 */
    {61994u, 58834u}, /* y = 18.5 */
    {62041u, 58918u}, /* y = 18.75 */
    {62087u, 59001u}, /* y = 19 */
    {62132u, 59081u}, /* y = 19.25 */
    {62175u, 59159u}, /* y = 19.5 */
    {62218u, 59235u}, /* y = 19.75 */
    {62259u, 59310u}, /* y = 20 */
    {62300u, 59383u}, /* y = 20.25 */
    {62339u, 59454u}, /* y = 20.5 */
    {62378u, 59524u}, /* y = 20.75 */
    {62415u, 59592u}, /* y = 21 */
    {62452u, 59658u}, /* y = 21.25 */
    {62488u, 59723u}, /* y = 21.5 */
    {62523u, 59787u}, /* y = 21.75 */
    {62557u, 59849u}, /* y = 22 */
    {62591u, 59910u}, /* y = 22.25 */
    {62623u, 59969u}, /* y = 22.5 */
    {62655u, 60028u}, /* y = 22.75 */
    {62687u, 60085u}, /* y = 23 */
    {62717u, 60141u}, /* y = 23.25 */
    {62747u, 60196u}, /* y = 23.5 */
    {62777u, 60250u}, /* y = 23.75 */
    {62805u, 60302u}, /* y = 24 */
    {62833u, 60354u}, /* y = 24.25 */
    {62861u, 60404u}, /* y = 24.5 */
    {62888u, 60454u}, /* y = 24.75 */
    {62915u, 60503u}, /* y = 25 */
    {62941u, 60551u}, /* y = 25.25 */
    {62966u, 60597u}, /* y = 25.5 */
    {62991u, 60644u}, /* y = 25.75 */
    {63015u, 60689u}, /* y = 26 */
    {63039u, 60733u}, /* y = 26.25 */
    {63063u, 60777u}, /* y = 26.5 */
    {63086u, 60819u}, /* y = 26.75 */
    {63109u, 60861u}, /* y = 27 */
    {63131u, 60903u}, /* y = 27.25 */
    {63153u, 60943u}, /* y = 27.5 */
    {63174u, 60983u}, /* y = 27.75 */
    {63195u, 61022u}, /* y = 28 */
    {63216u, 61061u}, /* y = 28.25 */
    {63236u, 61098u}, /* y = 28.5 */
    {63256u, 61136u}, /* y = 28.75 */
    {63276u, 61172u}, /* y = 29 */
    {63295u, 61208u}, /* y = 29.25 */
    {63314u, 61243u}, /* y = 29.5 */
    {63333u, 61278u}, /* y = 29.75 */
    {63351u, 61313u}, /* y = 30 */
    {63370u, 61346u}, /* y = 30.25 */
    {63387u, 61379u}, /* y = 30.5 */
    {63405u, 61412u}, /* y = 30.75 */
    {63422u, 61444u}, /* y = 31 */
    {63439u, 61476u}, /* y = 31.25 */
    {63455u, 61507u}, /* y = 31.5 */
    {63472u, 61538u}, /* y = 31.75 */
    {63488u, 61568u}, /* y = 32, octave 6 */
};

/* round(N / divisor) for N = high 2^shift + low: two 32-bit divides, no 64-bit helper. N / divisor = q_high 2^shift + (r 2^shift + low) / divisor, r = high mod divisor. */
/*@ assigns \nothing;
*/
static uint32_t bldc_divide_long(uint32_t high, uint32_t low, uint32_t shift, uint32_t divisor)
{
    const uint32_t q_high = high / divisor;
    const uint32_t remainder = ((high % divisor) << shift) + low;
    return (q_high << shift) + (remainder + (divisor >> 1)) / divisor;
}

/* Saturate a bus code and precompute its reciprocals (pure, reentrant) */
bldc_bus_t bldc_bus_condition(uint32_t bus_code)
{
    uint32_t code = bus_code;
    uint32_t period_min = BLDC_PERIOD_MIN_TICKS;
    uint32_t flags = 0u;
    if (code > BLDC_BUS_CODE_MAX) {
        code = BLDC_BUS_CODE_MAX;
        period_min = BLDC_PERIOD_NEVER; /* over-voltage: every edge goes to the safe state */
        flags = BLDC_FLAG_INPUT_SATURATED;
    } else if (code < BLDC_BUS_CODE_MIN) {
        code = BLDC_BUS_CODE_MIN;
        flags = BLDC_FLAG_INPUT_SATURATED;
    }
    const bldc_bus_t bus = {
        .x_numerator = bldc_divide_long(N_X_HIGH, N_X_LOW, N_X_SHIFT, code),
        .y_numerator = bldc_divide_long(N_Y_HIGH, N_Y_LOW, N_Y_SHIFT, code),
        .period_min = period_min,
        .bus_code = code,
        .flags = flags,
    };
    return bus;
}

/* Sign of 2 g(x): the turn-off current after x sectors (Q K) under the pair held at S(x), g = A e^-rho x + F x psi1(rho x) - X x^2/2 psi2(rho x), F = 2 C_off - C_on - P + X/2. 1 while the current has not yet reached zero */
/*@ requires readable_st: \valid_read(st);
    assigns \nothing;
*/
static uint32_t bldc_current_remains(const bldc_rule_edge_t *st, uint32_t x)
{
    const uint64_t rho_x = (uint64_t)st->rho * (uint64_t)x;
    const uint32_t y = (uint32_t)(rho_x >> 17u); /* y = rho x in Q24 */
    const uint32_t whole = y >> 24u;
    const uint32_t octave = (whole == 0u) ? 0u : (32u - (uint32_t)__builtin_clz(whole)); /* table segment: 0 for y < 1, else 32 - CLZ(integer part) */
    /*@ split octave; */ /*@ ghost ; */
    const uint32_t shift = (octave == 0u) ? 18u : 17u + octave; /* fraction bits of y within its row */
    const uint32_t row = (octave << 6u) + ((y >> shift) & 63u);
    const uint32_t r = y & ((1u << shift) - 1u);
    const uint32_t half = 1u << (shift - 1u);
    /*@ split row; */ /*@ ghost ; */
    const uint32_t psi1 = 65536u - ((uint32_t)bldc_psi_complement[row][0] + ((((uint32_t)bldc_psi_complement[row + 1u][0] - bldc_psi_complement[row][0]) * r + half) >> shift)); /* psi1(y) in Q16, linear interpolation */
    const uint32_t psi2 = 65536u - ((uint32_t)bldc_psi_complement[row][1] + ((((uint32_t)bldc_psi_complement[row + 1u][1] - bldc_psi_complement[row][1]) * r + half) >> shift)); /* psi2(y) in Q16, linear interpolation */
    /*@ merge row; */ /*@ ghost ; */
    const uint64_t y_psi1 = (uint64_t)y * (uint64_t)psi1;
    const uint64_t one_minus_e = (y_psi1 + 512ull) >> 10u; /* 1 - e^-y in Q30 */
    const int32_t e = (int32_t)((uint64_t)UNIT_Q - ((one_minus_e > (uint64_t)UNIT_Q) ? (uint64_t)UNIT_Q : one_minus_e)); /* e^-y = 1 - y psi1 in Q30, kept >= 0 against the table's error */
    const int32_t u1 = (int32_t)(x * psi1); /* x psi1 */
    const uint64_t x_x_psi2 = (uint64_t)x * (uint64_t)(x * psi2);
    const int32_t v2 = (int32_t)((x_x_psi2 + 8192ull) >> 14u); /* x^2 psi2 */
    const uint64_t s1_x = (uint64_t)(uint32_t)st->s1 * (uint64_t)x;
    const int32_t total = st->s0 + (int32_t)((s1_x + 8192ull) >> 14u); /* S(x) */
    const int32_t on = (total < 0) ? 0 : (total > PERIOD_Q) ? PERIOD_Q : total;
    const int32_t off = (total - PERIOD_Q < 0) ? 0 : (total - PERIOD_Q > PERIOD_Q) ? PERIOD_Q : total - PERIOD_Q;
    const int32_t f2 = 4 * off - 2 * on - 2 * PERIOD_Q + st->x; /* 2F */
    const int64_t twice_g = (int64_t)st->a2 * (int64_t)e + (int64_t)f2 * (int64_t)u1 - (int64_t)st->x * (int64_t)v2; /* 2 g(x) */
    return (twice_g > 0ll) ? 1u : 0u;
}

/* Duties and commutation time of the resistance-aware rule (pure, reentrant); any uint32_t value of each parameter is allowed. The rule holds the current by itself: the main duty is not used */
bldc_timing_t bldc_commutation_timing(const bldc_bus_t *bus, uint32_t period_ticks, uint32_t current_adc, uint32_t main_duty_counts)
{
    (void)main_duty_counts; /* not used by this method */
    uint32_t flags = bus->flags;
    const uint32_t measured = (period_ticks > BLDC_PERIOD_CAP_TICKS) ? BLDC_PERIOD_CAP_TICKS : period_ticks; /* the Hall counter's range */
    if (measured < bus->period_min) { /* above the top speed or over-voltage: braking is no longer controlled */
        const bldc_timing_t safe = {
            .period_min = BLDC_PERIOD_NEVER,
            .turn_on_compare = 0u,
            .turn_off_compare = 0u,
            .commutation_ticks = 0u,
            .flags = (uint16_t)(flags | BLDC_FLAG_INPUT_SATURATED),
        };
        return safe;
    }
    if (measured > BLDC_PERIOD_MAX_TICKS) { /* below the minimum speed */
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }
    const uint32_t period = (measured > BLDC_PERIOD_MAX_TICKS) ? BLDC_PERIOD_MAX_TICKS : measured; /* the table covers rho up to the slowest speed */
    const uint32_t current_code = (current_adc > BLDC_ADC_CODE_MAX) ? BLDC_ADC_CODE_MAX : current_adc; /* above the ADC's range: full scale */
    if (current_adc < BLDC_CURRENT_CODE_LOW || current_adc > BLDC_CURRENT_CODE_HIGH) { /* outside the braking-current range */
        flags |= BLDC_FLAG_INPUT_SATURATED;
    }
    const int32_t current = (int32_t)current_code - CURRENT_OFFSET_Q; /* I in codes, offset removed */
    const uint32_t i = (uint32_t)((current < 0) ? 0 : current); /* negative currents count as 0 */
    const uint32_t x = (bus->x_numerator + (period >> 1)) / period; /* X in Q7 counts */
    const uint32_t y = (bus->y_numerator * i + 1024u) >> 11u; /* Y = 3 P R I / U_d, Q7 */
    const uint64_t x_kappa_i = (uint64_t)x * (uint64_t)(KAPPA_Q * i);
    const uint32_t a = (uint32_t)((x_kappa_i + 1073741824ull) >> 31u); /* A = kappa i X */
    const uint64_t x_theta = (uint64_t)x * (uint64_t)THETA_HALF_Q;
    const bldc_rule_edge_t st = {
        .x = (int32_t)x,
        .a2 = 2 * (int32_t)a,
        .rho = K_RHO_Q * period,
        .s0 = 2 * PERIOD_Q + (int32_t)y - (int32_t)x,
        .s1 = (int32_t)((x_theta + 524288ull) >> 20u),
    };
    uint32_t lo = 0u;
    uint32_t hi = 16384u;
    /*@ loop invariant 0 <= step <= 14; loop invariant 0 <= lo <= 16384; loop invariant 0 <= hi <= 16384; loop assigns lo, hi, step; loop variant 14 - step; */
    for (uint32_t step = 0u; step < 14u; ++step) { /* t_com: bisection over x in (0, 1] sectors; g(0) = A >= 0 changes sign once */
        const uint32_t mid = (lo + hi) >> 1u;
        if (bldc_current_remains(&st, mid) != 0u) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    uint32_t fraction = lo + hi; /* Q15: the middle of the last bracket */
    if (hi == 16384u && bldc_current_remains(&st, hi) != 0u) {
        fraction = 2u << 14u; /* does not finish within the sector: the whole sector */
        flags |= BLDC_FLAG_TIME_CLAMPED;
    }
    const uint64_t s1_x = (uint64_t)(uint32_t)st.s1 * (uint64_t)fraction;
    const int32_t total = st.s0 + (int32_t)((s1_x + 16384ull) >> 15u); /* S(x_c) */
    if (total > 2 * PERIOD_Q || total < 0) { /* no duty pair in [0, 1] holds the current */
        flags |= BLDC_FLAG_FAIL_AREA_CLAMPED;
    }
    if (total < PERIOD_Q) { /* the turn-off phase off, the turn-on one modulated */
        flags |= BLDC_FLAG_HIGH_SPEED;
    }
    const uint32_t on = (uint32_t)((total < 0) ? 0 : (total > PERIOD_Q) ? PERIOD_Q : total);
    const uint32_t off = (uint32_t)((total - PERIOD_Q < 0) ? 0 : (total - PERIOD_Q > PERIOD_Q) ? PERIOD_Q : total - PERIOD_Q);
    const uint32_t scaled = (fraction * period + 16384u) >> 15u; /* x_c T */
    const uint32_t ticks = (scaled > measured) ? measured : scaled; /* at most the measured period */
    const bldc_timing_t timing = {
        .period_min = bus->period_min,
        .turn_on_compare = (uint16_t)((on + 64u) >> 7u),
        .turn_off_compare = (uint16_t)((off + 64u) >> 7u),
        .commutation_ticks = (uint16_t)ticks,
        .flags = (uint16_t)flags,
    };
    return timing;
}

/* Commutation decision on plain inputs: bldc_edge_of(), bldc_bus_condition() and bldc_commutation_timing() for the same inputs (pure, reentrant) */
void bldc_commutate(const bldc_inputs_t *inputs, bldc_outputs_t *out)
{
    const uint32_t hall_code = (uint32_t)inputs->hall_code;
    const uint32_t previous_hall_code = (uint32_t)inputs->previous_hall_code;
    const uint32_t period = (uint32_t)inputs->hall_period_ticks;
    uint32_t edge = BLDC_EDGE_NONE;
    uint32_t sector = BLDC_INVALID_SECTOR;
    if (hall_code <= 7u) {
        sector = (uint32_t)bldc_sector_of_hall[hall_code]; /* the sector of the new code */
        edge = bldc_edge_of(previous_hall_code, hall_code);
    }
    out->turn_on_compare = 0u;
    out->turn_off_compare = 0u;
    out->commutation_ticks = 0u;
    out->turn_on_switch = (uint8_t)BLDC_NO_SWITCH;
    out->turn_off_switch = (uint8_t)BLDC_NO_SWITCH;
    out->sector = (uint8_t)sector;
    out->flags = (uint8_t)BLDC_FLAG_INVALID_HALL;
    if (edge < BLDC_EDGE_COUNT) {
        const bldc_bus_t bus = bldc_bus_condition((uint32_t)inputs->bus_voltage_adc); /* bldc_bus_condition() */
        const bldc_timing_t timing = bldc_commutation_timing(&bus, period, (uint32_t)inputs->phase_current_adc, (uint32_t)inputs->main_duty_counts);
        out->turn_on_compare = timing.turn_on_compare;
        out->turn_off_compare = timing.turn_off_compare;
        out->commutation_ticks = timing.commutation_ticks;
        out->flags = (uint8_t)timing.flags;
        if (period >= timing.period_min) { /* a shorter interval (over-speed) or over-voltage: the safe state */
            out->turn_on_switch = bldc_edge_switch[edge][0];
            out->turn_off_switch = bldc_edge_switch[edge][1];
        }
    }
}
