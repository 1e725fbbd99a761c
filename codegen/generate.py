"""`generate SPEC`: write generated/<spec name>/ atomically.

Everything is rendered in memory first, so a spec or design error writes nothing; then
codegen.publish stages the tree beside the target and swaps it in with one atomic
exchange, keeping whatever in the target bldc-codegen did not write (verify and
simulation reports, a user's own files). The manifest lists every file with its SHA-256
and every folder, which is how later runs know what they may replace.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path

from codegen import __version__
from codegen.audit.motor_report import render_derivation
from codegen.control import current_loop
from codegen.core.float_model import float_model_context
from codegen.core.module import Core, build_core, core_context, manifest_entry
from codegen.derivation import derive
from codegen.firmware import render_firmware_files
from codegen.port import render_port_files
from codegen.proof.harness import render_proof_files
from codegen.publish import MANIFEST, PublishError, PublishResult, manifest_record, publish
from codegen.render import project_relative, provenance, render
from codegen.shown import said
from codegen.spec_loader import PAPER_AUDIT_NAME, load_spec
from codegen.spec_model import Spec
from codegen.unity_cases import unity_cases
from codegen.unity_render import render_unity_tests

#: output path -> template (relative to templates/)
CORE_FILES = {
    "c/bldc_commutation.h": "c/bldc_commutation.h.j2",
    "c/bldc_commutation.c": "c/bldc_commutation.c.j2",
    "python/bldc_fixed.py": "python/bldc_fixed.py.j2",
}


@dataclass(frozen=True)
class Generated:
    spec: Spec
    core: Core
    files: dict[str, str]


def _core_files(spec: Spec, core: Core) -> dict[str, str]:
    context = core_context(core)
    return {
        out: render(template, provenance=provenance(f"templates/{template}", spec), **context)
        for out, template in CORE_FILES.items()
    }


def render_core(spec_path: str | Path) -> Generated:
    """The core's files alone (CORE_FILES), exactly as `render_all` renders them, and a
    manifest that says so (`"output": "core"`): what the simulation compiles for a
    method's variant, without the port, firmware, tests, proof harness and DERIVATION.md
    it never reads (0.45 s of each variant's 0.75 s)."""
    spec = load_spec(spec_path)
    core = build_core(spec)
    files = _core_files(spec, core)
    record = manifest_record(files)
    manifest = {
        "generator": record["generator"],
        "generator_version": __version__,
        "output": "core",
        "spec": project_relative(spec.source_path),
        "spec_name": spec.name,
        "spec_sha256": spec.sha256,
        "core": manifest_entry(core),
        "folders": record["folders"],
        "files": record["files"],
    }
    files[MANIFEST] = json.dumps(manifest, indent=2) + "\n"
    return Generated(spec, core, files)


def render_all(spec_path: str | Path) -> Generated:
    spec = load_spec(spec_path)
    derivation = derive()
    # The paper's audit is one report for every motor (`audit`, generated/paper/).
    files: dict[str, str] = {"DERIVATION.md": render_derivation(derivation, spec)}
    core = build_core(spec)
    files.update(_core_files(spec, core))
    files.update(current_loop.render_loop_files(spec))
    files.update(render_proof_files(core))
    files.update({f"c/{name}": text for name, text in render_port_files(spec).items()})
    files.update(render_firmware_files(spec))
    float_template = "python/bldc_float.py.j2"
    files["python/bldc_float.py"] = render(
        float_template,
        provenance=provenance(f"templates/{float_template}", spec),
        **float_model_context(spec, derivation),
    )
    files.update(
        render_unity_tests(
            unity_cases(spec),
            lambda template: provenance(template, spec),
        )
    )
    record = manifest_record(files)
    manifest = {
        "generator": record["generator"],
        "generator_version": __version__,
        "spec": project_relative(spec.source_path),
        "spec_name": spec.name,
        "spec_sha256": spec.sha256,
        "core": manifest_entry(core),
        "current_loop": current_loop.manifest_entry(current_loop.design(spec)),
        "folders": record["folders"],
        "files": record["files"],
    }
    files[MANIFEST] = json.dumps(manifest, indent=2) + "\n"
    return Generated(spec, core, files)


def refuse_audit_folder(target: Path) -> None:
    """PublishError where `target`, as given or where its links lead, is a
    generated/paper/ folder: the paper audit's (`audit` writes AUDIT.md and AUDIT.html
    there), never a spec's tree (`generate -o generated/paper` had been accepted, though
    a spec named paper is refused for that folder)."""
    for path in (Path(os.path.abspath(target)), Path(os.path.realpath(target))):
        if path.name == PAPER_AUDIT_NAME and path.parent.name == "generated":
            raise PublishError(
                f"{said(target)} is the paper audit's folder (generated/{PAPER_AUDIT_NAME}/,"
                " where `audit` writes AUDIT.md), not a spec's: choose another output folder,"
                " e.g. generated/<spec name>"
            )


def write_tree(files: dict[str, str], target: Path) -> PublishResult:
    """Publish the rendered tree into `target` atomically (codegen.publish), never into
    the paper audit's folder."""
    refuse_audit_folder(target)
    return publish(files, target)


def generate(spec_path: str | Path, output: str | Path | None, project_root: Path) -> Generated:
    """Render and publish; `output` defaults to project_root/generated/<name> (the CLI
    passes its own, resolved against the working directory)."""
    result = render_all(spec_path)
    target = Path(output) if output else project_root / "generated" / result.spec.name
    write_tree(result.files, target)
    return result
