"""The order the suite is queued in (tests/conftest.py): the long tests first, dealt out
so that pytest-xdist's work stealing gives each worker the same share of them."""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from conftest import chunk_sizes, deal, heavy_unit
from xdist.scheduler.worksteal import WorkStealingScheduling


class _Node:
    """What WorkStealingScheduling needs of a worker: it records what it is sent."""

    def __init__(self, k: int) -> None:
        self.gateway = SimpleNamespace(id=f"gw{k}")
        self.shutting_down = False
        self.sent: list[int] = []

    def send_runtest_some(self, indices: list[int]) -> None:
        self.sent.extend(indices)

    def send_steal(self, indices: list[int]) -> None:
        raise AssertionError("nothing has run yet: no steal")

    def shutdown(self) -> None:
        self.shutting_down = True


@pytest.mark.parametrize(("count", "workers"), [(910, 2), (911, 2), (31, 2), (910, 3), (7, 4)])
def test_chunks_should_be_what_work_stealing_first_deals(count: int, workers: int) -> None:
    """The yardstick is xdist's own scheduler: a change in how it deals fails here."""
    config = SimpleNamespace(getvalue=lambda name: [f"{workers}*popen"])
    scheduler = WorkStealingScheduling(config)  # type: ignore[arg-type]
    nodes = [_Node(k) for k in range(workers)]
    collection = [f"t{i}" for i in range(count)]
    for node in nodes:
        scheduler.add_node(node)  # type: ignore[arg-type]
    for node in nodes:
        scheduler.add_node_collection(node, collection)  # type: ignore[arg-type]
    scheduler.schedule()
    dealt = [node.sent for node in nodes]
    starts = [sum(chunk_sizes(count, workers)[:k]) for k in range(workers)]
    assert [len(d) for d in dealt] == chunk_sizes(count, workers)
    assert [d[0] for d in dealt] == starts
    assert [i for d in dealt for i in d] == list(range(count))


def _units(costs: dict[str, float]) -> object:
    return lambda name: (name.split(".")[0], costs[name.split(".")[0]]) if "." in name else None


def test_deal_should_balance_the_long_units_and_start_each_chunk_with_them() -> None:
    costs = {"a": 40.0, "b": 36.0, "c": 30.0, "d": 20.0, "e": 10.0, "f": 5.0}
    short = [f"s{i}" for i in range(40)]
    items = [*short[:10], "c.1", "a.1", "a.2", *short[10:30]]  # a: a unit of three tests
    items += ["b.1", "d.1", "e.1", "f.1", "a.3", *short[30:]]
    ordered = deal(items, _units(costs), 2)  # type: ignore[arg-type]
    assert sorted(ordered) == sorted(items)
    first, second = ordered[: len(items) // 2], ordered[len(items) // 2 :]
    # longest first onto the emptier worker: a | b, then c -> b's (36), d -> a's (40) ...
    assert first[:5] == ["a.1", "a.2", "a.3", "d.1", "e.1"]
    assert second[:3] == ["b.1", "c.1", "f.1"]
    assert abs((40 + 20 + 10) - (36 + 30 + 5)) <= max(costs.values())
    # the short tests follow, in their order, after each chunk's long ones
    assert [t for t in ordered if t.startswith("s")] == short
    assert all(t.startswith("s") for t in first[5:] + second[3:])


def test_deal_should_queue_the_long_tests_first_without_workers_or_room() -> None:
    costs = {"a": 1.0, "b": 9.0}
    items = ["s0", "a.1", "s1", "b.1"]
    assert deal(items, _units(costs), 1) == ["b.1", "a.1", "s0", "s1"]  # type: ignore[arg-type]
    # more long tests than a chunk holds: one queue, longest first
    assert deal(items, _units(costs), 4) == ["b.1", "a.1", "s0", "s1"]  # type: ignore[arg-type]


def test_heavy_marks_should_give_units_and_costs(pytester: pytest.Pytester) -> None:
    """A test marked alone is a unit of its own (each parameter with its cost); a
    module that carries the mark is one unit, all its tests together; the rest none."""
    pytester.makepyfile(
        test_alone="""
        import pytest

        @pytest.mark.parametrize(
            "x", [pytest.param(1, marks=pytest.mark.heavy(seconds=36)), 2]
        )
        def test_proof(x):
            pass

        def test_short():
            pass
        """,
        test_module="""
        import pytest

        pytestmark = pytest.mark.heavy(seconds=42)

        def test_one():
            pass

        def test_two():
            pass
        """,
    )
    items, _ = pytester.inline_genitems()
    assert {i.nodeid: heavy_unit(i) for i in items} == {
        "test_alone.py::test_proof[1]": ("test_alone.py::test_proof[1]", 36.0),
        "test_alone.py::test_proof[2]": None,
        "test_alone.py::test_short": None,
        "test_module.py::test_one": ("test_module.py", 42.0),
        "test_module.py::test_two": ("test_module.py", 42.0),
    }


def test_a_heavy_mark_without_seconds_should_be_refused() -> None:
    mark = pytest.mark.heavy.mark
    item = SimpleNamespace(
        nodeid="tests/test_x.py::test_y", iter_markers_with_node=lambda name: iter([(None, mark)])
    )
    with pytest.raises(pytest.UsageError, match="heavy needs seconds=N"):
        heavy_unit(item)  # type: ignore[arg-type]
