"""What can be tested of the Dockerfile without a Docker engine: its rules, its entry command
and its health check, run here as the image would run them."""

from __future__ import annotations

import json
import re
import subprocess
import sys

from tests.live_server import ROOT, LiveServer, free_port

DOCKERFILE = (ROOT / "Dockerfile").read_text()


def instructions() -> list[tuple[str, str]]:
    text = re.sub(r"\\\n", " ", DOCKERFILE)
    out = []
    for line in text.splitlines():
        line = line.strip()
        if line and not line.startswith("#"):
            word, _, rest = line.partition(" ")
            out.append((word.upper(), rest.strip()))
    return out


def stages() -> dict[str, list[tuple[str, str]]]:
    """The instructions of each stage, by its name (the last, the image, as "")."""
    out: dict[str, list[tuple[str, str]]] = {}
    for word, rest in instructions():
        if word == "FROM":
            name = rest.split(" AS ")[1].strip() if " AS " in rest else ""
            out[name] = []
        out[name].append((word, rest))
    return out


def test_image_rules():
    ins = stages()[""]
    words = [w for w, _ in ins]
    assert re.match(r"python:3\.1[1-9]-slim$", dict(ins)["FROM"])
    # Dependencies in a layer before the code.
    first_code_copy = next(i for i, (w, r) in enumerate(ins) if w == "COPY" and r.startswith("app"))
    deps_install = next(i for i, (w, r) in enumerate(ins) if w == "RUN" and "pip install ." in r)
    assert deps_install < first_code_copy
    user = [r for w, r in ins if w == "USER"]
    assert user and user[-1] not in ("root", "0")
    assert any(w == "VOLUME" and "/data" in r for w, r in ins)
    assert "sqlite:////data/trical.db" in DOCKERFILE
    assert "HEALTHCHECK" in words and "/healthz" in dict(ins)["HEALTHCHECK"]
    cmd = json.loads(dict(ins)["CMD"])
    assert cmd[:2] == ["trical", "serve"] and "0.0.0.0" in cmd and "8000" in cmd
    # Every path the image copies exists in the repository, or comes from a stage before it.
    for w, r in instructions():
        if w == "COPY" and not r.startswith("--from="):
            for src in r.split()[:-1]:
                assert (ROOT / src).exists(), src


def test_the_compiled_loop_is_built_in_its_own_stage_and_copied_beside_its_source():
    """The image has no compiler: the stage "fused" builds the extension that setup.py declares, and the
    image copies the built module to where the package (installed in place) imports it from."""
    fused = stages()["fused"]
    assert re.match(r"python:3\.1[1-9]-slim AS fused$", fused[0][1])
    assert any(w == "RUN" and "gcc" in r for w, r in fused)
    assert any(w == "RUN" and "build_ext --inplace" in r for w, r in fused)
    declared = re.search(r'Extension\("([\w.]+)", \["([\w/.]+)"\]', (ROOT / "setup.py").read_text())
    assert declared, "setup.py declares the extension"
    module, source = declared.groups()
    assert (ROOT / source).exists() and ("COPY", f"{source} ./{source.rsplit('/', 1)[0]}/") in fused
    copied = [r for w, r in stages()[""] if w == "COPY" and r.startswith("--from=fused ")]
    built = "/srv/trical/" + module.replace(".", "/") + ".*.so"
    assert copied == [f"--from=fused {built} ./{source.rsplit('/', 1)[0]}/"]


def test_entry_command_and_health_check(tmp_path):
    ins = dict(instructions())
    port = free_port()
    cmd = json.loads(ins["CMD"])
    cmd = [sys.executable, "-m", "app.cli"] + [str(port) if c == "8000" else c for c in cmd[1:]]
    env = {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'data' / 'trical.db'}"}
    server = LiveServer(env, port=port, command=cmd).start()
    try:
        check = json.loads(ins["HEALTHCHECK"].split("CMD", 1)[1].strip())
        assert check[0] == "python"
        check = [sys.executable] + [c.replace(":8000/", f":{port}/") for c in check[1:]]
        assert subprocess.run(check, timeout=10).returncode == 0
        assert (tmp_path / "data" / "trical.db").exists()
    finally:
        server.stop()


def test_compose_runs_two_replicas_on_postgresql():
    import yaml

    compose = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
    services = compose["services"]
    assert services["trical"]["deploy"]["replicas"] == 2
    assert services["trical"]["build"] == "."
    assert services["trical"]["environment"]["TRICAL_DATABASE_URL"].startswith("postgresql://")
    assert "volumes" not in services["trical"]  # the replicas share nothing but the database
    assert services["trical"]["depends_on"]["db"]["condition"] == "service_healthy"
    assert services["db"]["image"].startswith("postgres:")
    proxy = services["proxy"]
    conf = proxy["volumes"][0].split(":")[0]
    assert "proxy_pass http://trical" in (ROOT / conf).read_text()


def test_nginx_limits_api_requests_per_address():
    conf = (ROOT / "deploy" / "nginx.conf").read_text()
    conf = "\n".join(line.split("#", 1)[0] for line in conf.splitlines())
    zone = re.search(r"limit_req_zone\s+\$binary_remote_addr\s+zone=(\w+):(\d+)m\s+rate=(\d+)r/s;", conf)
    assert zone, "nginx.conf needs a limit_req_zone keyed on $binary_remote_addr"
    name = zone.group(1)
    api = re.search(r"location\s+/api/\s*\{(.*?)\}", conf, re.S)
    assert api, "nginx.conf needs a location /api/ that applies the limit"
    block = api.group(1)
    burst = re.search(rf"limit_req\s+zone={name}\s+burst=(\d+)(\s+nodelay)?;", block)
    assert burst and int(burst.group(1)) >= int(zone.group(3)), "limit_req needs a burst of at least a second's rate"
    assert re.search(r"limit_req_status\s+429;", block)
    assert "proxy_pass http://trical;" in block
    # Every header the catch-all location forwards is forwarded for /api/ too.
    root = re.search(r"location\s+/\s*\{(.*?)\}", conf, re.S).group(1)
    for line in root.splitlines():
        if line.strip().startswith(("proxy_set_header", "proxy_read_timeout")):
            assert line.strip() in block, line.strip()
