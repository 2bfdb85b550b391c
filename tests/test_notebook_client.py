"""lab.teaching.kernel.notebook_client: waits for kernel messages in slices, so a missed zmq wake-up costs < 1 s, not the limit."""

import asyncio
import time
from queue import Empty

import nbformat
import pytest

from lab.teaching.kernel.notebook_client import NotebookRunner, sliced_get_msg


class MissesWakeUps:
    """A channel whose poll never wakes early (the missed edge): it only sees a message present when it starts."""

    def __init__(self, arrives_after):
        self.arrives = time.monotonic() + arrives_after
        self.calls = []

    async def get_msg(self, timeout=None):
        self.calls.append(timeout)
        if time.monotonic() >= self.arrives:
            return {"msg_type": "execute_reply"}
        await asyncio.sleep(timeout)
        raise Empty


def test_a_message_that_arrived_unnoticed_is_read_at_the_next_slice():
    channel = MissesWakeUps(arrives_after=0.2)
    msg = asyncio.run(sliced_get_msg(channel.get_msg, 0.5)(timeout=300))
    assert msg == {"msg_type": "execute_reply"}
    assert channel.calls == [0.5, 0.5]  # the unsliced wait would have slept all 300 s


def test_the_time_limit_still_holds():
    channel = MissesWakeUps(arrives_after=1e9)
    start = time.monotonic()
    with pytest.raises(Empty):
        asyncio.run(sliced_get_msg(channel.get_msg, 0.5)(timeout=1.2))
    assert time.monotonic() - start >= 1.2  # not before the limit (a lower bound: holds on a loaded machine)
    assert channel.calls[:2] == [0.5, 0.5] and all(0 <= t <= 0.5 for t in channel.calls)


def test_the_runner_uses_sliced_waits_and_executes_cells():
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("print(6 * 7)")])
    client = NotebookRunner(nb, timeout=120, kernel_name="python3")
    with client.setup_kernel():
        assert "sliced_get_msg" in client.kc.shell_channel.get_msg.__qualname__
        assert "sliced_get_msg" in client.kc.iopub_channel.get_msg.__qualname__
        client.execute_cell(nb.cells[0], 0)
    assert nb.cells[0].outputs[0]["text"] == "42\n"
