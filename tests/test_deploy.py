"""The course's deployment files: the Zero to JupyterHub values (validated against the chart's own schema), the
single-user image's Dockerfile (pinned base, the hand-out only, the tested versions), what is tracked in git."""

import re
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest
import yaml

ROOT = Path(__file__).resolve().parent.parent
DEPLOY = ROOT / "deploy"
CHART = "4.4.0"


def merge(defaults, values):
    """Helm's merge of a chart's default values with the user's: maps merge key by key, anything else replaces."""
    out = dict(defaults)
    for key, value in values.items():
        out[key] = merge(defaults[key], value) if isinstance(value, dict) and isinstance(defaults.get(key), dict) else value
    return out


@pytest.fixture(scope="module")
def chart():
    schema = yaml.safe_load((DEPLOY / "z2jh" / "values.schema.yaml").read_text())
    defaults = yaml.safe_load((DEPLOY / "z2jh" / "values.defaults.yaml").read_text())
    return schema, defaults


def values():
    return yaml.safe_load((DEPLOY / "values.yaml").read_text())


def test_values_are_valid_for_the_chart(chart):
    schema, defaults = chart
    jsonschema.validate(merge(defaults, values()), schema)


@pytest.mark.parametrize("change, message", [
    ({"singleuser": {"memory": {"limt": "2G"}}}, "'limt' was unexpected"),
    ({"proxy": {"https": {"enabled": "yes"}}}, "is not of type 'boolean'"),
    ({"cull": {"timeout": "an hour"}}, "is not of type 'integer', 'null'"),
])
def test_the_schema_check_catches_mistakes(chart, change, message):
    schema, defaults = chart
    with pytest.raises(jsonschema.ValidationError, match=message):
        jsonschema.validate(merge(defaults, merge(values(), change)), schema)


def test_the_hub_logs_people_in_over_https():
    v = values()
    config = v["hub"]["config"]
    assert config["JupyterHub"]["authenticator_class"] == "generic-oauth"
    oauth = config["GenericOAuthenticator"]
    for key in ("client_id", "client_secret", "oauth_callback_url", "authorize_url", "token_url", "userdata_url"):
        assert oauth[key]
    assert oauth["oauth_callback_url"].startswith("https://") and oauth["oauth_callback_url"].endswith("/hub/oauth_callback")
    assert config["Authenticator"]["allowed_users"] and config["Authenticator"]["admin_users"]
    assert config["Authenticator"]["allow_all"] is False
    assert v["proxy"]["https"]["enabled"] is True and v["proxy"]["https"]["hosts"]
    assert v["proxy"]["https"]["hosts"][0] in oauth["oauth_callback_url"]
    text = (DEPLOY / "values.yaml").read_text()
    assert "helm repo add jupyterhub https://hub.jupyter.org/helm-chart/" in text and f"--version {CHART}" in text
    guide = (ROOT / "docs" / "instructors" / "hub.md").read_text()  # the instructors' page on the hub
    assert "helm repo add jupyterhub https://hub.jupyter.org/helm-chart/" in guide and f"--version {CHART}" in guide


def _stages(dockerfile):
    stages, current = [], None
    for line in dockerfile.splitlines():
        if line.startswith("FROM "):
            current = [line]
            stages.append(current)
        elif current is not None:
            current.append(line)
    return stages


def test_the_image_is_pinned_and_holds_only_the_handout():
    text = (DEPLOY / "Dockerfile").read_text()
    base = re.search(r"^ARG BASE=(\S+)$", text, re.MULTILINE).group(1)
    assert re.fullmatch(r"quay\.io/jupyter/minimal-notebook:\d{4}-\d{2}-\d{2}", base), base  # a dated tag, not latest
    build, final = _stages(text)
    assert build[0] == "FROM ${BASE} AS build" and final[0] == "FROM ${BASE}"
    assert any("curvature-lab release /opt/curvature-lab" in line for line in build)
    copies = [line for line in final if line.startswith("COPY")]
    assert copies and all("--from=build" in c or c.endswith("deploy/constraints.txt /opt/constraints.txt") for c in copies)
    assert "-c /opt/constraints.txt" in "\n".join(final) and "fix-permissions" in "\n".join(final)
    default = re.search(r"^ARG LAB_LANG=(\w+)$", text, re.MULTILINE).group(1)
    assert default == values()["singleuser"]["extraEnv"]["LAB_LANG"]  # one default language
    ignored = (ROOT / ".dockerignore").read_text().split()
    assert {".git", ".venv", "tests", "*.whl"} <= set(ignored)


def test_the_constraints_are_the_versions_the_tests_ran():
    sys.path.insert(0, str(DEPLOY))
    try:
        import constraints
    finally:
        sys.path.remove(str(DEPLOY))
    pinned = dict(line.split("==") for line in (DEPLOY / "constraints.txt").read_text().splitlines()
                  if line and not line.startswith("#"))
    installed = constraints.closure()
    stale = {name: (pinned.get(name), version) for name, version in installed.items() if pinned.get(name) != version}
    assert stale == {}, f"deploy/constraints.txt is stale (pinned, installed): {stale}; run deploy/constraints.py"
    for name in ("jupyterlab", "ipykernel", "pyvista", "vtk", "ipywidgets", "jupyter-server-proxy", "nbgitpuller"):
        assert name in pinned


def test_git_holds_no_wheel_and_ignores_course_data():
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    assert not [f for f in tracked if f.endswith((".whl", ".tar.gz"))]
    ignore = (ROOT / ".gitignore").read_text().split()
    assert {"submissions/", "reports/"} <= set(ignore)


def test_the_handout_is_what_nbgitpuller_hands_out():
    text = (ROOT / "docs" / "instructors" / "handout.md").read_text()
    assert "curvature-lab release" in text and "--git" in text
    assert "solutions" in text  # it says why never the course repository
    for link in re.findall(r"https://HUB/hub/user-redirect/git-pull\?\S+", text):
        assert "curvature-lab-student" in link
