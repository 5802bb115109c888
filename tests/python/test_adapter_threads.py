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
