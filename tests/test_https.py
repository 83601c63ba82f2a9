"""HTTPS on a LAN: the certificate, and `trical serve --https` run as a user runs it (real TLS, real HTTP); the
phone's door itself is tests/test_phone_door.py's."""

from __future__ import annotations

import ipaddress
import re
import ssl
import stat
import subprocess
import sys
from html import escape

import httpx
from cryptography import x509
from cryptography.hazmat.primitives import hashes
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import ExtendedKeyUsageOID

from app import __version__
from app.reach import tls
from app.reach.qr import qr_svg_data_uri
from tests.live_server import ROOT, LiveServer, free_port

LAN_IP = "192.168.1.23"


def load(cert_path) -> x509.Certificate:
    return x509.load_pem_x509_certificate(cert_path.read_bytes())


def served_fingerprint(port: int) -> str:
    """The SHA-256 fingerprint of the certificate the server on 127.0.0.1:port presents."""
    pem = ssl.get_server_certificate(("127.0.0.1", port), timeout=10)
    digest = x509.load_pem_x509_certificate(pem.encode()).fingerprint(hashes.SHA256()).hex().upper()
    return ":".join(digest[i : i + 2] for i in range(0, len(digest), 2))


def server_env(tmp_path) -> dict:
    # Empty values count as unset: the test runner's HOST or TRICAL_PUBLIC_URL must not leak in.
    return {"TRICAL_DATABASE_URL": f"sqlite:///{tmp_path / 'trical.db'}", "HOST": "", "TRICAL_PUBLIC_URL": ""}


def trical(*args, tmp_path, **env):
    return subprocess.run(
        [sys.executable, "-m", "app.cli", *args],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=60,
        env={"PATH": "/usr/bin:/bin", **server_env(tmp_path), **env},
    )


def test_self_signed_certificate_for_the_lan(tmp_path):
    cert_path, key_path = tmp_path / "tls" / "cert.pem", tmp_path / "tls" / "key.pem"
    tls.make_self_signed(cert_path, key_path, ["localhost", "bench-pc", "127.0.0.1", LAN_IP])
    cert = load(cert_path)
    san = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    assert {"localhost", "bench-pc"} <= set(san.get_values_for_type(x509.DNSName))
    assert {ipaddress.ip_address("127.0.0.1"), ipaddress.ip_address(LAN_IP)} <= set(
        san.get_values_for_type(x509.IPAddress)
    )
    assert LAN_IP not in san.get_values_for_type(x509.DNSName)  # an address is an IP entry, not a name
    assert cert.extensions.get_extension_for_class(x509.BasicConstraints).value.ca is False
    assert cert.extensions.get_extension_for_class(x509.KeyUsage).value.digital_signature
    assert ExtendedKeyUsageOID.SERVER_AUTH in cert.extensions.get_extension_for_class(x509.ExtendedKeyUsage).value
    assert isinstance(cert.public_key(), ec.EllipticCurvePublicKey) and cert.public_key().curve.name == "secp256r1"
    assert (cert.not_valid_after_utc - cert.not_valid_before_utc).days >= 825
    assert stat.S_IMODE(key_path.stat().st_mode) == 0o600
    # The pair is what a TLS server can load.
    tls.check_certificate_files(cert_path, key_path)


def test_this_machines_hosts():
    addresses = tls.lan_addresses()
    assert addresses and all(isinstance(ipaddress.IPv4Address(a), ipaddress.IPv4Address) for a in addresses)
    assert addresses == ["127.0.0.1"] or not any(ipaddress.IPv4Address(a).is_loopback for a in addresses)
    hosts = tls.certificate_hosts(["10.1.2.3"])
    assert hosts[0] == "localhost" and "127.0.0.1" in hosts and "10.1.2.3" in hosts
    assert set(addresses) <= set(hosts)
    if tls.host_name():
        assert tls.host_name() in hosts


def test_stored_certificate_is_reused_until_it_no_longer_fits(tmp_path):
    hosts = ["localhost", "127.0.0.1", LAN_IP]
    cert, key, made = tls.self_signed_certificate(tmp_path, hosts)
    assert made and tls.certificate_names(cert) == set(hosts)
    first = tls.fingerprint(cert)
    assert tls.self_signed_certificate(tmp_path, hosts) == (cert, key, False)
    assert tls.fingerprint(cert) == first
    # The LAN address changed: a new certificate.
    _, _, made = tls.self_signed_certificate(tmp_path, ["localhost", "127.0.0.1", "192.168.1.99"])
    assert made and tls.fingerprint(cert) != first and "192.168.1.99" in tls.certificate_names(cert)
    # An expired one (or one about to expire) is made again.
    tls.make_self_signed(cert, key, hosts, days=0)
    assert tls.self_signed_certificate(tmp_path, hosts)[2] is True
    # A key that is not the certificate's is not reused either.
    tls.make_self_signed(tmp_path / "other.pem", tmp_path / "key.pem", hosts)
    assert tls.self_signed_certificate(tmp_path, hosts)[2] is True


def test_serve_https_with_a_self_signed_certificate(tmp_path):
    port, door_port = free_port(), free_port()
    cert_path = tmp_path / "tls" / "cert.pem"
    command = [sys.executable, "-m", "app.cli", "serve", "--https", "--port", str(port), "--phone-port", str(door_port)]
    server = LiveServer(server_env(tmp_path), port=port, command=command, https_ca=cert_path).start()
    try:
        health = httpx.get(f"https://127.0.0.1:{port}/healthz", verify=server.verify(), timeout=10)
        assert health.status_code == 200
        with httpx.Client(verify=server.verify(), timeout=10) as client:  # the name localhost is covered too
            assert client.get(f"https://localhost:{port}/healthz").status_code == 200
        # The desktop's listener and the phone's door present the one certificate.
        assert served_fingerprint(port) == served_fingerprint(door_port) == tls.fingerprint(cert_path)
        names = tls.certificate_names(cert_path)
        assert {"localhost", "127.0.0.1", *tls.lan_addresses()} <= names

        printed = server.log.read_text(encoding="utf-8")
        assert f"trical {__version__} on https://127.0.0.1:{port}" in printed  # the desktop's: loopback
        lan = tls.lan_addresses()[0]
        assert f"phone's door on https://{lan}:{door_port} (every interface)" in printed
        assert tls.fingerprint(cert_path) in printed and "signed itself" in printed
        # The start page's QR code is the door's, with a code; the page names the certificate's fingerprint.
        page = httpx.get(f"https://127.0.0.1:{port}/", verify=server.verify(), timeout=10).text
        url = re.search(r'alt="QR code of (https://[^"]+)"', page).group(1)
        assert url.startswith(f"https://{lan}:{door_port}/phone?pass=")
        assert escape(qr_svg_data_uri(url)) in page and tls.fingerprint(cert_path)[:11] in page
        assert "Traceback" not in printed
    finally:
        server.stop()
    # A second start reuses the stored certificate.
    again = LiveServer(server_env(tmp_path), port=port, command=command, https_ca=cert_path)
    fingerprint = tls.fingerprint(cert_path)
    again.start()
    try:
        assert served_fingerprint(port) == fingerprint
        assert "reusing the self-signed certificate" in again.log.read_text(encoding="utf-8")
    finally:
        again.stop()


def test_serve_https_with_given_files(tmp_path):
    given_cert, given_key = tmp_path / "given" / "site.crt", tmp_path / "given" / "site.key"
    tls.make_self_signed(given_cert, given_key, ["localhost", "127.0.0.1"])
    port = free_port()
    public = "https://trical.example.org/wizard?protocol=six"
    # --cert and --key alone mean --https.
    command = [
        sys.executable,
        "-m",
        "app.cli",
        "serve",
        "--host",
        "127.0.0.1",
        "--port",
        str(port),
        "--cert",
        str(given_cert),
        "--key",
        str(given_key),
    ]
    server = LiveServer(
        {**server_env(tmp_path), "TRICAL_PUBLIC_URL": public}, port=port, command=command, https_ca=given_cert
    ).start()
    try:
        assert httpx.get(f"{server.url}/healthz", verify=server.verify(), timeout=10).status_code == 200
        assert served_fingerprint(port) == tls.fingerprint(given_cert)
        printed = server.log.read_text(encoding="utf-8")
        assert f"certificate {given_cert} (SHA-256 {tls.fingerprint(given_cert)})" in printed
        assert "phone's door" not in printed  # the public address is the phones' way in
        # TRICAL_PUBLIC_URL, when set, is what the start page shows.
        page = httpx.get(f"{server.url}/", verify=server.verify(), timeout=10).text
        assert f'alt="QR code of {escape(public)}"' in page
    finally:
        server.stop()
    assert not (tmp_path / "tls").exists()  # nothing generated


def test_bad_certificate_options_are_one_line(tmp_path):
    cert, key = tmp_path / "c.pem", tmp_path / "k.pem"
    tls.make_self_signed(cert, key, ["localhost"])
    tls.make_self_signed(tmp_path / "c2.pem", tmp_path / "k2.pem", ["localhost"])
    (tmp_path / "notes.txt").write_text("not a certificate\n")
    port = str(free_port())
    cases = {
        "no such file": ["--cert", str(tmp_path / "missing.pem"), "--key", str(key)],
        "go together": ["--cert", str(cert)],
        "not a PEM certificate": ["--cert", str(tmp_path / "notes.txt"), "--key", str(key)],
        "its unencrypted private key": ["--cert", str(cert), "--key", str(tmp_path / "k2.pem")],
    }
    for needle, args in cases.items():
        out = trical("serve", "--https", "--host", "127.0.0.1", "--port", port, *args, tmp_path=tmp_path)
        assert out.returncode == 2, (needle, out.stdout, out.stderr)
        assert out.stderr.startswith("trical: error: ") and needle in out.stderr, out.stderr
        assert "Traceback" not in out.stderr and out.stderr.count("\n") == 1
    bad_url = trical("serve", "--https", "--port", port, tmp_path=tmp_path, TRICAL_PUBLIC_URL="phone.local")
    assert bad_url.returncode == 2 and "TRICAL_PUBLIC_URL" in bad_url.stderr


NO_LAN_SCRIPT = r"""
import subprocess, sys, time, httpx
subprocess.run(["ip", "link", "set", "lo", "up"], check=True)
command = [sys.executable, "-m", "app.cli", "serve", "--port", "8765"]
server = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
try:
    for _ in range(200):
        try:
            page = httpx.get("http://127.0.0.1:8765/", timeout=2).text
            break
        except httpx.TransportError:
            time.sleep(0.1)
    else:
        server.kill()
        sys.exit("the server did not answer within 20 s: " + server.stderr.read()[-2000:])
    print("QR" if 'id="phone-qr"' in page else "NO QR")
    print("SAID" if 'id="phone-no-lan"' in page else "NOT SAID")
finally:
    server.terminate()
    server.wait(timeout=10)
"""


def test_without_a_lan_address_the_start_page_says_so_instead_of_a_qr_code_to_nowhere(tmp_path):
    """A machine with no network but its loopback (a network namespace of its own, `unshare -n`, as a laptop off
    every network is): the start page draws no QR code of 127.0.0.1, which no phone can open, and says what to do."""
    import shutil

    from tests.processes import run_ok

    unshare = shutil.which("unshare")
    assert unshare and shutil.which("ip"), "util-linux's unshare and iproute2's ip are needed (Debian: both base)"
    out = run_ok(
        [unshare, "-n", sys.executable, "-c", NO_LAN_SCRIPT],
        timeout_s=90,
        cwd=ROOT,
        env={"PATH": "/usr/bin:/bin:/usr/sbin:/sbin", **server_env(tmp_path)},
    )
    assert out.stdout.split() == ["NO", "QR", "SAID"], out.stdout
