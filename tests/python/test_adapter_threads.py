"""Adapter.close() (and leaving ``with``) while another Python thread is inside execute() with
the GIL released: close waits for that call, later calls fail cleanly; no use after free."""
import threading

import pytest

import tessera
from conftest import field

CONFIG = {
    "tessera": {"threads": 1, "on_error": "warn"},
    "renders": [{
        "name": "main",
        "field": "temperature",
        "trigger": {"every": 1},
        "image": {"width": 8, "height": 8, "spp": 1},
        "camera": {"position": {"orbit": {"azimuth": 30, "elevation": 20, "distance": "fit"}},
                   "look_at": "center", "up": [0, 0, 1], "fov": 30},
        "transfer_function": {"range": "auto", "density_scale": 2.0, "opacity": [[0, 0], [1, 1]]},
        "output": {"file": "{name}", "formats": ["exr"]},
    }],
}
ROUNDS = 10


def execute_until_closed(viz, data, started, outcome):
    """Executes (every call renders) until the adapter stops it; records how it ended."""
    step = 0
    while True:
        started.release()
        try:
            viz.execute(step, 0.0, {"temperature": data})
        except tessera.TesseraError as e:  # closed before the call began
            outcome.append(str(e))
            return
        if viz.last_status != 0:  # refused while closing, or closed meanwhile
            outcome.append(viz.last_error)
            return
        step += 1


@pytest.mark.filterwarnings("ignore::tessera.TesseraWarning")
@pytest.mark.parametrize("how", ["close", "with"])
def test_close_while_another_thread_executes(tmp_path, how):
    data = field(8, 8, 8).T
    for _ in range(ROUNDS):
        started, outcome = threading.Semaphore(0), []
        viz = tessera.Adapter(CONFIG, output_dir=tmp_path, quiet=True)
        sim = threading.Thread(target=execute_until_closed, args=(viz, data, started, outcome))
        if how == "with":
            with viz:
                sim.start()
                started.acquire()
                started.acquire()  # the second call has begun: the first returned
        else:
            sim.start()
            started.acquire()
            started.acquire()
            viz.close()
        sim.join(timeout=60)
        assert not sim.is_alive()
        assert len(outcome) == 1 and "closed" in outcome[0], outcome
        with pytest.raises(tessera.TesseraError, match="closed"):
            viz.execute(0, 0.0, {"temperature": data})


TWO_RENDERS = {
    "tessera": {"threads": 1, "on_error": "warn"},
    "renders": [dict(CONFIG["renders"][0], name="a", output={"file": "a", "formats": ["exr"]}),
                dict(CONFIG["renders"][0], name="b", output={"file": "b", "formats": ["exr"]},
                     image={"width": 16, "height": 16, "spp": 2})],
}


def execute_and_record(viz, data, calls, stop):
    """Executes until told to stop; records each call's (status, message, images, results)."""
    step = 0
    while not stop.is_set():
        images = viz.execute(step, 0.0, {"temperature": data})
        calls.append((viz.last_status, viz.last_error, images, viz.results))
        step += 1


@pytest.mark.filterwarnings("ignore::tessera.TesseraWarning")
def test_two_threads_on_one_adapter_each_get_their_own_calls_outcome(tmp_path):
    """Calls from two threads overlap: the refused one does nothing and returns nothing (not
    the other call's images, which that call may be writing); one that ran returns exactly its
    renders. last_status / last_error / results are the calling thread's own."""
    data = field(8, 8, 8).T
    calls = [[], []]
    stop = threading.Event()
    with tessera.Adapter(TWO_RENDERS, output_dir=tmp_path, quiet=True) as viz:
        threads = [threading.Thread(target=execute_and_record, args=(viz, data, c, stop)) for c in calls]
        for t in threads:
            t.start()
        for _ in range(3000):  # until both threads saw calls refused and calls that ran
            done = [c[:] for c in calls]
            ran = sum(status == 0 for c in done for status, *_ in c)
            refused = sum(status != 0 for c in done for status, *_ in c)
            if ran >= 20 and refused >= 20:
                break
            threading.Event().wait(0.01)
        stop.set()
        for t in threads:
            t.join(timeout=60)
    assert ran >= 20 and refused >= 20, (ran, refused)
    for status, error, images, results in calls[0] + calls[1]:
        if status != 0:
            assert "another thread is inside a call on this adapter" in error, error
            assert images == {} and results == [], (error, list(images), [r["name"] for r in results])
        else:
            assert error == "" and [r["name"] for r in results] == ["a", "b"]
            assert sorted(images) == ["a", "b"] and images["a"].shape == (8, 8, 4) and images["b"].shape == (16, 16, 4)
