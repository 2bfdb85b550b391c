"""An nbclient ``NotebookClient`` whose waits for kernel messages cannot stall for a whole time limit.

nbclient waits for a cell's reply with one ``poll`` of the zmq socket for the whole cell time limit.
pyzmq's asyncio ``poll`` watches the socket's edge-triggered file descriptor; when that wake-up is missed
(seen here under load, with ipykernel 6.31 and 7.4 alike), the reply sits in the socket while the client
sleeps out the limit: a cell of 4 s took exactly its 60 s limit, a grading run stalled for 300 s, the
kernel idle all the while, and then the run went on as if nothing had happened.  A new ``poll`` checks
the socket's events before it waits, so waiting in slices of :data:`SLICE` seconds bounds such a stall.
"""

import time
from queue import Empty

from jupyter_core.utils import run_sync
from nbclient import NotebookClient

#: Longest wait in one poll of a kernel channel (seconds).
SLICE = 0.5


def sliced_get_msg(get_msg, slice_seconds=SLICE):
    """``get_msg(timeout)`` of a kernel channel, waiting in polls of at most ``slice_seconds``."""

    async def get(timeout=None):
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            left = slice_seconds if deadline is None else max(0.0, deadline - time.monotonic())
            try:
                return await get_msg(timeout=min(slice_seconds, left))
            except Empty:
                if deadline is not None and time.monotonic() >= deadline:
                    raise

    return get


class NotebookRunner(NotebookClient):
    """``nbclient.NotebookClient`` with sliced waits on the shell and IOPub channels (see the module)."""

    async def async_start_new_kernel_client(self):
        kc = await super().async_start_new_kernel_client()
        for channel in (kc.shell_channel, kc.iopub_channel):
            channel.get_msg = sliced_get_msg(channel.get_msg)
        return kc

    start_new_kernel_client = run_sync(async_start_new_kernel_client)  # nbclient binds the base's coroutine
