"""A real JupyterHub on 127.0.0.1 for tests/test_hub.py and benchmarks/hub_load.py (one copy of the start-up).

JupyterHub from pip with its ``DummyAuthenticator`` and ``SimpleLocalProcessSpawner``, and
``configurable-http-proxy`` from npm (``make test`` installs it into ``.venv/node``).  Each student's home
is a folder under ``root/home`` with copies of the given files; JupyterLab runs with test-only user
settings (every cell rendered, so explorers below the fold are in the page).
"""

import contextlib
import os
import shutil
import sys
from pathlib import Path

from tests.browser_support import free_port, serving

ROOT = Path(__file__).resolve().parent.parent
_BIN = Path("node") / "node_modules" / ".bin" / "configurable-http-proxy"
#: configurable-http-proxy: in this checkout's venv, else in the venv running Python (a git worktree has none)
PROXY = next((p for p in (ROOT / ".venv" / _BIN, Path(sys.prefix) / _BIN) if p.exists()), ROOT / ".venv" / _BIN)

CONFIG = """
import os, sys
c = get_config()
c.JupyterHub.ip = "127.0.0.1"
c.JupyterHub.port = {port}
c.JupyterHub.hub_ip = "127.0.0.1"
c.JupyterHub.hub_port = {hub_port}
c.ConfigurableHTTPProxy.api_url = "http://127.0.0.1:{api_port}"
c.ConfigurableHTTPProxy.command = [{proxy!r}]
c.JupyterHub.authenticator_class = "dummy"
c.DummyAuthenticator.password = "lab"
c.Authenticator.allow_all = True
c.JupyterHub.spawner_class = "simple"
c.SimpleLocalProcessSpawner.home_dir_template = {home!r} + "/{{username}}"
c.Spawner.cmd = [os.path.join(os.path.dirname(sys.executable), "jupyterhub-singleuser")]
c.Spawner.args = ["--allow-root", "--LabApp.expose_app_in_browser=True", "--LabApp.user_settings_dir=" + {settings!r}]
c.Spawner.default_url = "/lab"
c.Spawner.env_keep = ["PATH", "LANG", "VTK_DEFAULT_OPENGL_WINDOW", "PYTHONPATH"]
c.Spawner.start_timeout = 180
c.Spawner.http_timeout = 180
c.JupyterHub.db_url = "sqlite:///" + {db!r}
c.JupyterHub.cookie_secret_file = {secret!r}
c.ConfigurableHTTPProxy.pid_file = {pid!r}
"""


@contextlib.contextmanager
def jupyterhub(root, students, files=()):
    """Start JupyterHub in ``root`` with a home for each of ``students`` holding copies of ``files``.

    Yields ``(url, process)``; on exit the hub, its proxy and the single-user servers are stopped.
    """
    root = Path(root)
    port, hub_port, api_port = free_port(), free_port(), free_port()
    home, settings = root / "home", root / "settings" / "@jupyterlab" / "notebook-extension"
    settings.mkdir(parents=True)
    (settings / "tracker.jupyterlab-settings").write_text('{"windowingMode": "none"}')
    for user in students:
        (home / user).mkdir(parents=True)
        for path in files:
            shutil.copy(path, home / user / Path(path).name)
    config = root / "jupyterhub_config.py"
    config.write_text(CONFIG.format(port=port, hub_port=hub_port, api_port=api_port, proxy=str(PROXY), home=str(home),
                                    settings=str(root / "settings"), db=str(root / "hub.sqlite"),
                                    secret=str(root / "cookie_secret"), pid=str(root / "proxy.pid")))
    drop = ("DISPLAY", "PYTEST_XDIST_WORKER", "JUPYTERHUB_SERVICE_PREFIX")
    env = {k: v for k, v in os.environ.items() if k not in drop}
    env["PATH"] = f"{Path(sys.executable).parent}:{env.get('PATH', '')}"
    hub = [str(Path(sys.executable).parent / "jupyterhub"), "-f", str(config)]
    # own process group: stopping it also stops the proxy and the single-user servers
    with serving(hub, port, "jupyterhub", root / "hub.log", env=env, cwd=root, timeout=120, poll=0.5, stop_timeout=30,
                 own_group=True) as proc:
        yield f"http://127.0.0.1:{port}", proc


def login(context, hub, user, timeout_ms=240_000):
    """Log ``user`` in through the hub's login form in a new page of ``context``; returns the page."""
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    page = context.new_page()
    for attempt in range(3):  # a loaded hub's proxy may answer a first request with an error page (CI saw one once)
        page.goto(f"{hub}/hub/login")
        try:
            page.wait_for_selector("input[name=username]", timeout=60_000)
            break
        except PlaywrightTimeout:
            if attempt == 2:
                raise AssertionError(f"the hub's login form did not appear in 3 tries; the page said: "
                                     f"{page.inner_text('body')[:500]!r}") from None
    page.fill("input[name=username]", user)
    page.fill("input[name=password]", "lab")
    page.click("input[type=submit], button[type=submit]")
    page.wait_for_url(f"**/user/{user}/**", timeout=timeout_ms)
    return page


def descendants(pid):
    """Process ids of all descendants of ``pid`` (from /proc)."""
    children = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            with contextlib.suppress(OSError, IndexError, ValueError):
                ppid = int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1])
                children.setdefault(ppid, []).append(int(entry.name))
    out, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.append(child)
            todo.append(child)
    return out


def hub_processes(proc):
    """``{"servers": [pid …], "kernels": [pid …]}``: the single-user servers and kernels started by the hub."""
    found = {"servers": [], "kernels": []}
    for pid in descendants(proc.pid):
        with contextlib.suppress(OSError):
            cmd = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            if "ipykernel_launcher" in cmd:
                found["kernels"].append(pid)
            elif "jupyterhub-singleuser" in cmd:
                found["servers"].append(pid)
    return found
