"""Specifications of the event bus: registration, ordering, failures, pull mode."""

from __future__ import annotations

import logging
import threading
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from bodyplay.errors import ConfigError, UnknownEventError
from bodyplay.events import (
    ContactEvent,
    Event,
    EventBus,
    GestureEvent,
    PoseEvent,
    SubscriberErrorEvent,
)


def _gesture(t: float = 1.0) -> GestureEvent:
    return GestureEvent(t=t, emitted_t=t, gesture="wave", phase="performed", progress=1.0,
                        started_t=t - 0.5)


def _pose(t: float = 0.0) -> PoseEvent:
    return PoseEvent(t=t, emitted_t=t, frame=0, joints=np.zeros((17, 3)),
                     state=("tracked",) * 17, confidence=np.ones(17))


def test_bus_registers_builtin_events_at_creation() -> None:
    bus = EventBus()
    assert {"pose", "gesture", "contact", "tracking", "subscriber_error"} <= set(bus.names)


def test_subscribe_to_unknown_event_raises_listing_known_names() -> None:
    bus = EventBus()
    with pytest.raises(UnknownEventError) as info:
        bus.subscribe("gestrue", print)
    msg = str(info.value)
    assert "gestrue" in msg and "gesture" in msg and "pose" in msg


def test_decorator_on_unknown_event_fails_before_decorating() -> None:
    bus = EventBus()
    with pytest.raises(UnknownEventError):
        bus.on("nope")


def test_emit_of_unregistered_event_class_raises() -> None:
    @dataclass(frozen=True, eq=False)
    class Goal(Event):
        name: ClassVar[str] = "goal"

    bus = EventBus()
    with pytest.raises(UnknownEventError, match="goal"):
        bus.emit(Goal(t=0.0, emitted_t=0.0))
    bus.register(Goal)
    got: list[Event] = []
    bus.subscribe("goal", got.append)
    bus.emit(Goal(t=0.0, emitted_t=0.0))
    assert len(got) == 1


def test_register_rejects_second_class_under_same_name() -> None:
    @dataclass(frozen=True, eq=False)
    class FakePose(Event):
        name: ClassVar[str] = "pose"

    with pytest.raises(ConfigError, match="already registered"):
        EventBus().register(FakePose)


def test_emit_delivers_synchronously_in_subscription_order() -> None:
    bus = EventBus()
    order: list[str] = []
    bus.subscribe("gesture", lambda e: order.append("a"))

    @bus.on("gesture")
    def second(e: GestureEvent) -> None:
        order.append("b")

    bus.subscribe("gesture", lambda e: order.append("c"))
    bus.emit(_gesture())
    assert order == ["a", "b", "c"]


def test_unsubscribe_stops_delivery_and_reports_whether_it_was_subscribed() -> None:
    bus = EventBus()
    got: list[Event] = []
    bus.subscribe("pose", got.append)
    assert bus.unsubscribe("pose", got.append) is True
    assert bus.unsubscribe("pose", got.append) is False
    bus.emit(_pose())
    assert got == []


def test_raising_subscriber_is_reported_and_others_still_get_the_event(
    caplog: pytest.LogCaptureFixture,
) -> None:
    bus = EventBus()
    got: list[Event] = []
    errors: list[SubscriberErrorEvent] = []

    def broken(e: Event) -> None:
        raise RuntimeError("boom")

    bus.subscribe("gesture", broken)
    bus.subscribe("gesture", got.append)
    bus.subscribe("subscriber_error", errors.append)
    with caplog.at_level(logging.ERROR, logger="bodyplay.events"):
        bus.emit(_gesture())
    assert len(got) == 1
    assert len(errors) == 1 and "boom" in errors[0].error and errors[0].failures == 1
    assert errors[0].event_name == "gesture" and "broken" in errors[0].subscriber
    assert "boom" in caplog.text


def test_subscriber_is_unsubscribed_after_three_consecutive_failures() -> None:
    bus = EventBus()
    calls = []

    def broken(e: Event) -> None:
        calls.append(e)
        raise ValueError("always")

    errors: list[SubscriberErrorEvent] = []
    bus.subscribe("subscriber_error", errors.append)
    bus.subscribe("gesture", broken)
    for i in range(5):
        bus.emit(_gesture(float(i)))
    assert len(calls) == 3
    assert [e.unsubscribed for e in errors] == [False, False, True]
    assert broken not in bus.subscribers("gesture")


def test_a_success_resets_the_consecutive_failure_count() -> None:
    bus = EventBus(max_failures=2)
    outcomes = iter([True, False, True, False, True, True])
    calls = []

    def flaky(e: Event) -> None:
        calls.append(e)
        if next(outcomes):
            raise ValueError("flaky")

    bus.subscribe("gesture", flaky)
    for i in range(6):
        bus.emit(_gesture(float(i)))
    # fail, ok, fail, ok, fail, fail -> removed only after the last two in a row
    assert len(calls) == 6
    assert flaky not in bus.subscribers("gesture")


def test_drain_returns_events_since_last_drain_in_order() -> None:
    bus = EventBus()
    bus.emit(_gesture(1.0))
    bus.emit(_pose(2.0))
    first = bus.drain()
    assert [e.name for e in first] == ["gesture", "pose"]
    assert bus.drain() == []
    bus.emit(_gesture(3.0))
    bus.emit(_pose(4.0))
    assert [e.t for e in bus.drain(["pose"])] == [4.0]


def test_drain_queue_is_bounded_and_counts_dropped_events() -> None:
    bus = EventBus(queue_size=3)
    for i in range(5):
        bus.emit(_gesture(float(i)))
    assert [e.t for e in bus.drain()] == [2.0, 3.0, 4.0]
    assert bus.dropped == 2


def test_drain_from_another_thread_loses_no_events() -> None:
    bus = EventBus(queue_size=100_000)
    n = 20_000
    got: list[Event] = []
    done = threading.Event()

    def consumer() -> None:
        while not done.is_set():
            got.extend(bus.drain())
        got.extend(bus.drain())

    th = threading.Thread(target=consumer)
    th.start()
    for i in range(n):
        bus.emit(_gesture(float(i)))
    done.set()
    th.join()
    assert [e.t for e in got] == [float(i) for i in range(n)]


def test_contact_events_from_a_physics_world_share_the_bus_with_poses() -> None:
    bus = EventBus()
    contacts: list[ContactEvent] = []
    bus.subscribe("contact", contacts.append)

    def physics(e: PoseEvent) -> None:  # a world stepping on each pose
        bus.emit(ContactEvent(t=e.t, emitted_t=e.emitted_t, part="r_wrist", obj="ball",
                              phase="begin"))

    bus.subscribe("pose", physics)
    bus.emit(_pose(1.0))
    assert len(contacts) == 1 and contacts[0].t == 1.0


def test_bus_rejects_invalid_settings() -> None:
    with pytest.raises(ConfigError):
        EventBus(max_failures=0)
    with pytest.raises(ConfigError):
        EventBus(queue_size=-1)


@pytest.mark.benchmark
def test_bus_delivers_at_least_100k_events_per_second_to_10_subscribers() -> None:
    import time

    bus = EventBus()
    counts = [0] * 10

    def make(i: int):  # type: ignore[no-untyped-def]
        def cb(e: Event) -> None:
            counts[i] += 1

        return cb

    for i in range(10):
        bus.subscribe("gesture", make(i))
    events = [_gesture(float(i)) for i in range(50_000)]
    rates = []
    for _ in range(5):
        t0 = time.perf_counter()
        for e in events:
            bus.emit(e)
        rates.append(len(events) / (time.perf_counter() - t0))
        bus.drain()
    assert sorted(rates)[2] >= 100_000
