"""``trical serve``: the API and the pages, over HTTP or (``--https``) TLS with the phone page's address and
its QR code printed."""

from __future__ import annotations

import os
import sys
from typing import TYPE_CHECKING

from app import __version__

if TYPE_CHECKING:
    from collections.abc import Callable

    from app.config import Settings


def run(args, settings: Callable[[], Settings]) -> int:
    """``trical serve``: uvicorn on HTTP, or on TLS with ``--https`` (or ``--cert`` and ``--key``)."""
    import uvicorn

    config = settings()
    port = args.port or config.port
    if args.https or args.cert or args.key:
        return _serve_https(args, config, port)
    host = args.host or config.host or "127.0.0.1"
    print(f"trical {__version__} on http://{host}:{port}  (database {config.database_label})", flush=True)
    uvicorn.run("app.main:app", host=host, port=port, log_level="info")
    return 0


def _serve_https(args, settings: Settings, port: int) -> int:
    import uvicorn

    from app.reach import tls
    from app.reach.qr import qr_terminal

    if bool(args.cert) != bool(args.key):
        raise tls.CertificateError("--cert and --key go together: give both, or neither for a self-signed certificate")
    host = args.host or settings.host or "0.0.0.0"
    everywhere = host in ("0.0.0.0", "::")
    lan_ip = tls.lan_addresses()[0]
    url_host = lan_ip if everywhere else (f"[{host}]" if ":" in host else host)
    url = f"https://{url_host}:{port}/wizard?protocol=six"
    print(f"trical {__version__} on https://{host}:{port}  (database {settings.database_label})")
    if everywhere:
        print(
            f"listening on every interface ({host}) so that a phone on this network can connect; "
            "--host 127.0.0.1 keeps it to this machine"
        )
    if args.cert:
        tls.check_certificate_files(args.cert, args.key)
        cert, key = args.cert, args.key
        print(f"certificate {cert} (SHA-256 {tls.fingerprint(cert)})")
    else:
        hosts = tls.certificate_hosts([] if everywhere else [host])
        cert, key, made = tls.self_signed_certificate(settings.tls_dir, hosts)
        print(f"{'made a' if made else 'reusing the'} self-signed certificate {cert} for {', '.join(hosts)}")
        print(
            "The browser will warn that this certificate is not trusted (it signed itself). Proceed when its\n"
            "SHA-256 fingerprint is the one below (Chrome: Advanced → Proceed; Safari: Show Details → visit):\n"
            f"  {tls.fingerprint(cert)}"
        )
    if not settings.public_url:
        os.environ["TRICAL_PUBLIC_URL"] = url  # app.main builds its settings from the environment
    print(f"Open {url} on your phone")
    _print_qr(qr_terminal(url))
    uvicorn.run("app.main:app", host=host, port=port, log_level="info", ssl_certfile=str(cert), ssl_keyfile=str(key))
    return 0


def _print_qr(drawing: str) -> None:
    try:
        sys.stdout.write(drawing)
    except UnicodeEncodeError:  # a terminal that cannot show block characters
        print("(this terminal cannot draw the QR code: type the address above)")
    sys.stdout.flush()
