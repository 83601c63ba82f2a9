"""The phone's door (app.reach.phone_door): its codes and sessions, then `trical serve` as `make run` runs it,
reached at a LAN address as a phone reaches it — in a network namespace of its own (`unshare -n`) whose one
interface holds 10.77.0.1 and the default route, so that the test's LAN is the same on every machine and nothing
outside it can answer."""

from __future__ import annotations

import json
import shutil
import sys

from app.reach.phone_door import PASS_ALPHABET, PASS_LENGTH, PASS_TTL_S, REFUSALS, SESSION_TTL_S, PhoneDoor
from tests.live_server import ROOT
from tests.processes import run_ok


class Clock:
    def __init__(self):
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


def test_a_code_lets_in_one_device_for_ten_minutes_and_its_session_for_twelve_hours():
    clock = Clock()
    door = PhoneDoor(port=8443, desktop_origin="http://127.0.0.1:8000", fingerprint="AB:CD", clock=clock)
    url = door.entry_url("192.168.1.23")
    code = url.rpartition("pass=")[2]
    assert url == f"https://192.168.1.23:8443/phone?pass={code}" and len(code) == PASS_LENGTH
    assert set(code) <= set(PASS_ALPHABET)
    assert door.origin("fe80::1") == "https://[fe80::1]:8443"
    session, refusal = door.enter(code.upper())  # typed in capitals: the same code
    assert session and refusal is None and door.admits(session)
    assert door.enter(code) == (None, "used")  # a second device with the same code
    assert door.enter("abcdefghjk") == (None, "unknown")  # a made-up one
    assert not door.admits(None) and not door.admits("") and not door.admits("made-up")
    late = door.new_pass()
    clock.now += PASS_TTL_S + 1
    assert door.enter(late) == (None, "unknown")  # expired: forgotten
    clock.now += SESSION_TTL_S
    assert not door.admits(session)  # the phone's session ended too
    assert all(words.startswith("this ") for words in REFUSALS.values())


DOOR_SCRIPT = r"""
import json, re, ssl, subprocess, sys, time
import httpx

for command in (
    # The namespace's one interface holds a LAN address too, and the route to the LAN (no dummy or veth module
    # is needed: the kernel of a container may lack them).
    "ip link set lo up", "ip addr add 10.77.0.1/32 dev lo", "ip route add default dev lo src 10.77.0.1",
):
    subprocess.run(command.split(), check=True)
log = open(sys.argv[1], "w")
server = subprocess.Popen(
    [sys.executable, "-m", "app.cli", "serve", "--port", "8000"], stdout=log, stderr=subprocess.STDOUT
)
DESKTOP, DOOR = "http://127.0.0.1:8000", "https://10.77.0.1:8443"
try:
    for _ in range(300):
        try:
            httpx.get(DESKTOP + "/healthz", timeout=2)
            break
        except httpx.TransportError:
            time.sleep(0.1)
    else:
        sys.exit("the server did not answer within 30 s")
    # The phone trusts the certificate as a person does when its fingerprint is the one the start page shows.
    trusted = ssl.create_default_context(cafile=sys.argv[2])
    out = {}
    with httpx.Client(verify=trusted, timeout=10) as stranger:  # a peer on the LAN without the code
        api = stranger.get(DOOR + "/api/v1/calibrations")
        out["stranger_api"] = [api.status_code, api.json()["code"], api.json()["detail"]]
        page = stranger.get(DOOR + "/", headers={"Accept": "text/html"})
        out["stranger_page"] = [page.status_code, 'id="door-refused"' in page.text]
        wrote = stranger.post(DOOR + "/api/v1/calibrations", json={"method": "six_position", "readings": []})
        out["stranger_write"] = wrote.status_code
        out["stranger_static"] = stranger.get(DOOR + "/static/css/trical.css").status_code
        out["stranger_guess"] = stranger.get(DOOR + "/phone?pass=abcdefghjk", follow_redirects=False).status_code
    try:
        httpx.get("http://10.77.0.1:8000/healthz", timeout=3)
        out["desktop_on_lan"] = "answered"
    except httpx.ConnectError:
        out["desktop_on_lan"] = "refused"
    start = httpx.get(DESKTOP + "/", timeout=10).text
    url = re.search(r'alt="QR code of (https://[^"]+)"', start).group(1)
    out["qr"] = url
    out["fingerprint_shown"] = re.search(r'id="phone-fingerprint">([^<]+)<', start).group(1)
    with httpx.Client(verify=trusted, timeout=10) as phone:
        entered = phone.get(url, follow_redirects=False)
        out["enter"] = [entered.status_code, entered.headers.get("location"), entered.headers.get("set-cookie")]
        out["phone_page"] = phone.get(DOOR + "/").status_code
        readings = [
            {"up": up, "mean": [9.80665 * (up == f"+{a}") - 9.80665 * (up == f"-{a}") for a in "xyz"]}
            for up in ("-x", "+x", "-y", "+y", "-z", "+z")
        ]
        made = phone.post(DOOR + "/api/v1/calibrations", json={"method": "six_position", "readings": readings})
        out["phone_write"] = made.status_code
        link = phone.post(DOOR + f"/api/v1/calibrations/{made.json()['id']}/links").json()
        out["link"] = link["url"]
        out["again"] = phone.get(url, follow_redirects=False).status_code  # the same phone scans again
    listed = httpx.get(DESKTOP + "/api/v1/calibrations", timeout=10).json()["items"]
    out["desktop_sees"] = [c["id"] for c in listed] == [made.json()["id"]]
    with httpx.Client(verify=trusted, timeout=10) as second:
        late = second.get(url, follow_redirects=False)
        out["second_device"] = [late.status_code, late.json()["detail"]]
    print(json.dumps(out))
finally:
    server.terminate()
    server.wait(timeout=10)
"""


def test_the_phone_that_scanned_the_code_measures_and_the_rest_of_the_lan_gets_401(tmp_path):
    unshare = shutil.which("unshare")
    assert unshare and shutil.which("ip"), "util-linux's unshare and iproute2's ip are needed (Debian: both base)"
    log = tmp_path / "server.log"
    env = {
        "PATH": "/usr/bin:/bin:/usr/sbin:/sbin",
        "TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}",
        "HOST": "",
        "TRICAL_PUBLIC_URL": "",
    }
    cert = tmp_path / "tls" / "cert.pem"
    try:
        out = run_ok(
            [unshare, "-n", sys.executable, "-c", DOOR_SCRIPT, str(log), str(cert)], timeout_s=90, cwd=ROOT, env=env
        )
    except Exception:
        print(log.read_text(errors="replace")[-4000:] if log.exists() else "(no server log)")
        raise
    seen = json.loads(out.stdout)
    print(json.dumps(seen, indent=1))
    # A LAN peer without the code: 401 everywhere but the page's public scripts and styles, with what to do.
    status, code, detail = seen["stranger_api"]
    assert (status, code) == (401, "unauthorized")
    assert detail.startswith(REFUSALS["none"]) and "reload it for a new code" in detail
    assert seen["stranger_page"] == [401, True] and seen["stranger_write"] == 401
    assert seen["stranger_static"] == 200 and seen["stranger_guess"] == 401
    assert seen["desktop_on_lan"] == "refused"  # the desktop's listener stays on loopback
    # The start page's code lets the phone in: a Secure, HttpOnly session cookie, then the start page.
    assert seen["qr"].startswith("https://10.77.0.1:8443/phone?pass=")
    status, location, cookie = seen["enter"]
    assert status == 303 and location == "/"
    assert cookie.startswith("trical_phone=") and all(f in cookie for f in ("Secure", "HttpOnly", "SameSite=lax"))
    assert seen["phone_page"] == 200 and seen["phone_write"] == 201 and seen["again"] == 303
    assert seen["desktop_sees"]  # one store: what the phone made, the desktop lists
    # A link the phone sends to "my computer" opens on the computer's own listener, not at the door.
    assert seen["link"].startswith("http://127.0.0.1:8000/s/")
    # The code let one device in: a second one is refused, told why.
    status, detail = seen["second_device"]
    assert status == 401 and detail.startswith(REFUSALS["used"])
    from app.reach.tls import fingerprint

    assert fingerprint(cert).startswith(seen["fingerprint_shown"])
