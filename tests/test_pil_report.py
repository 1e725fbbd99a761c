"""`emulation.pil.report`'s publication of PIL.md and the braking run's CSV."""

from __future__ import annotations

import stat
from pathlib import Path

from emulation.pil.report import publish


def test_published_outputs_should_get_the_permissions_of_any_new_file(tmp_path: Path) -> None:
    """PIL.md and braking_commutations.csv are written beside and renamed; a temporary
    file from `tempfile` is its owner's alone (0600), and renamed so the CSV was, while
    the figures beside it were 0644."""
    plain = tmp_path / "plain.txt"
    plain.write_text("x", encoding="utf-8")  # the umask's permissions
    target = tmp_path / "pil" / "braking_commutations.csv"
    publish("a,b\n1,2\n", target)
    assert target.read_text(encoding="utf-8") == "a,b\n1,2\n"
    assert stat.S_IMODE(target.stat().st_mode) == stat.S_IMODE(plain.stat().st_mode)
    assert [p.name for p in target.parent.iterdir()] == [target.name]  # nothing left beside
