"""HTTPS on a LAN: this machine's addresses and a self-signed certificate for them.

Phone browsers give web pages the motion sensors only in a secure context, so ``trical serve --https``
serves over TLS with a certificate for localhost, the host name and the LAN addresses (or with the
certificate files the user gives).
"""

from __future__ import annotations

import contextlib
import datetime as dt
import hashlib
import ipaddress
import os
import re
import socket
import ssl
from pathlib import Path

CERT_NAME = "cert.pem"
KEY_NAME = "key.pem"
ROUTE_PROBES = ("10.255.255.254", "172.31.255.254", "192.168.255.254")
"""Private addresses whose route names the interface a LAN peer would reach; nothing is sent to them."""
MIN_REMAINING = dt.timedelta(days=1)
"""A stored certificate closer than this to its expiry is made again."""
_DNS_NAME = re.compile(r"^[A-Za-z0-9](?:[A-Za-z0-9-]*[A-Za-z0-9])?(?:\.[A-Za-z0-9](?:[A-Za-z0-9-]*[A-Za-z0-9])?)*$")


class CertificateError(ValueError):
    """Certificate files that cannot be used, or options that do not go together."""


def _usable(address: str) -> bool:
    try:
        ip = ipaddress.IPv4Address(address)
    except ValueError:
        return False
    return not (ip.is_loopback or ip.is_link_local or ip.is_unspecified or ip.is_multicast)


def lan_addresses() -> list[str]:
    """This machine's non-loopback IPv4 addresses, the one of the usual route first.

    Found without network traffic: connecting a UDP socket only picks the route, and the host name is
    resolved through the system's resolver.  Never fails.

    Returns
    -------
    list of str
        The addresses, or ``["127.0.0.1"]`` when there is none.
    """
    found: list[str] = []
    for probe in ROUTE_PROBES:
        try:
            with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
                s.connect((probe, 9))
                found.append(s.getsockname()[0])
        except OSError:
            continue
    with contextlib.suppress(OSError, UnicodeError):
        found += socket.gethostbyname_ex(socket.gethostname())[2]
    addresses = list(dict.fromkeys(a for a in found if _usable(a)))
    return addresses or ["127.0.0.1"]


EVERY_INTERFACE = ("0.0.0.0", "::")
"""The addresses a listener binds to be on every interface."""


def url_host(host: str) -> str:
    """``host`` as an address's host part: an IPv6 address in brackets (``[fe80::1]``), anything else as it is."""
    return f"[{host}]" if ":" in host else host


def host_name() -> str | None:
    """This machine's host name when it can go into a certificate, else None."""
    try:
        name = socket.gethostname()
    except OSError:
        return None
    return name if name.isascii() and _DNS_NAME.match(name) and name != "localhost" else None


def certificate_hosts(extra: list[str] | tuple[str, ...] = ()) -> list[str]:
    """The names and addresses a self-signed certificate of this machine covers.

    Parameters
    ----------
    extra : list of str
        More names or addresses (e.g. the address given to ``--host``).

    Returns
    -------
    list of str
        localhost, the host name (and its ``.local`` mDNS name), 127.0.0.1, the LAN addresses and `extra`.
    """
    hosts = ["localhost"]
    name = host_name()
    if name:
        hosts += [name] if "." in name else [name, f"{name}.local"]
    hosts += ["127.0.0.1", *lan_addresses(), *extra]
    return list(dict.fromkeys(h for h in hosts if h and h not in ("0.0.0.0", "::")))


def _general_names(hosts: list[str]) -> list:
    from cryptography import x509

    names: list[x509.GeneralName] = []
    for host in hosts:
        try:
            names.append(x509.IPAddress(ipaddress.ip_address(host)))
        except ValueError:
            names.append(x509.DNSName(host))
    return names


def make_self_signed(cert_path: Path | str, key_path: Path | str, hosts: list[str], days: int = 825) -> None:
    """Write a self-signed TLS server certificate for `hosts` and its key (PEM).

    Parameters
    ----------
    cert_path, key_path : path
        Files to write; their directory is created.  The key file is readable by its owner only.
    hosts : list of str
        DNS names and IP addresses; each becomes a subjectAltName entry of its kind.
    days : int
        Validity; 825 days is the longest Apple devices accept for a server certificate.
    """
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes, serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

    if not hosts:
        raise CertificateError("a certificate needs at least one host name or address")
    key = ec.generate_private_key(ec.SECP256R1())
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, f"trical on {hosts[0]}"[:64])])
    now = dt.datetime.now(dt.UTC)
    public = key.public_key()
    cert = (
        x509.CertificateBuilder()
        .subject_name(name)
        .issuer_name(name)
        .public_key(public)
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - dt.timedelta(minutes=5))  # a phone's clock may be a little behind
        .not_valid_after(now + dt.timedelta(days=days))
        .add_extension(x509.SubjectAlternativeName(_general_names(hosts)), critical=False)
        .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
        .add_extension(
            x509.KeyUsage(
                digital_signature=True,
                content_commitment=False,
                key_encipherment=False,
                data_encipherment=False,
                key_agreement=False,
                key_cert_sign=False,
                crl_sign=False,
                encipher_only=False,
                decipher_only=False,
            ),
            critical=True,
        )
        .add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH]), critical=False)
        .add_extension(x509.SubjectKeyIdentifier.from_public_key(public), critical=False)
        .add_extension(x509.AuthorityKeyIdentifier.from_issuer_public_key(public), critical=False)
        .sign(key, hashes.SHA256())
    )
    cert_path, key_path = Path(cert_path), Path(key_path)
    for path in (cert_path, key_path):
        path.parent.mkdir(parents=True, exist_ok=True)
    key_pem = key.private_bytes(
        serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
    )
    fd = os.open(key_path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "wb") as out:
        out.write(key_pem)
    os.chmod(key_path, 0o600)  # also when the file was there before with wider rights
    cert_path.write_bytes(cert.public_bytes(serialization.Encoding.PEM))


def certificate_names(cert_path: Path | str) -> set[str]:
    """The DNS names and IP addresses (as text) of a PEM certificate's subjectAltName."""
    from cryptography import x509

    cert = x509.load_pem_x509_certificate(Path(cert_path).read_bytes())
    try:
        san = cert.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    except x509.ExtensionNotFound:
        return set()
    return set(san.get_values_for_type(x509.DNSName)) | {str(ip) for ip in san.get_values_for_type(x509.IPAddress)}


def _reusable(cert_path: Path, key_path: Path, hosts: list[str]) -> bool:
    from cryptography import x509
    from cryptography.hazmat.primitives import serialization

    try:
        cert = x509.load_pem_x509_certificate(cert_path.read_bytes())
        key = serialization.load_pem_private_key(key_path.read_bytes(), password=None)
    except (OSError, ValueError, TypeError):
        return False
    if cert.public_key() != key.public_key():
        return False
    if cert.not_valid_after_utc - dt.datetime.now(dt.UTC) < MIN_REMAINING:
        return False
    return set(hosts) <= certificate_names(cert_path)


def self_signed_certificate(directory: Path | str, hosts: list[str]) -> tuple[Path, Path, bool]:
    """The self-signed certificate and key in `directory`, made again unless still valid for `hosts`.

    Parameters
    ----------
    directory : path
        Where ``cert.pem`` and ``key.pem`` are kept (Settings.tls_dir).
    hosts : list of str
        Names and addresses the certificate must cover.

    Returns
    -------
    cert_path, key_path : pathlib.Path
    made : bool
        True when the files were (re)generated, False when the stored ones were reused.
    """
    directory = Path(directory)
    cert_path, key_path = directory / CERT_NAME, directory / KEY_NAME
    if _reusable(cert_path, key_path, hosts):
        return cert_path, key_path, False
    try:
        make_self_signed(cert_path, key_path, hosts)
    except OSError as exc:
        raise CertificateError(f"cannot write the certificate to {directory}: {exc.strerror}") from None
    return cert_path, key_path, True


def check_certificate_files(cert_path: Path | str, key_path: Path | str) -> None:
    """Raise CertificateError unless the two files are a PEM certificate and its unencrypted key.

    The check is the one the server makes when it starts (``ssl.SSLContext.load_cert_chain``), so that
    a bad file is one line of explanation instead of a traceback from the server.
    """
    for path in (Path(cert_path), Path(key_path)):
        if not path.is_file():
            raise CertificateError(f"no such file: {path}")
        if not os.access(path, os.R_OK):
            raise CertificateError(f"cannot read {path}")
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    try:
        context.load_cert_chain(str(cert_path), str(key_path), password=lambda: b"")
    except ssl.SSLError as exc:
        raise CertificateError(
            f"{cert_path} and {key_path} are not a PEM certificate and its unencrypted "
            f"private key ({exc.reason or exc})"
        ) from None
    except OSError as exc:
        raise CertificateError(f"cannot read {cert_path} or {key_path}: {exc.strerror}") from None


def fingerprint(cert_path: Path | str) -> str:
    """SHA-256 fingerprint of the (first) certificate of a PEM file, as browsers show it (AB:CD:…)."""
    text = Path(cert_path).read_text(errors="replace")
    match = re.search(r"-----BEGIN CERTIFICATE-----.*?-----END CERTIFICATE-----", text, re.S)
    if not match:
        raise CertificateError(f"{cert_path} holds no PEM certificate")
    digest = hashlib.sha256(ssl.PEM_cert_to_DER_cert(match.group(0))).hexdigest().upper()
    return ":".join(digest[i : i + 2] for i in range(0, len(digest), 2))
