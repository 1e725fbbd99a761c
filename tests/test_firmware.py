"""`make firmware`: the generated core and port link into a Cortex-M3 image."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from codegen.build_firmware import MAP, build
from codegen.errors import ExitCode
from codegen.firmware import tim3_irq_number, vector_table
from codegen.publish import PublishError
from codegen.report_folder import BUILD_LEDGER

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "generated" / "paper_motor"

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
    """`firmware --build DIR` removes its own files of a former build that this one does
    not write (a stale Cube-style `it` report), and no other file: it had removed every
    *.su and *.ci in DIR."""
    mine = {tmp_path / "notes.su": "user", tmp_path / "graph.ci": "user"}
    for path, text in mine.items():
        path.write_text(text)
    (tmp_path / "it.su").write_text("stale")  # a former Cube-style build's, in its ledger
    (tmp_path / BUILD_LEDGER).write_text(f"it.su\t{hashlib.sha256(b'stale').hexdigest()}\n")
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
    (tmp_path / "main.o").write_text("mine")
    with pytest.raises(PublishError, match=r"main\.o is in the way"):
        build(ROOT / "generated" / "paper_motor", tmp_path)
    assert (tmp_path / "main.o").read_text() == "mine" and not (tmp_path / "core.o").exists()
    (tmp_path / "main.o").unlink()
    build(ROOT / "generated" / "paper_motor", tmp_path)
    assert "main.o" in _ledger(tmp_path)
    build(ROOT / "generated" / "paper_motor", tmp_path)  # its own files: replaced
    legacy = tmp_path / "legacy"
    legacy.mkdir()
    (legacy / "main.o").write_text("old object")
    (legacy / "firmware.map").write_text("\nDiscarded input sections\n .text 0x0 0x0 x/core.o\n")
    build(ROOT / "generated" / "paper_motor", legacy)  # a build folder from before the ledger
    assert (legacy / "main.o").read_bytes() != b"old object"


def test_a_build_interrupted_half_way_should_leave_the_folder_as_it_was(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, gone_pid: str
) -> None:
    """Written in place, a build interrupted (Ctrl-C, a compile error) after its first
    object had left core.o unlisted, and every later build into the folder refused it.
    The build compiles into a staging folder inside the build folder and moves its files
    in at the end: an interrupted one leaves nothing, and the next build runs."""
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
    assert len(calls) == 2 and list(tmp_path.iterdir()) == []
    gone = gone_pid
    killed = tmp_path / f"{BUILD_LEDGER}.staging-{gone}-abc123"  # a build killed (SIGKILL)
    killed.mkdir()
    (killed / "core.o").write_text("half")
    build(ROOT / "generated" / "paper_motor", tmp_path)
    assert (tmp_path / "firmware.elf").is_file() and not killed.exists()
    assert not [p for p in tmp_path.iterdir() if ".staging-" in p.name]


def _ledger(folder: Path) -> dict[str, str]:
    """The build ledger's `name<TAB>sha256` lines: name -> hash."""
    lines = (folder / BUILD_LEDGER).read_text().splitlines()
    return dict(line.split("\t") for line in lines)


def _contents(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def test_a_forged_build_ledger_line_should_not_let_the_build_overwrite_a_users_file(
    tmp_path: Path,
) -> None:
    """The build ledger listed names only: a line "main.o" (forged, or left by another
    folder's copy) had `firmware --build DIR` overwrite the user's own main.o. A listed
    file is the tool's only while its content has the SHA-256 recorded for it; a names-
    only ledger counts only where the folder's map is a build's (an earlier version's)."""
    build_dir = tmp_path / "build"
    build_dir.mkdir()
    (build_dir / "main.o").write_bytes(b"my own object\n")
    (build_dir / BUILD_LEDGER).write_text("main.o\n")
    before = _contents(build_dir)
    proc = subprocess.run(
        [sys.executable, "-m", "codegen", "firmware", str(ROOT / "spec" / "paper_motor.yaml"),
         "--generated", str(PAPER), "--build", str(build_dir)],
        cwd=tmp_path,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )  # fmt: skip
    assert proc.returncode == ExitCode.ENVIRONMENT, proc.stderr
    assert proc.stderr.splitlines() == [
        f"error: output: {build_dir / 'main.o'} is in the way and was not written by"
        f" bldc-codegen (the folder's {BUILD_LEDGER} does not list it with its content's"
        " SHA-256): move it away or choose another output folder"
    ]
    assert _contents(build_dir) == before
    digest = hashlib.sha256(b"an object of the tool's, overwritten since").hexdigest()
    (build_dir / BUILD_LEDGER).write_text(f"main.o\t{digest}\n")  # a hash it has not
    with pytest.raises(PublishError, match=r"main\.o is in the way and was not written"):
        build(PAPER, build_dir)
    assert (build_dir / "main.o").read_bytes() == b"my own object\n"


def test_a_rebuild_should_replace_the_builds_own_files_and_record_their_hashes(
    tmp_path: Path,
) -> None:
    """The ledger lists each file the build wrote with its content's SHA-256; a rebuild
    into the same folder replaces them all (a file moved in: a new inode), the user's
    own files beside them left alone."""
    (tmp_path / "notes.txt").write_text("mine")
    build(PAPER, tmp_path)
    ledger = _ledger(tmp_path)
    built = sorted(p.name for p in tmp_path.iterdir() if p.name not in (BUILD_LEDGER, "notes.txt"))
    assert sorted(ledger) == built and "main.o" in built and MAP in built
    assert all(hashlib.sha256((tmp_path / n).read_bytes()).hexdigest() == ledger[n] for n in built)
    inodes = {name: (tmp_path / name).stat().st_ino for name in built}
    build(PAPER, tmp_path)
    assert _ledger(tmp_path) == ledger  # the same sources: the same files
    assert all((tmp_path / name).stat().st_ino != inodes[name] for name in built)
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_a_build_file_the_user_edited_should_be_kept_and_the_build_refused(
    tmp_path: Path,
) -> None:
    """A file of the build edited by its user since (a map annotated by hand) had been
    overwritten by the next build, its name in the ledger: its content no longer has
    the hash recorded, so it is the user's and the build stops before it starts."""
    build(PAPER, tmp_path)
    with (tmp_path / MAP).open("a") as edited:
        edited.write("my notes on the layout\n")
    before = _contents(tmp_path)
    with pytest.raises(PublishError, match=r"firmware\.map is in the way and was not written"):
        build(PAPER, tmp_path)
    assert _contents(tmp_path) == before


def test_a_build_ledger_of_an_earlier_version_should_count_by_the_map(tmp_path: Path) -> None:
    """A build ledger of names without hashes (an earlier version's) counts as a build
    folder from before the ledger, as the report ledger's does: where the map is a
    build's, the new build's files are replaced and nothing else is removed; the ledger
    then lists them with their hashes."""
    (tmp_path / "main.o").write_text("old object")
    (tmp_path / MAP).write_text("\nDiscarded input sections\n .text 0x0 0x0 x/core.o\n")
    (tmp_path / "it.su").write_text("a former Cube-style build's, or the user's")
    (tmp_path / BUILD_LEDGER).write_text("it.su\nmain.o\nfirmware.map\n")
    build(PAPER, tmp_path)
    assert (tmp_path / "main.o").read_bytes() != b"old object"
    assert (tmp_path / "it.su").read_text() == "a former Cube-style build's, or the user's"
    assert "it.su" not in _ledger(tmp_path) and "main.o" in _ledger(tmp_path)


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
