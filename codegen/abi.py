"""The core's ABI, defined once: flags, the public structs and the special values.

The C header, the Python twin, the manifest (from which the verifier and the
simulation build their ctypes and numpy types) and the Unity vectors are all rendered
from these objects; no other module spells a flag value or a struct layout.
"""

from __future__ import annotations

from dataclasses import dataclass

from codegen.ir.nodes import IConst, StructField, StructType
from codegen.ir.types import U8, U16, U32


@dataclass(frozen=True)
class Flag:
    name: str  # BLDC_FLAG_<name> in C, FLAG_<name> in Python
    bit: int
    doc: str

    @property
    def value(self) -> int:
        return 1 << self.bit


FLAGS: tuple[Flag, ...] = (
    Flag("HIGH_SPEED", 0, "Eq. 18 high-speed segment: 4E > U_d (the turn-off phase is off)"),
    Flag("FAIL_AREA_CLAMPED", 1, "no duty pair in [0, 1] holds the current: clamped"),
    Flag("INPUT_SATURATED", 2, "an input was outside the spec's range"),
    Flag("INVALID_HALL", 3, "Hall code 000/111 or an impossible jump: every switch off"),
    Flag("TIME_CLAMPED", 4, "the commutation does not finish within the sector: clamped to it"),
)
FLAG = {f.name: f.value for f in FLAGS}

NO_SWITCH = 0xFF
EDGE_NONE = 0xFF
EDGE_COUNT = 12
INVALID_SECTOR = 0xFF
#: above every 16-bit Hall period: a timing with this minimum never applies (safe state)
PERIOD_NEVER = 0x10000

#: special values shared by C (BLDC_<name>) and Python (<name>)
VALUES: tuple[tuple[str, int, str], ...] = (
    ("NO_SWITCH", NO_SWITCH, "no switch: every transistor of that role off"),
    ("EDGE_NONE", EDGE_NONE, "no valid commutation: every switch off"),
    ("EDGE_COUNT", EDGE_COUNT, "edge = 6 x direction + sector entered (0 forward, 1 reverse)"),
    ("INVALID_SECTOR", INVALID_SECTOR, "the sector of Hall code 000 or 111"),
    ("PERIOD_NEVER", PERIOD_NEVER, "above every 16-bit period: the safe state"),
)

INPUTS = StructType(
    "bldc_inputs_t",
    "Inputs",
    (
        StructField("hall_code", U8, "A B C as bits 2 1 0"),
        StructField("previous_hall_code", U8, "code of the sector being left: gives the direction"),
        StructField("hall_period_ticks", U16, "last 60 degree interval, Hall ticks"),
        StructField("bus_voltage_adc", U16, "bus code"),
        StructField("phase_current_adc", U16, "current code of the commutated current I"),
        StructField("main_duty_counts", U16, "current controller output, TIM1 counts"),
    ),
    "Inputs of one commutation decision (bldc_commutate)",
)

OUTPUTS = StructType(
    "bldc_outputs_t",
    "Outputs",
    (
        StructField("turn_on_compare", U16, "D_on: ON time of turn_on_switch in TIM1 counts"),
        StructField("turn_off_compare", U16, "D_off: ON time of turn_off_switch in TIM1 counts"),
        StructField("commutation_ticks", U16, "Eq. 20 in Hall ticks, at most the Hall period"),
        StructField("turn_on_switch", U8, "0..5 (T1..T6) or BLDC_NO_SWITCH"),
        StructField("turn_off_switch", U8, "0..5 (T1..T6) or BLDC_NO_SWITCH"),
        StructField("sector", U8, "sector entered, 0..5 in Table 1 order; 0xFF if invalid"),
        StructField("flags", U8, "BLDC_FLAG_*"),
    ),
    "Result of one commutation decision",
)

TIMING = StructType(
    "bldc_timing_t",
    "Timing",
    (
        StructField(
            "period_min",
            U32,
            "an edge with a shorter interval goes to the safe state: BLDC_PERIOD_MIN_TICKS, "
            "or BLDC_PERIOD_NEVER when these values must not be applied",
        ),
        StructField("turn_on_compare", U16, "D_on in TIM1 counts, 0..P"),
        StructField("turn_off_compare", U16, "D_off in TIM1 counts, 0..P"),
        StructField("commutation_ticks", U16, "Eq. 20 in Hall ticks, 0..T"),
        StructField("flags", U16, "BLDC_FLAG_*"),
    ),
    "Duties and commutation time for one speed, current and main duty: what the next "
    "Hall edge applies",
)

PUBLIC_STRUCTS = (INPUTS, OUTPUTS, TIMING)


def flag_const(name: str) -> IConst:
    """BLDC_FLAG_<name> as an IR constant."""
    flag = next(f for f in FLAGS if f.name == name)
    return IConst(U32, flag.value, f"BLDC_FLAG_{flag.name}", doc=flag.doc)


def value_const(name: str) -> IConst:
    for n, v, doc in VALUES:
        if n == name:
            return IConst(U32, v, f"BLDC_{n}", doc=doc)
    raise KeyError(name)


def struct_layout(struct: StructType) -> list[dict[str, object]]:
    """A struct as the manifest records it: field name, C type, bits, signedness."""
    return [
        {"name": f.name, "c_type": f.ctype.name, "bits": f.ctype.bits, "signed": f.ctype.signed}
        for f in struct.fields
    ]


def manifest_entry() -> dict[str, object]:
    """The ABI as data, for generated/<name>/manifest.json."""
    return {
        "flags": {f.name: f.value for f in FLAGS},
        "values": {n: v for n, v, _ in VALUES},
        "structs": {s.c_name: struct_layout(s) for s in PUBLIC_STRUCTS},
    }


_CTYPES = {
    "uint8_t": "c_uint8",
    "uint16_t": "c_uint16",
    "uint32_t": "c_uint32",
    "int32_t": "c_int32",
}


def ctypes_struct(struct: StructType) -> type:
    """The struct as a ctypes.Structure (C layout), for calling the core from Python."""
    import ctypes

    fields = [(f.name, getattr(ctypes, _CTYPES[f.ctype.name])) for f in struct.fields]
    return type(struct.py_name, (ctypes.Structure,), {"_fields_": fields})


def numpy_dtype(struct: StructType) -> object:
    """The struct as an aligned numpy structured dtype (C layout), for batches."""
    import numpy as np

    return np.dtype(
        [
            (f.name, np.dtype(f"{'i' if f.ctype.signed else 'u'}{f.ctype.bits // 8}"))
            for f in struct.fields
        ],
        align=True,
    )
