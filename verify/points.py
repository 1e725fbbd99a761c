"""Input sets of the verifier: exhaustive, random (seeded) and boundary.

Each set is a structured array of the core's inputs (verify.host_core.INPUT_DTYPE).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from codegen.fixedpoint.scaling import Scaling
from codegen.reference import ExactModel, operating_codes
from codegen.spec_model import Spec
from verify.host_core import INPUT_DTYPE

Inputs = npt.NDArray[np.void]


def _inputs(*columns: npt.ArrayLike) -> Inputs:
    arrays = np.broadcast_arrays(*(np.asarray(c, dtype=np.int64) for c in columns))
    out = np.zeros(arrays[0].size, dtype=INPUT_DTYPE)
    for name, values in zip(INPUT_DTYPE.names or (), arrays, strict=True):
        out[name] = values.ravel()
    return out


def valid_edges(model: ExactModel) -> list[tuple[int, int]]:
    """(previous code, code) of the 12 commutations: 6 forward, 6 reverse."""
    return [(a, b) for a in model.hall_sequence for b in model.hall_sequence if model.edge(a, b)]


def exhaustive(spec: Spec, sc: Scaling, model: ExactModel) -> Inputs:
    """Every period code of the spec's speed range, at the bus minimum, nominal and
    maximum, for every valid Hall transition (both directions)."""
    bus_nominal, current, duty = operating_codes(spec, sc)
    periods = np.arange(sc.period_min_ticks, sc.period_max_ticks + 1)
    buses = np.array([sc.bus_code_min, bus_nominal, sc.bus_code_max])
    edges = np.array(valid_edges(model))
    e, b, t = np.meshgrid(np.arange(len(edges)), buses, periods, indexing="ij")
    return _inputs(edges[e, 1], edges[e, 0], t, b, current, duty)


def random_points(sc: Scaling, model: ExactModel, seed: int, count: int) -> Inputs:
    """Across the whole input space: mostly valid transitions, some invalid codes;
    periods log-uniform from half the minimum to the counter's top; every ADC code."""
    rng = np.random.default_rng(seed)
    edges = np.array(valid_edges(model))
    pick = edges[rng.integers(0, len(edges), count)]
    wild = rng.random(count) < 0.1
    hall = np.where(wild, rng.integers(0, 8, count), pick[:, 1])
    previous = np.where(wild, rng.integers(0, 8, count), pick[:, 0])
    low, high = np.log(sc.period_min_ticks / 2), np.log(sc.period_cap_ticks)
    period = np.exp(rng.uniform(low, high, count)).astype(np.int64)
    top = sc.adc_full_scale
    bus = np.where(
        rng.random(count) < 0.8,
        rng.integers(sc.bus_code_min, sc.bus_code_max + 1, count),
        rng.integers(0, top, count),
    )
    current = np.where(
        rng.random(count) < 0.8,
        rng.integers(
            sc.current_offset_code, sc.current_offset_code + sc.current_code_max + 1, count
        ),
        rng.integers(0, top, count),
    )
    duty = rng.integers(0, 2 * sc.period_counts, count)
    return _inputs(hall, previous, period, bus, current, duty)


def boundaries(spec: Spec, sc: Scaling, model: ExactModel) -> Inputs:
    """The segment cut-off and one code either side, the speed limits, zero current,
    out-of-range inputs and invalid Hall codes."""
    bus_nominal, current, duty = operating_codes(spec, sc)
    forward = valid_edges(model)[0]
    rows: list[tuple[int, int, int, int, int, int]] = []
    buses = (sc.bus_code_min, bus_nominal, sc.bus_code_max)
    for bus in buses:
        # 4E > U_d <=> lhs > rhs T B: the first low-speed period is ceil(lhs / (rhs B)).
        cut = -(-model.boundary_lhs // (model.boundary_rhs * bus))
        for period in range(cut - 2, cut + 3):
            for previous, code in valid_edges(model):
                rows.append((code, previous, period, bus, current, duty))
    speeds = (
        sc.period_min_ticks - 1,
        sc.period_min_ticks,
        sc.period_min_ticks + 1,
        sc.period_max_ticks - 1,
        sc.period_max_ticks,
        sc.period_max_ticks + 1,
        sc.period_cap_ticks,
        0,
        1,
    )
    currents = (
        sc.current_offset_code - 1,
        sc.current_offset_code,
        sc.current_offset_code + 1,
        sc.current_offset_code + sc.current_code_max,
        sc.current_offset_code + sc.current_code_max + 1,
        0,
        sc.adc_full_scale - 1,
    )
    bus_edges = (0, sc.bus_code_min - 1, *buses, sc.bus_code_max + 1, sc.adc_full_scale - 1)
    duties = (0, sc.period_counts, sc.period_counts + 1, 0xFFFF)
    for period in speeds:
        for bus in bus_edges:
            for i in currents:
                for d in duties:
                    rows.append((forward[1], forward[0], period, bus, i, d))
    for code in range(10):
        for previous in (*range(10), 0xFF):
            rows.append(
                (
                    code,
                    previous,
                    (sc.period_min_ticks + sc.period_max_ticks) // 2,
                    bus_nominal,
                    current,
                    duty,
                )
            )
    for code in (0xFF, 0x80):
        rows.append((code, forward[0], sc.period_max_ticks, bus_nominal, current, duty))
    return _inputs(*np.array(rows).T)
