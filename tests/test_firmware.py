"""`make firmware`: the generated core and port link into a Cortex-M3 image."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from codegen.build_firmware import build
from codegen.firmware import tim3_irq_number, vector_table
from codegen.report_folder import BUILD_LEDGER

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(shutil.which("arm-none-eabi-gcc") is None, reason="no arm gcc")


def test_tim3_vector_should_sit_at_its_svd_interrupt_number() -> None:
    table = vector_table()
    assert tim3_irq_number() == 29
    assert table[0] == "Reset_Handler"  # vector 1; vector 0 is the initial stack pointer
    assert table[15 + 29] == "TIM3_IRQHandler"  # vector 16 + 29
    assert table.count("TIM3_IRQHandler") == 1 and len(table) == 15 + 43


def vector(elf: Path, irq: int, work: Path) -> int:
    """The vector table's entry for interrupt `irq` in the linked image."""
    table = work / "vectors.bin"
    subprocess.run(
        ["arm-none-eabi-objcopy", "-O", "binary", "-j", ".isr_vector", str(elf), str(table)],
        check=True,
    )
    return int.from_bytes(table.read_bytes()[4 * (16 + irq) : 4 * (16 + irq + 1)], "little")


@pytest.mark.parametrize("name", ["paper_motor", "maxon_ec45_flat_48v"])
def test_firmware_should_link_with_the_handler_in_the_vector_table(
    name: str, tmp_path: Path
) -> None:
    sizes = build(ROOT / "generated" / name, tmp_path)
    elf = tmp_path / "firmware.elf"
    symbols = subprocess.run(
        ["arm-none-eabi-nm", str(elf)], check=True, capture_output=True, text=True
    ).stdout
    handler = next(
        int(line.split()[0], 16)
        for line in symbols.splitlines()
        if line.endswith(" TIM3_IRQHandler")
    )
    assert vector(elf, 29, tmp_path) == handler | 1  # Thumb bit set
    assert sizes["firmware.elf"].flash > 0 and "__aeabi" not in symbols
    # the timing slots: 32-byte aligned, so the two differ in address bit 4 alone (the
    # timing handler finds the one to fill by an XOR with 16)
    slots = next(line for line in symbols.splitlines() if line.endswith(" port_slots"))
    assert int(slots.split()[0], 16) % 32 == 0


def test_a_build_folder_should_keep_the_users_own_stack_reports(tmp_path: Path) -> None:
    """`firmware --build DIR` removes its own objects' .su and .ci before it compiles
    (a stale Cube-style `it` report too), and no other file: it had removed every *.su
    and *.ci in DIR."""
    mine = {tmp_path / "notes.su": "user", tmp_path / "graph.ci": "user"}
    for path, text in mine.items():
        path.write_text(text)
    (tmp_path / "it.su").write_text("stale")  # a former Cube-style build's, in its ledger
    (tmp_path / BUILD_LEDGER).write_text("it.su\n")
    build(ROOT / "generated" / "paper_motor", tmp_path)
    assert all(path.read_text() == text for path, text in mine.items())
    assert not (tmp_path / "it.su").exists() and (tmp_path / "core.su").is_file()


def test_a_build_folder_holding_a_users_file_of_a_build_name_should_be_refused(
    tmp_path: Path,
) -> None:
    """`firmware --build DIR` wrote its objects and image straight into DIR and
    replaced a user's `firmware.map` and `main.o`; a file of the build's names that DIR's
    ledger does not list stops the build before it starts, and a former build's own
    files (its ledger, or a map from before the ledger) are replaced."""
    from codegen.publish import PublishError

    (tmp_path / "main.o").write_text("mine")
    with pytest.raises(PublishError, match=r"main\.o is in the way"):
        build(ROOT / "generated" / "paper_motor", tmp_path)
    assert (tmp_path / "main.o").read_text() == "mine" and not (tmp_path / "core.o").exists()
    (tmp_path / "main.o").unlink()
    build(ROOT / "generated" / "paper_motor", tmp_path)
    assert "main.o" in (tmp_path / BUILD_LEDGER).read_text().split()
    build(ROOT / "generated" / "paper_motor", tmp_path)  # its own files: replaced
    legacy = tmp_path / "legacy"
    legacy.mkdir()
    (legacy / "main.o").write_text("old object")
    (legacy / "firmware.map").write_text("\nDiscarded input sections\n .text 0x0 0x0 x/core.o\n")
    build(ROOT / "generated" / "paper_motor", legacy)  # a build folder from before the ledger
    assert (legacy / "main.o").read_bytes() != b"old object"


def test_a_build_interrupted_half_way_should_leave_files_the_next_build_knows(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The build lists its names in its ledger before it writes them: recorded only at
    the end, a build interrupted (Ctrl-C, a compile error) after its first object had
    left core.o unlisted, and every later build into the folder refused it."""
    import codegen.build_firmware as build_module

    real = subprocess.run
    calls = []

    def failing(args: list[str], **kwargs: object) -> object:
        calls.append(args)
        if len(calls) == 2:  # after core.o: the second compile fails
            raise subprocess.CalledProcessError(1, args)
        return real(args, **kwargs)  # type: ignore[call-overload]

    with monkeypatch.context() as patch:
        patch.setattr(build_module.subprocess, "run", failing)
        with pytest.raises(subprocess.CalledProcessError):
            build(ROOT / "generated" / "paper_motor", tmp_path)
    assert (tmp_path / "core.o").is_file() and not (tmp_path / "firmware.elf").exists()
    build(ROOT / "generated" / "paper_motor", tmp_path)  # its own half-build: replaced
    assert (tmp_path / "firmware.elf").is_file()


def test_a_report_written_into_a_build_folder_should_leave_the_image(tmp_path: Path) -> None:
    """The build keeps its own ledger: in the report folders' one, `simulate -o` into a
    build folder took the image for a former report's files and deleted it."""
    from codegen.report_folder import staged_report

    build(ROOT / "generated" / "paper_motor", tmp_path)
    with staged_report(tmp_path, "REPORT.md", "<!-- report") as staging:
        (staging / "REPORT.md").write_text("<!-- report -->\n")
    assert (tmp_path / "firmware.elf").is_file() and (tmp_path / "core.o").is_file()
    assert (tmp_path / "REPORT.md").is_file()


# ------------------------------------------------------------ Cube integration

CUBE_SPEC = ROOT / "tests" / "fixtures" / "specs" / "offset_conventional.yaml"


def test_cube_integration_should_leave_only_the_hot_vectors_to_the_port() -> None:
    from codegen.port_drive import HANDLERS, handler_names
    from codegen.spec_loader import load_spec

    spec = load_spec(str(CUBE_SPEC))
    assert spec.firmware.integration == "cube"
    owned = {role for role, h in HANDLERS.items() if h.cube_owned}
    assert owned == {"hall", "timing"}
    assert handler_names(spec) == {
        "hall": "TIM3_IRQHandler",
        "timing": "TIM1_TRG_COM_IRQHandler",
        "bus": "bldc_port_tim1_up_irq",
        "adc": "bldc_port_adc_irq",
        "brk": "bldc_port_tim1_brk_irq",
        "hall_line0": "bldc_port_exti0_irq",
        "hall_lines9_5": "bldc_port_exti9_5_irq",
    }
    vector_spec = load_spec(str(ROOT / "spec" / "paper_motor.yaml"))
    assert set(handler_names(vector_spec).values()) == {h.vector for h in HANDLERS.values()}


def test_cube_stand_in_it_c_should_not_define_the_ports_vectors_and_say_why() -> None:
    from codegen.firmware import render_firmware_files
    from codegen.spec_loader import load_spec

    it_c = render_firmware_files(load_spec(str(CUBE_SPEC)))["firmware/stm32f1xx_it.c"]
    for vector in ("TIM3_IRQHandler", "TIM1_TRG_COM_IRQHandler"):
        assert f"void {vector}(void)\n{{" not in it_c
        assert f"void {vector}(void);" not in it_c
    for vector, call in (
        ("ADC1_2_IRQHandler", "bldc_port_adc_irq"),
        ("TIM1_UP_IRQHandler", "bldc_port_tim1_up_irq"),
        ("TIM1_BRK_IRQHandler", "bldc_port_tim1_brk_irq"),
        ("EXTI0_IRQHandler", "bldc_port_exti0_irq"),
        ("EXTI9_5_IRQHandler", "bldc_port_exti9_5_irq"),
    ):
        body = it_c[it_c.index(f"void {vector}(void)\n{{") :].split("}", 1)[0]
        assert f"{call}();" in body
    # what to untick in CubeMX, under the names its NVIC tab shows
    assert 'untick "Generate IRQ handler"' in it_c
    assert '"TIM3 global interrupt" (TIM3_IRQHandler)' in it_c
    assert '"TIM1 trigger and commutation interrupts" (TIM1_TRG_COM_IRQHandler)' in it_c
    assert "multiple definition of `TIM3_IRQHandler'" in it_c


@pytest.fixture(scope="module")
def cube_generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from codegen.generate import generate

    out = tmp_path_factory.mktemp("cube") / "generated"
    generate(CUBE_SPEC, out, ROOT)
    return out


def _defined(obj: Path) -> set[str]:
    out = subprocess.run(
        ["arm-none-eabi-nm", "--defined-only", str(obj)],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    return {line.split()[-1] for line in out.splitlines() if line.split()[1] in "Tt"}


def test_cube_firmware_should_enter_the_hall_edge_and_timing_in_the_port_directly(
    cube_generated: Path, tmp_path: Path
) -> None:
    build(cube_generated, tmp_path)
    port, it = _defined(tmp_path / "port.o"), _defined(tmp_path / "it.o")
    assert {"TIM3_IRQHandler", "TIM1_TRG_COM_IRQHandler"} <= port
    assert not {"TIM3_IRQHandler", "TIM1_TRG_COM_IRQHandler"} & it
    assert {"ADC1_2_IRQHandler", "TIM1_BRK_IRQHandler", "EXTI0_IRQHandler"} <= it
    assert "bldc_port_tim3_irq" not in port and "bldc_port_adc_irq" in port
    elf = tmp_path / "firmware.elf"
    symbols = {
        line.split()[-1]: int(line.split()[0], 16)
        for line in subprocess.run(
            ["arm-none-eabi-nm", str(elf)], check=True, capture_output=True, text=True
        ).stdout.splitlines()
        if len(line.split()) == 3
    }
    assert vector(elf, 29, tmp_path) == symbols["TIM3_IRQHandler"] | 1
    assert vector(elf, 26, tmp_path) == symbols["TIM1_TRG_COM_IRQHandler"] | 1


def test_a_cube_it_c_that_still_defines_tim3_irqhandler_should_not_link(
    cube_generated: Path, tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    """The CubeMX untick forgotten: stm32f1xx_it.c keeps its generated TIM3 handler.
    The link fails and names the symbol; no image picks one of the two silently."""
    copy = tmp_path / "generated"
    shutil.copytree(cube_generated, copy)
    it_c = copy / "firmware" / "stm32f1xx_it.c"
    it_c.write_text(
        it_c.read_text(encoding="utf-8")
        + "\nvoid TIM3_IRQHandler(void);\nvoid TIM3_IRQHandler(void)\n{\n}\n",
        encoding="utf-8",
    )
    capfd.readouterr()
    with pytest.raises(subprocess.CalledProcessError) as failed:
        build(copy, tmp_path / "build")
    assert "-T" in failed.value.cmd  # the link, not a compile, failed
    assert "multiple definition of `TIM3_IRQHandler'" in capfd.readouterr().err
    assert not (tmp_path / "build" / "firmware.elf").exists()
