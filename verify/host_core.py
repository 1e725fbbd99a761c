"""The generated core, built for the host as a shared library and called in batches.

One ctypes call per point would cost more than the core itself, so a small shim in the
library loops over arrays of the core's input and output structs. The structs are
mirrored as numpy structured dtypes with the C layout (aligned), built from the
manifest's ABI (`dtype_of`) and checked against sizeof() at load time.
"""

from __future__ import annotations

import ctypes
import importlib.util
import subprocess
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import numpy as np
import numpy.typing as npt

SHIM = """\
/* Batch entry for the verifier: not part of the firmware. */
#include <stddef.h>
#include "bldc_commutation.h"
size_t verify_sizeof_inputs(void) { return sizeof(bldc_inputs_t); }
size_t verify_sizeof_outputs(void) { return sizeof(bldc_outputs_t); }
void verify_batch(const bldc_inputs_t *in, bldc_outputs_t *out, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++) {
        bldc_commutate(&in[k], &out[k]);
    }
}
size_t verify_sizeof_timing(void) { return sizeof(bldc_timing_t); }
/* bldc_commutation_timing() on its own uint32_t parameters: args holds (bus code,
 * period, current, main duty) per point */
void verify_timing_batch(const uint32_t *args, bldc_timing_t *out, size_t n)
{
    size_t k;
    for (k = 0; k < n; k++) {
        const bldc_bus_t bus = bldc_bus_condition(args[4u * k]);
        out[k] = bldc_commutation_timing(&bus, args[4u * k + 1u], args[4u * k + 2u], args[4u * k + 3u]);
    }
}
"""
CFLAGS = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Wconversion", "-Werror", "-fPIC", "-shared"]


def load_twin(generated: Path, name: str = "bldc_fixed") -> ModuleType:
    """The generated Python twin `python/<name>.py` of an output folder, imported under
    a name of its own (two folders' twins do not share a module)."""
    path = generated / "python" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"{name}_{abs(hash(path))}", path)
    if spec is None or spec.loader is None:
        raise FileNotFoundError(path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def dtype_of(layout: list[dict[str, object]]) -> np.dtype:
    """A C struct as a numpy structured dtype (C layout), from the manifest's ABI."""
    fields = []
    for f in layout:
        kind = "i" if f["signed"] else "u"
        fields.append((str(f["name"]), np.dtype(f"{kind}{int(f['bits']) // 8}")))  # type: ignore[call-overload]
    return np.dtype(fields, align=True)


@dataclass(frozen=True)
class HostCore:
    library: ctypes.CDLL
    path: Path
    input_dtype: np.dtype
    output_dtype: np.dtype
    timing_dtype: np.dtype

    def timing(self, args: npt.NDArray[np.uint32]) -> npt.NDArray[np.void]:
        """bldc_commutation_timing() for each row (bus code, period, current, main duty)
        of `args`, its bus from bldc_bus_condition(): every uint32_t value allowed."""
        rows = np.ascontiguousarray(args, dtype=np.uint32).reshape(-1, 4)
        outputs = np.zeros(rows.shape[0], dtype=self.timing_dtype)
        self.library.verify_timing_batch(
            rows.ctypes.data_as(ctypes.c_void_p),
            outputs.ctypes.data_as(ctypes.c_void_p),
            ctypes.c_size_t(rows.shape[0]),
        )
        return outputs

    def run(self, inputs: npt.NDArray[np.void]) -> npt.NDArray[np.void]:
        inputs = np.ascontiguousarray(inputs, dtype=self.input_dtype)
        outputs = np.zeros(inputs.shape, dtype=self.output_dtype)
        self.library.verify_batch(
            inputs.ctypes.data_as(ctypes.c_void_p),
            outputs.ctypes.data_as(ctypes.c_void_p),
            ctypes.c_size_t(inputs.size),
        )
        return outputs


def compile_with_shim(
    source: Path, shim_text: str, build_dir: Path, name: str
) -> tuple[ctypes.CDLL, Path]:
    """gcc `source` (with its folder on the include path) and the shim `name`.c into
    lib`name`.so under CFLAGS (-Werror: any warning fails); the loaded library and its
    path."""
    build_dir.mkdir(parents=True, exist_ok=True)
    shim = build_dir / f"{name}.c"
    shim.write_text(shim_text, encoding="utf-8")
    library = build_dir / f"lib{name}.so"
    subprocess.run(
        ["gcc", *CFLAGS, f"-I{source.parent}", str(source), str(shim), "-o", str(library)],
        check=True,
        capture_output=True,
        text=True,
    )
    return ctypes.CDLL(str(library)), library


def build_host_core(
    c_dir: Path,
    build_dir: Path,
    input_dtype: np.dtype,
    output_dtype: np.dtype,
    timing_dtype: np.dtype,
) -> HostCore:
    """Compile c_dir/bldc_commutation.c with the batch shim; fail on any warning."""
    dll, library = compile_with_shim(c_dir / "bldc_commutation.c", SHIM, build_dir, "verify_batch")
    for entry in (dll.verify_batch, dll.verify_timing_batch):
        entry.restype = None
        entry.argtypes = [ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t]
    for name, dtype in (
        ("inputs", input_dtype),
        ("outputs", output_dtype),
        ("timing", timing_dtype),
    ):
        size = getattr(dll, f"verify_sizeof_{name}")
        size.restype = ctypes.c_size_t
        if size() != dtype.itemsize:
            raise RuntimeError(f"bldc_{name}_t is {size()} bytes in C, {dtype.itemsize} here")
    return HostCore(dll, library, input_dtype, output_dtype, timing_dtype)
